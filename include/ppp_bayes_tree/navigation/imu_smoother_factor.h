#pragma once
// The IMU factors of the smoother (Forster, Carlone, Dellaert, Scaramuzza, "On-manifold
// preintegration for real-time visual-inertial odometry", IEEE T-RO 33(1), 2017):
// - ImuSmootherFactor on (NavState_i, ImuBias_i, NavState_j): the 9-vector residual of
//   imuFactorError (imu_factor.h) with its analytic Jacobians in the NavState tangent
//   [dtheta; dv; dp] and the bias [accel; gyro], noise = the preintegration's covariance;
// - BiasRandomWalkFactor on (ImuBias_i, ImuBias_j): b_j - b_i with the random-walk
//   covariance of the interval (biasRandomWalkCovariance).
#include "ppp_bayes_tree/navigation/imu_factor.h"
#include "ppp_bayes_tree/navigation/imu_preintegration.h"
#include "ppp_bayes_tree/navigation/nav_state_value.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"

namespace ppp {

class ImuSmootherFactor : public smoother::NoiseModelFactorN<NavState, ImuBias, NavState> {
 public:
  /// Throws std::invalid_argument when the preintegration covers no time (its
  /// covariance would be singular).
  ImuSmootherFactor(smoother::Key state_i, smoother::Key bias_i, smoother::Key state_j,
                    const ImuPreintegration& preintegration, const NavigationFrame& frame);
  smoother::Vector evaluateError(const NavState& state_i, const ImuBias& bias_i, const NavState& state_j,
                                 smoother::Matrix* h_state_i, smoother::Matrix* h_bias_i,
                                 smoother::Matrix* h_state_j) const override;
  const ImuPreintegration& preintegration() const { return pim_; }

 private:
  ImuPreintegration pim_;
  NavigationFrame frame_;
};

class BiasRandomWalkFactor : public smoother::NoiseModelFactorN<ImuBias, ImuBias> {
 public:
  /// Throws std::invalid_argument for dt_s <= 0 or a noise without bias random walk.
  BiasRandomWalkFactor(smoother::Key bias_i, smoother::Key bias_j, const ImuNoise& noise, double dt_s);
  smoother::Vector evaluateError(const ImuBias& bias_i, const ImuBias& bias_j, smoother::Matrix* h_i,
                                 smoother::Matrix* h_j) const override;
  bool affineIn(smoother::Key) const override { return true; }  // b_j - b_i
};

}  // namespace ppp
