#include "ppp_bayes_tree/ppp/epoch_estimator.h"

namespace ppp {

EkfEstimator::EkfEstimator(const PppConfig& config) : ekf_(config.stochastic, config.estimator, config.start) {}

EstimatorEpochResult EkfEstimator::processEpoch(const EstimatorEpochInput& input) {
  if (input.ended_arcs) arcsEnded(*input.ended_arcs);
  return ekf_.processEpoch(input.time, *input.evaluate);
}

void EkfEstimator::arcsEnded(const std::vector<EndedArc>& ended) {
  for (const auto& e : ended) ekf_.removeArc(e.arc);
}

std::unique_ptr<EpochEstimator> makeEstimator(const std::string& name, const PppConfig& config, std::string* why) {
  if (name == "ekf") return std::make_unique<EkfEstimator>(config);
  if (why) {
    *why = (name == "smoother" || name == "both")
               ? "estimator '" + name + "' is not yet available (only 'ekf' for now)"
               : "unknown estimator '" + name + "' (expected ekf; smoother and both are not yet available)";
  }
  return nullptr;
}

}  // namespace ppp
