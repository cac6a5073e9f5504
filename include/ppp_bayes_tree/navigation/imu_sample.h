#pragma once
// ImuSample: one reading of a strapdown IMU in its own (body) frame: the
// specific force (the non-gravitational acceleration the accelerometers sense;
// at rest it points up with magnitude g) and the angular rate with respect to
// inertial space, stamped in GPS time.
#include <Eigen/Core>

#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

struct ImuSample {
  GnssTime time;                                             ///< GPST of the reading
  Eigen::Vector3d specific_force_mps2 = Eigen::Vector3d::Zero();  ///< f_b [m/s^2]
  Eigen::Vector3d angular_rate_radps = Eigen::Vector3d::Zero();   ///< w_b [rad/s]
};

}  // namespace ppp
