#pragma once
// The gnss_antenna lever arm: PPP estimates the antenna (marker) position; the
// body frame base_link is offset from it by the lever arm, fixed in the body.
// With the body attitude q_map_base (rotation taking base_link vectors into the
// map/ENU frame, as a sensor_msgs/Imu orientation in ENU, REP-103/REP-145):
//   p_antenna = p_base + R(q_map_base) * lever_arm_base  =>  p_base = p_antenna - R * lever_arm.
// Without an attitude the lever arm cannot be rotated and the nodes publish the
// antenna position as base_link (documented in config/ppp.yaml, ros.frames).
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ppp_ros {

/// base_link position in the map frame from the antenna position in the map
/// frame, the body attitude and the lever arm (antenna in base_link) [m].
inline Eigen::Vector3d baseLinkFromAntenna(const Eigen::Vector3d& antenna_map_m, const Eigen::Quaterniond& q_map_base,
                                           const Eigen::Vector3d& lever_arm_base_m) {
  return antenna_map_m - q_map_base.normalized() * lever_arm_base_m;
}

/// A usable attitude quaternion: finite and of unit norm within `tolerance`.
inline bool validAttitude(const Eigen::Quaterniond& q, double tolerance = 1e-3) {
  return q.coeffs().allFinite() && std::abs(q.norm() - 1.0) <= tolerance;
}

}  // namespace ppp_ros
