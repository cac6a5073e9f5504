#include "ppp_bayes_tree/ros/ins_odometry.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp_ros {

BasePose basePose(const InsState& state, const ImuExtrinsics& e, const OdometryFrame& frame) {
  const Eigen::Matrix3d ecef_base = state.nav.rotation_world_body * e.rotation_base_imu.transpose();
  const Eigen::Vector3d base_ecef = state.nav.position_world_m - ecef_base * e.translation_m;
  BasePose p;
  p.position_m = frame.enu_from_ecef * (base_ecef - frame.datum_ecef_m);
  p.rotation_map_base = frame.enu_from_ecef * ecef_base;
  return p;
}

double attitudeSigma_rad(const InsState& state) {
  const Eigen::Vector3d v = state.covariance.diagonal().segment<3>(ppp::InsErrorIndex::kAttitude);
  return std::sqrt(std::max(0.0, v.maxCoeff()));
}

namespace {

/// Copies a 3 x 3 block into a row-major 6 x 6 covariance at (row, col).
void setBlock(boost::array<double, 36>& c, int row, int col, const Eigen::Matrix3d& m) {
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) c[(row + r) * 6 + col + k] = m(r, k);
}

}  // namespace

nav_msgs::Odometry insOdometryMessage(const InsState& s, const ImuExtrinsics& e, const OdometryFrame& frame) {
  using I = ppp::InsErrorIndex;
  const BasePose pose = basePose(s, e, frame);
  const Eigen::Matrix3d ecef_base = s.nav.rotation_world_body * e.rotation_base_imu.transpose();
  // Angular rate of base_link relative to the Earth, in base_link; the velocity of its origin.
  const Eigen::Vector3d earth_rate_imu =
      s.nav.rotation_world_body.transpose() * Eigen::Vector3d(0.0, 0.0, ppp::kEarthRotationRate_radps);
  const Eigen::Vector3d w_base = e.rotation_base_imu * (s.angular_rate_radps - earth_rate_imu);
  const Eigen::Vector3d v_base_ecef = s.nav.velocity_world_mps - ecef_base * w_base.cross(e.translation_m);

  nav_msgs::Odometry odom;
  odom.header.stamp = utcStamp(s.time);
  odom.header.frame_id = frame.map_frame;
  odom.child_frame_id = frame.base_frame;
  odom.pose.pose.position.x = pose.position_m.x();
  odom.pose.pose.position.y = pose.position_m.y();
  odom.pose.pose.position.z = pose.position_m.z();
  const Eigen::Quaterniond q(pose.rotation_map_base);
  odom.pose.pose.orientation.w = q.w();
  odom.pose.pose.orientation.x = q.x();
  odom.pose.pose.orientation.y = q.y();
  odom.pose.pose.orientation.z = q.z();
  const Eigen::Vector3d v = ecef_base.transpose() * v_base_ecef;
  odom.twist.twist.linear.x = v.x();
  odom.twist.twist.linear.y = v.y();
  odom.twist.twist.linear.z = v.z();
  odom.twist.twist.angular.x = w_base.x();
  odom.twist.twist.angular.y = w_base.y();
  odom.twist.twist.angular.z = w_base.z();

  // Covariances: the attitude error is about the IMU axes (right perturbation): about the map axes A P A^T.
  const Eigen::Matrix3d P = frame.enu_from_ecef, A = frame.enu_from_ecef * s.nav.rotation_world_body;
  const Eigen::Matrix3d B = ecef_base.transpose(), G = e.rotation_base_imu;
  const auto blk = [&s](int r, int c) { return Eigen::Matrix3d(s.covariance.block<3, 3>(r, c)); };
  setBlock(odom.pose.covariance, 0, 0, P * blk(I::kPosition, I::kPosition) * P.transpose());
  setBlock(odom.pose.covariance, 0, 3, P * blk(I::kPosition, I::kAttitude) * A.transpose());
  setBlock(odom.pose.covariance, 3, 0, A * blk(I::kAttitude, I::kPosition) * P.transpose());
  setBlock(odom.pose.covariance, 3, 3, A * blk(I::kAttitude, I::kAttitude) * A.transpose());
  setBlock(odom.twist.covariance, 0, 0, B * blk(I::kVelocity, I::kVelocity) * B.transpose());
  setBlock(odom.twist.covariance, 3, 3, G * blk(I::kGyroBias, I::kGyroBias) * G.transpose());
  return odom;
}

}  // namespace ppp_ros
