#pragma once
// InsOdometry: the node's pose at the IMU rate for an estimator with inertial
// states (ekf_ins, smoother_ins). After each GNSS epoch the estimator's inertial
// state (the IMU's NavState in ECEF, the IMU bias and the 15-state INS error
// covariance; inertial_state.h: the EKF's, or the smoother's newest state with its
// marginal covariance) is taken; each later reading moves it by the INS mechanization
// (ppp::ecefInsStep, bias-corrected, each reading held from its time to the
// next one's as in the filter) and its covariance by the filter's error model.
// The readings that came before the epoch was processed (the epochs wait for
// corrections) are run through again without output, so the outputs never go
// back in time. A reading after a gap longer than the filter's
// max_imu_interval_s stops the odometry until the next epoch.
// insOdometryMessage turns a state into ppp/odometry/filtered (REP-105: pose of
// base_link in the map frame, twist in base_link) with the filter's covariance.
#include <deque>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <nav_msgs/Odometry.h>

#include "ppp_bayes_tree/navigation/imu_bias.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/navigation/ins_error_state.h"
#include "ppp_bayes_tree/navigation/nav_state.h"
#include "ppp_bayes_tree/ppp/estimators/ins_ekf_options.h"
#include "ppp_bayes_tree/ros/node_imu_input.h"

namespace ppp_ros {

/// The IMU's state at one time with what the odometry needs.
struct InsState {
  ppp::GnssTime time;
  ppp::NavState nav;  // IMU origin and axes, ECEF
  ppp::ImuBias bias;
  ppp::Matrix15d covariance = ppp::Matrix15d::Zero();  // INS error (ins_error_state.h order)
  Eigen::Vector3d angular_rate_radps = Eigen::Vector3d::Zero();  // bias-corrected reading held, IMU axes
};

class InsOdometry {
 public:
  explicit InsOdometry(const ppp::InsEkfOptions& options) : options_(options) {}

  /// The filter's state after an epoch at `state.time` with `held` the last reading at or
  /// before it; runs through `later` (the readings after it already received) without output.
  void restart(const InsState& state, const std::optional<ppp::ImuSample>& held,
               const std::deque<ppp::ImuSample>& later);
  /// One new reading: the state at its time; nullopt without a state, for a reading not
  /// after the state, or after a gap (the odometry then stops until the next restart).
  std::optional<InsState> step(const ppp::ImuSample& reading);
  /// No more odometry (the node fell back to GNSS only), until a restart.
  void stop();
  const std::optional<InsState>& current() const { return state_; }

 private:
  bool advance(const ppp::ImuSample& reading);

  ppp::InsEkfOptions options_;
  std::optional<InsState> state_;
  std::optional<ppp::ImuSample> held_;
};

/// The frames and datum the odometry is given in.
struct OdometryFrame {
  std::string map_frame, base_frame;
  Eigen::Vector3d datum_ecef_m = Eigen::Vector3d::Zero();
  Eigen::Matrix3d enu_from_ecef = Eigen::Matrix3d::Identity();
};

/// base_link's pose in the map (ENU) and its orientation.
struct BasePose {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation_map_base = Eigen::Matrix3d::Identity();
};
BasePose basePose(const InsState& state, const ImuExtrinsics& extrinsics, const OdometryFrame& frame);

/// ppp/odometry/filtered of an INS state: pose (position and orientation of base_link in
/// the map, covariance of the position and of the attitude about the map axes from the
/// filter) and twist in base_link (velocity and angular rate relative to the Earth; the
/// velocity's covariance from the filter, the angular rate's from the gyro bias).
nav_msgs::Odometry insOdometryMessage(const InsState& state, const ImuExtrinsics& extrinsics, const OdometryFrame& frame);

/// The largest attitude sigma of the state [rad].
double attitudeSigma_rad(const InsState& state);

}  // namespace ppp_ros
