#include "ppp_bayes_tree/ppp/model/stochastic_model.h"

#include <algorithm>
#include <cmath>

#include "ppp_bayes_tree/ppp/model/time_correlated_noise.h"

namespace ppp {

double StateNoise::processVariance_m2(double dt_s) const {
  const double dt = std::max(0.0, dt_s);
  const double q2dt = process_noise_m_per_sqrt_s * process_noise_m_per_sqrt_s * dt;
  if (kind == ProcessKind::White) return std::min(q2dt, initialVariance_m2());
  return q2dt;
}

StochasticModel methodTableStochasticModel() {
  StochasticModel m;
  m.position = {1.0, 5.0, ProcessKind::RandomWalk};
  m.zwd = {0.3, 3.0e-5, ProcessKind::RandomWalk};
  m.clock = {3.0e6, 2000.0, ProcessKind::White};
  m.phase_bias = {100.0, 0.0, ProcessKind::RandomWalk};
  m.initial_zwd_m = 0.1;
  return m;
}

double StochasticModel::codeVarianceFactor(double dt_s) const {
  return gaussMarkovVarianceFactor(dt_s, code_correlation_time_s);
}

double StochasticModel::zwdHeightVariance_m2(double dh_m) const {
  if (!std::isfinite(dh_m)) return 0.0;
  return zwd_per_sqrt_height_m_per_sqrt_m * zwd_per_sqrt_height_m_per_sqrt_m * std::abs(dh_m);
}

double StochasticModel::zwdHeightChangeBeyondNoise_m(double dh_m, double dh_sigma_m) const {
  if (!std::isfinite(dh_m) || !std::isfinite(dh_sigma_m)) return 0.0;
  return std::max(0.0, std::abs(dh_m) - zwd_height_change_threshold_sigmas * std::abs(dh_sigma_m));
}

std::string toString(ProcessKind kind) { return kind == ProcessKind::White ? "white" : "random_walk"; }

namespace {
std::string checkNoise(const std::string& name, const StateNoise& n) {
  if (!std::isfinite(n.initial_sigma_m) || n.initial_sigma_m <= 0.0)
    return name + ".initial_sigma_m must be a finite value > 0";
  if (!std::isfinite(n.process_noise_m_per_sqrt_s) || n.process_noise_m_per_sqrt_s < 0.0)
    return name + ".process_noise_m_per_sqrt_s must be a finite value >= 0";
  if (n.kind == ProcessKind::White && n.process_noise_m_per_sqrt_s <= 0.0)
    return name + ".process_noise_m_per_sqrt_s must be > 0 for a white state";
  return {};
}
}  // namespace

std::string StochasticModel::validate() const {
  for (const auto& [name, noise] : {std::pair<std::string, const StateNoise*>{"position", &position},
                                    {"zwd", &zwd}, {"clock", &clock}, {"phase_bias", &phase_bias},
                                    {"troposphere_gradient", &troposphere_gradient}}) {
    if (auto e = checkNoise(name, *noise); !e.empty()) return e;
  }
  if (!std::isfinite(initial_zwd_m)) return "zwd.initial_m must be finite";
  if (!std::isfinite(zwd_per_sqrt_height_m_per_sqrt_m) || zwd_per_sqrt_height_m_per_sqrt_m < 0.0)
    return "zwd.process_noise_m_per_sqrt_m_of_height must be a finite value >= 0";
  if (!std::isfinite(zwd_height_change_threshold_sigmas) || zwd_height_change_threshold_sigmas < 0.0)
    return "zwd.height_change_threshold_sigmas must be a finite value >= 0";
  if (!std::isfinite(code_correlation_time_s) || code_correlation_time_s < 0.0)
    return "code_correlation_time_s must be a finite value >= 0";
  return {};
}

}  // namespace ppp
