#include "ppp_bayes_tree/ros/ppp_node.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/NavSatFix.h>

#include "ppp_bayes_tree/evaluation/quantile.h"
#include "ppp_bayes_tree/ros/lever_arm.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/types/thread_cpu_time.h"

namespace ppp_ros {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

geometry_msgs::TransformStamped transform(const std::string& parent, const std::string& child, const ros::Time& stamp,
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

/// Messages missing between the last header.seq of `publisher` and `seq` (roscpp numbers
/// each publication's messages consecutively). A seq not above the last one (a publisher
/// that restarted, or one that leaves seq 0) starts counting afresh: no loss counted.
std::uint32_t sequenceGap(std::map<std::string, std::uint32_t>& last_seq, const std::string& publisher,
                          std::uint32_t seq) {
  const auto it = last_seq.find(publisher);
  if (it == last_seq.end()) {
    last_seq[publisher] = seq;
    return 0;
  }
  const std::uint32_t previous = it->second;
  it->second = seq;
  return seq > previous ? seq - previous - 1 : 0;
}

std::string secondsText(double s) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%+.3f s", s);
  return buf;
}

bool isProductRejection(const ppp::EpochRejection& r) {
  return r.stage == ppp::RejectionStage::Model &&
         (r.reason == ppp::RejectionReason::NoClock || r.reason == ppp::RejectionReason::NoOrbit);
}

}  // namespace

NodeConfig loadNodeConfig(const ros::NodeHandle& private_nh) {
  const std::string source = "ROS parameters " + private_nh.getNamespace();
  XmlRpc::XmlRpcValue params;
  YAML::Node root(YAML::NodeType::Map);
  if (private_nh.getParam(private_nh.getNamespace(), params) && params.getType() == XmlRpc::XmlRpcValue::TypeStruct)
    root = xmlRpcToYaml(params);
  NodeConfig c;
  c.ppp = ppp::bindPppConfig(root, source);  // the XmlRpc types kept (no text round trip)
  c.ros = bindRosNodeOptions(c.ppp.ros, source);
  return c;
}

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

PppNode::PppNode(ros::NodeHandle nh, ros::NodeHandle pnh, const std::string& estimator)
    : nh_(nh),
      pnh_(pnh),
      config_(loadNodeConfig(pnh)),
      corrections_([&] {
        ppp::CorrectionBufferOptions o;
        o.history_s = config_.ros.correction_history_s;
        return o;
      }()),
      tf_listener_(tf_buffer_),
      diagnostics_(nh, pnh),
      stream_biases_(config_.ros.correction_history_s) {
  config_.ros.estimator = estimator;
  const RosNodeOptions& o = config_.ros;
  if (o.atx.empty() && (config_.ppp.model.satellite_antenna ||
                        config_.ppp.model.receiver_antenna == ppp::ReceiverAntennaPolicy::Required))
    throw std::runtime_error("parameter ros/products/atx is empty, but measurement_model/corrections/"
                             "satellite_antenna is on or receiver_antenna is required: give the ANTEX file(s) or "
                             "turn them off");
  // The products (the core's one assembly, as ppp_solve): they resolve the systems and
  // the PPP-AR gate, so the estimator is made from their config. Streamed corrections
  // declare their clock centre and antenna model with the first batch (declareStreamedProducts).
  ppp::ProductAssemblyInputs products_in;
  products_in.atx = o.atx;
  if (!o.bias.empty()) products_in.bias = o.bias;
  if (!o.blq.empty()) products_in.blq = o.blq;
  // The live SSR feed carries no antenna model: the configuration states it (ssr.antenna_model).
  products_in.live_ssr = o.live() && !o.live_correction_topics.empty();
  products_ = ppp::ProductAssembly::assemble(products_in, config_.ppp);
  config_.ppp = products_.config();
  for (const auto& n : products_.notes()) ROS_INFO_STREAM("ppp_" << estimator << "_node: " << n);
  std::string why;
  estimator_ = ppp::makeEstimator(estimator, config_.ppp, &why);
  if (!estimator_) throw std::runtime_error("estimator '" + estimator + "' is not available: " + why);
  gate_ = ppp::CorrectionGate<Pending>({o.correction_wait_s, o.max_pending_epochs});
  {
    ppp::EpochTimeGuardOptions g;
    g.max_forward_step_s = o.max_forward_step_s;
    g.out_of_order_window_s = o.reset_backwards_threshold_s;
    g.confirm_epochs = o.time_jump_confirm_epochs;
    obs_guard_ = ppp::EpochTimeGuard<Pending>(g);
    // Correction batches: farther apart than the history cannot be interpolated anyway;
    // out-of-order batches go to the buffer, which orders them and drops duplicates.
    g.max_forward_step_s = o.correction_history_s;
    g.drop_out_of_order = false;
    corr_guard_ = ppp::EpochTimeGuard<CorrectionInput>(g);
  }
  if (o.datum_mode == "configured") {
    ppp::Geodetic g{o.datum_latitude_deg * ppp::kDegToRad, o.datum_longitude_deg * ppp::kDegToRad, o.datum_height_m};
    setDatum(ppp::geodeticToEcef(g));
  }
  counters_.estimator = estimator;
  attachLaggedOutput();
  if (smoother()) announceSmootherCost();

  // Queues as configured (observations: at least what the correction wait buffers);
  // whatever is lost before the node anyway is counted from header.seq.
  if (o.live()) {
    startLiveInput();
  } else {
    obs_sub_ = nh_.subscribe(o.observations_topic, static_cast<std::uint32_t>(o.observation_queue_size),
                             &PppNode::onObservations, this);
    corr_sub_ = nh_.subscribe(o.corrections_topic, static_cast<std::uint32_t>(o.correction_queue_size),
                              &PppNode::onCorrections, this);
  }
  odom_pub_ = nh_.advertise<nav_msgs::Odometry>("ppp/odometry/filtered", 100);
  fix_pub_ = nh_.advertise<sensor_msgs::NavSatFix>("ppp/fix", 100);
  status_pub_ = nh_.advertise<ppp_bayes_tree::PppStatus>("ppp/status", 100);
  path_pub_ = nh_.advertise<nav_msgs::Path>("ppp/path/filtered", 2, true);
  if (smoother()) {  // the EKF node does not advertise the smoothed topics
    smoothed_odom_pub_ = nh_.advertise<nav_msgs::Odometry>("ppp/odometry/smoothed", 100);
    smoothed_path_pub_ = nh_.advertise<nav_msgs::Path>("ppp/path/smoothed", 2, true);
    smoothed_path_timer_ =
        nh_.createTimer(ros::Duration(1.0 / o.smoothed_path_publish_rate_hz), &PppNode::onSmoothedPathTimer, this);
  }
  if (!o.attitude_topic.empty()) attitude_sub_ = nh_.subscribe(o.attitude_topic, 200, &PppNode::onAttitude, this);
  // base_link -> gnss_antenna: the lever arm, fixed in the body.
  static_tf_.sendTransform(transform(o.base_frame, o.antenna_frame, ros::Time(0), o.antenna_lever_arm_m,
                                     Eigen::Quaterniond::Identity()));
  datum_srv_ = nh_.advertiseService("set_datum", &PppNode::onSetDatum, this);
  timer_ = nh_.createTimer(ros::Duration(0.1), &PppNode::onTimer, this);
  path_timer_ = nh_.createTimer(ros::Duration(1.0 / o.path_publish_rate_hz), &PppNode::onPathTimer, this);
  path_.header.frame_id = o.map_frame;

  diagnostics_.setHardwareID("ppp_" + estimator);
  diagnostics_.add("inputs", this, &PppNode::diagnoseInputs);
  if (live_) diagnostics_.add("live streams", this, &PppNode::diagnoseLive);
  else diagnostics_.add("corrections", this, &PppNode::diagnoseCorrections);
  diagnostics_.add("solution", this, &PppNode::diagnoseSolution);
  diagnostics_.add("ambiguity resolution", this, &PppNode::diagnoseAmbiguities);
  last_diag_time_ = ros::WallTime::now();
  sim_clock_watch_ = std::make_unique<SimClockWatch>(nh_, "ppp_" + estimator + "_node");
  std::string inputs = nh_.resolveName(o.observations_topic) + " and " + nh_.resolveName(o.corrections_topic);
  if (live_) {
    inputs = "the live streams";
    for (const auto& sub : stream_subs_) inputs += " " + sub->topic();
  }
  ROS_INFO_STREAM("ppp_" << estimator << "_node: config from " << config_.ppp.source_name << ", " << products_.antexFiles()
                         << " ANTEX file(s), bias " << (o.bias.empty() ? "none" : o.bias) << ", waiting for " << inputs
                         << (o.attitude_topic.empty() ? std::string(", no attitude source")
                                                      : ", attitude from " + nh_.resolveName(o.attitude_topic)));
}

void PppNode::warn(const std::string& category, const std::string& text) {
  // Each case: logged the first time, then at most every 10 s (counted always).
  const ros::WallTime now = ros::WallTime::now();
  auto it = last_warning_.find(category);
  if (it != last_warning_.end() && (now - it->second).toSec() < 10.0) return;
  last_warning_[category] = now;
  ROS_WARN_STREAM(text);
}

void PppNode::setDatum(const Eigen::Vector3d& p) {
  datum_ecef_m_ = p;
  const ppp::Geodetic g = ppp::ecefToGeodetic(p);
  ecef_to_enu_ = ppp::rotationEnuFromEcef(g.latitude_rad, g.longitude_rad);
  // earth -> map: map axes (E, N, U) expressed in ECEF: columns of R^T.
  const Eigen::Quaterniond q(Eigen::Matrix3d(ecef_to_enu_.transpose()));
  static_tf_.sendTransform(transform(config_.ros.earth_frame, config_.ros.map_frame, ros::Time(0), p, q.normalized()));
  ROS_INFO("map datum: lat %.9f deg, lon %.9f deg, h %.4f m", g.latitude_rad * ppp::kRadToDeg,
           g.longitude_rad * ppp::kRadToDeg, g.height_m);
}

bool PppNode::onSetDatum(ppp_bayes_tree::SetDatum::Request& req, ppp_bayes_tree::SetDatum::Response& res) {
  if (!std::isfinite(req.latitude_deg) || !std::isfinite(req.longitude_deg) || !std::isfinite(req.height_m) ||
      std::abs(req.latitude_deg) > 90.0 || std::abs(req.height_m) > 1e6) {
    res.success = false;
    res.message = "invalid datum (latitude in [-90, 90] deg, finite longitude, |height| < 1000 km)";
    return true;
  }
  setDatum(ppp::geodeticToEcef({req.latitude_deg * ppp::kDegToRad, req.longitude_deg * ppp::kDegToRad, req.height_m}));
  path_.poses.clear();
  smoothed_path_stale_ = true;  // re-read in the new map frame at the next path period
  res.success = true;
  res.message = "datum set";
  return true;
}

PppNode::~PppNode() {
  if (ppp::PppSmoother* sm = laggedSmoother(); sm && lagged_output_) lagged_output_->finish(*sm);
}

ppp::PppSmoother* PppNode::laggedSmoother() {
  auto* s = dynamic_cast<ppp::SmootherEstimator*>(estimator_.get());
  return s && s->smoother().fixedLag_s() > 0.0 ? &s->smoother() : nullptr;
}

void PppNode::attachLaggedOutput() {
  ppp::PppSmoother* sm = laggedSmoother();
  if (!sm) {
    if (!config_.ros.smoothed_trajectory_csv.empty() && smoother())
      ROS_WARN("ppp: ros/smoothed/trajectory_csv is ignored: the full smoother (smoother/fixed_lag_s 0) keeps every "
               "state");
    return;
  }
  if (!lagged_output_)
    lagged_output_ = std::make_unique<ppp::LaggedTrajectoryOutput>(config_.ros.smoothed_trajectory_csv,
                                                                   config_.ros.path_max_poses);
  lagged_output_->attach(*sm);
}

void PppNode::announceSmootherCost() const {
  const double lag_s = config_.ppp.smoother.fixed_lag_s;
  if (lag_s <= 0.0) {
    // Measured with scripts/bench_live_node.sh (simulated loiter, ~9 satellites, 1 Hz at 30x).
    ROS_WARN("ppp_smoother_node: full smoother (smoother/fixed_lag_s 0): every state stays in memory, about 25 KB "
             "per epoch, and the update time grows with the trajectory (1 h at 1 Hz: RSS 125 MB, update p99 8.8 ms; "
             "15 min at 10 Hz: 285 MB, p99 39 ms, past a 10 Hz budget). For long bags and live use a fixed lag: "
             "config/live.yaml (launch files: smoother_memory:=bounded; 15 min at 10 Hz: 49 MB, p99 6.2 ms) writes "
             "each state leaving the lag to ros/smoothed/trajectory_csv");
    return;
  }
  ROS_INFO_STREAM("ppp_smoother_node: fixed-lag smoother, lag " << lag_s << " s: memory and update time bounded; "
                  << (config_.ros.smoothed_trajectory_csv.empty()
                          ? std::string("states leaving the lag are not written (ros/smoothed/trajectory_csv \"\")")
                          : "states leaving the lag written to " + config_.ros.smoothed_trajectory_csv));
}

void PppNode::resetEstimator(const std::string& why) {
  ++counters_.estimator_resets;
  counters_.epochs_discarded_at_reset += static_cast<std::uint32_t>(gate_.size());
  warn("reset", "ppp: estimator reset: " + why + "; " + std::to_string(gate_.size()) +
                    " epoch(s) waiting for corrections discarded (counted)");
  std::string unused;
  if (ppp::PppSmoother* sm = laggedSmoother(); sm && lagged_output_) lagged_output_->finish(*sm);
  estimator_ = ppp::makeEstimator(config_.ros.estimator, config_.ppp, &unused);
  attachLaggedOutput();  // the file continues (rows not after the last one are refused and counted)
  processor_.reset();
  gate_.clear();
  path_.poses.clear();
  attitude_of_epoch_.clear();
  last_smoothed_index_.reset();
  smoothed_path_stale_ = true;  // publishes the (empty) new trajectory
  last_received_.reset();
  last_output_time_.reset();
  epochs_fixed_ = 0;
  ambiguity_releases_ = 0;
  first_solved_.reset();
  first_fixed_.reset();
}

void PppNode::onAttitude(const sensor_msgs::Imu::ConstPtr& msg) {
  ++attitude_received_;
  const auto& o = msg->orientation;
  const Eigen::Quaterniond q(o.w, o.x, o.y, o.z);
  // REP-145: orientation_covariance[0] = -1 means no orientation estimate.
  if (!validAttitude(q) || msg->orientation_covariance[0] == -1.0 || msg->header.stamp.isZero()) {
    ++attitude_invalid_;
    warn("attitude_invalid", "ppp: attitude message without a valid orientation (unit quaternion, covariance[0] != -1, "
                             "stamp) ignored");
    return;
  }
  Attitude a;
  a.stamp = msg->header.stamp;
  a.q_map_base = q.normalized();
  std::copy(msg->orientation_covariance.begin(), msg->orientation_covariance.end(), a.covariance.begin());
  attitude_ = a;
}

void PppNode::attachAttitude(const ros::Time& stamp) {
  // The newest attitude within max_age of the epoch is this epoch's (kept for the smoothed outputs).
  if (attitude_ && std::abs((attitude_->stamp - stamp).toSec()) <= config_.ros.attitude_max_age_s) {
    attitude_of_epoch_[stamp] = *attitude_;
    while (attitude_of_epoch_.size() > config_.ros.path_max_poses) attitude_of_epoch_.erase(attitude_of_epoch_.begin());
    return;
  }
  if (!lever_arm_note_logged_) {
    lever_arm_note_logged_ = true;
    if (config_.ros.attitude_topic.empty())
      ROS_INFO_STREAM("ppp: no attitude source (ros.attitude.topic): " << config_.ros.base_frame
                      << " is published at the antenna position (lever arm "
                      << config_.ros.antenna_lever_arm_m.transpose() << " m not applied)");
  }
  if (!config_.ros.attitude_topic.empty()) {
    ++epochs_without_attitude_;
    warn("attitude_missing", "ppp: no attitude within " + std::to_string(config_.ros.attitude_max_age_s) +
                                 " s of the epoch: " + config_.ros.base_frame + " published at the antenna position");
  }
}

PppNode::BodyPose PppNode::bodyPose(const Eigen::Vector3d& antenna_enu_m, const ros::Time& stamp) const {
  BodyPose pose;
  pose.position_m = antenna_enu_m;
  const auto it = attitude_of_epoch_.find(stamp);
  if (it != attitude_of_epoch_.end()) {
    pose.attitude = &it->second;
    pose.q_map_base = it->second.q_map_base;
    pose.position_m = baseLinkFromAntenna(antenna_enu_m, pose.q_map_base, config_.ros.antenna_lever_arm_m);
  }
  return pose;
}

geometry_msgs::Pose PppNode::BodyPose::toMsg() const {
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

nav_msgs::Odometry PppNode::odometry(const ros::Time& stamp, const BodyPose& pose, const Eigen::Matrix3d& cov) const {
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = config_.ros.map_frame;
  odom.child_frame_id = config_.ros.base_frame;
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

void PppNode::onCorrections(const ros::MessageEvent<ppp_bayes_tree::PreciseCorrections const>& event) {
  const ppp_bayes_tree::PreciseCorrections::ConstPtr& msg = event.getMessage();
  ++corr_received_;
  if (const std::uint32_t lost = sequenceGap(corr_seq_, event.getPublisherName(), msg->header.seq)) {
    counters_.corrections_lost += lost;
    warn("corr_lost", "ppp: " + std::to_string(lost) + " correction message(s) lost before the node (header.seq gap "
                          "from " + event.getPublisherName() + "; queue ros.input.correction_queue_size " +
                          std::to_string(config_.ros.correction_queue_size) + "): counted");
  }
  ConversionIssues issues;
  CorrectionInput input;
  try {
    input.batch = fromMessage(*msg, issues);
    input.biases = biasesFromMessage(*msg, issues);
  } catch (const std::exception& e) {
    issues_.add(std::string("correction batch dropped: ") + e.what());
    warn("corrections_time", std::string("ppp: correction batch dropped: ") + e.what());
    return;
  }
  for (const auto& [reason, n] : issues.counts) {
    if (reason.find("unknown satellite") != std::string::npos) counters_.corrections_unknown_satellites += n;
    issues_.counts[reason] += n;
    warn("corr:" + reason.substr(0, 20), "ppp: corrections: " + reason);
  }
  if (input.batch.satellites.empty()) {
    warn("corr_empty", "ppp: correction batch without a usable satellite ignored");
    return;
  }
  declareStreamedProducts(*msg, input.batch);
  if (!input.biases.biases.empty()) stream_bias_kind_ = phaseInformation(msg->ar_bias_kind);
  last_correction_age_s_ = (ros::Time::now() - msg->header.stamp).toSec();
  const ppp::GnssTime time = input.batch.time;
  auto outcome = corr_guard_.push(time, std::move(input));
  for (const auto& d : outcome.dropped) {
    ++counters_.corrections_time_jump_dropped;
    last_time_drop_ = "correction batch " + d.time.toString() + " (" + secondsText(d.step_s) + "): " + ppp::text(d.reason);
    warn("corr_jump", "ppp: " + last_time_drop_ + ": dropped (counted)");
  }
  applyCorrectionOutcome(outcome);
  drain();
}

void PppNode::applyCorrectionOutcome(ppp::EpochTimeGuard<CorrectionInput>::Outcome& outcome) {
  if (outcome.reset_step_s) {
    warn("corrections_back", "ppp: correction time went back by " + secondsText(*outcome.reset_step_s) + ", confirmed (" +
                                 std::to_string(outcome.accepted.size()) + " batches): buffer of " +
                                 std::to_string(corrections_.size()) + " batches cleared");
    corrections_.clear();
    stream_biases_.clear();
  }
  for (auto& e : outcome.accepted) acceptCorrections(std::move(e.payload));
}

void PppNode::acceptCorrections(CorrectionInput input) {
  const ppp::BatchAddResult r = corrections_.add(std::move(input.batch));
  if (r == ppp::BatchAddResult::Added) stream_biases_.add(input.biases);
  if (r == ppp::BatchAddResult::Duplicate) warn("corr_dup", "ppp: duplicate correction batch ignored");
  if (r == ppp::BatchAddResult::TooOld) warn("corr_old", "ppp: correction batch older than the history ignored");
  if (r != ppp::BatchAddResult::Duplicate && r != ppp::BatchAddResult::TooOld) last_corr_arrival_ = ros::Time::now();
}

void PppNode::onObservations(const ros::MessageEvent<ppp_bayes_tree::GnssObservations const>& event) {
  const ppp_bayes_tree::GnssObservations::ConstPtr& msg = event.getMessage();
  ++obs_received_;
  if (const std::uint32_t lost = sequenceGap(obs_seq_, event.getPublisherName(), msg->header.seq)) {
    counters_.observations_lost += lost;
    warn("obs_lost", "ppp: " + std::to_string(lost) + " observation message(s) lost before the node (header.seq gap "
                         "from " + event.getPublisherName() + "; queue ros.input.observation_queue_size " +
                         std::to_string(config_.ros.observation_queue_size) + "): counted");
  }
  Pending p;
  p.msg = msg;
  p.arrival = ros::Time::now();
  last_obs_arrival_ = p.arrival;
  try {
    p.time = fromMessageTime(msg->week, msg->seconds_of_week, msg->time_system);
  } catch (const std::exception& e) {
    ++counters_.observations_invalid;
    warn("obs_time", std::string("ppp: observation epoch dropped: ") + e.what());
    return;
  }
  const ppp::GnssTime time = p.time;
  auto outcome = obs_guard_.push(time, std::move(p));
  for (const auto& d : outcome.dropped) {
    last_time_drop_ = "observation epoch " + d.time.toString() + " (" + secondsText(d.step_s) + "): " + ppp::text(d.reason);
    switch (d.reason) {
      case ppp::TimeDropReason::Duplicate: ++counters_.epochs_duplicate; break;
      case ppp::TimeDropReason::OutOfOrder: ++counters_.epochs_out_of_order; break;
      case ppp::TimeDropReason::UnconfirmedJump: ++counters_.epochs_time_jump_dropped; break;
    }
    warn("obs_drop:" + ppp::text(d.reason), "ppp: " + last_time_drop_ + ": dropped (counted)");
  }
  if (outcome.reset_step_s) {
    resetEstimator("time went back by " + secondsText(*outcome.reset_step_s) + " (beyond " +
                   std::to_string(config_.ros.reset_backwards_threshold_s) + " s), confirmed by " +
                   std::to_string(outcome.accepted.size()) + " consecutive epochs");
    // The observations' confirmed loop vouches for correction batches held as a jump back
    // to the new time line (within the correction history of its first epoch).
    const std::optional<ppp::GnssTime> held = corr_guard_.firstHeld();
    const std::optional<ppp::GnssTime>& last = corr_guard_.lastAccepted();
    if (held && last && *held < *last && !outcome.accepted.empty() &&
        std::abs(*held - outcome.accepted.front().time) <= config_.ros.correction_history_s) {
      auto corrections = corr_guard_.confirmHeld();
      applyCorrectionOutcome(corrections);
    }
  }
  if (outcome.forward_jump_s)
    warn("forward_jump", "ppp: time went forward by " + secondsText(*outcome.forward_jump_s) + ", confirmed by " +
                             std::to_string(outcome.accepted.size()) + " consecutive epochs: accepted");
  for (auto& e : outcome.accepted) acceptObservation(std::move(e.payload));
  drain();
}

void PppNode::acceptObservation(Pending p) {
  last_received_ = p.time;
  if (p.msg->satellites.empty()) {
    ++counters_.empty_epochs;
    warn("empty", "ppp: empty epoch " + p.time.toString() + " (no satellites): no solution");
    ppp_bayes_tree::PppStatus s = counters_;
    s.header.stamp = utcStamp(p.time);
    s.header.frame_id = config_.ros.map_frame;
    s.solution_state = ppp_bayes_tree::PppStatus::NO_SOLUTION;
    s.solution_state_text = "no_solution";
    s.reason = "empty epoch";
    setFixState(ppp::PppEpochRecord{}, false, s);
    s.corrections_stale_s = correctionsStale_s().value_or(kNaN);
    status_pub_.publish(s);
    return;
  }
  const ppp::GnssTime time = p.time;
  const double arrival_s = p.arrival.toSec();
  gate_.push(time, arrival_s, std::move(p));
}

std::optional<double> PppNode::correctionsStale_s() const {
  std::optional<double> stale;
  if (last_received_ && corrections_.newest()) stale = *last_received_ - *corrections_.newest();
  if (last_obs_arrival_ && last_corr_arrival_) {
    const double by_arrival = (*last_obs_arrival_ - *last_corr_arrival_).toSec();
    stale = stale ? std::max(*stale, by_arrival) : by_arrival;
  }
  return stale;
}

void PppNode::onTimer(const ros::TimerEvent&) {
  // A ros::Timer runs on the ROS clock: under sim time only once /clock has come, so
  // the live chunks held for a valid clock go on from here too (gnss_stream_subscriber.h).
  for (auto& sub : stream_subs_) sub->releaseHeld();
  drain();
}

void PppNode::onPathTimer(const ros::TimerEvent&) {
  if (path_.poses.empty()) return;
  path_.header.stamp = path_.poses.back().header.stamp;
  path_pub_.publish(path_);
}

void PppNode::onSmoothedPathTimer(const ros::TimerEvent&) {
  // The whole trajectory is re-read at this rate only (O(states), no covariance).
  const ppp::SmoothedTrajectoryProvider* sm = smoother();
  if (!sm || !smoothed_path_stale_ || !datum_ecef_m_) return;
  smoothed_path_stale_ = false;
  const auto start = std::chrono::steady_clock::now();
  const std::vector<ppp::SmoothedEpoch> trajectory =
      lagged_output_ ? lagged_output_->joined(sm->smoothedTrajectory(false), config_.ros.path_max_poses)
                     : sm->smoothedTrajectory(false);
  nav_msgs::Path path;
  path.header.frame_id = config_.ros.map_frame;
  const std::size_t first = trajectory.size() > config_.ros.path_max_poses ? trajectory.size() - config_.ros.path_max_poses : 0;
  path.poses.reserve(trajectory.size() - first);
  for (std::size_t k = first; k < trajectory.size(); ++k) {
    const ros::Time stamp = utcStamp(trajectory[k].time);
    geometry_msgs::PoseStamped pose;
    pose.header.stamp = stamp;
    pose.header.frame_id = config_.ros.map_frame;
    pose.pose = bodyPose(ecef_to_enu_ * (trajectory[k].state.position_ecef_m - *datum_ecef_m_), stamp).toMsg();
    path.poses.push_back(pose);
  }
  if (!path.poses.empty()) path.header.stamp = path.poses.back().header.stamp;
  smoothed_path_read_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  smoothed_path_read_max_s_ = std::max(smoothed_path_read_max_s_, smoothed_path_read_s_);
  smoothed_path_poses_ = path.poses.size();
  smoothed_path_pub_.publish(path);
}

void PppNode::publishSmoothedOdometry(const ppp::GnssTime& newest) {
  const ppp::SmoothedTrajectoryProvider* smoother = this->smoother();
  if (!smoother || !datum_ecef_m_) return;
  // Delay 0: the lag boundary (fixed lag: the state at t - lag, clamped to the window) or the newest state.
  double delay_s = config_.ros.smoothed_odometry_delay_s;
  if (delay_s == 0.0) delay_s = smoother->fixedLag_s();
  const std::optional<ppp::SmoothedEpoch> e = smoother->smoothedEpochAt(newest - delay_s, true);
  if (!e || !e->covariance || (last_smoothed_index_ && e->index <= *last_smoothed_index_)) return;
  last_smoothed_index_ = e->index;
  const int p = e->state.layout.position();
  const Eigen::Matrix3d cov_ecef = e->covariance->block<3, 3>(p, p);
  const Eigen::Matrix3d cov_enu = ecef_to_enu_ * cov_ecef * ecef_to_enu_.transpose();
  const ros::Time stamp = utcStamp(e->time);
  smoothed_odom_pub_.publish(odometry(stamp, bodyPose(ecef_to_enu_ * (e->state.position_ecef_m - *datum_ecef_m_), stamp), cov_enu));
}

void PppNode::drain() {
  if (live_) {
    drainLive();
  } else {
    const ros::Time now = ros::Time::now();
    while (auto ready = gate_.pop(now.toSec(), corrections_, last_received_)) processEpoch(ready->payload);
  }
  diagnostics_.update();
}

void PppNode::startLiveInput() {
  const RosNodeOptions& o = config_.ros;
  live_ = std::make_unique<ppp::LiveGnssInput>(o.live_input);  // throws on an unreadable navigation file
  auto subscribe = [&](const LiveStreamTopic& t, const std::string& stream) {
    stream_subs_.push_back(std::make_unique<GnssStreamSubscriber>(
        nh_, t.topic, t.format, static_cast<std::uint32_t>(o.live_queue_size),
        [this](ppp::StreamChunk&& chunk) { onStreamChunk(std::move(chunk)); }, stream));
  };
  // The observation topics are one receiver's (ublox_gps: RXM-RAWX and RXM-SFRBX on two
  // topics): one stream, so that one decoder sees them all (the SFRBX GPS week comes from
  // RAWX). Each correction topic is a stream of its own.
  std::string receiver;
  for (const auto& t : o.live_observation_topics) receiver += (receiver.empty() ? "" : "+") + nh_.resolveName(t.topic);
  for (const auto& t : o.live_observation_topics) subscribe(t, receiver);
  for (const auto& t : o.live_correction_topics) subscribe(t, "");
}

void PppNode::onStreamChunk(ppp::StreamChunk&& chunk) {
  const double cpu0_s = ppp::threadCpu_s();
  live_->feed(chunk);
  live_decode_cpu_s_ += ppp::threadCpu_s() - cpu0_s;
  drain();
}

void PppNode::drainLive() {
  const double cpu0_s = ppp::threadCpu_s();
  std::vector<ppp::LiveReadyEpoch> ready = live_->takeReadyEpochs(ros::Time::now().toSec());
  live_decode_cpu_s_ += ppp::threadCpu_s() - cpu0_s;
  for (const std::string& event : live_->takeTimeEvents()) warn("epoch_time", "ppp: " + event);
  if (ready.empty()) return;
  // The epochs are laid out by the header as it is now.
  if (live_->takeHeaderChanged()) {
    layout_ = live_->header();
    layout_changed_ = true;
  }
  for (const ppp::LiveReadyEpoch& e : ready) processLiveEpoch(e);
}

void PppNode::processLiveEpoch(const ppp::LiveReadyEpoch& ready) {
  const ppp::ObsEpoch& epoch = ready.epoch;
  ++obs_received_;
  last_obs_arrival_ = ros::Time::now();
  // LiveGnssInput drops small steps back; what still goes back is a receiver restart
  // (a jump beyond ros.live.restart_jump_s): reset as on a bag loop.
  if (last_output_time_ && epoch.time <= *last_output_time_) {
    ++live_receiver_restarts_;
    resetEstimator("receiver restart: observation time went back by " + secondsText(epoch.time - *last_output_time_) +
                   " (live input)");
  }
  last_received_ = epoch.time;
  const bool broadcast = ready.mode == ppp::LiveProductMode::BroadcastOnly;
  product_mode_ = broadcast ? ppp_bayes_tree::PppStatus::PRODUCTS_BROADCAST_ONLY
                            : ppp_bayes_tree::PppStatus::PRODUCTS_PRECISE;
  product_mode_text_ = std::string(ppp::liveProductModeName(ready.mode));
  if (broadcast && config_.ros.live_input.expect_corrections)
    warn("broadcast_only", "ppp: corrections missing or too old at " + epoch.time.toString() +
                               ": broadcast orbits and clocks only (widened sigmas)");
  if (epoch.satellites.empty()) {
    ++counters_.empty_epochs;
    warn("empty", "ppp: empty epoch " + epoch.time.toString() + " (no satellites): no solution");
    return;
  }
  processObsEpoch(epoch);
  if (ready.arrival_s) {
    live_latency_s_.push_back(ros::Time::now().toSec() - *ready.arrival_s);
    if (live_latency_s_.size() > kLatencyWindow) live_latency_s_.pop_front();
  }
}

void PppNode::startProcessor() {
  const ppp::OceanLoadingLookup ocean = products_.oceanLoading(layout_.marker_name);
  if (!ocean.note.empty() && !ocean.coefficients) warn("blq", "ppp: " + ocean.note);
  // Live input: its broadcast + SSR ephemeris, and its SSR biases unless a Bias-SINEX file is given.
  const ppp::EphemerisSource& ephemeris =
      live_ ? live_->ephemeris() : static_cast<const ppp::EphemerisSource&>(corrections_);
  processor_biases_ = products_.codeBiases().get();
  if (live_ && !processor_biases_) processor_biases_ = live_->biases();
  processor_ = std::make_unique<ppp::PppEpochProcessor>(layout_, config_.ppp, ephemeris, products_.antennas(),
                                                         processor_biases_, ocean.coefficients);
  for (const auto& w : processor_->receiverAntennaWarnings()) warn("antenna:" + w, "ppp: " + w);
  phase_biases_ = {};  // the new processor gets the phase information at its first epoch
  if (layout_.approx_position_ecef_m) estimator_->setApproximatePosition(*layout_.approx_position_ecef_m);
  layout_changed_ = false;
}

bool PppNode::acceptLivePhaseBiases() {
  // SSR phase biases of the live feed: the assembly's gate decides (once they arrive).
  if (!live_ || !live_->hasPhaseBiases()) return false;
  if (!products_.acceptStreamedPhaseBiases(live_->biases(), ppp::PhaseInformation::SsrPhaseBiases)) return false;
  ROS_INFO_STREAM("ppp: " << products_.arGate().text());
  return true;
}

void PppNode::processEpoch(const Pending& p) {
  ppp::ObsEpoch epoch;
  ConversionIssues issues;
  try {
    layout_changed_ |= fromMessage(*p.msg, layout_, epoch, issues);
  } catch (const std::exception& e) {
    ++counters_.observations_invalid;
    warn("obs_convert", std::string("ppp: observation epoch dropped: ") + e.what());
    return;
  }
  for (const auto& [reason, n] : issues.counts) {
    counters_.observations_invalid += n;
    issues_.counts[reason] += n;
    warn("obs:" + reason.substr(0, 24), "ppp: observations: " + reason + " (excluded, counted)");
  }
  processObsEpoch(epoch);
}

void PppNode::processObsEpoch(const ppp::ObsEpoch& epoch) {
  // Live SSR biases arrive after the start: the processor is remade with them (once: then stable).
  const bool live_biases_arrived = live_ && !products_.codeBiases() && processor_ && live_->biases() != processor_biases_;
  if (!processor_ || live_biases_arrived) startProcessor();
  else if (layout_changed_) {
    processor_->setObservationTypes(layout_);
    layout_changed_ = false;
  }
  updatePhaseBiases();  // the live SSR phase biases and the batches' biases through the assembly's gate
  const auto start = std::chrono::steady_clock::now();
  const double cpu0_s = ppp::threadCpu_s();
  const ppp::PppEpochRecord rec = processor_->process(epoch, *estimator_);
  estimator_cpu_s_ += ppp::threadCpu_s() - cpu0_s;
  const double update_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (rec.refused) {  // cannot happen after the time checks above, kept as a guard
    warn("refused", "ppp: epoch refused: " + rec.reason);
    return;
  }
  ++counters_.epochs_processed;
  // Outputs never go back in time, one stamp one fix (the time guard and the FIFO gate
  // ensure it; kept as a guard).
  const bool publishable = !last_output_time_ || epoch.time > *last_output_time_;
  if (!publishable) {
    ++counters_.epochs_out_of_order;
    warn("output_order", "ppp: solution at " + epoch.time.toString() + " not after the last published one: not published");
  }

  ppp_bayes_tree::PppStatus s = counters_;
  s.header.stamp = utcStamp(epoch.time);
  s.header.frame_id = config_.ros.map_frame;
  s.reason = rec.reason;
  s.warnings = processor_->receiverAntennaWarnings();
  s.converged_horizontal_sigma_m = config_.ros.converged_horizontal_sigma_m;
  s.converged_vertical_sigma_m = config_.ros.converged_vertical_sigma_m;
  s.satellites_observed = static_cast<std::uint16_t>(rec.satellites_observed);
  s.satellites_used = static_cast<std::uint16_t>(rec.used.size());
  s.satellites_rejected = static_cast<std::uint16_t>(rec.rejected.size());
  for (const auto& u : rec.used) s.used.push_back(u.toString());
  std::uint16_t late = 0;
  for (const auto& r : rec.rejected) {
    s.rejected.push_back(r.satellite.toString() + " " + r.text());
    if (isProductRejection(r)) ++late;
  }
  s.satellites_without_corrections = late;
  counters_.corrections_late += late;
  s.corrections_late = counters_.corrections_late;
  if (late > 0) warn("late", "ppp: " + std::to_string(late) + " satellite(s) without corrections at " +
                                 epoch.time.toString() + " excluded (e.g. " + s.rejected.back() + ")");
  s.update_time_s = update_s;
  s.correction_latency_s = corrections_.newest() ? epoch.time - *corrections_.newest() : kNaN;
  s.corrections_stale_s = correctionsStale_s().value_or(kNaN);
  s.active_biases = static_cast<std::uint16_t>(rec.active_biases);
  s.product_mode = product_mode_;
  s.product_mode_text = product_mode_text_;
  // The EKF updates its whole state; the smoother re-eliminates the variables it reports.
  s.variables_reeliminated = static_cast<std::uint32_t>(
      rec.smoother ? rec.smoother->variables_reeliminated
                   : static_cast<std::size_t>(estimator_->core().layout().dim() + rec.active_biases));
  const std::vector<ppp::ArcId> active_arcs = estimator_->core().activeArcs();
  {
    std::map<ppp::ArcId, std::string> sat_of_arc;
    for (const auto& r : rec.residuals) sat_of_arc[r.arc] = r.satellite.toString() + " ";
    for (const ppp::ArcId a : active_arcs) s.active_bias_arcs.push_back(sat_of_arc[a] + "arc " + std::to_string(a));
  }
  const bool solved = rec.status == ppp::EpochStatus::Ok && rec.solution.position_ecef_m;
  Eigen::Vector3d sigma_enu = Eigen::Vector3d::Constant(kNaN);
  s.zwd_m = s.zwd_sigma_m = s.receiver_clock_m = s.receiver_clock_sigma_m = kNaN;
  if (solved) {
    if (!datum_ecef_m_) setDatum(*rec.solution.position_ecef_m);
    const Eigen::Matrix3d cov_enu = ecef_to_enu_ * *rec.solution.covariance_ecef_m2 * ecef_to_enu_.transpose();
    sigma_enu = cov_enu.diagonal().cwiseMax(0.0).cwiseSqrt();
    s.zwd_m = rec.solution.zwd_m.value_or(kNaN);
    const ppp::ReceiverStateLayout& layout = rec.state_layout;
    s.zwd_sigma_m = std::sqrt(std::max(0.0, rec.receiver_covariance(layout.zwd(), layout.zwd())));
    s.receiver_clock_m = rec.solution.receiver_clock_m.value_or(kNaN);  // the reference system's clock
    const int clock = layout.firstClock();
    s.receiver_clock_sigma_m = std::sqrt(std::max(0.0, rec.receiver_covariance(clock, clock)));
  }
  s.sigma_east_m = sigma_enu.x();
  s.sigma_north_m = sigma_enu.y();
  s.sigma_up_m = sigma_enu.z();
  s.solution_state = solutionState(solved, sigma_enu, config_.ros);
  s.solution_state_text = solutionStateText(s.solution_state);
  setFixState(rec, solved, s);
  if (rec.status == ppp::EpochStatus::Failed) warn("failed", "ppp: estimator failed at " + epoch.time.toString() + ": " + rec.reason);
  last_status_ = s;
  last_smoother_ = rec.smoother;
  have_status_ = true;
  if (publishable) {
    last_output_time_ = epoch.time;
    if (solved) {
      attachAttitude(s.header.stamp);
      publishSolution(rec, s);
      publishSmoothedOdometry(epoch.time);
      smoothed_path_stale_ = true;
    }
    status_pub_.publish(s);
  }
  if (rec.estimator_reset) {
    // The core restarted the estimator from its last good state (as offline in
    // ppp_solve); the node only counts and reports it.
    ++estimator_restarts_;
    warn("restart", "ppp: estimator restarted from its last good state at " + epoch.time.toString() + ": " +
                        rec.reason);
  }
}

void PppNode::publishSolution(const ppp::PppEpochRecord& rec, const ppp_bayes_tree::PppStatus& status) {
  const RosNodeOptions& o = config_.ros;
  const Eigen::Vector3d& p = *rec.solution.position_ecef_m;
  const Eigen::Matrix3d cov_enu = ecef_to_enu_ * *rec.solution.covariance_ecef_m2 * ecef_to_enu_.transpose();
  // The estimate is the antenna (marker) position; base_link = antenna - R * lever arm
  // with an attitude for this epoch, else base_link is the antenna position (documented).
  const Eigen::Vector3d enu = ecef_to_enu_ * (p - *datum_ecef_m_);
  const ros::Time stamp = status.header.stamp;
  const BodyPose body = bodyPose(enu, stamp);
  const nav_msgs::Odometry odom = odometry(stamp, body, cov_enu);
  odom_pub_.publish(odom);

  sensor_msgs::NavSatFix fix;
  fix.header.stamp = stamp;
  fix.header.frame_id = o.antenna_frame;  // REP-145: the fix is the antenna's position
  const ppp::Geodetic g = ppp::ecefToGeodetic(p);
  fix.latitude = g.latitude_rad * ppp::kRadToDeg;
  fix.longitude = g.longitude_rad * ppp::kRadToDeg;
  fix.altitude = g.height_m;
  const Eigen::Matrix3d r_local = ppp::rotationEnuFromEcef(g.latitude_rad, g.longitude_rad);
  const Eigen::Matrix3d cov_local = r_local * *rec.solution.covariance_ecef_m2 * r_local.transpose();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) fix.position_covariance[r * 3 + c] = cov_local(r, c);  // ENU, m^2 (REP-145)
  fix.position_covariance_type = sensor_msgs::NavSatFix::COVARIANCE_TYPE_KNOWN;
  // Carrier-phase fixed: STATUS_GBAS_FIX, as ublox_gps reports an RTK fix (doc/ros_interface.md).
  fix.status.status = status.fix_state == ppp_bayes_tree::PppStatus::FIX_FIXED ? sensor_msgs::NavSatStatus::STATUS_GBAS_FIX
                                                                               : sensor_msgs::NavSatStatus::STATUS_FIX;
  fix.status.service = sensor_msgs::NavSatStatus::SERVICE_GPS;
  fix_pub_.publish(fix);

  geometry_msgs::PoseStamped pose;
  pose.header = odom.header;
  pose.pose = odom.pose.pose;
  path_.poses.push_back(pose);
  if (path_.poses.size() > o.path_max_poses) path_.poses.erase(path_.poses.begin());

  if (o.publish_tf) {
    // map -> base_link, or map -> odom when another node publishes odom -> base_link.
    std::string err;
    if (tf_buffer_.canTransform(o.odom_frame, o.base_frame, ros::Time(0), &err)) {
      const auto ob = tf_buffer_.lookupTransform(o.odom_frame, o.base_frame, ros::Time(0));
      const Eigen::Quaterniond q_ob(ob.transform.rotation.w, ob.transform.rotation.x, ob.transform.rotation.y,
                                    ob.transform.rotation.z);
      const Eigen::Vector3d t_ob(ob.transform.translation.x, ob.transform.translation.y, ob.transform.translation.z);
      // T_map_odom = T_map_base * T_odom_base^-1
      const Eigen::Quaterniond q_mo = body.q_map_base * q_ob.inverse();
      const Eigen::Vector3d t_mo = body.position_m - q_mo * t_ob;
      tf_.sendTransform(transform(o.map_frame, o.odom_frame, stamp, t_mo, q_mo));
    } else {
      tf_.sendTransform(transform(o.map_frame, o.base_frame, stamp, body.position_m, body.q_map_base));
    }
  }
}

void PppNode::diagnoseInputs(diagnostic_updater::DiagnosticStatusWrapper& s) {
  const ros::WallTime now = ros::WallTime::now();
  const double dt = std::max(1e-3, (now - last_diag_time_).toSec());
  const double obs_rate = (obs_received_ - obs_at_last_diag_) / dt, corr_rate = (corr_received_ - corr_at_last_diag_) / dt;
  obs_at_last_diag_ = obs_received_;
  corr_at_last_diag_ = corr_received_;
  last_diag_time_ = now;
  s.add("observation messages", obs_received_);
  s.add("observation rate [Hz, wall]", obs_rate);
  s.add("correction messages", corr_received_);
  s.add("correction rate [Hz, wall]", corr_rate);
  s.add("pending epochs", gate_.size());
  s.add("duplicate epochs dropped", counters_.epochs_duplicate);
  s.add("out-of-order epochs dropped", counters_.epochs_out_of_order);
  s.add("isolated bad stamps dropped (time jump not confirmed)", counters_.epochs_time_jump_dropped);
  s.add("epochs held as a candidate time jump", obs_guard_.held());
  s.add("estimator resets (sustained jump back in time)", counters_.estimator_resets);
  s.add("epochs discarded at resets", counters_.epochs_discarded_at_reset);
  s.add("observation messages lost before the node (header.seq gaps)", counters_.observations_lost);
  s.add("correction messages lost before the node (header.seq gaps)", counters_.corrections_lost);
  s.add("correction batches dropped (isolated bad stamps)", counters_.corrections_time_jump_dropped);
  s.add("last stamp dropped", last_time_drop_.empty() ? std::string("none") : last_time_drop_);
  s.add("empty epochs", counters_.empty_epochs);
  s.add("invalid observations excluded", counters_.observations_invalid);
  if (!config_.ros.attitude_topic.empty()) {
    s.add("attitude messages", attitude_received_);
    s.add("attitude messages invalid (ignored)", attitude_invalid_);
    s.add("solved epochs without a current attitude (at the antenna)", epochs_without_attitude_);
  }
  for (const auto& [reason, n] : issues_.counts) s.add(reason, n);
  const std::size_t lost = std::size_t{counters_.observations_lost} + counters_.corrections_lost;
  if (obs_received_ == 0) s.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no observations received yet");
  else if (lost > lost_at_last_diag_)
    s.summary(diagnostic_msgs::DiagnosticStatus::WARN, std::to_string(lost - lost_at_last_diag_) +
                                                           " message(s) lost before the node since the last report");
  else if (config_.ros.expected_observation_rate_hz > 0 && obs_rate < 0.5 * config_.ros.expected_observation_rate_hz)
    s.summary(diagnostic_msgs::DiagnosticStatus::WARN, "observation rate below half the expected rate");
  else s.summary(diagnostic_msgs::DiagnosticStatus::OK, "receiving");
  lost_at_last_diag_ = lost;
}

void PppNode::diagnoseCorrections(diagnostic_updater::DiagnosticStatusWrapper& s) {
  s.add("batches held", corrections_.size());
  s.add("newest batch", corrections_.newest() ? corrections_.newest()->toString() : std::string("none"));
  s.add("age of the last batch at arrival [s]", last_correction_age_s_);
  s.add("satellite-epochs without corrections", counters_.corrections_late);
  s.add("corrections for unknown satellites", counters_.corrections_unknown_satellites);
  s.add("correction messages lost before the node (header.seq gaps)", counters_.corrections_lost);
  s.add("correction batches dropped (isolated bad stamps)", counters_.corrections_time_jump_dropped);
  const std::optional<double> stale = correctionsStale_s();
  s.add("observations ahead of the corrections [s]", stale.value_or(kNaN));
  s.add("stale thresholds WARN / ERROR [s]", std::to_string(config_.ros.corrections_stale_warn_s) + " / " +
                                                 std::to_string(config_.ros.corrections_stale_error_s));
  if (corrections_.size() == 0) s.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no corrections received yet");
  else if (stale && *stale > config_.ros.corrections_stale_error_s)
    s.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
              "corrections stopped: observations " + std::to_string(static_cast<long>(*stale)) +
                  " s ahead of the newest batch " + corrections_.newest()->toString());
  else if (stale && *stale > config_.ros.corrections_stale_warn_s)
    s.summary(diagnostic_msgs::DiagnosticStatus::WARN,
              "corrections stale: observations " + std::to_string(static_cast<long>(*stale)) +
                  " s ahead of the newest batch");
  else if (std::isfinite(last_correction_age_s_) && last_correction_age_s_ > config_.ros.max_correction_latency_s)
    s.summary(diagnostic_msgs::DiagnosticStatus::WARN, "corrections arrive late");
  else s.summary(diagnostic_msgs::DiagnosticStatus::OK, "corrections current");
}

void PppNode::diagnoseSolution(diagnostic_updater::DiagnosticStatusWrapper& s) {
  s.add("estimator", config_.ros.estimator);
  s.add("epochs processed", counters_.epochs_processed);
  if (!have_status_) {
    s.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no epoch processed yet");
    return;
  }
  s.add("solution state", last_status_.solution_state_text);
  for (const auto& w : last_status_.warnings) s.add("warning", w);
  s.add("satellites used", last_status_.satellites_used);
  s.add("update time [s]", last_status_.update_time_s);
  s.add("sigma east/north/up [m]", std::to_string(last_status_.sigma_east_m) + " " +
                                       std::to_string(last_status_.sigma_north_m) + " " +
                                       std::to_string(last_status_.sigma_up_m));
  s.add("estimator restarts after a failed update", estimator_restarts_);
  if (const ppp::SmoothedTrajectoryProvider* sm = smoother()) {
    const ppp::SmootherEpochDiagnostics r = last_smoother_.value_or(ppp::SmootherEpochDiagnostics{});
    s.add("smoother: fixed lag [s] (0: full)", sm->fixedLag_s());
    s.add("smoother: variables re-eliminated", r.variables_reeliminated);
    s.add("smoother: variables relinearized", r.variables_relinearized);
    s.add("smoother: cliques touched", r.cliques_touched);
    s.add("smoother: variables marginalized", r.variables_marginalized);
    s.add("smoother: iSAM2 update time [s]", r.update_time_s);
    s.add("smoothed path: poses", smoothed_path_poses_);
    if (lagged_output_) {
      s.add("smoothed trajectory: states past the lag", lagged_output_->statesHandedOut());
      if (const ppp::SmoothedTrajectoryWriter* w = lagged_output_->writer())
        s.add("smoothed trajectory: " + w->path() + " rows written / refused",
              std::to_string(w->rowsWritten()) + " / " + std::to_string(w->rowsRefused()));
    }
    s.add("smoothed path: last / max re-read time [s]",
          std::to_string(smoothed_path_read_s_) + " / " + std::to_string(smoothed_path_read_max_s_));
  }
  if (last_status_.solution_state == ppp_bayes_tree::PppStatus::NO_SOLUTION)
    s.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no solution: " + last_status_.reason);
  else if (!last_status_.warnings.empty())
    s.summary(diagnostic_msgs::DiagnosticStatus::WARN, last_status_.solution_state_text + "; " + last_status_.warnings[0]);
  else s.summary(diagnostic_msgs::DiagnosticStatus::OK, last_status_.solution_state_text);
}

void PppNode::diagnoseLive(diagnostic_updater::DiagnosticStatusWrapper& s) {
  using diagnostic_msgs::DiagnosticStatus;
  const double now_s = ros::Time::now().toSec();
  std::uint8_t level = DiagnosticStatus::OK;
  std::string summary;
  auto raise = [&](std::uint8_t l, const std::string& text) {
    if (l > level || summary.empty()) {  // the first of the worst level
      summary = text;
      level = std::max(level, l);
    }
  };
  const bool broadcast = live_->mode() == ppp::LiveProductMode::BroadcastOnly;
  s.add("product mode", std::string(ppp::liveProductModeName(live_->mode())));
  s.add("epochs released precise SSR", live_->releasedEpochs(ppp::LiveProductMode::PreciseSsr));
  s.add("epochs released broadcast only", live_->releasedEpochs(ppp::LiveProductMode::BroadcastOnly));
  s.add("satellites without an ephemeris at their epoch (waiting)", live_->satellitesWithoutEphemeris());
  s.add("navigation records held", live_->navigationRecords());
  s.add("estimator resets at receiver restarts", live_receiver_restarts_);
  // Cost figures (thread CPU time, so meaningful on a loaded machine) and latency.
  std::uint64_t decoded_epochs = 0;
  for (const ppp::LiveStreamStatus& st : live_->streams()) decoded_epochs += st.observation_epochs;
  double conversion_cpu_s = 0.0;
  for (const auto& sub : stream_subs_) conversion_cpu_s += sub->counters().conversion_cpu_s;
  const auto per_epoch_ms = [](double cpu_s, std::uint64_t n) { return n > 0 ? 1e3 * cpu_s / static_cast<double>(n) : kNaN; };
  s.add("input CPU: message conversion [s]", conversion_cpu_s);
  s.add("input CPU: decoding and release (LiveGnssInput) [s]", live_decode_cpu_s_);
  s.add("input CPU per decoded epoch [ms]", per_epoch_ms(conversion_cpu_s + live_decode_cpu_s_, decoded_epochs));
  s.add("estimator CPU [s]", estimator_cpu_s_);
  s.add("estimator CPU per processed epoch [ms]", per_epoch_ms(estimator_cpu_s_, counters_.epochs_processed));
  std::vector<double> latency(live_latency_s_.begin(), live_latency_s_.end());
  std::sort(latency.begin(), latency.end());
  s.add("latency epochs (callback of the epoch's last chunk -> solution published, the last " +
            std::to_string(kLatencyWindow) + " at most)",
        latency.size());
  s.add("latency median [s]", ppp::quantileOfSorted(latency, 0.5));
  s.add("latency p99 [s]", ppp::quantileOfSorted(latency, 0.99));
  s.add("latency max [s]", ppp::quantileOfSorted(latency, 1.0));
  for (const auto& sub : stream_subs_) {
    const GnssStreamSubscriber::Counters& c = sub->counters();
    const std::string p = sub->topic() + ": ";
    s.add(p + "messages (type)", std::to_string(c.messages) + " (" + (c.type.empty() ? "none yet" : c.type) + ")");
    s.add(p + "messages lost before the node (header.seq gaps)", c.lost);
    s.add(p + "messages held until the ROS clock was valid (sim time before /clock)", c.held_for_clock);
    if (c.lost > 0) raise(DiagnosticStatus::WARN, sub->topic() + ": " + std::to_string(c.lost) +
                                                      " message(s) lost before the node (a queue overflowed)");
    s.add(p + "messages of a wrong type/MD5 / malformed (dropped)",
          std::to_string(c.wrong_type) + " / " + std::to_string(c.malformed));
    if (!c.last_error.empty()) s.add(p + "last error", c.last_error);
    s.add(p + "reconnects", "not known on a topic (see the transport node's diagnostics)");
    if (c.wrong_type + c.malformed > 0) raise(DiagnosticStatus::WARN, sub->topic() + ": messages dropped (" + c.last_error + ")");
  }
  bool have_observations = false;
  for (const ppp::LiveStreamStatus& st : live_->streams()) {
    const std::string p = st.stream + ": ";
    std::uint64_t frames = 0;
    for (const auto& [type, n] : st.frames_by_type) frames += n;
    s.add(p + "format", std::string(ppp::streamFormatName(st.format)));
    s.add(p + "bytes / frames", std::to_string(st.bytes) + " / " + std::to_string(frames));
    s.add(p + "CRC/checksum errors", st.problems.count(ppp::StreamProblemKind::ChecksumError));
    s.add(p + "problems (all kinds)", st.problems.totalProblems());
    s.add(p + "observation epochs decoded / ignored", std::to_string(st.observation_epochs) + " / " +
                                                          std::to_string(st.ignored_epochs));
    s.add(p + "epochs back in time dropped / receiver restarts",
          std::to_string(st.time_backwards) + " / " + std::to_string(st.restarts));
    s.add(p + "epoch time outliers dropped / forward jumps",
          std::to_string(st.time_outliers) + " / " + std::to_string(st.forward_jumps));
    if (!st.reference_date_warning.empty()) raise(DiagnosticStatus::WARN, p + st.reference_date_warning);
    s.add(p + "ephemerides decoded", st.ephemerides);
    s.add(p + "SSR messages", st.ssr_messages);
    s.add(p + "SSR age [s]", st.ssr_age_s.value_or(kNaN));
    s.add(p + "latency [s]", st.latency_s.value_or(kNaN));
    s.add(p + "since the last chunk [s]", st.last_arrival_s ? now_s - *st.last_arrival_s : kNaN);
    s.add(p + "stall", std::string(ppp::streamStallName(st.stall)));
    if (st.observation_epochs > 0) have_observations = true;
    if (st.stall == ppp::StreamStall::Error)
      raise(DiagnosticStatus::ERROR, "observation stream " + st.stream + " stalled (ERROR threshold " +
                                         std::to_string(config_.ros.live_input.stall_error_s) + " s)");
    else if (st.stall == ppp::StreamStall::Warn)
      raise(DiagnosticStatus::WARN, "observation stream " + st.stream + " stalled (WARN threshold " +
                                        std::to_string(config_.ros.live_input.stall_warn_s) + " s)");
  }
  if (!have_observations) raise(DiagnosticStatus::WARN, "no observation epoch decoded yet");
  // Broadcast only is the configured operation without a correction stream (OK), a fallback otherwise (WARN).
  if (broadcast && config_.ros.live_input.expect_corrections)
    raise(DiagnosticStatus::WARN, "broadcast only: corrections stopped or too old (widened sigmas)");
  if (summary.empty())
    summary = broadcast ? "receiving, broadcast only (no correction stream configured)" : "receiving, precise SSR";
  s.summary(level, summary);
}

PppNode::PhaseBiasChoice PppNode::choosePhaseBiases() {
  // Streamed phase information goes to the product assembly's PPP-AR gate, which
  // decides (as for ppp_solve): the live feed's SSR phase biases (RTCM 1265-1270,
  // IGS-SSR), or the biases the correction batches carry.
  if (live_) acceptLivePhaseBiases();
  else if (!stream_biases_.empty() && stream_bias_kind_ != ppp::PhaseInformation::None &&
           products_.acceptStreamedPhaseBiases(&stream_biases_, stream_bias_kind_))
    ROS_INFO_STREAM("ppp: " << products_.arGate().text());
  if (const ppp::BiasProvider* p = products_.phaseBiases()) return {p, p->describeSource()};
  if (products_.arGate().mode == ppp::AmbiguityResolutionMode::Off) return {nullptr, "ambiguity resolution off"};
  return {nullptr, products_.arGate().text()};
}

void PppNode::declareStreamedProducts(const ppp_bayes_tree::PreciseCorrections& msg, const ppp::CorrectionBatch& batch) {
  // Once, at the first batch: the clock centre and the antenna model
  // of the stream's orbits and clocks decide the satellite antennas and the PPP-AR gate.
  if (streamed_declared_ || live_) return;
  streamed_declared_ = true;
  const ppp::StreamedProductInfo info = streamedProductInfo(msg, batch);
  if (!products_.declareStreamedProducts(info)) return;
  ROS_INFO_STREAM("ppp: the correction stream declares "
                  << (info.clock_centre.empty() ? "no clock centre" : "clocks of " + info.clock_centre) << " and "
                  << (info.antenna_model.empty() ? "no antenna model" : "antenna model " + info.antenna_model) << ": "
                  << products_.arGate().text());
  if (processor_) startProcessor();  // the antennas may have changed
}

void PppNode::updatePhaseBiases() {
  PhaseBiasChoice choice = choosePhaseBiases();
  const bool changed = choice.provider != phase_biases_.provider || choice.source != phase_biases_.source;
  phase_biases_ = std::move(choice);
  if (!changed && phase_bias_logged_) return;
  processor_->setPhaseBiases(phase_biases_.provider);
  if (!arEnabled()) return;
  if (phase_biases_.provider)
    ROS_INFO_STREAM("ppp: ambiguity resolution with " << phase_biases_.source);
  else if (!phase_bias_logged_)  // once: the status and diagnostics carry it per epoch
    ROS_WARN_STREAM("ppp: " << phase_biases_.source);
  phase_bias_logged_ = true;
}

void PppNode::setFixState(const ppp::PppEpochRecord& rec, bool solved, ppp_bayes_tree::PppStatus& s) {
  using ppp_bayes_tree::PppStatus;
  s.ambiguity_resolution_enabled = arEnabled();
  s.phase_bias_source = phase_biases_.provider ? phase_biases_.source : "";
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
  else if (!phase_biases_.provider) s.float_reason = phase_biases_.source;
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
  s.time_to_first_fix_s = first_fixed_ && first_solved_ ? *first_fixed_ - *first_solved_ : kNaN;
}

void PppNode::diagnoseAmbiguities(diagnostic_updater::DiagnosticStatusWrapper& s) {
  using diagnostic_msgs::DiagnosticStatus;
  const bool enabled = arEnabled();
  s.add("enabled", enabled);
  s.add("phase information", phase_biases_.provider ? phase_biases_.source : std::string("none"));
  s.add("epochs fixed", epochs_fixed_);
  s.add("held integers released (float departed, wide lane changed)", ambiguity_releases_);
  s.add("time to first fix [s]", first_fixed_ && first_solved_ ? *first_fixed_ - *first_solved_ : kNaN);
  s.add("first fix", first_fixed_ ? first_fixed_->toString() : std::string("none yet"));
  if (have_status_) {
    s.add("fix state", last_status_.fix_state_text);
    s.add("float reason", last_status_.float_reason);
    s.add("ambiguities held", last_status_.ambiguities_fixed);
    s.add("wide lanes fixed", last_status_.wide_lanes_fixed);
    s.add("ratio", last_status_.ratio);
  }
  if (!enabled) s.summary(DiagnosticStatus::OK, "off (float)");
  else if (!have_status_) s.summary(DiagnosticStatus::OK, "on, no epoch processed yet");
  else if (!phase_biases_.provider) s.summary(DiagnosticStatus::WARN, phase_biases_.source);
  else if (have_status_ && last_status_.fix_state == ppp_bayes_tree::PppStatus::FIX_FIXED)
    s.summary(DiagnosticStatus::OK, "fixed (" + std::to_string(last_status_.ambiguities_fixed) + " held)");
  else s.summary(DiagnosticStatus::OK, have_status_ ? "float: " + last_status_.float_reason : "no epoch yet");
}

}  // namespace ppp_ros
