#include "ppp_bayes_tree/ppp/estimators/ins_in_motion_alignment.h"

#include <algorithm>
#include <cmath>

#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

/// The Earth's rate about the down axis, in the body axes of `rotation_ecef_body` [rad/s]:
/// the part of its rate a levelled body at rest sees whatever its heading.
Eigen::Vector3d earthRateAboutDown(const Eigen::Matrix3d& rotation_ecef_body, const Eigen::Vector3d& position_ecef_m) {
  const Eigen::Vector3d down_ecef = rotationEcefNed(position_ecef_m).col(2);
  const Eigen::Vector3d earth_rate_ecef(0.0, 0.0, kEarthRotationRate_radps);
  return rotation_ecef_body.transpose() * (down_ecef * down_ecef.dot(earth_rate_ecef));
}

/// The uncertainty of the levelled mean rate as a gyro bias [rad/s]: the Earth's horizontal
/// rate (its direction needs the heading; Groves 2nd ed. 14.2.4) and the standard error of
/// the interval's mean (the readings' largest per-axis scatter over sqrt(n): the unit's own
/// noise, not its datasheet's), root-sum-squared.
double levelledRateSigma_radps(const Eigen::Vector3d& position_ecef_m, const LevelingResult& level) {
  const Eigen::Vector3d down_ecef = rotationEcefNed(position_ecef_m).col(2);
  const double horizontal_radps = kEarthRotationRate_radps * std::hypot(down_ecef.x(), down_ecef.y());  // cos(lat)
  const double n = static_cast<double>(level.samples);
  return std::sqrt(horizontal_radps * horizontal_radps + level.gyro_variance_radps2 / n);
}

/// The gyros' bias from the levelled mean rate (Earth's rate about down removed), with its
/// sigma, when it is no slow turn and the grade's prior does not explain it; nullopt otherwise.
std::optional<std::pair<Eigen::Vector3d, double>> gyroBiasFromLevelling(const Eigen::Vector3d& mean_rate_radps,
                                                                        double levelled_sigma_radps,
                                                                        const ImuNoise& noise) {
  if (mean_rate_radps.norm() > kMaxGyroBiasAtLevelling_radps) return std::nullopt;
  const double prior_sigma = noise.gyro_bias_instability_radps;
  const double variance = prior_sigma * prior_sigma + levelled_sigma_radps * levelled_sigma_radps;
  if (mean_rate_radps.squaredNorm() <= kGyroBiasTestChiSquare * variance) return std::nullopt;
  return std::make_pair(mean_rate_radps, std::sqrt(variance));
}

}  // namespace

void keepLevellingHistory(std::vector<ImuSample>& history, const std::vector<ImuSample>& readings,
                          const GnssTime& time) {
  history.insert(history.end(), readings.begin(), readings.end());
  const auto old = std::find_if(history.begin(), history.end(),
                                [&](const ImuSample& s) { return time - s.time <= kLevellingHistory_s; });
  history.erase(history.begin(), old);
}

InMotionLevel levelInMotion(const std::vector<ImuSample>& history, const Eigen::Vector3d& position_ecef_m,
                            const GnssTime& start, const ImuNoise& noise) {
  InMotionLevel out;
  std::size_t interval_end = 0;
  const LevelingResult level =
      levelAtLatestStaticInterval(history, position_ecef_m, StaticIntervalThresholds{}, &interval_end);
  if (level.status != LevelingStatus::Level) {
    out.problem = "no initial attitude: no heading given, and no static interval to level in the " +
                  std::to_string(history.size()) +
                  " readings before the start (last refusal: " + levelingStatusText(level.status) + ")";
    return out;
  }
  // The accelerometers' error along gravity is what the mean force's magnitude lacks
  // of the local gravity's (Groves 2nd ed. 14.2.1; a sensor reading 1 % high would
  // otherwise push the vertical velocity by 0.1 m/s every second).
  const Eigen::Vector3d f = level.mean_specific_force_mps2;
  const double gravity_mps2 = ecefNavigationFrame(position_ecef_m).gravity_world_mps2.norm();
  out.accel_bias_mps2 = f - gravity_mps2 * f.normalized();
  const Eigen::Matrix3d levelled =
      rotationEcefNed(position_ecef_m) * rotationNedBody(level.roll_rad, level.pitch_rad, 0.0);
  const Eigen::Vector3d mean_rate_radps = level.mean_angular_rate_radps - earthRateAboutDown(levelled, position_ecef_m);
  const auto bias = gyroBiasFromLevelling(mean_rate_radps, levelledRateSigma_radps(position_ecef_m, level), noise);
  if (bias) {
    out.gyro_bias_radps = bias->first;
    out.gyro_bias_sigma_radps = bias->second;
  }
  out.rotation_ecef_body = propagateAttitude(levelled, history, interval_end, start, out.gyro_bias_radps);
  return out;
}

std::optional<CourseHeading> CourseHeadingTrack::add(const GnssTime& time, const Eigen::Vector3d& antenna_ecef_m) {
  track_.emplace_back(time, antenna_ecef_m);
  while (track_.size() > 2 && time - track_[1].first >= options_.course_interval_s) track_.pop_front();
  const double dt_s = time - track_.front().first;
  if (dt_s < options_.course_interval_s) return std::nullopt;
  CourseHeading c;
  c.velocity_ecef_mps = (antenna_ecef_m - track_.front().second) / dt_s;
  c.heading = headingFromGnssVelocity(c.velocity_ecef_mps, antenna_ecef_m, options_.velocity_sigma_mps,
                                      options_.min_horizontal_speed_mps);
  if (c.heading.status != HeadingStatus::Heading) return std::nullopt;
  track_.clear();
  return c;
}

Eigen::Matrix3d attitudeCovarianceWithHeading(const Eigen::Matrix3d& rotation_ned_body,
                                              const Eigen::Matrix3d& attitude_covariance_body,
                                              double heading_sigma_rad) {
  // The attitude error is in the body axes: in NED it is R_ned_body times it.
  const Eigen::Matrix3d& ned_body = rotation_ned_body;
  Eigen::Matrix3d C = ned_body * attitude_covariance_body * ned_body.transpose();
  C.row(2).setZero();
  C.col(2).setZero();
  C(2, 2) = heading_sigma_rad * heading_sigma_rad;
  return ned_body.transpose() * C * ned_body;
}

NavState alignedToCourse(const NavState& nav, double heading_rad, const Eigen::Vector3d& antenna_ecef_m,
                         const Eigen::Vector3d& lever_arm_body_m) {
  // The body x axis along the course; the antenna stays where it is.
  NavState out = nav;
  out.rotation_world_body = withYaw(nav.rotation_world_body, nav.position_world_m, heading_rad);
  out.position_world_m = antenna_ecef_m - out.rotation_world_body * lever_arm_body_m;
  return out;
}

}  // namespace ppp
