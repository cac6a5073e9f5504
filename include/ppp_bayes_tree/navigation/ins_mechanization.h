#pragma once
// EcefInsMechanization: a strapdown inertial navigator in the Earth-fixed frame
// (attitude R_ecef_body, velocity and position of the IMU in ECEF), advanced one
// IMU reading at a time. Reference: Groves, "Principles of GNSS, Inertial, and
// Multisensor Integrated Navigation Systems", 2nd ed., 2013, ch. 5 (the Earth-frame
// navigation equations, with the second-order refinements of the precision forms):
//   attitude   R+ = Exp(-w_ie dt) R- Exp(w_ib dt)          (body rate minus Earth rate;
//                                                          exact for rates held over dt)
//   force      f_e = 1/2 (R- + R+) f_b                     (mean attitude over the interval)
//   velocity   v+ = v- + (f_e + g(p_mid) - w_ie x (v- + v+)) dt   (Coriolis 2 w_ie x v by the
//                                                          trapezoid, solved for v+)
//   position   p+ = p- + (v- + v+) dt / 2
// with g the WGS 84 normal gravity (gravitation plus centrifugal) of
// ecefNavigationFrame at the mid-interval position p_mid = p- + v- dt/2. Each reading
// (bias-corrected by an ImuBias) is held constant over its interval [t, t + dt];
// readings that are the interval's mean (or its mid-point value) make the scheme
// second order in dt. w_ie = (0, 0, 7.2921151467e-5) rad/s (WGS 84).
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <string>

#include "ppp_bayes_tree/navigation/imu_bias.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/navigation/nav_state.h"

namespace ppp {

/// One mechanization step without checks: `state` is in ECEF (NavState's world =
/// ECEF), the readings are already bias-corrected, dt_s > 0.
NavState ecefInsStep(const NavState& state, const Eigen::Vector3d& specific_force_mps2,
                     const Eigen::Vector3d& angular_rate_radps, double dt_s);

/// What became of one reading given to EcefInsMechanization::propagate.
enum class InsStepStatus { Applied, NonPositiveInterval, IntervalTooLong, NonFiniteReading };
constexpr std::size_t kInsStepStatusCount = 4;
/// "applied", "interval not positive or not a number",
/// "interval too long", "reading not finite".
std::string insStepStatusText(InsStepStatus status);

class EcefInsMechanization {
 public:
  struct Options {
    /// Readings held longer than this are refused (a gap: the held-reading model
    /// no longer describes the motion) [s].
    double max_interval_s = 0.1;
  };

  EcefInsMechanization(const NavState& initial_ecef, const ImuBias& bias);
  EcefInsMechanization(const NavState& initial_ecef, const ImuBias& bias, const Options& options);

  /// Advances by dt_s with `sample` held over it, corrected by the bias. A refused
  /// reading leaves the state unchanged and is counted under its status.
  InsStepStatus propagate(const ImuSample& sample, double dt_s);

  const NavState& state() const { return state_; }
  const ImuBias& bias() const { return bias_; }
  void setState(const NavState& state_ecef) { state_ = state_ecef; }
  void setBias(const ImuBias& bias) { bias_ = bias; }
  /// Readings that ended with `status` (Applied counts the steps taken).
  std::size_t count(InsStepStatus status) const { return counts_[static_cast<std::size_t>(status)]; }

 private:
  InsStepStatus check(const ImuSample& sample, double dt_s) const;

  NavState state_;
  ImuBias bias_;
  Options options_;
  std::array<std::size_t, kInsStepStatusCount> counts_{};
};

}  // namespace ppp
