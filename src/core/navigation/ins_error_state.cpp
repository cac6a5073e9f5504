#include "ppp_bayes_tree/navigation/ins_error_state.h"

#include <cmath>

#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

using Index = InsErrorIndex;
const Eigen::Vector3d kEarthRateEcef_radps(0.0, 0.0, kEarthRotationRate_radps);

/// 1 / tau, zero for a random walk (infinite or non-positive tau).
double inverseCorrelationTime(double tau_s) { return std::isfinite(tau_s) && tau_s > 0.0 ? 1.0 / tau_s : 0.0; }

/// Driving-noise density of a bias: the random-walk density, or for a Gauss-Markov
/// process the instability times sqrt(2 / tau).
double biasDrivingDensity(double random_walk_density, double instability, double tau_s) {
  const double inverse_tau = inverseCorrelationTime(tau_s);
  return inverse_tau > 0.0 ? instability * std::sqrt(2.0 * inverse_tau) : random_walk_density;
}

}  // namespace

Eigen::Matrix3d ecefGravityGradient(const Eigen::Vector3d& position_ecef_m) {
  const NavigationFrame frame = ecefNavigationFrame(position_ecef_m);
  const Eigen::Matrix3d w_hat = so3::hat(frame.earth_rate_world_radps);
  const Eigen::Vector3d gravitation = frame.gravity_world_mps2 - w_hat * w_hat * position_ecef_m;
  const double radius_m = position_ecef_m.norm();
  const Eigen::Vector3d up = position_ecef_m / radius_m;
  return gravitation.norm() / radius_m * (3.0 * up * up.transpose() - Eigen::Matrix3d::Identity()) + w_hat * w_hat;
}

Matrix15d insErrorStateF(const NavState& state_ecef, const Eigen::Vector3d& specific_force_mps2,
                         const Eigen::Vector3d& angular_rate_radps, const InsBiasModel& bias_model) {
  const Eigen::Matrix3d& r = state_ecef.rotation_world_body;
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  Matrix15d f = Matrix15d::Zero();
  f.block<3, 3>(Index::kAttitude, Index::kAttitude) = -so3::hat(angular_rate_radps);
  f.block<3, 3>(Index::kAttitude, Index::kGyroBias) = -identity;
  f.block<3, 3>(Index::kVelocity, Index::kAttitude) = -r * so3::hat(specific_force_mps2);
  f.block<3, 3>(Index::kVelocity, Index::kVelocity) = -2.0 * so3::hat(kEarthRateEcef_radps);
  f.block<3, 3>(Index::kVelocity, Index::kPosition) = ecefGravityGradient(state_ecef.position_world_m);
  f.block<3, 3>(Index::kVelocity, Index::kAccelBias) = -r;
  f.block<3, 3>(Index::kPosition, Index::kVelocity) = identity;
  f.block<3, 3>(Index::kAccelBias, Index::kAccelBias) =
      -inverseCorrelationTime(bias_model.accel_correlation_time_s) * identity;
  f.block<3, 3>(Index::kGyroBias, Index::kGyroBias) =
      -inverseCorrelationTime(bias_model.gyro_correlation_time_s) * identity;
  return f;
}

Matrix15x12d insErrorStateG(const NavState& state_ecef) {
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  Matrix15x12d g = Matrix15x12d::Zero();
  g.block<3, 3>(Index::kVelocity, 0) = -state_ecef.rotation_world_body;  // n_a
  g.block<3, 3>(Index::kAttitude, 3) = -identity;                         // n_g
  g.block<3, 3>(Index::kAccelBias, 6) = identity;                         // n_ba
  g.block<3, 3>(Index::kGyroBias, 9) = identity;                          // n_bg
  return g;
}

Matrix12d insNoiseSpectralDensity(const ImuNoise& noise, const InsBiasModel& bias_model) {
  const double accel_bias = biasDrivingDensity(noise.accel_bias_random_walk_mps3_per_sqrthz,
                                               noise.accel_bias_instability_mps2, bias_model.accel_correlation_time_s);
  const double gyro_bias = biasDrivingDensity(noise.gyro_bias_random_walk_radps2_per_sqrthz,
                                              noise.gyro_bias_instability_radps, bias_model.gyro_correlation_time_s);
  Eigen::Matrix<double, kInsNoiseSize, 1> sigma;
  sigma << Eigen::Vector3d::Constant(noise.accel_noise_density_mps2_per_sqrthz),
      Eigen::Vector3d::Constant(noise.gyro_noise_density_radps_per_sqrthz), Eigen::Vector3d::Constant(accel_bias),
      Eigen::Vector3d::Constant(gyro_bias);
  return sigma.array().square().matrix().asDiagonal();
}

InsDiscreteModel discretizeInsErrorModel(const Matrix15d& f, const Matrix15x12d& g, const Matrix12d& density,
                                         double dt_s, int order) {
  InsDiscreteModel model;
  const Matrix15d f_dt = f * dt_s;
  model.transition = Matrix15d::Identity() + f_dt;
  if (order >= 2) model.transition += 0.5 * f_dt * f_dt;
  model.process_noise = discreteInsProcessNoise(model.transition, g, density, dt_s);
  return model;
}

Matrix15d discreteInsProcessNoise(const Matrix15d& transition, const Matrix15x12d& g, const Matrix12d& density,
                                  double dt_s) {
  const Matrix15d input = g * density * g.transpose();
  return 0.5 * dt_s * (transition * input * transition.transpose() + input);
}

Matrix15d propagateInsCovariance(const Matrix15d& covariance, const InsDiscreteModel& model) {
  const Matrix15d next = model.transition * covariance * model.transition.transpose() + model.process_noise;
  return 0.5 * (next + next.transpose());
}

void applyInsErrorCorrection(const Vector15d& error, NavState* state_ecef, ImuBias* bias) {
  *state_ecef = state_ecef->retract(error.head<9>());
  bias->accel_mps2 += error.segment<3>(Index::kAccelBias);
  bias->gyro_radps += error.segment<3>(Index::kGyroBias);
}

Matrix15d insErrorResetJacobian(const Vector15d& error) {
  Matrix15d j = Matrix15d::Identity();
  j.block<3, 3>(Index::kAttitude, Index::kAttitude) = so3::rightJacobian(error.segment<3>(Index::kAttitude));
  return j;
}

Eigen::Vector3d insAntennaPosition(const NavState& state_ecef, const Eigen::Vector3d& lever_arm_body_m,
                                   const Vector15d& error) {
  const Eigen::Matrix3d R = state_ecef.rotation_world_body * so3::expMap(error.segment<3>(Index::kAttitude));
  return state_ecef.position_world_m + error.segment<3>(Index::kPosition) + R * lever_arm_body_m;
}

Eigen::Matrix<double, 3, kInsErrorStateSize> insAntennaPositionJacobian(const NavState& state_ecef,
                                                                       const Eigen::Vector3d& lever_arm_body_m,
                                                                       const Vector15d& error) {
  const Eigen::Vector3d a = error.segment<3>(Index::kAttitude);
  const Eigen::Matrix3d R = state_ecef.rotation_world_body * so3::expMap(a);
  Eigen::Matrix<double, 3, kInsErrorStateSize> J = Eigen::Matrix<double, 3, kInsErrorStateSize>::Zero();
  J.block<3, 3>(0, Index::kAttitude) = -R * so3::hat(lever_arm_body_m) * so3::rightJacobian(a);
  J.block<3, 3>(0, Index::kPosition) = Eigen::Matrix3d::Identity();
  return J;
}

Eigen::Matrix3d insAntennaPositionCovariance(const NavState& state_ecef, const Eigen::Vector3d& lever_arm_body_m,
                                             const Matrix15d& covariance, const Vector15d& error) {
  const Eigen::Matrix<double, 3, kInsErrorStateSize> J = insAntennaPositionJacobian(state_ecef, lever_arm_body_m, error);
  return J * covariance * J.transpose();
}

}  // namespace ppp
