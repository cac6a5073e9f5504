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
  const Eigen::Vector3d accel = specific_force_mps2 - bias_estimate_.accel_mps2;
  const Eigen::Vector3d rotation_vector = (angular_rate_radps - bias_estimate_.gyro_radps) * dt_s;
  const Eigen::Matrix3d step_rotation = so3::expMap(rotation_vector);
  const Eigen::Matrix3d step_jacobian = so3::rightJacobian(rotation_vector);
  // Covariance and bias Jacobians use the deltas before this reading.
  propagateCovariance(step_rotation, accel, step_jacobian, dt_s);
  propagateBiasJacobians(step_rotation, accel, step_jacobian, dt_s);
  // Deltas: position first (it uses the old velocity), then velocity, then rotation.
  const Eigen::Vector3d accel_i = deltas_.rotation * accel;
  deltas_.position_m += deltas_.velocity_mps * dt_s + 0.5 * accel_i * dt_s * dt_s;
  deltas_.velocity_mps += accel_i * dt_s;
  deltas_.rotation = deltas_.rotation * step_rotation;
  delta_time_s_ += dt_s;
}

void ImuPreintegration::propagateCovariance(const Eigen::Matrix3d& step_rotation,
                                            const Eigen::Vector3d& accel_mps2,
                                            const Eigen::Matrix3d& step_jacobian, double dt_s) {
  const Eigen::Matrix3d& dr = deltas_.rotation;
  const Eigen::Matrix3d dr_accel_hat = dr * so3::hat(accel_mps2);
  const double dt2 = dt_s * dt_s;
  // Error-state transition (order dtheta, dv, dp) and noise maps.
  Matrix9d a = Matrix9d::Identity();
  a.block<3, 3>(0, 0) = step_rotation.transpose();
  a.block<3, 3>(3, 0) = -dr_accel_hat * dt_s;
  a.block<3, 3>(6, 0) = -0.5 * dr_accel_hat * dt2;
  a.block<3, 3>(6, 3) = Eigen::Matrix3d::Identity() * dt_s;
  Eigen::Matrix<double, 9, 3> b_gyro = Eigen::Matrix<double, 9, 3>::Zero();
  b_gyro.block<3, 3>(0, 0) = step_jacobian * dt_s;
  Eigen::Matrix<double, 9, 3> b_accel = Eigen::Matrix<double, 9, 3>::Zero();
  b_accel.block<3, 3>(3, 0) = dr * dt_s;
  b_accel.block<3, 3>(6, 0) = 0.5 * dr * dt2;
  // Discrete white-noise variances: density^2 / dt.
  const double gyro_var = noise_.gyro_noise_density_radps_per_sqrthz * noise_.gyro_noise_density_radps_per_sqrthz / dt_s;
  const double accel_var =
      noise_.accel_noise_density_mps2_per_sqrthz * noise_.accel_noise_density_mps2_per_sqrthz / dt_s;
  covariance_ = a * covariance_ * a.transpose() + gyro_var * b_gyro * b_gyro.transpose() +
                accel_var * b_accel * b_accel.transpose();
}

void ImuPreintegration::propagateBiasJacobians(const Eigen::Matrix3d& step_rotation,
                                               const Eigen::Vector3d& accel_mps2,
                                               const Eigen::Matrix3d& step_jacobian, double dt_s) {
  const Eigen::Matrix3d& dr = deltas_.rotation;
  const Eigen::Matrix3d dr_accel_hat = dr * so3::hat(accel_mps2);
  const double dt2 = dt_s * dt_s;
  d_position_d_ba_ += d_velocity_d_ba_ * dt_s - 0.5 * dr * dt2;
  d_position_d_bg_ += d_velocity_d_bg_ * dt_s - 0.5 * dr_accel_hat * d_rotation_d_bg_ * dt2;
  d_velocity_d_ba_ -= dr * dt_s;
  d_velocity_d_bg_ -= dr_accel_hat * d_rotation_d_bg_ * dt_s;
  d_rotation_d_bg_ = step_rotation.transpose() * d_rotation_d_bg_ - step_jacobian * dt_s;
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
