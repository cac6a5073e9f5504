#include "ppp_bayes_tree/ppp/epoch_estimator.h"

namespace ppp {

EkfEstimator::EkfEstimator(const PppConfig& config)
    : ekf_(config.stochastic, config.estimator, config.start, ReceiverStateLayout(config.signals.systems)) {}

EstimatorEpochResult EkfEstimator::processEpoch(const EstimatorEpochInput& input) {
  if (input.ended_arcs) arcsEnded(*input.ended_arcs);
  return ekf_.processEpoch(input.time, *input.evaluate);
}

void EkfEstimator::arcsEnded(const std::vector<EndedArc>& ended) {
  for (const auto& e : ended) ekf_.removeArc(e.arc);
}

SmootherEstimator::SmootherEstimator(const PppConfig& config)
    : smoother_(config.stochastic, config.smoother, config.start, ReceiverStateLayout(config.signals.systems)) {}

EstimatorEpochResult SmootherEstimator::processEpoch(const EstimatorEpochInput& input) {
  if (input.ended_arcs) arcsEnded(*input.ended_arcs);
  last_ = smoother_.processEpoch(input.time, *input.evaluate);
  return last_;
}

void SmootherEstimator::arcsEnded(const std::vector<EndedArc>& ended) {
  for (const auto& e : ended) smoother_.removeArc(e.arc);
}

std::unique_ptr<EpochEstimator> makeEstimator(const std::string& name, const PppConfig& config, std::string* why) {
  if (name == "ekf") return std::make_unique<EkfEstimator>(config);
  if (name == "smoother") return std::make_unique<SmootherEstimator>(config);
  if (why) {
    *why = name == "both" ? "estimator 'both' is run by the caller as 'ekf' and 'smoother' (one pipeline each)"
                          : "unknown estimator '" + name + "' (expected ekf or smoother)";
  }
  return nullptr;
}

}  // namespace ppp
