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

SmootherEstimator::SmootherEstimator(const PppConfig& config)
    : smoother_(config.stochastic, config.smoother, config.start) {}

EstimatorEpochResult SmootherEstimator::processEpoch(const EstimatorEpochInput& input) {
  if (input.ended_arcs) arcsEnded(*input.ended_arcs);
  last_ = smoother_.processEpoch(input.time, *input.evaluate);
  return toEstimatorEpochResult(last_);
}

void SmootherEstimator::arcsEnded(const std::vector<EndedArc>& ended) {
  for (const auto& e : ended) smoother_.removeArc(e.arc);
}

EstimatorEpochResult toEstimatorEpochResult(const SmootherEpochResult& r) {
  EstimatorEpochResult e;
  e.time = r.time;
  e.status = r.status;
  e.reason = r.reason;
  e.solution = r.solution;
  e.dt_s = r.dt_s;
  e.used = r.used;
  e.rejected = r.rejected;
  e.prefit_rejections = r.prefit_rejections;
  e.active_biases = r.active_biases;
  e.iterations = r.iterations;
  e.residuals = r.residuals;
  return e;
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
