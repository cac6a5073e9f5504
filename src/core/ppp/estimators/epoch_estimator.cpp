#include "ppp_bayes_tree/ppp/estimators/epoch_estimator.h"

#include <algorithm>

#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"

namespace ppp {

EkfEstimator::EkfEstimator(const EstimatorOptions& options)
    : ekf_(options.stochastic, options.ekf, options.start, ReceiverStateLayout(options.systems, options.troposphere_gradients)),
      ambiguity_(options.ambiguity_resolution) {}

namespace {

/// Without phase biases nothing can be fixed: the epoch stays float with that
/// reason, without the resolver's work (a streamed run resolves from the start
/// and gets its phase biases later, product_assembly.h).
bool floatWithoutPhaseBiases(const EstimatorEpochInput& input, EstimatorEpochResult& r) {
  if (input.phase_biases) return false;
  AmbiguityFixSummary summary;
  summary.float_reason = AmbiguityFloatReason::NoConsistentPhaseBiases;
  r.ambiguity_fix = summary;
  return true;
}

}  // namespace

EstimatorEpochResult EkfEstimator::processEpoch(const EstimatorEpochInput& input) {
  if (input.ended_arcs) arcsEnded(*input.ended_arcs);
  last_ = ekf_.processEpoch(input.time, *input.evaluate, input.evaluate_start);
  if (ambiguity_.options().enabled && !floatWithoutPhaseBiases(input, last_)) resolveAmbiguities(input, last_);
  return last_;
}

void EkfEstimator::resolveAmbiguities(const EstimatorEpochInput& input, EstimatorEpochResult& r) {
  // The filter stays float; the fixed solution is a constrained copy of it,
  // conditioned on the integers validated across epochs and held.
  if (r.estimator_reset) ambiguity_.releaseAll();
  if (input.observations && input.arcs) ambiguity_.addEpoch(*input.observations, *input.arcs, input.phase_biases);
  AmbiguityFixSummary summary;
  if (r.status == EpochStatus::Ok && r.solution) {
    const std::vector<ArcId> arcs = ekf_.activeArcs();
    const int receiver_dim = r.solution->state.layout.dim();
    std::map<ArcId, double> elevation_rad;
    for (const auto& res : r.residuals) elevation_rad[res.arc] = res.elevation_rad;
    const auto fixed = ambiguity_.resolveAndHold(ekf_.stateVector(), ekf_.covarianceMatrix(), receiver_dim, arcs,
                                                 input.phase_biases, summary, &elevation_rad);
    if (fixed) {
      r.solution->state = ReceiverState::fromVector(fixed->x.head(receiver_dim), r.solution->state.layout);
      r.solution->covariance = fixed->P.topLeftCorner(receiver_dim, receiver_dim);
      r.ambiguities = AmbiguityState::Fixed;
    }
  }
  r.ambiguity_fix = summary;
}

void EkfEstimator::arcsEnded(const std::vector<EndedArc>& ended) {
  for (const auto& e : ended) ekf_.removeArc(e.arc);
  ambiguity_.arcsEnded(ended);
}

SmootherEstimator::SmootherEstimator(const EstimatorOptions& options)
    : smoother_(options.stochastic, options.smoother, options.start, ReceiverStateLayout(options.systems, options.troposphere_gradients)),
      ambiguity_(options.ambiguity_resolution) {}

EstimatorEpochResult SmootherEstimator::processEpoch(const EstimatorEpochInput& input) {
  if (input.ended_arcs) arcsEnded(*input.ended_arcs);
  last_ = smoother_.processEpoch(input.time, *input.evaluate, input.evaluate_start);
  if (ambiguity_.options().enabled && !floatWithoutPhaseBiases(input, last_)) resolveAmbiguities(input, last_);
  return last_;
}

void SmootherEstimator::resolveAmbiguities(const EstimatorEpochInput& input, EstimatorEpochResult& r) {
  // The EKF's decision path (resolveAndHold) on the smoother's float joint; the
  // held integers are factors of the graph, a wrong one released is removed.
  if (r.estimator_reset) ambiguity_.releaseAll();  // a restart drops the graph's fixes
  if (input.observations && input.arcs) ambiguity_.addEpoch(*input.observations, *input.arcs, input.phase_biases);
  AmbiguityFixSummary summary;
  if (r.status == EpochStatus::Ok && r.solution) {
    bool changed = false;
    try {
      const std::optional<PppSmoother::FilteredJoint> joint = smoother_.floatJoint();
      if (!joint) {
        summary.float_reason = AmbiguityFloatReason::NumericalFailure;
      } else {
        const int receiver_dim = r.solution->state.layout.dim();
        std::map<ArcId, double> elevation_rad;
        for (const auto& res : r.residuals) elevation_rad[res.arc] = res.elevation_rad;
        const auto fixed = ambiguity_.resolveAndHold(joint->x, joint->P, receiver_dim, joint->arcs,
                                                     input.phase_biases, summary, &elevation_rad);
        std::vector<std::pair<ArcId, ArcId>> wrong;
        for (const AmbiguityRelease& rel : summary.released)
          if (rel.reason != AmbiguityReleaseReason::ArcEnded) wrong.emplace_back(rel.arc, rel.reference_arc);
        // Removals and additions in one graph update.
        const Eigen::MatrixXd none(0, joint->x.size());
        const PppSmoother::FixChanges c =
            smoother_.updateFixes(wrong, fixed ? fixed->constraint_rows : none,
                                  fixed ? fixed->constraint_values : Eigen::VectorXd(0));
        changed = c.removed > 0 || c.added > 0;
      }
    } catch (const std::exception& e) {
      summary.float_reason = AmbiguityFloatReason::NumericalFailure;
      r.reason += std::string("; ambiguity fix not applied: ") + e.what();
    }
    if (changed) {
      r.solution->state = smoother_.filteredSolution().state;
      r.solution->covariance = smoother_.filteredSolution().covariance;
    }
    if (summary.fixed()) r.ambiguities = AmbiguityState::Fixed;
  }
  r.ambiguity_fix = summary;
}

void SmootherEstimator::arcsEnded(const std::vector<EndedArc>& ended) {
  for (const auto& e : ended) smoother_.removeArc(e.arc);
  ambiguity_.arcsEnded(ended);
}

std::unique_ptr<EpochEstimator> makeEkfEstimator(const EstimatorOptions& options) {
  return std::make_unique<EkfEstimator>(options);
}

std::unique_ptr<EpochEstimator> makeSmootherEstimator(const EstimatorOptions& options) {
  return std::make_unique<SmootherEstimator>(options);
}

std::unique_ptr<EpochEstimator> makeEstimator(const std::string& name, const EstimatorOptions& options, std::string* why) {
  if (const EstimatorEntry* e = findEstimator(name)) return e->make(options);
  if (why) {
    *why = name == kAllEstimators ? "estimator '" + name + "' is run by the caller as " +
                                        registeredEstimatorNames(" and ") + " (one pipeline each)"
                                  : "unknown estimator '" + name + "' (expected " +
                                        registeredEstimatorNames(" or ") + ")";
  }
  return nullptr;
}

}  // namespace ppp
