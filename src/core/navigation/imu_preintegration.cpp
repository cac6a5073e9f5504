#include "ppp_bayes_tree/navigation/imu_preintegration.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "ppp_bayes_tree/navigation/so3.h"

namespace ppp {

ImuPreintegration::ImuPreintegration(const ImuNoise& noise, const ImuBias& bias_estimate)
    : noise_(noise), bias_estimate_(bias_estimate) {}

void ImuPreintegration::reset(const ImuBias& bias_estimate) {
  *this = ImuPreintegration(noise_, bias_estimate);
}

void ImuPreintegration::integrate(const Eigen::Vector3d& specific_force_mps2,
                                  const Eigen::Vector3d& angular_rate_radps, double dt_s) {
  if (!(dt_s > 0.0)) return;
  StepTerms step;
  step.accel_mps2 = specific_force_mps2 - bias_estimate_.accel_mps2;
  const Eigen::Vector3d rotation_vector = (angular_rate_radps - bias_estimate_.gyro_radps) * dt_s;
  step.rotation = so3::expMap(rotation_vector);
  step.jacobian = so3::rightJacobian(rotation_vector);
  // The reading is applied in the body axes at the middle of the interval,
  // dR_k Exp(phi/2), as the mechanization's mean attitude (ins_mechanization.h).
  step.half_rotation = so3::expMap(0.5 * rotation_vector);
  step.half_jacobian = so3::rightJacobian(0.5 * rotation_vector);
  step.mid_rotation = deltas_.rotation * step.half_rotation;
  // Covariance and bias Jacobians use the deltas before this reading.
  propagateCovariance(step, dt_s);
  propagateBiasJacobians(step, dt_s);
  // Deltas: position first (it uses the old velocity), then velocity, then rotation.
  const Eigen::Vector3d accel_i = step.mid_rotation * step.accel_mps2;
  deltas_.position_m += deltas_.velocity_mps * dt_s + 0.5 * accel_i * dt_s * dt_s;
  deltas_.velocity_mps += accel_i * dt_s;
  deltas_.rotation = deltas_.rotation * step.rotation;
  delta_time_s_ += dt_s;
}

void ImuPreintegration::propagateCovariance(const StepTerms& step, double dt_s) {
  const Eigen::Matrix3d mid_accel_hat = step.mid_rotation * so3::hat(step.accel_mps2);
  const double dt2 = dt_s * dt_s;
  // Error-state transition (order dtheta, dv, dp) and noise maps. An error dtheta
  // of dR_k is Exp(phi/2)^T dtheta at the mid attitude; the gyro noise turns the
  // mid attitude by J_r(phi/2) n_g dt/2.
  const Eigen::Matrix3d theta_to_velocity = -mid_accel_hat * step.half_rotation.transpose();
  const Eigen::Matrix3d gyro_to_velocity = -mid_accel_hat * step.half_jacobian * (0.5 * dt_s);
  Matrix9d a = Matrix9d::Identity();
  a.block<3, 3>(0, 0) = step.rotation.transpose();
  a.block<3, 3>(3, 0) = theta_to_velocity * dt_s;
  a.block<3, 3>(6, 0) = 0.5 * theta_to_velocity * dt2;
  a.block<3, 3>(6, 3) = Eigen::Matrix3d::Identity() * dt_s;
  Eigen::Matrix<double, 9, 3> b_gyro = Eigen::Matrix<double, 9, 3>::Zero();
  b_gyro.block<3, 3>(0, 0) = step.jacobian * dt_s;
  b_gyro.block<3, 3>(3, 0) = gyro_to_velocity * dt_s;
  b_gyro.block<3, 3>(6, 0) = 0.5 * gyro_to_velocity * dt2;
  Eigen::Matrix<double, 9, 3> b_accel = Eigen::Matrix<double, 9, 3>::Zero();
  b_accel.block<3, 3>(3, 0) = step.mid_rotation * dt_s;
  b_accel.block<3, 3>(6, 0) = 0.5 * step.mid_rotation * dt2;
  // Discrete white-noise variances: density^2 / dt.
  const double gyro_var = noise_.gyro_noise_density_radps_per_sqrthz * noise_.gyro_noise_density_radps_per_sqrthz / dt_s;
  const double accel_var =
      noise_.accel_noise_density_mps2_per_sqrthz * noise_.accel_noise_density_mps2_per_sqrthz / dt_s;
  covariance_ = a * covariance_ * a.transpose() + gyro_var * b_gyro * b_gyro.transpose() +
                accel_var * b_accel * b_accel.transpose();
}

void ImuPreintegration::propagateBiasJacobians(const StepTerms& step, double dt_s) {
  const Eigen::Matrix3d mid_accel_hat = step.mid_rotation * so3::hat(step.accel_mps2);
  const double dt2 = dt_s * dt_s;
  // The mid attitude turns with the gyro bias through dR_k and through the half step.
  const Eigen::Matrix3d d_mid_rotation_d_bg =
      step.half_rotation.transpose() * d_rotation_d_bg_ - step.half_jacobian * (0.5 * dt_s);
  d_position_d_ba_ += d_velocity_d_ba_ * dt_s - 0.5 * step.mid_rotation * dt2;
  d_position_d_bg_ += d_velocity_d_bg_ * dt_s - 0.5 * mid_accel_hat * d_mid_rotation_d_bg * dt2;
  d_velocity_d_ba_ -= step.mid_rotation * dt_s;
  d_velocity_d_bg_ -= mid_accel_hat * d_mid_rotation_d_bg * dt_s;
  d_rotation_d_bg_ = step.rotation.transpose() * d_rotation_d_bg_ - step.jacobian * dt_s;
}

std::size_t ImuPreintegration::integrateBetween(const std::vector<ImuSample>& samples, const GnssTime& start,
                                                const GnssTime& end) {
  // The last sample at or before `start` holds at the start of the interval.
  auto first = std::upper_bound(samples.begin(), samples.end(), start,
                                [](const GnssTime& t, const ImuSample& s) { return t < s.time; });
  if (first == samples.begin()) return 0;
  --first;
  std::size_t used = 0;
  for (auto it = first; it != samples.end() && it->time < end; ++it) {
    const GnssTime from = std::max(it->time, start);
    const auto next = std::next(it);
    const GnssTime to = (next == samples.end() || next->time > end) ? end : next->time;
    integrate(it->specific_force_mps2, it->angular_rate_radps, to - from);
    ++used;
  }
  return used;
}

PreintegratedDeltas ImuPreintegration::correctedDeltas(const ImuBias& bias) const {
  const Eigen::Vector3d dba = bias.accel_mps2 - bias_estimate_.accel_mps2;
  const Eigen::Vector3d dbg = bias.gyro_radps - bias_estimate_.gyro_radps;
  PreintegratedDeltas out;
  out.rotation = deltas_.rotation * so3::expMap(d_rotation_d_bg_ * dbg);
  out.velocity_mps = deltas_.velocity_mps + d_velocity_d_ba_ * dba + d_velocity_d_bg_ * dbg;
  out.position_m = deltas_.position_m + d_position_d_ba_ * dba + d_position_d_bg_ * dbg;
  return out;
}

NavState predictNavState(const ImuPreintegration& pim, const NavState& state_i, const ImuBias& bias,
                         const NavigationFrame& frame) {
  const PreintegratedDeltas d = pim.correctedDeltas(bias);
  const double dt = pim.deltaTime_s();
  const FrameIntegrals g = frameIntegrals(frame, state_i.position_world_m, dt);
  const Eigen::Vector3d& w = frame.earth_rate_world_radps;
  const Eigen::Matrix3d& ri = state_i.rotation_world_body;
  const Eigen::Vector3d inertial_velocity_i = state_i.velocity_world_mps + w.cross(state_i.position_world_m);
  const Eigen::Vector3d position_frozen =
      state_i.position_world_m + inertial_velocity_i * dt + g.position_m + ri * d.position_m;
  const Eigen::Vector3d velocity_frozen = inertial_velocity_i + g.velocity_mps + ri * d.velocity_mps;
  const Eigen::Matrix3d qt = g.frame_rotation.transpose();
  NavState j;
  j.rotation_world_body = qt * ri * d.rotation;
  j.position_world_m = qt * position_frozen;
  j.velocity_world_mps = qt * velocity_frozen - w.cross(j.position_world_m);
  return j;
}

}  // namespace ppp
