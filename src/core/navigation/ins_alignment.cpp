#include "ppp_bayes_tree/navigation/ins_alignment.h"

#include <algorithm>
#include <cmath>

#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp {

Eigen::Matrix3d rotationNedEnu() {
  Eigen::Matrix3d m;
  m << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  return m;
}

namespace {

struct IntervalStatistics {
  std::size_t samples = 0;
  bool finite = true;
  Eigen::Vector3d mean_force = Eigen::Vector3d::Zero();
  Eigen::Vector3d force_spread = Eigen::Vector3d::Zero();  ///< per-axis standard deviation
  Eigen::Vector3d mean_rate = Eigen::Vector3d::Zero();
  Eigen::Vector3d rate_variance = Eigen::Vector3d::Zero();  ///< per-axis variance of the rates
  double gyro_rms = 0.0;
};

IntervalStatistics intervalStatistics(const std::vector<ImuSample>& samples) {
  IntervalStatistics s;
  s.samples = samples.size();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum_sq = Eigen::Vector3d::Zero(), sum_rate = Eigen::Vector3d::Zero();
  Eigen::Vector3d sum_rate_sq = Eigen::Vector3d::Zero();
  double rate_sq = 0.0;
  for (const ImuSample& r : samples) {
    if (!r.specific_force_mps2.allFinite() || !r.angular_rate_radps.allFinite()) {
      s.finite = false;
      return s;
    }
    sum += r.specific_force_mps2;
    sum_sq += r.specific_force_mps2.cwiseAbs2();
    sum_rate += r.angular_rate_radps;
    sum_rate_sq += r.angular_rate_radps.cwiseAbs2();
    rate_sq += r.angular_rate_radps.squaredNorm();
  }
  if (s.samples == 0) return s;
  const double n = static_cast<double>(s.samples);
  s.mean_force = sum / n;
  s.force_spread = (sum_sq / n - s.mean_force.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt();
  s.mean_rate = sum_rate / n;
  s.rate_variance = (sum_rate_sq / n - s.mean_rate.cwiseAbs2()).cwiseMax(0.0);
  s.gyro_rms = std::sqrt(rate_sq / n);
  return s;
}

LevelingStatus intervalStatus(const IntervalStatistics& s, double gravity_mps2, const StaticIntervalThresholds& t) {
  if (!s.finite) return LevelingStatus::NonFiniteReading;
  if (s.samples < t.min_samples) return LevelingStatus::TooFewSamples;
  if (s.force_spread.maxCoeff() > t.max_accel_spread_mps2) return LevelingStatus::AccelerometerSpread;
  if (s.gyro_rms > t.max_gyro_rate_radps) return LevelingStatus::GyroRate;
  if (std::abs(s.mean_force.norm() - gravity_mps2) > t.max_gravity_mismatch_mps2) return LevelingStatus::NotGravity;
  return LevelingStatus::Level;
}

}  // namespace

Eigen::Matrix3d rotationNedBody(double roll_rad, double pitch_rad, double yaw_rad) {
  return so3::expMap(Eigen::Vector3d(0, 0, yaw_rad)) * so3::expMap(Eigen::Vector3d(0, pitch_rad, 0)) *
         so3::expMap(Eigen::Vector3d(roll_rad, 0, 0));
}

Eigen::Matrix3d rotationEcefNed(const Eigen::Vector3d& position_ecef_m) {
  const Geodetic g = ecefToGeodetic(position_ecef_m);
  return (rotationNedEnu() * rotationEnuFromEcef(g.latitude_rad, g.longitude_rad)).transpose();
}

EulerAngles eulerAngles(const Eigen::Matrix3d& r) {
  EulerAngles e;
  e.roll_rad = std::atan2(r(2, 1), r(2, 2));
  e.pitch_rad = std::atan2(-r(2, 0), std::hypot(r(2, 1), r(2, 2)));
  e.yaw_rad = std::atan2(r(1, 0), r(0, 0));
  return e;
}

Eigen::Matrix3d withYaw(const Eigen::Matrix3d& rotation_ecef_body, const Eigen::Vector3d& position_ecef_m,
                        double yaw_rad) {
  const Eigen::Matrix3d ecef_ned = rotationEcefNed(position_ecef_m);
  const EulerAngles e = eulerAngles(ecef_ned.transpose() * rotation_ecef_body);
  return ecef_ned * rotationNedBody(e.roll_rad, e.pitch_rad, yaw_rad);
}

LevelingResult levelAtLatestStaticInterval(const std::vector<ImuSample>& samples,
                                           const Eigen::Vector3d& position_ecef_m,
                                           const StaticIntervalThresholds& thresholds, std::size_t* interval_end) {
  const std::size_t n = std::max<std::size_t>(thresholds.min_samples, 1);
  const std::size_t step = std::max<std::size_t>(n / 2, 1);
  LevelingResult last;
  last.samples = samples.size();
  if (samples.size() < n) return last;
  for (std::size_t end = samples.size();; end -= std::min(step, end - n)) {
    const std::vector<ImuSample> window(samples.begin() + static_cast<std::ptrdiff_t>(end - n),
                                        samples.begin() + static_cast<std::ptrdiff_t>(end));
    last = levelFromStaticInterval(window, position_ecef_m, thresholds);
    if (last.status == LevelingStatus::Level) {
      if (interval_end) *interval_end = end;
      return last;
    }
    if (end == n) return last;
  }
}

Eigen::Matrix3d propagateAttitude(const Eigen::Matrix3d& rotation_ecef_body, const std::vector<ImuSample>& samples,
                                  std::size_t first, const GnssTime& until, const Eigen::Vector3d& gyro_bias_radps) {
  const Eigen::Vector3d earth_rate(0.0, 0.0, kEarthRotationRate_radps);
  Eigen::Matrix3d R = rotation_ecef_body;
  for (std::size_t k = first; k < samples.size() && until - samples[k].time > 0.0; ++k) {
    const GnssTime next = k + 1 < samples.size() && until - samples[k + 1].time > 0.0 ? samples[k + 1].time : until;
    const double dt_s = next - samples[k].time;
    R = so3::expMap(-earth_rate * dt_s) * R * so3::expMap((samples[k].angular_rate_radps - gyro_bias_radps) * dt_s);
  }
  return R;
}

std::string levelingStatusText(LevelingStatus status) {
  switch (status) {
    case LevelingStatus::Level: return "level";
    case LevelingStatus::TooFewSamples: return "too few samples";
    case LevelingStatus::NonFiniteReading: return "reading not finite";
    case LevelingStatus::AccelerometerSpread: return "accelerometer spread over the threshold";
    case LevelingStatus::GyroRate: return "gyro rate over the threshold";
    case LevelingStatus::NotGravity: return "mean specific force is not gravity";
  }
  return "unknown status";
}

LevelingResult levelFromStaticInterval(const std::vector<ImuSample>& samples, const Eigen::Vector3d& position_ecef_m,
                                       const StaticIntervalThresholds& thresholds) {
  const IntervalStatistics s = intervalStatistics(samples);
  const Geodetic g = ecefToGeodetic(position_ecef_m);
  const double gravity_mps2 = normalGravity_mps2(g.latitude_rad, g.height_m);
  LevelingResult out;
  out.status = intervalStatus(s, gravity_mps2, thresholds);
  out.samples = s.samples;
  out.mean_specific_force_mps2 = s.mean_force;
  out.accel_spread_mps2 = s.force_spread.maxCoeff();
  out.mean_angular_rate_radps = s.mean_rate;
  out.gyro_variance_radps2 = s.rate_variance.maxCoeff();
  out.gyro_rms_radps = s.gyro_rms;
  if (out.status != LevelingStatus::Level) return out;
  const Eigen::Vector3d& f = s.mean_force;
  out.roll_rad = std::atan2(-f.y(), -f.z());
  out.pitch_rad = std::atan2(f.x(), std::hypot(f.y(), f.z()));
  out.tilt_sigma_rad = out.accel_spread_mps2 / (gravity_mps2 * std::sqrt(static_cast<double>(s.samples)));
  return out;
}

std::string headingStatusText(HeadingStatus status) {
  switch (status) {
    case HeadingStatus::Heading: return "heading";
    case HeadingStatus::SpeedTooLow: return "horizontal speed below the threshold";
    case HeadingStatus::NonFiniteVelocity: return "velocity not finite";
  }
  return "unknown status";
}

HeadingResult headingFromGnssVelocity(const Eigen::Vector3d& velocity_ecef_mps, const Eigen::Vector3d& position_ecef_m,
                                      double velocity_sigma_mps, double min_horizontal_speed_mps) {
  HeadingResult out;
  if (!velocity_ecef_mps.allFinite() || !position_ecef_m.allFinite()) {
    out.status = HeadingStatus::NonFiniteVelocity;
    return out;
  }
  const Eigen::Vector3d ned = rotationEcefNed(position_ecef_m).transpose() * velocity_ecef_mps;
  out.horizontal_speed_mps = std::hypot(ned.x(), ned.y());
  if (!(out.horizontal_speed_mps >= min_horizontal_speed_mps) || out.horizontal_speed_mps <= 0.0) {
    out.status = HeadingStatus::SpeedTooLow;
    return out;
  }
  out.status = HeadingStatus::Heading;
  out.heading_rad = std::atan2(ned.y(), ned.x());
  out.heading_sigma_rad = velocity_sigma_mps / out.horizontal_speed_mps;
  return out;
}

std::string alignmentStateText(AlignmentState state) {
  switch (state) {
    case AlignmentState::NotAligned: return "not aligned";
    case AlignmentState::LevelOnly: return "level only (roll and pitch, no heading)";
    case AlignmentState::Aligned: return "aligned";
  }
  return "unknown state";
}

InsAttitudeQuality insAttitudeQuality(AlignmentState state, const Eigen::Matrix3d& rotation_ned_body,
                                      const Eigen::Matrix3d& attitude_covariance_body_rad2,
                                      double publish_tilt_sigma_rad, double publish_heading_sigma_rad) {
  InsAttitudeQuality q;
  q.state = state;
  const Eigen::Matrix3d C = rotation_ned_body * attitude_covariance_body_rad2 * rotation_ned_body.transpose();
  q.tilt_sigma_rad = std::sqrt(std::max(C(0, 0), C(1, 1)));
  q.heading_sigma_rad = std::sqrt(std::max(C(2, 2), 0.0));
  q.publishable = attitudePublishable(q.state) && q.tilt_sigma_rad <= publish_tilt_sigma_rad &&
                  q.heading_sigma_rad <= publish_heading_sigma_rad;
  return q;
}

LevelingResult CoarseAlignment::addStaticInterval(const std::vector<ImuSample>& samples,
                                                  const Eigen::Vector3d& position_ecef_m,
                                                  const StaticIntervalThresholds& thresholds) {
  const LevelingResult result = levelFromStaticInterval(samples, position_ecef_m, thresholds);
  if (result.status == LevelingStatus::Level) {
    leveling_ = result;
    level_ = true;
  }
  return result;
}

HeadingResult CoarseAlignment::addGnssVelocity(const Eigen::Vector3d& velocity_ecef_mps,
                                               const Eigen::Vector3d& position_ecef_m, double velocity_sigma_mps,
                                               double min_horizontal_speed_mps) {
  const HeadingResult result =
      headingFromGnssVelocity(velocity_ecef_mps, position_ecef_m, velocity_sigma_mps, min_horizontal_speed_mps);
  if (result.status == HeadingStatus::Heading) {
    heading_ = result;
    heading_known_ = true;
  }
  return result;
}

AlignmentState CoarseAlignment::state() const {
  if (!level_) return AlignmentState::NotAligned;
  return heading_known_ ? AlignmentState::Aligned : AlignmentState::LevelOnly;
}

Eigen::Matrix3d CoarseAlignment::rotationEcefBody(const Eigen::Vector3d& position_ecef_m) const {
  if (state() != AlignmentState::Aligned) return Eigen::Matrix3d::Identity();
  return rotationEcefNed(position_ecef_m) *
         rotationNedBody(leveling_.roll_rad, leveling_.pitch_rad, heading_.heading_rad);
}

}  // namespace ppp
