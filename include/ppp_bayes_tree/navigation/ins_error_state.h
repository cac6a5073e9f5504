#pragma once
// The 15-state error model of the ECEF strapdown mechanization (ins_mechanization.h)
// for a Kalman filter: continuous-time F and G, the discrete transition and process
// noise, and the closed-loop correction. Estimator-agnostic: plain Eigen functions.
//
// Order and signs: dx = [dtheta; dv; dp; dba; dbg] (indices 0, 3, 6, 9, 12), the
// truth being the estimate moved by dx:
//   R_true = R Exp(dtheta)  (rotation on the right, in the body frame, like NavState),
//   v_true = v + dv, p_true = p + dp (ECEF), b_true = b + db (ImuBias [accel; gyro]).
// With w and f the bias-corrected readings, R = R_ecef_body, G the gravity gradient:
//   dtheta' = -[w]x dtheta - dbg - n_g          (the Earth rate cancels for a right error)
//   dv'     = -R [f]x dtheta - 2 [w_ie]x dv + G dp - R dba - R n_a
//   dp'     = dv
//   dba'    = -dba / tau_a + n_ba,  dbg' = -dbg / tau_g + n_bg   (tau infinite: random walk)
// Noise w = [n_a; n_g; n_ba; n_bg] with spectral densities from ImuNoise. This is the
// model of Groves, "Principles of GNSS, Inertial, and Multisensor Integrated Navigation
// Systems", 2nd ed., 2013, ch. 14 (ECEF system model) with the attitude error on the
// right and errors defined as truth minus estimate (Groves: estimate minus truth).
#include <Eigen/Core>
#include <limits>

#include "ppp_bayes_tree/navigation/imu_bias.h"
#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/navigation/nav_state.h"

namespace ppp {

constexpr int kInsErrorStateSize = 15;
constexpr int kInsNoiseSize = 12;
using Vector15d = Eigen::Matrix<double, kInsErrorStateSize, 1>;
using Matrix15d = Eigen::Matrix<double, kInsErrorStateSize, kInsErrorStateSize>;
using Matrix15x12d = Eigen::Matrix<double, kInsErrorStateSize, kInsNoiseSize>;
using Matrix12d = Eigen::Matrix<double, kInsNoiseSize, kInsNoiseSize>;

/// First index of each block of the error state.
struct InsErrorIndex {
  static constexpr int kAttitude = 0;
  static constexpr int kVelocity = 3;
  static constexpr int kPosition = 6;
  static constexpr int kAccelBias = 9;
  static constexpr int kGyroBias = 12;
};

/// How the biases move. Infinite correlation times (the default): random walks driven
/// by ImuNoise's random-walk densities. Finite: first-order Gauss-Markov processes
/// whose steady-state sigma is ImuNoise's bias instability (driving density
/// sigma * sqrt(2 / tau)).
struct InsBiasModel {
  double accel_correlation_time_s = std::numeric_limits<double>::infinity();
  double gyro_correlation_time_s = std::numeric_limits<double>::infinity();
};

/// Gradient d g / d p of the ECEF gravity [1/s^2]: the point-mass gravitation
/// (|gamma| / r) (3 u u^T - I) with u = p / |p| and |gamma| from normal gravity, plus
/// the centrifugal term -[w_ie]x^2. Within about 0.5 % of the ellipsoidal model.
Eigen::Matrix3d ecefGravityGradient(const Eigen::Vector3d& position_ecef_m);

/// Continuous-time F at the state, with the bias-corrected readings.
Matrix15d insErrorStateF(const NavState& state_ecef, const Eigen::Vector3d& specific_force_mps2,
                         const Eigen::Vector3d& angular_rate_radps, const InsBiasModel& bias_model = {});
/// Continuous-time noise input G (15 x 12), noise order [n_a; n_g; n_ba; n_bg].
Matrix15x12d insErrorStateG(const NavState& state_ecef);
/// Spectral densities of [n_a; n_g; n_ba; n_bg] (diagonal) [unit^2 / Hz].
Matrix12d insNoiseSpectralDensity(const ImuNoise& noise, const InsBiasModel& bias_model = {});

struct InsDiscreteModel {
  Matrix15d transition = Matrix15d::Identity();     ///< Phi
  Matrix15d process_noise = Matrix15d::Zero();      ///< Q_k
};

/// Phi = I + F dt (order 1) or I + F dt + F^2 dt^2 / 2 (order 2, the default), and
/// Q_k = (Phi G Qc G^T Phi^T + G Qc G^T) dt / 2 (the trapezoid of the integral).
InsDiscreteModel discretizeInsErrorModel(const Matrix15d& f, const Matrix15x12d& g, const Matrix12d& density,
                                         double dt_s, int order = 2);
/// Q_k of discretizeInsErrorModel for the step's transition Phi and the densities
/// `density` (linear in them: the process noise of a part of the noise, e.g. the
/// accelerometers' alone, without discretizing the transition again).
Matrix15d discreteInsProcessNoise(const Matrix15d& transition, const Matrix15x12d& g, const Matrix12d& density,
                                  double dt_s);

/// P+ = Phi P Phi^T + Q_k (symmetrised).
Matrix15d propagateInsCovariance(const Matrix15d& covariance, const InsDiscreteModel& model);

/// Closed-loop reset: moves the state and the bias by an estimated error dx (the
/// truth is the estimate moved by dx): R Exp(dtheta), v + dv, p + dp, b + db. The
/// filter's error estimate is zero afterwards.
void applyInsErrorCorrection(const Vector15d& error, NavState* state_ecef, ImuBias* bias);

/// Jacobian of the error after the reset w.r.t. the error before it: I with the
/// attitude block Jr(dtheta) = I - [dtheta/2]x + O(dtheta^2) (the right Jacobian of
/// SO(3)); the covariance after the reset is J P J^T.
Matrix15d insErrorResetJacobian(const Vector15d& error);

/// The GNSS antenna's position (ECEF) [m] at a state moved by an error dx:
/// p + dp + R Exp(dtheta) l, with l the lever arm (antenna minus the IMU's origin) in the
/// body axes [m].
Eigen::Vector3d insAntennaPosition(const NavState& state_ecef, const Eigen::Vector3d& lever_arm_body_m,
                                   const Vector15d& error = Vector15d::Zero());
/// Its Jacobian with respect to dx (3 x 15): position I, attitude -R Exp(dtheta) [l]x
/// Jr(dtheta) (so3.h: Exp(a + d) ~= Exp(a) Exp(Jr(a) d)), zero elsewhere.
Eigen::Matrix<double, 3, kInsErrorStateSize> insAntennaPositionJacobian(const NavState& state_ecef,
                                                                       const Eigen::Vector3d& lever_arm_body_m,
                                                                       const Vector15d& error = Vector15d::Zero());
/// The antenna position's covariance J P J^T [m^2] for the error's covariance P, J at dx.
Eigen::Matrix3d insAntennaPositionCovariance(const NavState& state_ecef, const Eigen::Vector3d& lever_arm_body_m,
                                             const Matrix15d& covariance, const Vector15d& error = Vector15d::Zero());

}  // namespace ppp
