#include "ppp_bayes_tree/ppp/estimators/ins_odometry.h"

#include "ppp_bayes_tree/navigation/ins_mechanization.h"

namespace ppp {

void InsOdometry::restart(const InsState& state, const std::optional<ImuSample>& held,
                          const std::deque<ImuSample>& later) {
  state_ = state;
  held_ = held;
  if (held_) state_->angular_rate_radps = held_->angular_rate_radps - state_->bias.gyro_radps;
  for (const ImuSample& r : later)
    if (!advance(r)) break;
}

void InsOdometry::stop() {
  state_.reset();
  held_.reset();
}

std::optional<InsState> InsOdometry::step(const ImuSample& reading) {
  if (!state_ || reading.time - state_->time <= 0.0) return std::nullopt;
  if (!advance(reading)) return std::nullopt;
  return state_;
}

bool InsOdometry::advance(const ImuSample& reading) {
  // The held reading moves the state from its time to this reading's (the filter's model).
  const double dt_s = reading.time - state_->time;
  if (dt_s <= 0.0) return true;
  if (!held_ || dt_s > options_.max_imu_interval_s) {
    stop();
    return false;
  }
  const Eigen::Vector3d f_b = held_->specific_force_mps2 - state_->bias.accel_mps2;
  const Eigen::Vector3d w_b = held_->angular_rate_radps - state_->bias.gyro_radps;
  const InsDiscreteModel model =
      discretizeInsErrorModel(insErrorStateF(state_->nav, f_b, w_b, options_.bias_model), insErrorStateG(state_->nav),
                              insNoiseSpectralDensity(options_.noise, options_.bias_model), dt_s);
  state_->covariance = propagateInsCovariance(state_->covariance, model);
  state_->nav = ecefInsStep(state_->nav, f_b, w_b, dt_s);
  state_->time = reading.time;
  held_ = reading;
  state_->angular_rate_radps = reading.angular_rate_radps - state_->bias.gyro_radps;
  return true;
}

}  // namespace ppp
