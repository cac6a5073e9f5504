#include "ppp_bayes_tree/ros/node_outputs.h"

#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <ros/console.h>

#include "ppp_bayes_tree/ros/lever_arm.h"
#include "ppp_bayes_tree/ros/node_inputs.h"
#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp_ros {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool isProductRejection(const ppp::EpochRejection& r) {
  return r.stage == ppp::RejectionStage::Model &&
         (r.reason == ppp::RejectionReason::NoClock || r.reason == ppp::RejectionReason::NoOrbit);
}

/// The lagged output's smoother (nullptr: not a fixed-lag smoother).
ppp::PppSmoother* laggedSmoother(ppp::PppEstimator& estimator) {
  auto* s = dynamic_cast<ppp::PppSmoother*>(&estimator);
  return s && s->fixedLag_s() > 0.0 ? s : nullptr;
}

}  // namespace

std::uint8_t solutionState(bool solved, const Eigen::Vector3d& sigma_enu_m, const RosNodeOptions& o) {
  if (!solved || !sigma_enu_m.allFinite()) return ppp_bayes_tree::PppStatus::NO_SOLUTION;
  const double horizontal = std::hypot(sigma_enu_m.x(), sigma_enu_m.y());
  if (horizontal <= o.converged_horizontal_sigma_m && sigma_enu_m.z() <= o.converged_vertical_sigma_m)
    return ppp_bayes_tree::PppStatus::CONVERGED;
  return ppp_bayes_tree::PppStatus::CONVERGING;
}

std::string solutionStateText(std::uint8_t state) {
  switch (state) {
    case ppp_bayes_tree::PppStatus::CONVERGED: return "converged";
    case ppp_bayes_tree::PppStatus::CONVERGING: return "converging";
    default: return "no_solution";
  }
}

EpochFigures epochFigures(const NodeInputs& inputs, const ppp::PppEstimator& estimator, const ppp::ObsEpoch& epoch,
                          const ppp::PppEpochRecord& rec, double update_s, std::vector<std::string> warnings) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  EpochFigures f;
  f.update_time_s = update_s;
  const std::optional<ppp::GnssTime> newest = inputs.corrections().newest();
  f.correction_latency_s = newest ? epoch.time - *newest : kNaN;
  f.corrections_stale_s = inputs.correctionsStale_s().value_or(kNaN);
  f.product_mode = inputs.productMode();
  f.product_mode_text = inputs.productModeText();
  // The EKF updates its whole state; the smoother re-eliminates the variables it reports.
  f.variables_reeliminated = static_cast<std::uint32_t>(
      rec.smoother ? rec.smoother->variables_reeliminated
                   : static_cast<std::size_t>(estimator.layout().dim() + rec.active_biases));
  f.active_arcs = estimator.activeArcs();
  f.warnings = std::move(warnings);
  return f;
}

DatumRequest datumRequest(double latitude_deg, double longitude_deg, double height_m) {
  if (!std::isfinite(latitude_deg) || !std::isfinite(longitude_deg) || !std::isfinite(height_m) ||
      std::abs(latitude_deg) > 90.0 || std::abs(height_m) > 1e6)
    return {std::nullopt, "invalid datum (latitude in [-90, 90] deg, finite longitude, |height| < 1000 km)"};
  return {ppp::geodeticToEcef({latitude_deg * ppp::kDegToRad, longitude_deg * ppp::kDegToRad, height_m}), "datum set"};
}

std::optional<Eigen::Vector3d> configuredDatum(const RosNodeOptions& o) {
  if (o.datum_mode != "configured") return std::nullopt;
  return ppp::geodeticToEcef(
      ppp::Geodetic{o.datum_latitude_deg * ppp::kDegToRad, o.datum_longitude_deg * ppp::kDegToRad, o.datum_height_m});
}

bool solvedEpoch(const ppp::PppEpochRecord& rec) {
  return rec.status == ppp::EpochStatus::Ok && rec.solution.position_ecef_m.has_value();
}

geometry_msgs::TransformStamped transformMsg(const std::string& parent, const std::string& child, const ros::Time& stamp,
                                             const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = stamp;
  m.header.frame_id = parent;
  m.child_frame_id = child;
  m.transform.translation.x = t.x();
  m.transform.translation.y = t.y();
  m.transform.translation.z = t.z();
  m.transform.rotation.w = q.w();
  m.transform.rotation.x = q.x();
  m.transform.rotation.y = q.y();
  m.transform.rotation.z = q.z();
  return m;
}

sensor_msgs::NavSatFix navSatFix(const Eigen::Vector3d& p, const Eigen::Matrix3d& cov_ecef, std::uint8_t fix_state,
                                 const ros::Time& stamp, const std::string& antenna_frame) {
  sensor_msgs::NavSatFix fix;
  fix.header.stamp = stamp;
  fix.header.frame_id = antenna_frame;  // REP-145: the fix is the antenna's position
  const ppp::Geodetic g = ppp::ecefToGeodetic(p);
  fix.latitude = g.latitude_rad * ppp::kRadToDeg;
  fix.longitude = g.longitude_rad * ppp::kRadToDeg;
  fix.altitude = g.height_m;
  const Eigen::Matrix3d r_local = ppp::rotationEnuFromEcef(g.latitude_rad, g.longitude_rad);
  const Eigen::Matrix3d cov_local = r_local * cov_ecef * r_local.transpose();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) fix.position_covariance[r * 3 + c] = cov_local(r, c);  // ENU, m^2 (REP-145)
  fix.position_covariance_type = sensor_msgs::NavSatFix::COVARIANCE_TYPE_KNOWN;
  // Carrier-phase fixed: STATUS_GBAS_FIX, as ublox_gps reports an RTK fix (doc/ros_interface.md).
  fix.status.status = fix_state == ppp_bayes_tree::PppStatus::FIX_FIXED ? sensor_msgs::NavSatStatus::STATUS_GBAS_FIX
                                                                        : sensor_msgs::NavSatStatus::STATUS_FIX;
  fix.status.service = sensor_msgs::NavSatStatus::SERVICE_GPS;
  return fix;
}

NodeOutputs::NodeOutputs(const RosNodeOptions& options, WarningSink warn) : options_(options), warn_(std::move(warn)) {
  path_.header.frame_id = options_.map_frame;
}

geometry_msgs::TransformStamped NodeOutputs::setDatum(const Eigen::Vector3d& p) {
  datum_ecef_m_ = p;
  const ppp::Geodetic g = ppp::ecefToGeodetic(p);
  ecef_to_enu_ = ppp::rotationEnuFromEcef(g.latitude_rad, g.longitude_rad);
  ROS_INFO("map datum: lat %.9f deg, lon %.9f deg, h %.4f m", g.latitude_rad * ppp::kRadToDeg,
           g.longitude_rad * ppp::kRadToDeg, g.height_m);
  // earth -> map: map axes (E, N, U) expressed in ECEF: columns of R^T.
  const Eigen::Quaterniond q(Eigen::Matrix3d(ecef_to_enu_.transpose()));
  return transformMsg(options_.earth_frame, options_.map_frame, ros::Time(0), p, q.normalized());
}

geometry_msgs::TransformStamped NodeOutputs::leverArmTransform() const {
  return transformMsg(options_.base_frame, options_.antenna_frame, ros::Time(0), options_.antenna_lever_arm_m,
                      Eigen::Quaterniond::Identity());
}

void NodeOutputs::receiveAttitude(const sensor_msgs::Imu& msg) {
  ++attitude_counters_.received;
  const auto& o = msg.orientation;
  const Eigen::Quaterniond q(o.w, o.x, o.y, o.z);
  if (!validAttitude(q) || msg.orientation_covariance[0] == -1.0 || msg.header.stamp.isZero()) {
    ++attitude_counters_.invalid;
    warn_("attitude_invalid", "ppp: attitude message without a valid orientation (unit quaternion, covariance[0] != -1, "
                              "stamp) ignored");
    return;
  }
  Attitude a;
  a.stamp = msg.header.stamp;
  a.q_map_base = q.normalized();
  std::copy(msg.orientation_covariance.begin(), msg.orientation_covariance.end(), a.covariance.begin());
  attitude_ = a;
}

void NodeOutputs::attachAttitude(const ros::Time& stamp) {
  // The newest attitude within max_age of the epoch is this epoch's (kept for the smoothed outputs).
  if (attitude_ && std::abs((attitude_->stamp - stamp).toSec()) <= options_.attitude_max_age_s) {
    attitude_of_epoch_[stamp] = *attitude_;
    while (attitude_of_epoch_.size() > options_.path_max_poses) attitude_of_epoch_.erase(attitude_of_epoch_.begin());
    return;
  }
  if (!lever_arm_note_logged_) {
    lever_arm_note_logged_ = true;
    if (options_.attitude_topic.empty())
      ROS_INFO_STREAM("ppp: no attitude source (ros.attitude.topic): " << options_.base_frame
                      << " is published at the antenna position (lever arm "
                      << options_.antenna_lever_arm_m.transpose() << " m not applied)");
  }
  if (!options_.attitude_topic.empty()) {
    ++attitude_counters_.epochs_without;
    warn_("attitude_missing", "ppp: no attitude within " + std::to_string(options_.attitude_max_age_s) +
                                  " s of the epoch: " + options_.base_frame + " published at the antenna position");
  }
}

NodeOutputs::BodyPose NodeOutputs::bodyPose(const Eigen::Vector3d& antenna_enu_m, const ros::Time& stamp) const {
  BodyPose pose;
  pose.position_m = antenna_enu_m;
  const auto it = attitude_of_epoch_.find(stamp);
  if (it != attitude_of_epoch_.end()) {
    pose.attitude = &it->second;
    pose.q_map_base = it->second.q_map_base;
    pose.position_m = baseLinkFromAntenna(antenna_enu_m, pose.q_map_base, options_.antenna_lever_arm_m);
  }
  return pose;
}

geometry_msgs::Pose NodeOutputs::BodyPose::toMsg() const {
  geometry_msgs::Pose p;
  p.position.x = position_m.x();
  p.position.y = position_m.y();
  p.position.z = position_m.z();
  p.orientation.w = q_map_base.w();
  p.orientation.x = q_map_base.x();
  p.orientation.y = q_map_base.y();
  p.orientation.z = q_map_base.z();
  return p;
}

nav_msgs::Odometry NodeOutputs::odometry(const ros::Time& stamp, const BodyPose& pose, const Eigen::Matrix3d& cov) const {
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = options_.map_frame;
  odom.child_frame_id = options_.base_frame;
  odom.pose.pose = pose.toMsg();
  // Position: the antenna's ENU covariance (the attitude's share through the lever arm is not added).
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) odom.pose.covariance[r * 6 + c] = cov(r, c);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)  // orientation: the attitude source's, else not estimated
      odom.pose.covariance[(r + 3) * 6 + c + 3] = pose.attitude ? pose.attitude->covariance[r * 3 + c] : (r == c ? 1e6 : 0.0);
  for (int i = 0; i < 6; ++i) odom.twist.covariance[i * 6 + i] = 1e6;  // twist not estimated
  return odom;
}

ppp_bayes_tree::PppStatus NodeOutputs::withCounters(const ppp_bayes_tree::PppStatus& input_counters) const {
  ppp_bayes_tree::PppStatus s = input_counters;
  s.epochs_processed = counters_.epochs_processed;
  s.epochs_out_of_order = input_counters.epochs_out_of_order + counters_.epochs_not_published;
  s.corrections_late = counters_.corrections_late;
  return s;
}

ppp_bayes_tree::PppStatus NodeOutputs::emptyEpochStatus(const ppp::GnssTime& time,
                                                        const ppp_bayes_tree::PppStatus& counters,
                                                        double corrections_stale_s, const PhaseBiasChoice& phase,
                                                        bool ar_enabled) {
  ppp_bayes_tree::PppStatus s = withCounters(counters);
  s.header.stamp = utcStamp(time);
  s.header.frame_id = options_.map_frame;
  s.solution_state = ppp_bayes_tree::PppStatus::NO_SOLUTION;
  s.solution_state_text = "no_solution";
  s.reason = "empty epoch";
  setFixState(ppp::PppEpochRecord{}, false, phase, ar_enabled, s);
  s.corrections_stale_s = corrections_stale_s;
  return s;
}

std::uint16_t NodeOutputs::setSatellites(const ppp::PppEpochRecord& rec, ppp_bayes_tree::PppStatus& s) const {
  s.satellites_observed = static_cast<std::uint16_t>(rec.satellites_observed);
  s.satellites_used = static_cast<std::uint16_t>(rec.used.size());
  s.satellites_rejected = static_cast<std::uint16_t>(rec.rejected.size());
  for (const auto& u : rec.used) s.used.push_back(u.toString());
  std::uint16_t late = 0;
  for (const auto& r : rec.rejected) {
    s.rejected.push_back(r.satellite.toString() + " " + r.text());
    if (isProductRejection(r)) ++late;
  }
  return late;
}

Eigen::Vector3d NodeOutputs::setSolution(const ppp::PppEpochRecord& rec, ppp_bayes_tree::PppStatus& s) const {
  Eigen::Vector3d sigma_enu = Eigen::Vector3d::Constant(kNaN);
  s.zwd_m = s.zwd_sigma_m = s.receiver_clock_m = s.receiver_clock_sigma_m = kNaN;
  if (!solvedEpoch(rec)) return sigma_enu;
  const Eigen::Matrix3d cov_enu = ecef_to_enu_ * *rec.solution.covariance_ecef_m2 * ecef_to_enu_.transpose();
  sigma_enu = cov_enu.diagonal().cwiseMax(0.0).cwiseSqrt();
  s.zwd_m = rec.solution.zwd_m.value_or(kNaN);
  const ppp::ReceiverStateLayout& layout = rec.state_layout;
  s.zwd_sigma_m = std::sqrt(std::max(0.0, rec.receiver_covariance(layout.zwd(), layout.zwd())));
  s.receiver_clock_m = rec.solution.receiver_clock_m.value_or(kNaN);  // the reference system's clock
  const int clock = layout.firstClock();
  s.receiver_clock_sigma_m = std::sqrt(std::max(0.0, rec.receiver_covariance(clock, clock)));
  return sigma_enu;
}

ppp_bayes_tree::PppStatus NodeOutputs::epochStatus(const ppp::GnssTime& time, const ppp::PppEpochRecord& rec,
                                                   const ppp_bayes_tree::PppStatus& counters,
                                                   const EpochFigures& figures, const PhaseBiasChoice& phase,
                                                   bool ar_enabled) {
  ++counters_.epochs_processed;
  ppp_bayes_tree::PppStatus s = withCounters(counters);
  s.header.stamp = utcStamp(time);
  s.header.frame_id = options_.map_frame;
  s.reason = rec.reason;
  s.warnings = figures.warnings;
  s.converged_horizontal_sigma_m = options_.converged_horizontal_sigma_m;
  s.converged_vertical_sigma_m = options_.converged_vertical_sigma_m;
  const std::uint16_t late = setSatellites(rec, s);
  s.satellites_without_corrections = late;
  counters_.corrections_late += late;
  s.corrections_late = counters_.corrections_late;
  if (late > 0) warn_("late", "ppp: " + std::to_string(late) + " satellite(s) without corrections at " +
                                  time.toString() + " excluded (e.g. " + s.rejected.back() + ")");
  s.update_time_s = figures.update_time_s;
  s.correction_latency_s = figures.correction_latency_s;
  s.corrections_stale_s = figures.corrections_stale_s;
  s.active_biases = static_cast<std::uint16_t>(rec.active_biases);
  s.product_mode = figures.product_mode;
  s.product_mode_text = figures.product_mode_text;
  s.variables_reeliminated = figures.variables_reeliminated;
  {
    std::map<ppp::ArcId, std::string> sat_of_arc;
    for (const auto& r : rec.residuals) sat_of_arc[r.arc] = r.satellite.toString() + " ";
    for (const ppp::ArcId a : figures.active_arcs) s.active_bias_arcs.push_back(sat_of_arc[a] + "arc " + std::to_string(a));
  }
  const bool solved = solvedEpoch(rec);
  const Eigen::Vector3d sigma_enu = setSolution(rec, s);
  s.sigma_east_m = sigma_enu.x();
  s.sigma_north_m = sigma_enu.y();
  s.sigma_up_m = sigma_enu.z();
  s.solution_state = solutionState(solved, sigma_enu, options_);
  s.solution_state_text = solutionStateText(s.solution_state);
  setFixState(rec, solved, phase, ar_enabled, s);
  if (rec.status == ppp::EpochStatus::Failed) warn_("failed", "ppp: estimator failed at " + time.toString() + ": " + rec.reason);
  last_status_ = s;
  last_smoother_ = rec.smoother;
  return s;
}

void NodeOutputs::setFixState(const ppp::PppEpochRecord& rec, bool solved, const PhaseBiasChoice& phase,
                              bool ar_enabled, ppp_bayes_tree::PppStatus& s) {
  using ppp_bayes_tree::PppStatus;
  s.ambiguity_resolution_enabled = ar_enabled;
  s.phase_bias_source = phase.provider ? phase.source : "";
  const bool fixed = solved && rec.solution.status == ppp::SolutionStatus::PppFixed;
  if (solved && !first_solved_) first_solved_ = rec.solution.time;
  if (fixed) {
    ++epochs_fixed_;
    if (!first_fixed_) first_fixed_ = rec.solution.time;
  }
  s.fix_state = !solved ? PppStatus::FIX_NO_SOLUTION : fixed ? PppStatus::FIX_FIXED : PppStatus::FIX_FLOAT;
  s.fix_state_text = !solved ? "no_solution" : fixed ? "fixed" : "float";
  if (fixed) s.float_reason = "";
  else if (!s.ambiguity_resolution_enabled) s.float_reason = "ambiguity resolution off";
  else if (!phase.provider) s.float_reason = phase.source;
  else if (rec.ambiguity_fix) s.float_reason = rec.ambiguity_fix->text();
  else s.float_reason = solved ? "" : "no solution";
  if (rec.ambiguity_fix) {
    s.ambiguities_fixed = static_cast<std::uint16_t>(std::max(0, rec.ambiguity_fix->held));
    s.wide_lanes_fixed = static_cast<std::uint16_t>(std::max(0, rec.ambiguity_fix->wide_lanes_fixed));
    s.ratio = rec.ambiguity_fix->ratio;
    s.ambiguities_released = static_cast<std::uint16_t>(rec.ambiguity_fix->released.size());
    for (const ppp::AmbiguityRelease& r : rec.ambiguity_fix->released)
      if (r.reason != ppp::AmbiguityReleaseReason::ArcEnded) ++ambiguity_releases_;
  }
  s.ambiguity_releases = ambiguity_releases_;
  s.epochs_fixed = epochs_fixed_;
  if (first_fixed_) s.first_fix_stamp = utcStamp(*first_fixed_);
  s.time_to_first_fix_s = timeToFirstFix_s();
}

double NodeOutputs::timeToFirstFix_s() const {
  return first_fixed_ && first_solved_ ? *first_fixed_ - *first_solved_ : kNaN;
}

SolutionMessages NodeOutputs::solution(const ppp::PppEpochRecord& rec, const ppp_bayes_tree::PppStatus& status,
                                       const std::optional<geometry_msgs::TransformStamped>& odom_to_base) {
  const ros::Time stamp = status.header.stamp;
  attachAttitude(stamp);
  const Eigen::Vector3d& p = *rec.solution.position_ecef_m;
  const Eigen::Matrix3d cov_enu = ecef_to_enu_ * *rec.solution.covariance_ecef_m2 * ecef_to_enu_.transpose();
  // The estimate is the antenna (marker) position; base_link = antenna - R * lever arm
  // with an attitude for this epoch, else base_link is the antenna position (documented).
  const BodyPose body = bodyPose(ecef_to_enu_ * (p - *datum_ecef_m_), stamp);
  SolutionMessages out;
  out.odometry = odometry(stamp, body, cov_enu);
  out.fix = navSatFix(p, *rec.solution.covariance_ecef_m2, status.fix_state, stamp, options_.antenna_frame);

  geometry_msgs::PoseStamped pose;
  pose.header = out.odometry.header;
  pose.pose = out.odometry.pose.pose;
  path_.poses.push_back(pose);
  if (path_.poses.size() > options_.path_max_poses) path_.poses.erase(path_.poses.begin());

  out.tf = mapTransform(stamp, body.position_m, body.q_map_base, odom_to_base);
  return out;
}

std::optional<geometry_msgs::TransformStamped> NodeOutputs::mapTransform(
    const ros::Time& stamp, const Eigen::Vector3d& position_m, const Eigen::Quaterniond& q_map_base,
    const std::optional<geometry_msgs::TransformStamped>& odom_to_base) const {
  if (!options_.publish_tf) return std::nullopt;
  if (!odom_to_base) return transformMsg(options_.map_frame, options_.base_frame, stamp, position_m, q_map_base);
  // map -> odom when another node publishes odom -> base_link: T_map_odom = T_map_base * T_odom_base^-1
  const auto& ob = odom_to_base->transform;
  const Eigen::Quaterniond q_ob(ob.rotation.w, ob.rotation.x, ob.rotation.y, ob.rotation.z);
  const Eigen::Vector3d t_ob(ob.translation.x, ob.translation.y, ob.translation.z);
  const Eigen::Quaterniond q_mo = q_map_base * q_ob.inverse();
  const Eigen::Vector3d t_mo = position_m - q_mo * t_ob;
  return transformMsg(options_.map_frame, options_.odom_frame, stamp, t_mo, q_mo);
}

const nav_msgs::Path* NodeOutputs::filteredPath() {
  if (path_.poses.empty()) return nullptr;
  path_.header.stamp = path_.poses.back().header.stamp;
  return &path_;
}

std::optional<nav_msgs::Odometry> NodeOutputs::smoothedOdometry(const ppp::SmoothedTrajectoryProvider& smoother,
                                                                const ppp::GnssTime& newest) {
  if (!datum_ecef_m_) return std::nullopt;
  // Delay 0: the lag boundary (fixed lag: the state at t - lag, clamped to the window) or the newest state.
  double delay_s = options_.smoothed_odometry_delay_s;
  if (delay_s == 0.0) delay_s = smoother.fixedLag_s();
  const std::optional<ppp::SmoothedEpoch> e = smoother.smoothedEpochAt(newest - delay_s, true);
  if (!e || !e->covariance || (last_smoothed_index_ && e->index <= *last_smoothed_index_)) return std::nullopt;
  last_smoothed_index_ = e->index;
  const int p = e->state.layout.position();
  const Eigen::Matrix3d cov_ecef = e->covariance->block<3, 3>(p, p);
  const Eigen::Matrix3d cov_enu = ecef_to_enu_ * cov_ecef * ecef_to_enu_.transpose();
  const ros::Time stamp = utcStamp(e->time);
  return odometry(stamp, bodyPose(ecef_to_enu_ * (e->state.position_ecef_m - *datum_ecef_m_), stamp), cov_enu);
}

std::optional<nav_msgs::Path> NodeOutputs::smoothedPath(const ppp::SmoothedTrajectoryProvider& sm) {
  // The whole trajectory is re-read at the path rate only (O(states), no covariance).
  if (!smoothed_path_stale_ || !datum_ecef_m_) return std::nullopt;
  smoothed_path_stale_ = false;
  const auto start = std::chrono::steady_clock::now();
  const std::vector<ppp::SmoothedEpoch> trajectory =
      lagged_output_ ? lagged_output_->joined(sm.smoothedTrajectory(false), options_.path_max_poses)
                     : sm.smoothedTrajectory(false);
  nav_msgs::Path path;
  path.header.frame_id = options_.map_frame;
  const std::size_t first = trajectory.size() > options_.path_max_poses ? trajectory.size() - options_.path_max_poses : 0;
  path.poses.reserve(trajectory.size() - first);
  for (std::size_t k = first; k < trajectory.size(); ++k) {
    const ros::Time stamp = utcStamp(trajectory[k].time);
    geometry_msgs::PoseStamped pose;
    pose.header.stamp = stamp;
    pose.header.frame_id = options_.map_frame;
    pose.pose = bodyPose(ecef_to_enu_ * (trajectory[k].state.position_ecef_m - *datum_ecef_m_), stamp).toMsg();
    path.poses.push_back(pose);
  }
  if (!path.poses.empty()) path.header.stamp = path.poses.back().header.stamp;
  smoothed_path_read_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  smoothed_path_read_max_s_ = std::max(smoothed_path_read_max_s_, smoothed_path_read_s_);
  smoothed_path_poses_ = path.poses.size();
  return path;
}

void NodeOutputs::attachLaggedOutput(ppp::PppEstimator& estimator) {
  ppp::PppSmoother* sm = laggedSmoother(estimator);
  if (!sm) {
    if (!options_.smoothed_trajectory_csv.empty() && estimator.smoothing())
      ROS_WARN("ppp: ros/smoothed/trajectory_csv is ignored: the full smoother (smoother/fixed_lag_s 0) keeps every "
               "state");
    return;
  }
  if (!lagged_output_)
    lagged_output_ = std::make_unique<ppp::LaggedTrajectoryOutput>(options_.smoothed_trajectory_csv,
                                                                   options_.path_max_poses);
  lagged_output_->attach(*sm);
}

void NodeOutputs::finishLaggedOutput(ppp::PppEstimator& estimator) {
  if (ppp::PppSmoother* sm = laggedSmoother(estimator); sm && lagged_output_) lagged_output_->finish(*sm);
}

void NodeOutputs::resetTrajectory() {
  path_.poses.clear();
  attitude_of_epoch_.clear();
  last_smoothed_index_.reset();
  smoothed_path_stale_ = true;  // publishes the (empty) new trajectory
  epochs_fixed_ = 0;
  ambiguity_releases_ = 0;
  first_solved_.reset();
  first_fixed_.reset();
}

void NodeOutputs::clearPathsForDatum() {
  path_.poses.clear();
  smoothed_path_stale_ = true;  // re-read in the new map frame at the next path period
}

}  // namespace ppp_ros
