#pragma once
// The node's pose at the IMU rate for an estimator with inertial states (ekf_ins,
// smoother_ins): ppp::InsOdometry (ppp/estimators/ins_odometry.h) carries the
// estimator's inertial state (inertial_state.h: the EKF's, or the smoother's newest
// state with its marginal covariance) from each GNSS epoch through the later readings.
// insOdometryMessage turns a state into ppp/odometry/filtered (REP-105: pose of
// base_link in the map frame, twist in base_link) with the filter's covariance.
#include <string>

#include <Eigen/Core>
#include <nav_msgs/Odometry.h>

#include "ppp_bayes_tree/ppp/estimators/ins_odometry.h"
#include "ppp_bayes_tree/ros/node_imu_input.h"

namespace ppp_ros {

using ppp::InsOdometry;
using ppp::InsState;

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
