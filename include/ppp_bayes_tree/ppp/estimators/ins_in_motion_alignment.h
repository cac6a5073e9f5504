#pragma once
// The alignment in motion that the GNSS/INS estimators share (PppInsEkf,
// PppInsSmoother) when neither an attitude nor a heading is given (InsEkfOptions):
// - roll and pitch from the latest static interval of the readings before the
//   start (the last kLevellingHistory_s of them), carried to the start by the
//   gyros less their bias; the accelerometers' error along gravity from that
//   interval, and the gyros' bias (their mean at rest) where it is more than the
//   grade's bias instability and the Earth's unknown horizontal rate explain
//   (levelInMotion);
// - the heading from the course over ground of the antenna track once it moves
//   faster than HeadingAlignment::min_horizontal_speed_mps over at least
//   course_interval_s (CourseHeadingTrack): the course becomes the heading of the
//   body x axis (a platform moving along x), with sigma velocity sigma / speed;
// - the attitude's error covariance with the heading's variance set
//   (attitudeCovarianceWithHeading) and the state turned to the course
//   (alignedToCourse).
#include <Eigen/Core>
#include <deque>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/navigation/nav_state.h"
#include "ppp_bayes_tree/ppp/estimators/ins_ekf_options.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

/// How far back the readings before a start in motion are kept [s].
constexpr double kLevellingHistory_s = 120.0;

/// The largest mean rate of the levelling interval taken as the gyros' bias [rad/s]:
/// 1 deg/s, the zero-rate offset of a consumer MEMS gyro (Bosch BMI088 data sheet
/// BST-BMI088-DS001, gyroscope specification: +-1 deg/s typical). The levelling accepts
/// slow turns (StaticIntervalThresholds::max_gyro_rate_radps, 2.9 deg/s): a mean
/// rate above this is a turn, and the bias is left at zero.
constexpr double kMaxGyroBiasAtLevelling_radps = 1.0 * kDegToRad;

/// The test that takes the levelled mean rate m as the gyros' bias: m^T m / (s_p^2 + s_m^2)
/// above the chi-square 0.999 quantile of 3 degrees of freedom, with s_p the grade's bias
/// instability (the bias the estimators otherwise start from: zero with that sigma) and s_m
/// the levelled rate's own uncertainty (the Earth's horizontal rate, which the unknown
/// heading leaves in it, and the standard error of the readings' mean from their own scatter). A gyro whose turn-on bias
/// is within its datasheet's instability keeps the estimators' prior; one whose mean at rest
/// says otherwise (a consumer gyro's zero-rate offset of tenths of a degree per second)
/// starts from that mean with the sigma s_m.
constexpr double kGyroBiasTestChiSquare = 16.266;

/// Appends `readings` to `history` and drops those more than kLevellingHistory_s before `time`.
void keepLevellingHistory(std::vector<ImuSample>& history, const std::vector<ImuSample>& readings,
                          const GnssTime& time);

/// Roll and pitch at a start in motion (heading 0 at the static interval, carried by the gyros).
struct InMotionLevel {
  std::optional<Eigen::Matrix3d> rotation_ecef_body;  ///< at the start; nullopt: see problem
  /// The accelerometers' error along gravity: the mean force less the local gravity's
  /// magnitude (Groves 2nd ed. 14.2.1) [m/s^2].
  Eigen::Vector3d accel_bias_mps2 = Eigen::Vector3d::Zero();
  /// The gyros' bias: their mean rate over the static interval less the Earth's rate
  /// about the levelled down axis (Groves 2nd ed. 14.2.4; the turn-on bias of a
  /// consumer MEMS gyro is tenths of a degree per second, which the in-run
  /// instability does not cover); zero when that exceeds
  /// kMaxGyroBiasAtLevelling_radps (a slow turn), or when the grade's prior explains it
  /// (kGyroBiasTestChiSquare). The Earth's horizontal rate, whose direction needs the
  /// heading, stays in it: at most 15 deg/h cos(latitude) [rad/s].
  Eigen::Vector3d gyro_bias_radps = Eigen::Vector3d::Zero();
  /// The sigma of gyro_bias_radps per axis when it was taken from the levelling [rad/s]:
  /// the levelled rate's uncertainty and the grade's instability, root-sum-squared (the
  /// estimators start the gyro bias with it).
  /// nullopt: not taken, the grade's prior stands.
  std::optional<double> gyro_bias_sigma_radps;
  std::string problem;  ///< why there is no attitude
};

/// Levels at the latest static interval of `history` (the readings before the start)
/// and carries the attitude through the later readings to `start`. `noise` is the IMU's
/// grade (its gyro bias instability, beside the levelled rate's uncertainty, decides
/// whether the mean rate at rest is a bias).
InMotionLevel levelInMotion(const std::vector<ImuSample>& history, const Eigen::Vector3d& position_ecef_m,
                            const GnssTime& start, const ImuNoise& noise);

/// The course over ground of the antenna track, once it gives a heading.
struct CourseHeading {
  HeadingResult heading;                                 ///< status Heading
  Eigen::Vector3d velocity_ecef_mps = Eigen::Vector3d::Zero();  ///< the track's mean velocity
};

/// The antenna positions of the solved epochs over the last course interval.
class CourseHeadingTrack {
 public:
  explicit CourseHeadingTrack(const InsEkfOptions::HeadingAlignment& options) : options_(options) {}
  /// Adds the antenna position of a solved epoch; the course once the track spans at
  /// least course_interval_s and moves fast enough (the track is then cleared).
  std::optional<CourseHeading> add(const GnssTime& time, const Eigen::Vector3d& antenna_ecef_m);
  void clear() { track_.clear(); }

 private:
  InsEkfOptions::HeadingAlignment options_;
  std::deque<std::pair<GnssTime, Eigen::Vector3d>> track_;
};

/// An attitude error covariance about the body axes [rad^2] with the heading's (NED
/// down axis) variance set to sigma^2 and its correlations removed (tilt kept).
Eigen::Matrix3d attitudeCovarianceWithHeading(const Eigen::Matrix3d& rotation_ned_body,
                                              const Eigen::Matrix3d& attitude_covariance_body,
                                              double heading_sigma_rad);

/// `nav` with the heading of the course (roll and pitch kept, in the NED frame of its
/// position) and its position moved so that its antenna is at `antenna_ecef_m`.
NavState alignedToCourse(const NavState& nav, double heading_rad, const Eigen::Vector3d& antenna_ecef_m,
                         const Eigen::Vector3d& lever_arm_body_m);

}  // namespace ppp
