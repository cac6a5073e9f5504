#include "ppp_bayes_tree/ppp/ppp_smoother.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "ppp_bayes_tree/ppp/ppp_factors.h"
#include "ppp_bayes_tree/ppp/prefit_screening.h"
#include "ppp_bayes_tree/smoother/batch_solver.h"
#include "ppp_bayes_tree/smoother/elimination.h"
#include "ppp_bayes_tree/smoother/prior_factor.h"

namespace ppp {

using smoother::Key;
using smoother::KeyVector;
using smoother::NoiseModel;
using smoother::Vector;

namespace {

constexpr int kRx = ReceiverState::kDim;
using SteadyClock = std::chrono::steady_clock;

double secondsSince(SteadyClock::time_point t0) {
  return std::chrono::duration<double>(SteadyClock::now() - t0).count();
}

}  // namespace

std::string PppSmootherOptions::validate() const {
  if (auto problem = screening.validate(); !problem.empty()) return problem;
  if (!(huber_width_sigmas > 0.0)) return "huber_width_sigmas must be > 0";
  if (!(relinearize_position_m > 0.0) || !(relinearize_zwd_m > 0.0) || !(relinearize_clock_m > 0.0) ||
      !(relinearize_bias_m > 0.0))
    return "relinearization thresholds must be > 0";
  if (relinearize_skip < 1) return "relinearize_skip must be >= 1";
  if (!(wildfire_threshold_m >= 0.0)) return "wildfire_threshold_m must be >= 0";
  if (!(fixed_lag_s >= 0.0)) return "fixed_lag_s must be >= 0 (0: full smoother)";
  return {};
}

PppSmoother::PppSmoother(StochasticModel model, PppSmootherOptions options, CodeLeastSquaresOptions start_options)
    : model_(model), options_(options), start_options_(start_options) {
  if (auto problem = options_.validate(); !problem.empty()) throw std::invalid_argument(problem);
  if (auto problem = model_.validate(); !problem.empty()) throw std::invalid_argument(problem);
  if (options_.fixed_lag_s > 0.0) {
    smoother::FixedLagParams p;
    p.lag_s = options_.fixed_lag_s;
    p.isam2 = isamParams();
    lag_ = std::make_unique<smoother::FixedLagSmoother>(p);
  } else {
    isam_ = std::make_unique<smoother::ISAM2>(isamParams());
  }
}

PppSmoother::~PppSmoother() = default;
PppSmoother::PppSmoother(PppSmoother&&) noexcept = default;
PppSmoother& PppSmoother::operator=(PppSmoother&&) noexcept = default;

smoother::ISAM2Params PppSmoother::isamParams() const {
  smoother::ISAM2Params p;
  p.relinearize_skip = options_.relinearize_skip;
  Eigen::VectorXd state(kRx);
  state << options_.relinearize_position_m, options_.relinearize_position_m, options_.relinearize_position_m,
      options_.relinearize_zwd_m, options_.relinearize_clock_m;
  p.relinearize_thresholds_by_symbol['x'] = state;
  p.relinearize_threshold_by_symbol['b'] = options_.relinearize_bias_m;
  p.wildfire_threshold = options_.wildfire_threshold_m;
  // Without a robust kernel the phase factors are affine in the biases: relinearizing
  // a bias changes nothing but would re-eliminate every state of its arc.
  p.skip_affine_variables = true;
  p.factorization = options_.factorization;
  return p;
}

const smoother::ISAM2& PppSmoother::isam2() const { return lag_ ? lag_->isam2() : *isam_; }

smoother::Values PppSmoother::batchSmoothedValues() const {
  if (!record_graph_) throw std::logic_error("batchSmoothedValues: the graph was not recorded (setRecordGraph)");
  smoother::Values initial = recorded_values_;
  const smoother::ISAM2& isam = isam2();
  for (Key key : initial.keys()) {
    if (isam.exists(key)) initial.update(key, isam.calculateEstimate(key));
  }
  for (const auto& s : states_)  // marginalized states: their last estimate
    if (!isam.exists(stateKey(s.index))) initial.update(stateKey(s.index), s.last_estimate.vector());
  smoother::BatchParams params;
  params.max_iterations = 20;
  params.absolute_delta_tolerance = 1e-6;  // [m]
  return smoother::optimizeBatch(recorded_factors_, initial, params).values;
}

std::vector<SmoothedEpoch> PppSmoother::trajectoryFrom(const smoother::Values& v) const {
  std::vector<SmoothedEpoch> out;
  for (const auto& s : states_) {
    if (!v.exists(stateKey(s.index))) continue;
    SmoothedEpoch e;
    e.time = s.time;
    e.index = s.index;
    e.state = ReceiverState::fromVector(v.at(stateKey(s.index)));
    out.push_back(e);
  }
  return out;
}

double PppSmoother::sigmaOf(double variance_m2) { return std::sqrt(std::max(variance_m2, 1e-12)); }

std::optional<GnssTime> PppSmoother::lastTime() const {
  if (states_.empty()) return std::nullopt;
  return states_.back().time;
}

ReceiverState PppSmoother::receiverState() const { return initialised() ? filtered_.state : ReceiverState{}; }
ReceiverCovariance PppSmoother::receiverCovariance() const {
  return initialised() ? filtered_.covariance : ReceiverCovariance::Zero();
}

std::vector<ArcId> PppSmoother::activeArcs() const {
  std::vector<ArcId> out;
  for (const auto& [arc, slot] : arcs_) out.push_back(arc);
  return out;
}

std::optional<double> PppSmoother::biasEstimate_m(ArcId arc) const {
  auto it = arcs_.find(arc);
  if (it == arcs_.end() || !isam2().exists(it->second.key)) return std::nullopt;
  return isam2().calculateEstimate(it->second.key)(0);
}

std::optional<double> PppSmoother::biasEstimate_m(const SatelliteId& satellite, ArcId arc) const {
  if (!initialised()) return std::nullopt;
  const Key key = biasKey(satellite, arc);
  if (!isam2().exists(key)) return std::nullopt;
  return isam2().calculateEstimate(key)(0);
}

std::vector<SmoothedEpoch> PppSmoother::smoothedTrajectory(bool with_covariance) const {
  std::vector<SmoothedEpoch> out;
  out.reserve(states_.size());
  const smoother::ISAM2& isam = isam2();
  // One full back-substitution (exact, where the per-update partial one may leave
  // changes below its threshold in the older states) and one covariance pass.
  const smoother::Values estimate = isam.calculateBestEstimate();
  std::unordered_map<Key, smoother::Matrix> covariances;
  if (with_covariance) covariances = isam.bayesTree().marginalCovariances();
  for (const auto& s : states_) {
    SmoothedEpoch e;
    e.time = s.time;
    e.index = s.index;
    const Key key = stateKey(s.index);
    if (isam.exists(key)) {
      e.state = ReceiverState::fromVector(estimate.at(key));
      if (with_covariance) e.covariance = ReceiverCovariance(covariances.at(key));
    } else {
      e.state = s.last_estimate;
    }
    out.push_back(e);
  }
  return out;
}

std::optional<SmoothedEpoch> PppSmoother::smoothedEpochAt(const GnssTime& time, bool with_covariance) const {
  auto after = std::upper_bound(states_.begin(), states_.end(), time,
                                [](const GnssTime& t, const StateRecord& s) { return t < s.time; });
  if (after == states_.begin()) return std::nullopt;
  const smoother::ISAM2& isam = isam2();
  auto it = std::prev(after);
  if (!isam.exists(stateKey(it->index))) {
    // Fixed lag: the marginalized states are a prefix (oldest first); take the oldest kept.
    const auto kept = std::partition_point(states_.begin(), states_.end(),
                                           [&](const StateRecord& s) { return !isam.exists(stateKey(s.index)); });
    if (kept != states_.end()) it = kept;
  }
  SmoothedEpoch e;
  e.time = it->time;
  e.index = it->index;
  const Key key = stateKey(it->index);
  if (isam.exists(key)) {
    e.state = ReceiverState::fromVector(isam.calculateEstimate(key));
    if (with_covariance) e.covariance = ReceiverCovariance(isam.marginalCovariance(key));
  } else {
    e.state = it->last_estimate;
  }
  return e;
}

SmootherEpochResult PppSmoother::processEpoch(const GnssTime& time, const MeasurementFunction& evaluate) {
  const auto t_start = SteadyClock::now();
  SmootherEpochResult result;
  result.time = time;
  auto finish = [&](EpochStatus status, std::string reason) {
    result.status = status;
    result.reason = std::move(reason);
    result.active_biases = activeBiasCount();
    result.epoch_time_s = secondsSince(t_start);
    return result;
  };

  // 1. Predicted state: the code least squares at the first epoch, else the last filtered state.
  const bool first = !initialised();
  ReceiverState predicted;
  if (first) {
    ReceiverState start;
    start.position_ecef_m = approx_position_ecef_m_.value_or(Eigen::Vector3d::Zero());
    start.zwd_m = model_.initial_zwd_m;
    const CodeLeastSquaresResult ls = codeLeastSquares(evaluate, start, start_options_);
    result.iterations += ls.iterations;
    if (!ls.ok) {
      result.rejected = ls.rejected;
      return finish(EpochStatus::NoSolution, "no initial position: " + ls.reason);
    }
    predicted = ls.state;
  } else {
    result.dt_s = time - states_.back().time;
    if (!std::isfinite(result.dt_s) || result.dt_s <= 0.0)
      return finish(EpochStatus::Failed, "epoch " + time.toString() + " is not after the last solved epoch " +
                                             states_.back().time.toString());
    predicted = filtered_.state;
  }
  const double dt = result.dt_s;

  // 2. Linearise once at the prediction; usable measurements; white clock shift.
  const EpochMeasurements epoch0 = evaluate(predicted);
  result.iterations += 1;
  result.rejected = epoch0.rejected;
  std::vector<SatelliteMeasurement> cand = usableMeasurements(epoch0.used, result.rejected);
  if (options_.screening.clock_from_code_median) {
    if (const auto shift = medianCodeClockShift_m(cand)) {
      predicted.clock_m += *shift;
      applyClockShift(cand, *shift);
    }
  }

  // 3. Arc bookkeeping on a copy (committed only with a solution), then screening.
  std::map<ArcId, ArcSlot> arcs = arcs_;
  for (const auto& m : cand)
    for (auto it = arcs.begin(); it != arcs.end(); ++it)
      if (it->second.satellite == m.satellite && it->first != m.arc) {
        arcs.erase(it);
        break;
      }
  for (auto it = arcs.begin(); it != arcs.end();)
    it = time - it->second.last_used > options_.screening.stale_arc_timeout_s ? arcs.erase(it) : std::next(it);

  PrefitScreeningResult screening =
      screenPrefit(cand, options_.screening, [&arcs](ArcId arc) -> std::optional<ArcBiasPrior> {
        auto it = arcs.find(arc);
        if (it == arcs.end()) return std::nullopt;
        return ArcBiasPrior{it->second.filtered_m, it->second.filtered_variance_m2};
      });
  result.prefit_rejections += static_cast<int>(screening.rejected.size());
  result.rejected.insert(result.rejected.end(), screening.rejected.begin(), screening.rejected.end());
  const std::vector<SatelliteMeasurement>& screened = screening.kept;
  const int n_sat = static_cast<int>(screened.size());
  if (n_sat < options_.screening.min_satellites)
    return finish(EpochStatus::NoSolution, std::to_string(n_sat) + " satellites usable after screening, at least " +
                                               std::to_string(options_.screening.min_satellites) + " needed");

  // 4. New factors and variables.
  const std::uint32_t index = first ? 0u : states_.back().index + 1;
  const Key x = stateKey(index);
  smoother::NonlinearFactorGraph factors;
  smoother::Values values;
  values.insert(x, predicted.vector());
  if (first) {
    Eigen::VectorXd sigmas(kRx);
    sigmas << Eigen::Vector3d::Constant(model_.position.initial_sigma_m), model_.zwd.initial_sigma_m,
        model_.clock.initial_sigma_m;
    factors.push_back(std::make_shared<smoother::PriorFactor>(x, predicted.vector(), NoiseModel::sigmas(sigmas)));
  } else {
    const Key previous = stateKey(states_.back().index);
    factors.push_back(std::make_shared<ReceiverRandomWalkFactor>(
        previous, x, sigmaOf(model_.position.processVariance_m2(dt)), sigmaOf(model_.zwd.processVariance_m2(dt))));
    factors.push_back(
        std::make_shared<ClockPriorFactor>(x, predicted.clock_m, sigmaOf(model_.clock.processVariance_m2(dt))));
  }
  auto noise = [&](double sigma) {
    NoiseModel::Ptr n = NoiseModel::isotropic(1, sigma);
    if (options_.robust) n = n->withRobust({smoother::RobustKernel::Type::Huber, options_.huber_width_sigmas});
    return n;
  };
  KeyVector newest{x};
  std::vector<bool> new_arc(screened.size(), false);
  std::vector<Key> bias_of(screened.size());
  std::vector<double> phase_prefit(screened.size());
  for (std::size_t k = 0; k < screened.size(); ++k) {
    const SatelliteMeasurement& m = screened[k];
    auto it = arcs.find(m.arc);
    if (it == arcs.end()) {  // new arc: bias from phase minus code, a priori sigma
      const Key b = biasKey(m.satellite, m.arc);
      const double b0 = m.phaseResidualWithoutBias_m() - m.codeResidual_m();
      if (isam2().exists(b)) {  // the arc left the active set earlier (stale) and returns
        it = arcs.emplace(m.arc, ArcSlot{m.satellite, b, time, index, isam2().calculateEstimate(b)(0),
                                         model_.phase_bias.initialVariance_m2()})
                 .first;
      } else {
        values.insert(b, Vector::Constant(1, b0));
        factors.push_back(std::make_shared<smoother::PriorFactor>(
            b, Vector::Constant(1, b0), NoiseModel::isotropic(1, model_.phase_bias.initial_sigma_m)));
        it = arcs.emplace(m.arc, ArcSlot{m.satellite, b, time, index, b0, model_.phase_bias.initialVariance_m2()})
                 .first;
        new_arc[k] = true;
        ++result.new_biases;
      }
    }
    ArcSlot& slot = it->second;
    slot.last_used = time;
    slot.last_state = index;
    bias_of[k] = slot.key;
    phase_prefit[k] = m.phaseResidualWithoutBias_m() - slot.filtered_m;
    newest.push_back(slot.key);
    SatellitePrediction prediction(m, predicted, options_.exact_range);
    factors.push_back(std::make_shared<PppCodeFactor>(x, prediction, noise(m.code_sigma_m)));
    factors.push_back(std::make_shared<PppPhaseFactor>(x, slot.key, prediction, noise(m.phase_sigma_m)));
  }

  // 5. One iSAM2 update, newest state and observed biases in the root.
  std::map<Key, std::uint32_t> bias_last_state = bias_last_state_;
  for (Key b : bias_of) bias_last_state[b] = index;
  const auto t_update = SteadyClock::now();
  try {
    if (lag_) {
      std::unordered_map<Key, double> stamps{{x, time - (states_.empty() ? time : states_.front().time)}};
      const smoother::FixedLagResult r = lag_->update(factors, values, stamps, newest);
      result.variables_relinearized = r.isam2.variables_relinearized;
      result.variables_reeliminated = r.isam2.variables_reeliminated;
      result.factors_relinearized = r.isam2.factors_relinearized;
      result.cliques_touched = r.isam2.cliquesTouched();
      result.variables_marginalized = r.variables_marginalized;
    } else {
      smoother::ISAM2UpdateParams up;
      up.newest_keys = newest;
      up.ordering_group = [&bias_last_state](Key key) {
        if (smoother::keySymbol(key) == 'x') return static_cast<int>(smoother::keyIndex(key));
        auto it = bias_last_state.find(key);
        return it == bias_last_state.end() ? 0 : static_cast<int>(it->second);
      };
      const smoother::ISAM2Result r = isam_->update(factors, values, up);
      result.variables_relinearized = r.variables_relinearized;
      result.variables_reeliminated = r.variables_reeliminated;
      result.factors_relinearized = r.factors_relinearized;
      result.cliques_touched = r.cliquesTouched();
    }
  } catch (const std::exception& e) {
    result.update_time_s = secondsSince(t_update);
    return finish(EpochStatus::Failed, std::string("smoother update failed: ") + e.what());
  }
  result.update_time_s = secondsSince(t_update);

  // 6. Filtered estimate and marginals of the root variables (new state, observed biases).
  const smoother::ISAM2& isam = isam2();
  KeyVector marginal_keys{x};
  for (Key b : bias_of) marginal_keys.push_back(b);
  const smoother::Matrix joint = isam.jointMarginalCovariance(marginal_keys);
  EpochSolution solution;
  const Vector x_est = isam.calculateEstimate(x);
  solution.state = ReceiverState::fromVector(x_est);
  solution.covariance = joint.topLeftCorner<kRx, kRx>();
  if (!x_est.allFinite() || !solution.covariance.allFinite())
    return finish(EpochStatus::Failed, "non-finite filtered estimate or covariance");

  // Commit.
  for (std::size_t k = 0; k < screened.size(); ++k) {
    ArcSlot& slot = arcs.at(screened[k].arc);
    slot.filtered_m = isam.calculateEstimate(slot.key)(0);
    slot.filtered_variance_m2 = joint(kRx + static_cast<int>(k), kRx + static_cast<int>(k));
    result.biases.push_back({screened[k].arc, slot.satellite, slot.filtered_m,
                             std::sqrt(std::max(0.0, slot.filtered_variance_m2))});
  }
  arcs_ = std::move(arcs);
  bias_last_state_ = std::move(bias_last_state);
  states_.push_back({time, index, solution.state});
  if (record_graph_) {
    recorded_factors_.insert(recorded_factors_.end(), factors.begin(), factors.end());
    for (Key key : values.keys()) recorded_values_.insert(key, values.at(key));
  }
  if (lag_) {  // keep the latest estimate of the states still in the window
    for (auto it = states_.rbegin(); it != states_.rend() && isam.exists(stateKey(it->index)); ++it)
      it->last_estimate = ReceiverState::fromVector(isam.calculateEstimate(stateKey(it->index)));
    for (auto it = bias_last_state_.begin(); it != bias_last_state_.end();)
      it = isam.exists(it->first) ? std::next(it) : bias_last_state_.erase(it);
  }
  filtered_ = solution;
  result.solution = solution;

  // Residuals: prefit at the prediction, postfit at the filtered state.
  for (std::size_t k = 0; k < screened.size(); ++k) {
    const SatelliteMeasurement& m = screened[k];
    const SatellitePrediction prediction(m, predicted, options_.exact_range);
    MeasurementResidual r;
    r.satellite = m.satellite;
    r.arc = m.arc;
    r.new_arc = new_arc[k];
    r.elevation_rad = m.elevation_rad;
    r.azimuth_rad = m.azimuth_rad;
    r.code_prefit_m = m.codeResidual_m();
    r.phase_prefit_m = phase_prefit[k];
    r.code_postfit_m = m.observed_code_m - prediction.code_m(x_est, nullptr);
    r.phase_postfit_m = m.observed_phase_m - prediction.phase_m(x_est, nullptr) - arcs_.at(m.arc).filtered_m;
    r.code_sigma_m = m.code_sigma_m;
    r.phase_sigma_m = m.phase_sigma_m;
    result.residuals.push_back(r);
    result.used.push_back(m.satellite);
  }
  return finish(EpochStatus::Ok, {});
}

}  // namespace ppp
