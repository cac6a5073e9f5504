#include "ppp_bayes_tree/navigation/ins_mechanization.h"

#include <Eigen/LU>
#include <cmath>

#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

const Eigen::Vector3d kEarthRateEcef_radps(0.0, 0.0, kEarthRotationRate_radps);

/// R+ = Exp(-w_ie dt) R- Exp(w_ib dt): the body turns by w_ib in inertial space while
/// the Earth-fixed frame turns by w_ie.
Eigen::Matrix3d attitudeUpdate(const Eigen::Matrix3d& rotation_ecef_body, const Eigen::Vector3d& angular_rate_radps,
                               double dt_s) {
  return so3::expMap(-kEarthRateEcef_radps * dt_s) * rotation_ecef_body * so3::expMap(angular_rate_radps * dt_s);
}

/// v+ from (I + [w_ie]x dt) v+ = (I - [w_ie]x dt) v- + (f_e + g) dt.
Eigen::Vector3d velocityUpdate(const Eigen::Vector3d& velocity_mps, const Eigen::Vector3d& acceleration_mps2,
                               double dt_s) {
  const Eigen::Matrix3d coriolis = so3::hat(kEarthRateEcef_radps) * dt_s;
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  return (identity + coriolis).inverse() * ((identity - coriolis) * velocity_mps + acceleration_mps2 * dt_s);
}

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

}  // namespace

NavState ecefInsStep(const NavState& state, const Eigen::Vector3d& specific_force_mps2,
                     const Eigen::Vector3d& angular_rate_radps, double dt_s) {
  NavState next;
  next.rotation_world_body = attitudeUpdate(state.rotation_world_body, angular_rate_radps, dt_s);
  const Eigen::Vector3d force_ecef_mps2 =
      0.5 * (state.rotation_world_body + next.rotation_world_body) * specific_force_mps2;
  const Eigen::Vector3d mid_position_m = state.position_world_m + 0.5 * dt_s * state.velocity_world_mps;
  const Eigen::Vector3d gravity_mps2 = ecefNavigationFrame(mid_position_m).gravity_world_mps2;
  next.velocity_world_mps = velocityUpdate(state.velocity_world_mps, force_ecef_mps2 + gravity_mps2, dt_s);
  next.position_world_m = state.position_world_m + 0.5 * dt_s * (state.velocity_world_mps + next.velocity_world_mps);
  return next;
}

std::string insStepStatusText(InsStepStatus status) {
  switch (status) {
    case InsStepStatus::Applied: return "applied";
    case InsStepStatus::NonPositiveInterval: return "interval not positive or not a number";
    case InsStepStatus::IntervalTooLong: return "interval too long";
    case InsStepStatus::NonFiniteReading: return "reading not finite";
  }
  return "unknown status";
}

EcefInsMechanization::EcefInsMechanization(const NavState& initial_ecef, const ImuBias& bias)
    : EcefInsMechanization(initial_ecef, bias, Options{}) {}

EcefInsMechanization::EcefInsMechanization(const NavState& initial_ecef, const ImuBias& bias, const Options& options)
    : state_(initial_ecef), bias_(bias), options_(options) {}

InsStepStatus EcefInsMechanization::check(const ImuSample& sample, double dt_s) const {
  if (!std::isfinite(dt_s) || dt_s <= 0.0) return InsStepStatus::NonPositiveInterval;
  if (dt_s > options_.max_interval_s) return InsStepStatus::IntervalTooLong;
  if (!finite(sample.specific_force_mps2) || !finite(sample.angular_rate_radps)) {
    return InsStepStatus::NonFiniteReading;
  }
  return InsStepStatus::Applied;
}

InsStepStatus EcefInsMechanization::propagate(const ImuSample& sample, double dt_s) {
  const InsStepStatus status = check(sample, dt_s);
  ++counts_[static_cast<std::size_t>(status)];
  if (status != InsStepStatus::Applied) return status;
  state_ = ecefInsStep(state_, sample.specific_force_mps2 - bias_.accel_mps2,
                       sample.angular_rate_radps - bias_.gyro_radps, dt_s);
  return status;
}

}  // namespace ppp
