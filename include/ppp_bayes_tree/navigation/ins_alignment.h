#pragma once
// Coarse alignment of a strapdown IMU (Groves, "Principles of GNSS, Inertial, and
// Multisensor Integrated Navigation Systems", 2nd ed., 2013, ch. 5, initialization and
// alignment):
// - levelling: roll and pitch from the specific force averaged over a static interval
//   (at rest it is minus gravity in the body frame). The interval is refused, with its
//   reason, when it is too short, holds a non-finite reading, the accelerometers spread
//   or the gyros turn beyond thresholds, or the mean force is not gravity.
// - heading from GNSS velocity in motion: the course over ground, taken as the yaw of
//   the body x axis. This assumes a platform moving along its x axis (a car, a
//   fixed-wing aircraft, a walker carrying the IMU facing forward) with negligible
//   side slip; it is wrong for a hovering or sideways-moving platform.
// - AlignmentState: not aligned / level only / aligned; only an aligned attitude is
//   published.
// Angles are the ZYX Euler angles (yaw, pitch, roll) of R_ned_body, NED being the
// local North-East-Down frame: an IMU with x forward, y right, z down reads roll = pitch
// = 0 when level; one with z up reads roll = 180 deg. Yaw is the heading of the body x
// axis from north, clockwise. Roll and pitch are singular at pitch +-90 deg.
#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

// ---- Attitude from Euler angles ----------------------------------------------------

/// R_ned_body = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Matrix3d rotationNedBody(double roll_rad, double pitch_rad, double yaw_rad);
/// R_ned_enu: swaps east and north and flips up (its own inverse).
Eigen::Matrix3d rotationNedEnu();
/// R_ecef_ned at the geodetic latitude and longitude of `position_ecef_m`.
Eigen::Matrix3d rotationEcefNed(const Eigen::Vector3d& position_ecef_m);

struct EulerAngles {
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
  double yaw_rad = 0.0;  ///< heading of the body x axis from north, clockwise
};
/// The ZYX Euler angles of R_ned_body.
EulerAngles eulerAngles(const Eigen::Matrix3d& rotation_ned_body);
/// R_ecef_body with its yaw replaced by `yaw_rad`, roll and pitch kept.
Eigen::Matrix3d withYaw(const Eigen::Matrix3d& rotation_ecef_body, const Eigen::Vector3d& position_ecef_m,
                        double yaw_rad);

// ---- Levelling from a static interval ----------------------------------------------

struct StaticIntervalThresholds {
  std::size_t min_samples = 100;
  double max_accel_spread_mps2 = 0.1;       ///< largest per-axis standard deviation of f
  double max_gyro_rate_radps = 0.05;        ///< root mean square of |w| (2.9 deg/s)
  double max_gravity_mismatch_mps2 = 0.5;   ///< | |mean f| - normal gravity |
};

enum class LevelingStatus { Level, TooFewSamples, NonFiniteReading, AccelerometerSpread, GyroRate, NotGravity };
/// "level", "too few samples", "reading not finite", "accelerometer spread over the
/// threshold", "gyro rate over the threshold", "mean specific force is not gravity".
std::string levelingStatusText(LevelingStatus status);

struct LevelingResult {
  LevelingStatus status = LevelingStatus::TooFewSamples;
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
  /// Standard deviation of roll and pitch from the accelerometer noise:
  /// accel spread / (g sqrt(N)). An accelerometer bias b adds b / g, unobservable here.
  double tilt_sigma_rad = 0.0;
  std::size_t samples = 0;
  Eigen::Vector3d mean_specific_force_mps2 = Eigen::Vector3d::Zero();
  double accel_spread_mps2 = 0.0;
  Eigen::Vector3d mean_angular_rate_radps = Eigen::Vector3d::Zero();  ///< the gyros' mean over the interval
  double gyro_variance_radps2 = 0.0;  ///< the largest per-axis variance of the gyros' readings over it
  double gyro_rms_radps = 0.0;
};

/// Roll and pitch of R_ned_body from readings at rest near `position_ecef_m`:
/// roll = atan2(-f_y, -f_z), pitch = atan2(f_x, sqrt(f_y^2 + f_z^2)) of the mean f.
LevelingResult levelFromStaticInterval(const std::vector<ImuSample>& samples, const Eigen::Vector3d& position_ecef_m,
                                       const StaticIntervalThresholds& thresholds = {});

/// Levelling for a start in motion: the latest interval of `thresholds.min_samples`
/// readings in `samples` that levels (searched back from the end in steps of half an
/// interval); `interval_end` gets the index after it. The last refusal when none levels.
LevelingResult levelAtLatestStaticInterval(const std::vector<ImuSample>& samples,
                                           const Eigen::Vector3d& position_ecef_m,
                                           const StaticIntervalThresholds& thresholds, std::size_t* interval_end);

/// R_ecef_body carried through the gyro readings samples[first, ...) up to `until`
/// (each reading held to the next one's time), less a gyro bias b:
/// R <- Exp(-w_ie dt) R Exp((w_b - b) dt).
Eigen::Matrix3d propagateAttitude(const Eigen::Matrix3d& rotation_ecef_body, const std::vector<ImuSample>& samples,
                                  std::size_t first, const GnssTime& until,
                                  const Eigen::Vector3d& gyro_bias_radps = Eigen::Vector3d::Zero());

// ---- Heading from GNSS velocity ----------------------------------------------------

enum class HeadingStatus { Heading, SpeedTooLow, NonFiniteVelocity };
/// "heading", "horizontal speed below the threshold", "velocity not finite".
std::string headingStatusText(HeadingStatus status);

struct HeadingResult {
  HeadingStatus status = HeadingStatus::SpeedTooLow;
  double heading_rad = 0.0;        ///< course over ground from north, clockwise, (-pi, pi]
  double heading_sigma_rad = 0.0;  ///< velocity sigma / horizontal speed
  double horizontal_speed_mps = 0.0;
};

/// The course over ground of an ECEF velocity at `position_ecef_m`, given when the
/// horizontal speed reaches `min_horizontal_speed_mps`; `velocity_sigma_mps` is the
/// standard deviation of each horizontal velocity component.
HeadingResult headingFromGnssVelocity(const Eigen::Vector3d& velocity_ecef_mps, const Eigen::Vector3d& position_ecef_m,
                                      double velocity_sigma_mps, double min_horizontal_speed_mps = 2.0);

// ---- Alignment state ---------------------------------------------------------------

enum class AlignmentState { NotAligned, LevelOnly, Aligned };
/// "not aligned", "level only (roll and pitch, no heading)", "aligned".
std::string alignmentStateText(AlignmentState state);
/// Only an aligned attitude (roll, pitch and heading) is good enough to publish.
inline bool attitudePublishable(AlignmentState state) { return state == AlignmentState::Aligned; }

/// How good an estimator's attitude is: the alignment state and the standard
/// deviations of tilt (the larger of the north and east axes) and heading (down axis).
/// Publishable once aligned with both sigmas within the thresholds.
struct InsAttitudeQuality {
  AlignmentState state = AlignmentState::NotAligned;
  double tilt_sigma_rad = 0.0;
  double heading_sigma_rad = 0.0;
  bool publishable = false;
};

/// The quality of an attitude R_ned_body of the given alignment from its error covariance
/// about the body axes (R_true = R Exp(dtheta), ins_error_state.h) [rad^2]: the covariance
/// turned to NED, tilt sigma the larger of north and east, heading sigma down; publishable
/// when aligned with both sigmas within the thresholds [rad]. The EKF's and the GNSS/INS
/// smoother's definition.
InsAttitudeQuality insAttitudeQuality(AlignmentState state, const Eigen::Matrix3d& rotation_ned_body,
                                      const Eigen::Matrix3d& attitude_covariance_body_rad2,
                                      double publish_tilt_sigma_rad, double publish_heading_sigma_rad);

/// Collects a levelling and a heading. The state is Aligned once both are accepted
/// (in either order), LevelOnly with the levelling alone; refused inputs change nothing.
class CoarseAlignment {
 public:
  LevelingResult addStaticInterval(const std::vector<ImuSample>& samples, const Eigen::Vector3d& position_ecef_m,
                                   const StaticIntervalThresholds& thresholds = {});
  HeadingResult addGnssVelocity(const Eigen::Vector3d& velocity_ecef_mps, const Eigen::Vector3d& position_ecef_m,
                                double velocity_sigma_mps, double min_horizontal_speed_mps = 2.0);

  AlignmentState state() const;
  const LevelingResult& leveling() const { return leveling_; }
  const HeadingResult& heading() const { return heading_; }
  /// R_ecef_body at `position_ecef_m` from the accepted roll, pitch and heading;
  /// identity unless Aligned.
  Eigen::Matrix3d rotationEcefBody(const Eigen::Vector3d& position_ecef_m) const;

 private:
  bool level_ = false;
  bool heading_known_ = false;
  LevelingResult leveling_;
  HeadingResult heading_;
};

}  // namespace ppp
