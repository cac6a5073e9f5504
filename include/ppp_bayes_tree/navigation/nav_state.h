#pragma once
// NavState: the kinematic state of the IMU body in a world frame W (ECEF for the
// estimators): attitude R_world_body, position and velocity of the body origin
// in W. Its tangent space (9-vector) is ordered [dtheta; dv; dp]: the rotation
// perturbation is on the right (R Exp(dtheta), in the body frame), velocity and
// position perturbations are added in W.
#include <Eigen/Core>

#include "ppp_bayes_tree/navigation/so3.h"

namespace ppp {

struct NavState {
  Eigen::Matrix3d rotation_world_body = Eigen::Matrix3d::Identity();
  Eigen::Vector3d position_world_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_world_mps = Eigen::Vector3d::Zero();

  /// The state moved by a tangent vector [dtheta; dv; dp].
  NavState retract(const Eigen::Matrix<double, 9, 1>& delta) const {
    NavState s;
    s.rotation_world_body = rotation_world_body * so3::expMap(delta.segment<3>(0));
    s.velocity_world_mps = velocity_world_mps + delta.segment<3>(3);
    s.position_world_m = position_world_m + delta.segment<3>(6);
    return s;
  }
  /// The tangent vector d with this->retract(d) == other.
  Eigen::Matrix<double, 9, 1> localCoordinates(const NavState& other) const {
    Eigen::Matrix<double, 9, 1> d;
    d << so3::logMap(rotation_world_body.transpose() * other.rotation_world_body),
        other.velocity_world_mps - velocity_world_mps, other.position_world_m - position_world_m;
    return d;
  }
};

}  // namespace ppp
