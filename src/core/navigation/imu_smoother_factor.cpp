#include "ppp_bayes_tree/navigation/imu_smoother_factor.h"

#include <stdexcept>
#include <string>

namespace ppp {

namespace {

smoother::NoiseModel::Ptr preintegrationNoise(const ImuPreintegration& pim) {
  if (!(pim.deltaTime_s() > 0.0))
    throw std::invalid_argument("ImuSmootherFactor: the preintegration covers no time (" +
                                std::to_string(pim.deltaTime_s()) + " s)");
  return smoother::NoiseModel::covariance(pim.covariance());
}

smoother::NoiseModel::Ptr randomWalkNoise(const ImuNoise& noise, double dt_s) {
  if (!(dt_s > 0.0))
    throw std::invalid_argument("BiasRandomWalkFactor: interval " + std::to_string(dt_s) + " s, must be > 0");
  if (!(noise.accel_bias_random_walk_mps3_per_sqrthz > 0.0) || !(noise.gyro_bias_random_walk_radps2_per_sqrthz > 0.0))
    throw std::invalid_argument("BiasRandomWalkFactor: the IMU noise has no bias random walk");
  return smoother::NoiseModel::covariance(biasRandomWalkCovariance(noise, dt_s));
}

}  // namespace

ImuSmootherFactor::ImuSmootherFactor(smoother::Key state_i, smoother::Key bias_i, smoother::Key state_j,
                                     const ImuPreintegration& preintegration, const NavigationFrame& frame)
    : NoiseModelFactorN(preintegrationNoise(preintegration), {state_i, bias_i, state_j}),
      pim_(preintegration),
      frame_(frame) {}

smoother::Vector ImuSmootherFactor::evaluateError(const NavState& state_i, const ImuBias& bias_i,
                                                  const NavState& state_j, smoother::Matrix* h_state_i,
                                                  smoother::Matrix* h_bias_i, smoother::Matrix* h_state_j) const {
  const bool want = h_state_i || h_bias_i || h_state_j;
  ImuFactorJacobians jac;
  const Vector9d r = imuFactorError(pim_, state_i, bias_i, state_j, frame_, want ? &jac : nullptr);
  if (h_state_i) *h_state_i = jac.d_state_i;
  if (h_bias_i) *h_bias_i = jac.d_bias_i;
  if (h_state_j) *h_state_j = jac.d_state_j;
  return r;
}

BiasRandomWalkFactor::BiasRandomWalkFactor(smoother::Key bias_i, smoother::Key bias_j, const ImuNoise& noise,
                                           double dt_s)
    : NoiseModelFactorN(randomWalkNoise(noise, dt_s), {bias_i, bias_j}) {}

smoother::Vector BiasRandomWalkFactor::evaluateError(const ImuBias& bias_i, const ImuBias& bias_j,
                                                     smoother::Matrix* h_i, smoother::Matrix* h_j) const {
  if (h_i) *h_i = -smoother::Matrix::Identity(6, 6);
  if (h_j) *h_j = smoother::Matrix::Identity(6, 6);
  return biasRandomWalkError(bias_i, bias_j);
}

}  // namespace ppp
