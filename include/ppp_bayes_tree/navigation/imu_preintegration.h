#pragma once
// ImuPreintegration: the IMU readings between two epochs i and j summarised as
// relative motion in the body frame at i, independent of the states at i and j
// (Forster, Carlone, Dellaert, Scaramuzza 2017, "On-Manifold Preintegration for
// Real-Time Visual-Inertial Odometry", IEEE T-RO 33(1), sections V-VI):
//   dR = prod Exp((w_k - bg) dt_k),
//   dv = sum dR_k Exp(phi_k/2) (f_k - ba) dt_k,
//   dp = sum dv_k dt_k + 1/2 dR_k Exp(phi_k/2) (f_k - ba) dt_k^2,   phi_k = (w_k - bg) dt_k,
// integrated with the bias estimate held at construction. Each reading is the
// interval's specific force in the body axes as they turn through it (Groves,
// 2nd ed., ch. 5, "Precision Specific-Force Frame Transformation"), so it is
// applied at the interval's mid attitude dR_k Exp(phi_k/2), consistent with the
// mechanization's mean attitude (ins_mechanization.h); Forster's dR_k (the axes
// at the start) would leave a first-order error |w x f| dt_k / 2. It carries
//   - the 9x9 covariance of the noise of [dtheta; dv; dp] (eq. 63), propagated
//     reading by reading from the white-noise densities (discrete variance
//     density^2 / dt_k),
//   - the Jacobians of the deltas w.r.t. the biases (appendix, eqs. 69-70, taken at
//     the mid attitude), which
//     give the first-order correction for a new bias without integrating again
//     (eq. 44): dR(b) = dR Exp(dR/dbg dbg), dv(b) = dv + dv/dba dba + dv/dbg dbg,
//     dp(b) likewise.
// The bias random walk is not in this covariance: it is a factor of its own
// (imu_factor.h).
#include <Eigen/Core>
#include <vector>

#include "ppp_bayes_tree/navigation/imu_bias.h"
#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/navigation/nav_state.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"

namespace ppp {

using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Vector9d = Eigen::Matrix<double, 9, 1>;

/// Rotation, velocity and position deltas of one interval, in the body frame at i.
struct PreintegratedDeltas {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
};

class ImuPreintegration {
 public:
  ImuPreintegration(const ImuNoise& noise, const ImuBias& bias_estimate);

  /// Adds one reading covering dt_s > 0, applied at the interval's mid attitude
  /// (a reading with dt_s <= 0 is ignored).
  void integrate(const Eigen::Vector3d& specific_force_mps2, const Eigen::Vector3d& angular_rate_radps,
                 double dt_s);
  /// Adds the readings covering [start, end]: each sample holds until the next
  /// one's time; the last sample before `start` covers the beginning. Returns the
  /// number of readings used (0 when no sample is at or before `start`).
  std::size_t integrateBetween(const std::vector<ImuSample>& samples, const GnssTime& start,
                               const GnssTime& end);
  /// Back to an empty interval with a new bias estimate.
  void reset(const ImuBias& bias_estimate);
  /// Adds `extra` to the interval's covariance: more noise over it, e.g. an adaptive
  /// process noise (ins_process_noise_adaptation.h).
  void addCovariance(const Matrix9d& extra) { covariance_ += extra; }

  double deltaTime_s() const { return delta_time_s_; }
  const PreintegratedDeltas& deltas() const { return deltas_; }
  const Matrix9d& covariance() const { return covariance_; }  ///< order [dtheta; dv; dp]
  const ImuBias& biasEstimate() const { return bias_estimate_; }
  const ImuNoise& noise() const { return noise_; }

  const Eigen::Matrix3d& dRotation_dGyroBias() const { return d_rotation_d_bg_; }
  const Eigen::Matrix3d& dVelocity_dAccelBias() const { return d_velocity_d_ba_; }
  const Eigen::Matrix3d& dVelocity_dGyroBias() const { return d_velocity_d_bg_; }
  const Eigen::Matrix3d& dPosition_dAccelBias() const { return d_position_d_ba_; }
  const Eigen::Matrix3d& dPosition_dGyroBias() const { return d_position_d_bg_; }

  /// The deltas for another bias, by the first-order correction (eq. 44).
  PreintegratedDeltas correctedDeltas(const ImuBias& bias) const;

 private:
  /// One reading's terms: bias-corrected specific force, the step rotation
  /// Exp(phi) and its right Jacobian, the half step Exp(phi/2) and its right
  /// Jacobian, and the mid attitude dR_k Exp(phi/2).
  struct StepTerms {
    Eigen::Vector3d accel_mps2;
    Eigen::Matrix3d rotation, jacobian, half_rotation, half_jacobian, mid_rotation;
  };
  void propagateCovariance(const StepTerms& step, double dt_s);
  void propagateBiasJacobians(const StepTerms& step, double dt_s);

  ImuNoise noise_;
  ImuBias bias_estimate_;
  double delta_time_s_ = 0.0;
  PreintegratedDeltas deltas_;
  Matrix9d covariance_ = Matrix9d::Zero();
  Eigen::Matrix3d d_rotation_d_bg_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d d_velocity_d_ba_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d d_velocity_d_bg_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d d_position_d_ba_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d d_position_d_bg_ = Eigen::Matrix3d::Zero();
};

/// The state at j from the state at i, the bias (applied by the first-order
/// correction) and the world frame. In a rotating frame (earth rate w != 0) the
/// motion is composed in W frozen at t_i and brought back (see FrameIntegrals):
///   R_j = Q^T R_i dR,
///   v_j = Q^T (v_i + w x p_i + int(gamma) + R_i dv) - w x p_j,
///   p_j = Q^T (p_i + (v_i + w x p_i) dt + iint(gamma) + R_i dp).
/// This carries attitude transport, Coriolis, the centrifugal term and the turning
/// of gravity during the interval. With w = 0 it is Forster's eq. (33).
NavState predictNavState(const ImuPreintegration& pim, const NavState& state_i, const ImuBias& bias,
                         const NavigationFrame& frame);

}  // namespace ppp
