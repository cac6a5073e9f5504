#include "ppp_bayes_tree/navigation/imu_factor.h"

#include <Eigen/Geometry>

#include "ppp_bayes_tree/navigation/so3.h"

namespace ppp {
namespace {

/// The parts of the residual that the Jacobians reuse.
struct ResidualParts {
  PreintegratedDeltas deltas;
  FrameIntegrals frame;
  Eigen::Matrix3d rotation_error;  // E = dR^T R_i^T Q R_j
  Eigen::Vector3d velocity_world;  // u_v: the velocity change in W frozen at i, minus gravity
  Eigen::Vector3d position_world;  // u_p: likewise for the position
  Vector9d residual;
};

ResidualParts residualParts(const ImuPreintegration& pim, const NavState& si, const ImuBias& bi,
                            const NavState& sj, const NavigationFrame& frame) {
  ResidualParts r;
  const double dt = pim.deltaTime_s();
  const Eigen::Vector3d& w = frame.earth_rate_world_radps;
  r.deltas = pim.correctedDeltas(bi);
  r.frame = frameIntegrals(frame, si.position_world_m, dt);
  const Eigen::Matrix3d& q = r.frame.frame_rotation;
  const Eigen::Matrix3d& ri = si.rotation_world_body;
  r.rotation_error = r.deltas.rotation.transpose() * ri.transpose() * q * sj.rotation_world_body;
  const Eigen::Vector3d inertial_velocity_i = si.velocity_world_mps + w.cross(si.position_world_m);
  r.velocity_world =
      q * (sj.velocity_world_mps + w.cross(sj.position_world_m)) - inertial_velocity_i - r.frame.velocity_mps;
  r.position_world = q * sj.position_world_m - si.position_world_m - inertial_velocity_i * dt - r.frame.position_m;
  r.residual << so3::logMap(r.rotation_error), ri.transpose() * r.velocity_world - r.deltas.velocity_mps,
      ri.transpose() * r.position_world - r.deltas.position_m;
  return r;
}

void fillJacobians(const ImuPreintegration& pim, const ResidualParts& r, const NavState& si, const ImuBias& bi,
                   const NavigationFrame& frame, ImuFactorJacobians& jac) {
  const double dt = pim.deltaTime_s();
  const Eigen::Matrix3d& q = r.frame.frame_rotation;
  const Eigen::Matrix3d rit = si.rotation_world_body.transpose();
  const Eigen::Matrix3d w_hat = so3::hat(frame.earth_rate_world_radps);
  const Eigen::Matrix3d jr_inv = so3::rightJacobianInverse(r.residual.head<3>());
  const Eigen::Matrix3d i3 = Eigen::Matrix3d::Identity();
  // Rotation row: E = dR^T R_i^T Q R_j; R_i^T Q R_j = dR E.
  jac.d_state_j.block<3, 3>(0, 0) = jr_inv;
  jac.d_state_i.block<3, 3>(0, 0) = -jr_inv * r.rotation_error.transpose() * r.deltas.rotation.transpose();
  const Eigen::Vector3d dbg = bi.gyro_radps - pim.biasEstimate().gyro_radps;
  const Eigen::Matrix3d jr_bias = so3::rightJacobian(pim.dRotation_dGyroBias() * dbg);
  jac.d_bias_i.block<3, 3>(0, 3) = -jr_inv * r.rotation_error.transpose() * jr_bias * pim.dRotation_dGyroBias();
  // Velocity row.
  jac.d_state_i.block<3, 3>(3, 0) = so3::hat(rit * r.velocity_world);
  jac.d_state_i.block<3, 3>(3, 3) = -rit;
  jac.d_state_i.block<3, 3>(3, 6) = rit * (-w_hat - r.frame.d_velocity_d_position);
  jac.d_state_j.block<3, 3>(3, 3) = rit * q;
  jac.d_state_j.block<3, 3>(3, 6) = rit * q * w_hat;
  jac.d_bias_i.block<3, 3>(3, 0) = -pim.dVelocity_dAccelBias();
  jac.d_bias_i.block<3, 3>(3, 3) = -pim.dVelocity_dGyroBias();
  // Position row.
  jac.d_state_i.block<3, 3>(6, 0) = so3::hat(rit * r.position_world);
  jac.d_state_i.block<3, 3>(6, 3) = -rit * dt;
  jac.d_state_i.block<3, 3>(6, 6) = rit * (-i3 - w_hat * dt - r.frame.d_position_d_position);
  jac.d_state_j.block<3, 3>(6, 6) = rit * q;
  jac.d_bias_i.block<3, 3>(6, 0) = -pim.dPosition_dAccelBias();
  jac.d_bias_i.block<3, 3>(6, 3) = -pim.dPosition_dGyroBias();
}

}  // namespace

Vector9d imuFactorError(const ImuPreintegration& pim, const NavState& state_i, const ImuBias& bias_i,
                        const NavState& state_j, const NavigationFrame& frame, ImuFactorJacobians* jacobians) {
  const ResidualParts parts = residualParts(pim, state_i, bias_i, state_j, frame);
  if (jacobians) {
    *jacobians = ImuFactorJacobians{};
    fillJacobians(pim, parts, state_i, bias_i, frame, *jacobians);
  }
  return parts.residual;
}

Vector6d biasRandomWalkError(const ImuBias& bias_i, const ImuBias& bias_j) {
  return bias_j.vector() - bias_i.vector();
}

Matrix6d biasRandomWalkCovariance(const ImuNoise& noise, double dt_s) {
  Matrix6d c = Matrix6d::Zero();
  const double sa = noise.accel_bias_random_walk_mps3_per_sqrthz;
  const double sg = noise.gyro_bias_random_walk_radps2_per_sqrthz;
  c.diagonal() << Eigen::Vector3d::Constant(sa * sa * dt_s), Eigen::Vector3d::Constant(sg * sg * dt_s);
  return c;
}

}  // namespace ppp
