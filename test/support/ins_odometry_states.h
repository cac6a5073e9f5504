#pragma once
// States and readings of the IMU-rate odometry tests (ppp::InsOdometry, core, and the
// node's odometry message, ROS): a level state moving north at 10 m/s near Bern and
// the reading that keeps it so.
#include <Eigen/Core>

#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/ppp/estimators/ins_odometry.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp::test {

/// A state moving north at 10 m/s, level, x north (NED body = identity), at rest in attitude.
inline InsState movingState(const GnssTime& t) {
  const Eigen::Vector3d p = geodeticToEcef({46.877 * kDegToRad, 7.465 * kDegToRad, 950.0});
  InsState s;
  s.time = t;
  s.nav.position_world_m = p;
  s.nav.rotation_world_body = rotationEcefNed(p);
  s.nav.velocity_world_mps = rotationEcefNed(p) * Eigen::Vector3d(10.0, 0.0, 0.0);
  s.covariance = Matrix15d::Identity() * 1e-4;
  return s;
}

/// The reading at `t` that cancels gravity in the state's attitude (no rotation).
inline ImuSample steadyReading(const InsState& s, const GnssTime& t) {
  ImuSample r;
  r.time = t;
  r.specific_force_mps2 = -s.nav.rotation_world_body.transpose() * ecefNavigationFrame(s.nav.position_world_m).gravity_world_mps2;
  return r;
}

}  // namespace ppp::test
