#include "ppp_bayes_tree/ppp/ppp_estimator_base.h"

#include <chrono>
#include <cmath>

#include "ppp_bayes_tree/ppp/postfit_screening.h"

namespace ppp {

PppEstimatorBase::PppEstimatorBase(StochasticModel model, ScreeningOptions screening,
                                   CodeLeastSquaresOptions start_options, ReceiverStateLayout layout)
    : model_(model), screening_(screening), start_options_(start_options), layout_(layout) {}

bool PppEstimatorBase::fail(EstimatorEpochResult& result, EpochStatus status, NoSolutionReason why, std::string text) {
  result.status = status;
  result.no_solution_reason = why;
  result.reason = std::move(text);
  result.solution.reset();
  return false;
}

void PppEstimatorBase::removeArc(ArcId arc) {
  arcs_.erase(arc);
  arcRemoved(arc);
}

EstimatorEpochResult PppEstimatorBase::processEpoch(const GnssTime& time, const MeasurementFunction& evaluate,
                                                    const MeasurementFunction* evaluate_start) {
  const auto t_start = std::chrono::steady_clock::now();
  EstimatorEpochResult result;
  result.time = time;
  auto finish = [&]() {
    result.active_biases = biasCount();
    finishEpoch(result);
    result.epoch_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    return result;
  };

  // 1. Start from the code least squares, or check that time advances.
  std::optional<ReceiverState> start;
  double dt = 0.0;
  bool first = true;
  if (!hasState()) {
    ReceiverState s(layout_);
    s.position_ecef_m = approx_position_ecef_m_.value_or(Eigen::Vector3d::Zero());
    s.zwd_m = model_.initial_zwd_m;
    if (!approx_position_ecef_m_ && evaluate_start != nullptr) {
      // No approximate position: the start model from the Earth centre gives one.
      const CodeLeastSquaresResult coarse = codeLeastSquares(*evaluate_start, s, start_options_);
      result.iterations += coarse.iterations;
      if (!coarse.ok) {
        result.rejected = coarse.rejected;
        fail(result, EpochStatus::NoSolution, NoSolutionReason::NoInitialPosition,
             "no initial position: no approximate position, start model from the Earth centre: " + coarse.reason);
        return finish();
      }
      s.position_ecef_m = coarse.state.position_ecef_m;
      for (const GnssSystem system : layout_.clockSystems()) s.setClock_m(system, coarse.state.clock_m(system));
    }
    const CodeLeastSquaresResult ls = codeLeastSquares(evaluate, s, start_options_);
    result.iterations += ls.iterations;
    if (!ls.ok) {
      result.rejected = ls.rejected;
      fail(result, EpochStatus::NoSolution, NoSolutionReason::NoInitialPosition, "no initial position: " + ls.reason);
      return finish();
    }
    start = ls.state;
  } else {
    const GnssTime last = *lastSolvedTime();
    dt = time - last;
    result.dt_s = dt;
    first = startsAt(time) && dt == 0.0;
    if (!(std::isfinite(dt) && dt > 0.0) && !first) {
      fail(result, EpochStatus::Failed, NoSolutionReason::EpochNotAfterLastSolved,
           "epoch " + time.toString() + " is not after the last solved epoch " + last.toString());
      return finish();
    }
  }

  // 2-3. Prediction; linearise once there; usable measurements; white clock shifts.
  EpochSolveInput in;
  in.time = time;
  in.dt_s = dt;
  in.first = first;
  in.evaluate = &evaluate;
  in.predicted = predict(dt, first, start);
  const EpochMeasurements epoch0 = evaluate(in.predicted);
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
        in.predicted.setClock_m(system, in.predicted.clock_m(system) + *shift);
        applyClockShift(cand, layout_, system, *shift);
      }
    }
  }

  // 4. Arc bookkeeping on a copy: a new arc of a satellite replaces its bias; stale arcs go.
  std::map<ArcId, ActiveArc> arcs = arcs_;
  for (const auto& m : cand) {
    for (auto it = arcs.begin(); it != arcs.end(); ++it) {
      if (it->second.satellite == m.satellite && it->first != m.arc) {
        in.dropped_arcs.push_back(it->first);
        arcs.erase(it);
        break;
      }
    }
  }
  for (auto it = arcs.begin(); it != arcs.end();) {
    if (time - it->second.last_used > screening_.stale_arc_timeout_s) {
      in.dropped_arcs.push_back(it->first);
      it = arcs.erase(it);
    } else {
      ++it;
    }
  }

  // 5. Prefit screening against the estimator's bias priors.
  PrefitScreeningResult screening =
      screenPrefit(cand, screening_, [&](ArcId arc) -> std::optional<ArcBiasPrior> {
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
    return finish();
  }

  // 6. New arcs: initial bias from phase minus code.
  in.screened.reserve(screening.kept.size());
  for (auto& m : screening.kept) {
    ScreenedMeasurement s;
    s.active_arc = arcs.count(m.arc) > 0;
    s.new_arc_bias_m = m.phaseResidualWithoutBias_m() - m.codeResidual_m();
    s.m = std::move(m);
    in.screened.push_back(std::move(s));
  }

  // 7. The estimator's update.
  EpochSolveOutput out;
  if (!solve(in, out, result)) {
    if (result.status == EpochStatus::Failed && recoverAfterFailure(result)) {
      result.estimator_reset = true;
      ++resets_;
    }
    return finish();
  }

  // 8. Commit the active set; residual records.
  for (const auto& row : out.rows) arcs[row.m.arc] = ActiveArc{row.m.satellite, time};
  arcs_ = std::move(arcs);
  result.status = EpochStatus::Ok;
  result.no_solution_reason = NoSolutionReason::None;
  result.reason.clear();
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

  // 9. Epoch consistency test of the postfit residuals (postfit_screening.h): an
  // inconsistent solution is flagged, and inflated or withheld.
  if (screening_.consistency_check) {
    std::vector<PostfitResidualPair> pairs;
    pairs.reserve(result.residuals.size());
    for (const auto& r : result.residuals)
      pairs.push_back({r.code_postfit_m, r.phase_postfit_m, r.code_sigma_m, r.phase_sigma_m});
    const ConsistencyTest test = postfitConsistency(pairs, screening_.consistency_false_alarm);
    result.consistency_statistic = test.statistic;
    result.consistency_dof = test.dof;
    result.consistency = test.describe(screening_.consistency_false_alarm);
    if (test.consistent()) {
      result.integrity = SolutionIntegrity::Consistent;
    } else {
      result.integrity = SolutionIntegrity::Inconsistent;
      if (screening_.consistency_action == ConsistencyAction::Withhold) {
        fail(result, EpochStatus::NoSolution, NoSolutionReason::InconsistentSolution,
             "solution withheld: " + result.consistency);
      } else {
        result.consistency_variance_factor = test.varianceFactor();
        result.solution->covariance *= result.consistency_variance_factor;
      }
    }
  }
  return finish();
}

}  // namespace ppp
