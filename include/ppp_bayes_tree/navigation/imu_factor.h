#pragma once
// The error functions of the IMU factors, with analytic Jacobians, for a
// smoother whose states are (NavState, ImuBias) at the GNSS epochs:
//
// - imuFactorError: the 9-vector residual between (state_i, bias_i) and state_j
//   given the preintegrated readings (Forster et al. 2017, eq. 45), ordered
//   [rotation; velocity; position] like the preintegration's covariance:
//     r_R = Log(dR(b_i)^T R_i^T Q R_j)
//     r_v = R_i^T (Q (v_j + w x p_j) - v_i - w x p_i - int(gamma)) - dv(b_i)
//     r_p = R_i^T (Q p_j - p_i - (v_i + w x p_i) dt - iint(gamma)) - dp(b_i)
//   With a non-rotating frame (w = 0, Q = I) these are
//     [Log(dR^T R_i^T R_j); R_i^T (v_j - v_i - g dt) - dv; R_i^T (p_j - p_i - v_i dt - g dt^2/2) - dp].
//   Jacobians are taken w.r.t. the NavState tangent [dtheta (right, body); dv; dp]
//   of each state and the bias vector [accel; gyro]; bias_j does not enter.
// - biasRandomWalkError: b_j - b_i (6-vector [accel; gyro]); its covariance for
//   an interval dt is diag(sigma_ba^2 dt, sigma_bg^2 dt) from the random-walk densities.
#include <Eigen/Core>

#include "ppp_bayes_tree/navigation/imu_preintegration.h"

namespace ppp {

using Matrix96d = Eigen::Matrix<double, 9, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct ImuFactorJacobians {
  Matrix9d d_state_i = Matrix9d::Zero();  ///< d r / d [dtheta_i; dv_i; dp_i]
  Matrix9d d_state_j = Matrix9d::Zero();  ///< d r / d [dtheta_j; dv_j; dp_j]
  Matrix96d d_bias_i = Matrix96d::Zero();  ///< d r / d [ba_i; bg_i]
};

/// The residual; fills `jacobians` when not null.
Vector9d imuFactorError(const ImuPreintegration& pim, const NavState& state_i, const ImuBias& bias_i,
                        const NavState& state_j, const NavigationFrame& frame,
                        ImuFactorJacobians* jacobians = nullptr);

/// b_j - b_i; the Jacobians are -I (bias_i) and +I (bias_j).
Vector6d biasRandomWalkError(const ImuBias& bias_i, const ImuBias& bias_j);
/// Covariance of biasRandomWalkError over dt_s from the noise's random-walk densities.
Matrix6d biasRandomWalkCovariance(const ImuNoise& noise, double dt_s);

}  // namespace ppp
