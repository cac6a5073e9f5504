#include "ppp_bayes_tree/ppp/estimators/ppp_estimator.h"

#include <chrono>
#include <cmath>

#include "ppp_bayes_tree/ppp/screening/postfit_screening.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {

PppEstimator::PppEstimator(StochasticModel model, ScreeningOptions screening, CodeLeastSquaresOptions start_options,
                           ReceiverStateLayout layout, AmbiguityResolutionOptions ambiguity_resolution)
    : model_(model),
      screening_(screening),
      start_options_(start_options),
      layout_(layout),
      ambiguity_(std::move(ambiguity_resolution)) {}

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

EstimatorEpochResult PppEstimator::processEpoch(const EstimatorEpochInput& input) {
  if (input.ended_arcs) arcsEnded(*input.ended_arcs);
  bridged_.clear();
  if (input.bridged_arcs) bridged_ = *input.bridged_arcs;
  bridged_arc_changes_ = input.bridged_arc_changes;
  receiveEpochInput(input);
  last_ = processEpoch(input.time, *input.evaluate, input.evaluate_start);
  // An epoch that stopped before the bridged arcs were tested ends them (never carried unverified).
  for (const BridgedArc& b : bridged_) endBridgedArc(b, "the epoch stopped before the slip test", last_);
  bridged_.clear();
  bridged_arc_changes_ = nullptr;
  if (ambiguity_.options().enabled && !floatWithoutPhaseBiases(input, last_)) resolveAmbiguities(input, last_);
  return last_;
}

void PppEstimator::arcsEnded(const std::vector<EndedArc>& ended) {
  for (const auto& e : ended) removeArc(e.arc);
  ambiguity_.arcsEnded(ended);
}

void PppEstimator::verifyBridgedArcs(const std::vector<BridgedArc>& bridged,
                                     const std::vector<SatelliteMeasurement>& /*usable*/, EstimatorEpochResult& result) {
  for (const BridgedArc& b : bridged) endBridgedArc(b, "the estimator bridges no gap", result);
}

void PppEstimator::endBridgedArc(const BridgedArc& bridged, const std::string& reason, EstimatorEpochResult& result) {
  EndedArc ended;
  ended.satellite = bridged.satellite;
  ended.arc = bridged.arc;
  ended.reason = "gap of " + format("%.0f", bridged.gap_s) + " s not bridged: " + reason;
  if (bridged.repair) ended.reason += " (slip repair " + bridged.repair->text + " refused)";
  removeArc(bridged.arc);
  ambiguity_.arcsEnded({ended});
  ++result.bridged_arcs_ended;
  if (bridged.repair) ++result.repaired_arcs_ended;
  std::string line = bridged.satellite.toString() + " arc " + std::to_string(bridged.arc) + ": " + ended.reason;
  // The satellite's phases from now on are a new arc's (none of this one's state taken up again).
  if (bridged_arc_changes_) {
    if (const std::optional<ArcId> renewed = bridged_arc_changes_->restartArc(bridged, ended.reason)) {
      line += "; new arc " + std::to_string(*renewed);
      arcs_changed_ = true;
    }
  }
  result.gap_bridge.push_back(line);
}

bool PppEstimator::chooseRepairCandidate(const BridgedArc& bridged, const SlipCandidate& candidate,
                                         EstimatorEpochResult& result) {
  if (!bridged_arc_changes_ || !bridged_arc_changes_->chooseRepairCandidate(bridged, candidate)) return false;
  ++result.repair_candidates_chosen;
  arcs_changed_ = true;
  return true;
}

bool PppEstimator::fail(EstimatorEpochResult& result, EpochStatus status, NoSolutionReason why, std::string text) {
  result.status = status;
  result.no_solution_reason = why;
  result.reason = std::move(text);
  result.solution.reset();
  return false;
}

void PppEstimator::removeArc(ArcId arc) {
  arcs_.erase(arc);
  arcRemoved(arc);
}

EstimatorEpochResult PppEstimator::processEpoch(const GnssTime& time, const MeasurementFunction& evaluate,
                                                    const MeasurementFunction* evaluate_start) {
  const auto t_start = std::chrono::steady_clock::now();
  EstimatorEpochResult result;
  result.time = time;
  EpochSolveInput in;
  in.time = time;
  in.evaluate = &evaluate;

  // 1. Start from the code least squares, or check that time advances.
  std::optional<ReceiverState> start;
  if (!startOrAdvance(evaluate, evaluate_start, in, start, result)) return finished(std::move(result), t_start);

  // 2. The estimator's prediction.
  in.predicted = predict(in.dt_s, in.first, start);

  // 3. Linearise once at the prediction; usable measurements; white clock shifts.
  std::vector<SatelliteMeasurement> usable = lineariseAtPrediction(evaluate, in.predicted, result);
  if (!bridged_.empty()) {
    arcs_changed_ = false;
    verifyBridgedArcs(bridged_, usable, result);
    // Another slip candidate applied to an arc's phases, or an arc restarted: the measurements again.
    if (arcs_changed_) usable = lineariseAtPrediction(evaluate, in.predicted, result);
    arcs_changed_ = false;
  }
  bridged_.clear();

  // 4. Arc bookkeeping on a copy of the active set.
  std::map<ArcId, ActiveArc> arcs = bookArcs(usable, time, in.dropped_arcs);

  // 5. Prefit screening against the estimator's bias priors.
  std::optional<std::vector<SatelliteMeasurement>> kept = screenAgainstPriors(usable, arcs, result);
  if (!kept) return finished(std::move(result), t_start);

  // 6. New arcs: initial bias from phase minus code.
  in.screened = withInitialBiases(std::move(*kept), arcs);

  // 7. The estimator's update (a restart from the last good state after a failure).
  EpochSolveOutput out;
  if (!solveOrRecover(in, out, result)) return finished(std::move(result), t_start);

  // 8. Commit the active set; residual records.
  commitEpoch(in, std::move(out), std::move(arcs), result);

  // 9. Epoch consistency test of the postfit residuals.
  if (screening_.consistency_check) testConsistency(result);
  return finished(std::move(result), t_start);
}

EstimatorEpochResult PppEstimator::finished(EstimatorEpochResult result,
                                                std::chrono::steady_clock::time_point t_start) const {
  result.active_biases = biasCount();
  finishEpoch(result);
  result.epoch_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return result;
}

// Step 1
bool PppEstimator::startOrAdvance(const MeasurementFunction& evaluate, const MeasurementFunction* evaluate_start,
                                      EpochSolveInput& in, std::optional<ReceiverState>& start,
                                      EstimatorEpochResult& result) const {
  in.dt_s = 0.0;
  in.first = true;
  if (hasState()) {
    const GnssTime last = *lastSolvedTime();
    in.dt_s = in.time - last;
    result.dt_s = in.dt_s;
    in.first = startsAt(in.time) && in.dt_s == 0.0;
    if (!(std::isfinite(in.dt_s) && in.dt_s > 0.0) && !in.first)
      return fail(result, EpochStatus::Failed, NoSolutionReason::EpochNotAfterLastSolved,
                  "epoch " + in.time.toString() + " is not after the last solved epoch " + last.toString());
    return true;
  }
  ReceiverState s(layout_);
  s.position_ecef_m = approx_position_ecef_m_.value_or(Eigen::Vector3d::Zero());
  s.zwd_m = model_.initial_zwd_m;
  if (!approx_position_ecef_m_ && evaluate_start != nullptr) {
    // No approximate position: the start model from the Earth centre gives one.
    const CodeLeastSquaresResult coarse = codeLeastSquares(*evaluate_start, s, start_options_);
    result.iterations += coarse.iterations;
    if (!coarse.ok) {
      result.rejected = coarse.rejected;
      return fail(result, EpochStatus::NoSolution, NoSolutionReason::NoInitialPosition,
                  "no initial position: no approximate position, start model from the Earth centre: " + coarse.reason);
    }
    s.position_ecef_m = coarse.state.position_ecef_m;
    for (const GnssSystem system : layout_.clockSystems()) s.setClock_m(system, coarse.state.clock_m(system));
  }
  const CodeLeastSquaresResult ls = codeLeastSquares(evaluate, s, start_options_);
  result.iterations += ls.iterations;
  if (!ls.ok) {
    result.rejected = ls.rejected;
    return fail(result, EpochStatus::NoSolution, NoSolutionReason::NoInitialPosition,
                "no initial position: " + ls.reason);
  }
  start = ls.state;
  return true;
}

// Step 3
std::vector<SatelliteMeasurement> PppEstimator::lineariseAtPrediction(const MeasurementFunction& evaluate,
                                                                          ReceiverState& predicted,
                                                                          EstimatorEpochResult& result) const {
  const EpochMeasurements epoch0 = evaluate(predicted);
  result.iterations += 1;
  result.rejected = epoch0.rejected;
  std::vector<SatelliteMeasurement> cand = usableMeasurements(epoch0.used, result.rejected);
  for (auto it = cand.begin(); it != cand.end();) {
    if (matchesLayout(*it, layout_)) {
      ++it;
      continue;
    }
    result.rejected.push_back({it->satellite, RejectionReason::NoReceiverClock,
                               "Jacobian outside the receiver state layout (no clock for the system)"});
    it = cand.erase(it);
  }
  if (screening_.clock_from_code_median) {
    for (const GnssSystem system : layout_.clockSystems()) {
      if (const auto shift = medianCodeClockShift_m(cand, layout_, system)) {
        predicted.setClock_m(system, predicted.clock_m(system) + *shift);
        applyClockShift(cand, layout_, system, *shift);
      }
    }
  }
  return cand;
}

// Step 4
std::map<ArcId, PppEstimator::ActiveArc> PppEstimator::bookArcs(
    const std::vector<SatelliteMeasurement>& usable, const GnssTime& time, std::vector<ArcId>& dropped_arcs) const {
  std::map<ArcId, ActiveArc> arcs = arcs_;
  // A new arc of a satellite replaces its bias.
  for (const auto& m : usable) {
    for (auto it = arcs.begin(); it != arcs.end(); ++it) {
      if (it->second.satellite == m.satellite && it->first != m.arc) {
        dropped_arcs.push_back(it->first);
        arcs.erase(it);
        break;
      }
    }
  }
  // Stale arcs go.
  for (auto it = arcs.begin(); it != arcs.end();) {
    if (time - it->second.last_used > screening_.stale_arc_timeout_s) {
      dropped_arcs.push_back(it->first);
      it = arcs.erase(it);
    } else {
      ++it;
    }
  }
  return arcs;
}

// Step 5
std::optional<std::vector<SatelliteMeasurement>> PppEstimator::screenAgainstPriors(
    const std::vector<SatelliteMeasurement>& usable, const std::map<ArcId, ActiveArc>& arcs,
    EstimatorEpochResult& result) const {
  PrefitScreeningResult screening =
      screenPrefit(usable, screening_, [&](ArcId arc) -> std::optional<ArcBiasPrior> {
        if (!arcs.count(arc)) return std::nullopt;
        return predictedBias(arc);
      },
      layout_);
  result.prefit_rejections += static_cast<int>(screening.rejected.size());
  result.rejected.insert(result.rejected.end(), screening.rejected.begin(), screening.rejected.end());
  const int n_sat = static_cast<int>(screening.kept.size());
  if (n_sat < screening_.min_satellites) {
    fail(result, EpochStatus::NoSolution, NoSolutionReason::TooFewSatellites,
         std::to_string(n_sat) + " satellites usable after screening, at least " +
             std::to_string(screening_.min_satellites) + " needed");
    return std::nullopt;
  }
  return std::move(screening.kept);
}

// Step 6
std::vector<PppEstimator::ScreenedMeasurement> PppEstimator::withInitialBiases(
    std::vector<SatelliteMeasurement> kept, const std::map<ArcId, ActiveArc>& arcs) {
  std::vector<ScreenedMeasurement> screened;
  screened.reserve(kept.size());
  for (auto& m : kept) {
    ScreenedMeasurement s;
    s.active_arc = arcs.count(m.arc) > 0;
    s.new_arc_bias_m = m.phaseResidualWithoutBias_m() - m.codeResidual_m();
    s.m = std::move(m);
    screened.push_back(std::move(s));
  }
  return screened;
}

// Step 7
bool PppEstimator::solveOrRecover(const EpochSolveInput& in, EpochSolveOutput& out, EstimatorEpochResult& result) {
  if (solve(in, out, result)) return true;
  if (result.status == EpochStatus::Failed && recoverAfterFailure(result)) {
    result.estimator_reset = true;
    ++resets_;
  }
  return false;
}

// Step 8
void PppEstimator::commitEpoch(const EpochSolveInput& in, EpochSolveOutput out, std::map<ArcId, ActiveArc> arcs,
                                   EstimatorEpochResult& result) {
  for (const auto& row : out.rows) arcs[row.m.arc] = ActiveArc{row.m.satellite, in.time};
  arcs_ = std::move(arcs);
  result.status = EpochStatus::Ok;
  result.no_solution_reason = NoSolutionReason::None;
  result.reason.clear();
  keepSolvedHeight(in.time, out.solution, in.first);
  result.solution = std::move(out.solution);
  result.ambiguities = out.ambiguities;
  for (const auto& row : out.rows) {
    result.used.push_back(row.m.satellite);
    MeasurementResidual r;
    r.satellite = row.m.satellite;
    r.arc = row.m.arc;
    r.new_arc = row.new_arc;
    r.elevation_rad = row.m.elevation_rad;
    r.azimuth_rad = row.m.azimuth_rad;
    r.code_prefit_m = in.screened[row.screened_index].m.codeResidual_m();
    r.phase_prefit_m = row.phase_prefit_m;
    r.code_postfit_m = row.code_postfit_m;
    r.phase_postfit_m = row.phase_postfit_m;
    r.code_sigma_m = row.m.code_sigma_m;
    r.phase_sigma_m = row.m.phase_sigma_m;
    result.residuals.push_back(r);
  }
}

double PppEstimator::zwdProcessVariance_m2(double dt_s) const {
  const double in_time = model_.zwd.processVariance_m2(dt_s);
  if (!(model_.zwd_per_sqrt_height_m_per_sqrt_m > 0.0)) return in_time;  // off: no geodetic conversions
  return in_time + model_.zwdHeightVariance_m2(expectedHeightChange_m(dt_s));
}

void PppEstimator::keepSolvedHeight(const GnssTime& time, const EpochSolution& solution, bool first) {
  if (first) solved_heights_.clear();
  if (!(model_.zwd_per_sqrt_height_m_per_sqrt_m > 0.0)) return;  // off: no geodetic conversions
  const Geodetic g = ecefToGeodetic(solution.state.position_ecef_m);
  const Eigen::Vector3d up = rotationEnuFromEcef(g.latitude_rad, g.longitude_rad).row(2).transpose();
  solved_heights_.push_back(SolvedHeight{time, g.height_m, up.dot(solution.positionCovariance_m2() * up)});
  // The heights within the window, at least the last two.
  while (solved_heights_.size() > 2 && time - solved_heights_.front().time > kHeightRateWindow_s)
    solved_heights_.pop_front();
}

double PppEstimator::expectedHeightChange_m(double dt_s) const {
  if (solved_heights_.size() < 2 || !(dt_s > 0.0)) return 0.0;
  // The oldest height within the window, or the previous one when it is further back.
  const SolvedHeight& from = solved_heights_.front();
  const SolvedHeight& last = solved_heights_.back();
  const double span_s = last.time - from.time;
  if (!(span_s > 0.0)) return 0.0;
  const double dh_m = model_.zwdHeightChangeBeyondNoise_m(last.height_m - from.height_m,
                                                          std::sqrt(last.variance_m2 + from.variance_m2));
  return dh_m * dt_s / span_s;
}

// Step 9 (postfit_screening.h): an inconsistent solution is flagged, and inflated or withheld.
void PppEstimator::testConsistency(EstimatorEpochResult& result) const {
  std::vector<PostfitResidualPair> pairs;
  pairs.reserve(result.residuals.size());
  for (const auto& r : result.residuals)
    pairs.push_back({r.code_postfit_m, r.phase_postfit_m, r.code_sigma_m, r.phase_sigma_m});
  const double alpha = screening_.consistency_false_alarm;
  if (!consistency_quantile_ || !(consistency_quantile_->alpha() == alpha)) consistency_quantile_.emplace(alpha);
  const ConsistencyTest test = postfitConsistency(pairs, *consistency_quantile_);
  result.consistency_statistic = test.statistic;
  result.consistency_dof = test.dof;
  result.consistency = test.describe(screening_.consistency_false_alarm);
  if (test.consistent()) {
    result.integrity = SolutionIntegrity::Consistent;
    return;
  }
  result.integrity = SolutionIntegrity::Inconsistent;
  if (screening_.consistency_action == ConsistencyAction::Withhold) {
    fail(result, EpochStatus::NoSolution, NoSolutionReason::InconsistentSolution,
         "solution withheld: " + result.consistency);
  } else {
    result.consistency_variance_factor = test.varianceFactor();
    result.solution->covariance *= result.consistency_variance_factor;
  }
}

}  // namespace ppp
