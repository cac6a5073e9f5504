#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"

#include <algorithm>
#include <chrono>
#include <tuple>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "ppp_bayes_tree/ppp/ambiguity/integer_ambiguity_factor.h"
#include "ppp_bayes_tree/ppp/model/ppp_factors.h"
#include "ppp_bayes_tree/ppp/screening/postfit_screening.h"
#include "ppp_bayes_tree/ppp/screening/prefit_screening.h"
#include "ppp_bayes_tree/smoother/batch_solver.h"
#include "ppp_bayes_tree/smoother/elimination.h"
#include "ppp_bayes_tree/smoother/prior_factor.h"

namespace ppp {

using smoother::Key;
using smoother::KeyVector;
using smoother::NoiseModel;
using smoother::Vector;

namespace {

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
  if (!(fixed_ambiguity_sigma_cycles > 0.0)) return "fixed_ambiguity_sigma_cycles must be > 0";
  return {};
}

PppSmoother::PppSmoother(StochasticModel model, PppSmootherOptions options, CodeLeastSquaresOptions start_options,
                         ReceiverStateLayout layout)
    : PppEstimator(model, options.screening, start_options, layout),
      options_(options) {
  if (auto problem = options_.validate(); !problem.empty()) throw std::invalid_argument(problem);
  if (auto problem = model_.validate(); !problem.empty()) throw std::invalid_argument(problem);
  newGraph();
}

void PppSmoother::newGraph() {
  isam_.reset();
  lag_.reset();
  if (options_.fixed_lag_s > 0.0) {
    smoother::FixedLagParams p;
    p.lag_s = options_.fixed_lag_s;
    p.isam2 = isamParams();
    lag_ = std::make_unique<smoother::FixedLagSmoother>(p);
  } else {
    isam_ = std::make_unique<smoother::ISAM2>(isamParams());
  }
}

PppSmoother::PppSmoother(const EstimatorOptions& options)
    : PppSmoother(options.stochastic, options.smoother, options.start,
                  ReceiverStateLayout(options.systems, options.troposphere_gradients)) {
  resolver() = AmbiguityResolver(options.ambiguity_resolution);
}

PppSmoother::~PppSmoother() = default;
PppSmoother::PppSmoother(PppSmoother&&) noexcept = default;
PppSmoother& PppSmoother::operator=(PppSmoother&&) noexcept = default;

smoother::ISAM2Params PppSmoother::isamParams() const {
  smoother::ISAM2Params p;
  p.relinearize_skip = options_.relinearize_skip;
  Eigen::VectorXd state = Eigen::VectorXd::Constant(layout_.dim(), options_.relinearize_clock_m);
  state.segment<ReceiverStateLayout::kPositionSize>(layout_.position()).setConstant(options_.relinearize_position_m);
  state(layout_.zwd()) = options_.relinearize_zwd_m;
  // The gradients are tropospheric delays like the ZWD (and enter every factor linearly).
  if (layout_.hasGradients())
    state.segment<ReceiverStateLayout::kGradientSize>(layout_.gradientNorth()).setConstant(options_.relinearize_zwd_m);
  p.relinearize_thresholds_by_symbol['x'] = state;
  p.relinearize_threshold_by_symbol['b'] = options_.relinearize_bias_m;
  // The inertial variables of a GNSS/INS smoother (none in a GNSS-only graph):
  // [attitude rad; velocity m/s; position m] and [accel m/s^2; gyro rad/s].
  Eigen::VectorXd nav(9);
  nav << Eigen::Vector3d::Constant(kRelinearizeAttitude_rad), Eigen::Vector3d::Constant(kRelinearizeVelocity_mps),
      Eigen::Vector3d::Constant(options_.relinearize_position_m);
  p.relinearize_thresholds_by_symbol[kNavStateSymbol] = nav;
  Eigen::VectorXd bias(6);
  bias << Eigen::Vector3d::Constant(kRelinearizeAccelBias_mps2), Eigen::Vector3d::Constant(kRelinearizeGyroBias_radps);
  p.relinearize_thresholds_by_symbol[kImuBiasSymbol] = bias;
  p.wildfire_threshold = options_.wildfire_threshold_m;
  // Without a robust kernel the phase factors are affine in the biases: relinearizing
  // a bias changes nothing but would re-eliminate every state of its arc.
  p.skip_affine_variables = true;
  p.factorization = options_.factorization.value_or(PppSmootherOptions::kDefaultFactorization);
  return p;
}

const smoother::ISAM2& PppSmoother::isam2() const { return lag_ ? lag_->isam2() : *isam_; }

smoother::Values PppSmoother::batchSmoothedValues() const {
  if (!options_.record_graph)
    throw std::logic_error("batchSmoothedValues: the graph was not recorded (PppSmootherOptions::record_graph)");
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

SmoothedSolution PppSmoother::finalSmoothedSolution() const {
  SmoothedSolution out;
  if (!options_.record_graph) {
    out.trajectory = smoothedTrajectory();
    out.bias_m = [this](const SatelliteId& satellite, ArcId arc) { return biasEstimate_m(satellite, arc); };
    return out;
  }
  auto values = std::make_shared<const smoother::Values>(batchSmoothedValues());
  out.trajectory = trajectoryFrom(*values);
  out.bias_m = [values](const SatelliteId& satellite, ArcId arc) -> std::optional<double> {
    const Key key = biasKey(satellite, arc);
    if (!values->exists(key)) return std::nullopt;
    return values->at(key)(0);
  };
  return out;
}

std::vector<SmoothedEpoch> PppSmoother::trajectoryFrom(const smoother::Values& v) const {
  std::vector<SmoothedEpoch> out;
  for (const auto& s : states_) {
    if (!v.exists(stateKey(s.index))) continue;
    SmoothedEpoch e;
    e.time = s.time;
    e.index = s.index;
    e.state = ReceiverState::fromVector(v.at(stateKey(s.index)), layout_);
    out.push_back(e);
  }
  return out;
}

double PppSmoother::sigmaOf(double variance_m2) { return std::sqrt(std::max(variance_m2, 1e-12)); }

std::optional<GnssTime> PppSmoother::lastTime() const {
  if (states_.empty()) return std::nullopt;
  return states_.back().time;
}

ReceiverState PppSmoother::receiverState() const { return initialised() ? filtered_.state : ReceiverState(layout_); }
ReceiverCovariance PppSmoother::receiverCovariance() const {
  return initialised() ? filtered_.covariance : ReceiverCovariance::Zero(layout_.dim(), layout_.dim());
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
      e.state = ReceiverState::fromVector(estimate.at(key), layout_);
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
  if (lag_ && !isam.exists(stateKey(it->index))) {
    // Fixed lag: the marginalized states are a prefix (oldest first); take the oldest kept.
    // (A full smoother after a restart: the states before it keep their last estimate.)
    const auto kept = std::partition_point(states_.begin(), states_.end(),
                                           [&](const StateRecord& s) { return !isam.exists(stateKey(s.index)); });
    if (kept != states_.end()) it = kept;
  }
  SmoothedEpoch e;
  e.time = it->time;
  e.index = it->index;
  const Key key = stateKey(it->index);
  if (isam.exists(key)) {
    e.state = ReceiverState::fromVector(isam.calculateEstimate(key), layout_);
    if (with_covariance) e.covariance = ReceiverCovariance(isam.marginalCovariance(key));
  } else {
    e.state = it->last_estimate;
  }
  return e;
}

void PppSmoother::releaseLeftStates() {
  if (!sink_ || options_.record_graph) return;
  const smoother::ISAM2& isam = isam2();
  // The newest state is always in the graph, so at least one state stays.
  while (states_.size() > 1 && !isam.exists(stateKey(states_.front().index))) {
    SmoothedEpoch e;
    e.time = states_.front().time;
    e.index = states_.front().index;
    e.state = states_.front().last_estimate;
    if (!handed_out_through_ || e.index > *handed_out_through_) sink_(e);
    states_.pop_front();
  }
}

std::size_t PppSmoother::finishTrajectory() {
  if (!sink_) return 0;
  std::vector<SmoothedEpoch> rest = smoothedTrajectory(false);
  if (handed_out_through_)
    rest.erase(std::remove_if(rest.begin(), rest.end(),
                              [&](const SmoothedEpoch& e) { return e.index <= *handed_out_through_; }),
               rest.end());
  for (const SmoothedEpoch& e : rest) sink_(e);
  // Keep the newest state (the next epoch links to it) but never hand it out twice:
  // from here on only states after it are handed out.
  if (!states_.empty()) {
    const StateRecord newest = states_.back();
    states_.clear();
    states_.push_back(newest);
    handed_out_through_ = newest.index;
  }
  return rest.size();
}

ReceiverState PppSmoother::predict(double, bool, const std::optional<ReceiverState>& start) {
  return start ? *start : filtered_.state;
}

std::optional<ArcBiasPrior> PppSmoother::predictedBias(ArcId arc) const {
  auto it = arcs_.find(arc);
  if (it == arcs_.end()) return std::nullopt;
  return ArcBiasPrior{it->second.filtered_m, it->second.filtered_variance_m2};
}

void PppSmoother::finishEpoch(EstimatorEpochResult& result) const {
  if (!result.smoother) result.smoother.emplace();
}

/// The state carried between the steps of solve().
struct PppSmoother::SolveEpoch {
  SolveEpoch(const EpochSolveInput& input, SmootherEpochDiagnostics& diagnostics, std::map<ArcId, ArcSlot> active)
      : in(input), diag(diagnostics), arcs(std::move(active)), n_sat(input.screened.size()), new_arc(n_sat, false),
        bias_of(n_sat), phase_prefit(n_sat), code_factor(n_sat), kept(n_sat, true), n_kept(n_sat) {}

  const EpochSolveInput& in;
  SmootherEpochDiagnostics& diag;
  std::map<ArcId, ArcSlot> arcs;  // the active set after this epoch (committed in step 6)
  std::size_t n_sat;              // screened satellites
  // Steps 1-2: the new state, factors and variables.
  std::uint32_t index = 0;
  Key x = 0;
  smoother::NonlinearFactorGraph factors;
  smoother::Values values;
  KeyVector newest;                        // eliminated last (root clique)
  KeyVector inertial_keys;                 // the new state's inertial variables (none without an IMU)
  std::vector<bool> new_arc;               // per satellite: a new bias variable
  std::vector<Key> bias_of;                // per satellite: its bias variable
  std::vector<double> phase_prefit;        // per satellite: at the prediction, minus the bias prior
  std::vector<std::size_t> code_factor;    // position of each satellite's code factor in `factors` (phase: +1)
  // Steps 3-4: the update and the postfit check.
  std::map<Key, std::uint32_t> bias_last_state;
  smoother::Values marginalized;                   // fixed lag: the states and biases this update marginalized
  std::vector<smoother::FactorIndex> graph_index;  // of each new factor
  SteadyClock::time_point t_update;
  std::vector<bool> kept;
  std::size_t n_kept;
  std::vector<smoother::FactorIndex> removed_factors;
  // Step 5: the filtered joint of the new state and the kept biases.
  smoother::Matrix joint;
  std::vector<int> marginal_of;  // position of each kept bias in the joint marginal
  Vector x_est;
  EpochSolution solution;
};

namespace {

/// The constrained ordering: states (and the inertial variables of a state, if any)
/// by index, biases by the last state they were observed at (eliminated after it),
/// oldest first.
/// The update's step times added to the epoch's (SmootherEpochDiagnostics::isam2_step_time_s).
void addStepTimes(const smoother::ISAM2Result& r, SmootherEpochDiagnostics& diag) {
  static_assert(smoother::ISAM2Result::kNumSteps == std::tuple_size_v<decltype(diag.isam2_step_time_s)>);
  for (std::size_t i = 0; i < r.step_time_s.size(); ++i) diag.isam2_step_time_s[i] += r.step_time_s[i];
}

std::function<int(Key)> orderingByLastState(const std::map<Key, std::uint32_t>& bias_last_state) {
  return [&bias_last_state](Key key) {
    const char symbol = smoother::keySymbol(key);
    if (symbol == 'x' || symbol == PppSmoother::kNavStateSymbol || symbol == PppSmoother::kImuBiasSymbol)
      return static_cast<int>(smoother::keyIndex(key));
    auto it = bias_last_state.find(key);
    return it == bias_last_state.end() ? 0 : static_cast<int>(it->second);
  };
}

}  // namespace

bool PppSmoother::solve(const EpochSolveInput& in, EpochSolveOutput& out, EstimatorEpochResult& result) {
  SolveEpoch e(in, result.smoother.emplace(), arcs_);
  for (const ArcId arc : in.dropped_arcs) e.arcs.erase(arc);

  // 1. The new state with its prior (first) or its random walk and clock priors.
  addStateFactors(e);

  // 2. Each satellite's code and phase factors; a bias variable per new arc.
  addMeasurementFactors(e);

  // 3. One iSAM2 update, newest state and observed biases in the root.
  if (!updateWithNewFactors(e, result)) return false;

  // 4. Postfit check: the worst satellite's factors are removed while it fails.
  if (!postfitCheck(e, result)) return false;
  e.diag.update_time_s = secondsSince(e.t_update);

  // 5. Filtered estimate and marginals of the root variables (new state, kept biases).
  if (!filteredMarginals(e, result)) return false;

  // 6. Commit the filtered joint, active set, state record and graph bookkeeping.
  commitEpoch(e);
  out.solution = e.solution;
  out.ambiguities = AmbiguityState::Float;

  // 7. Residuals: prefit at the prediction, postfit at the filtered state.
  out.rows = residualRows(e);
  return true;
}

smoother::NoiseModel::Ptr PppSmoother::measurementNoise(double sigma) const {
  NoiseModel::Ptr n = NoiseModel::isotropic(1, sigma);
  if (options_.robust) n = n->withRobust({smoother::RobustKernel::Type::Huber, options_.huber_width_sigmas});
  return n;
}

// Step 1
void PppSmoother::addStateFactors(SolveEpoch& e) const {
  const EpochSolveInput& in = e.in;
  const ReceiverState& predicted = in.predicted;
  e.index = in.first ? 0u : states_.back().index + 1;
  e.x = stateKey(e.index);
  e.values.insert(e.x, predicted.vector());
  if (in.first) {
    Eigen::VectorXd sigmas = Eigen::VectorXd::Constant(layout_.dim(), model_.clock.initial_sigma_m);
    sigmas.segment<ReceiverStateLayout::kPositionSize>(layout_.position()).setConstant(model_.position.initial_sigma_m);
    sigmas(layout_.zwd()) = model_.zwd.initial_sigma_m;
    if (layout_.hasGradients())
      sigmas.segment<ReceiverStateLayout::kGradientSize>(layout_.gradientNorth())
          .setConstant(model_.troposphere_gradient.initial_sigma_m);
    e.factors.push_back(std::make_shared<smoother::PriorFactor>(e.x, predicted.vector(), NoiseModel::sigmas(sigmas)));
  } else {
    const Key previous = stateKey(states_.back().index);
    e.factors.push_back(std::make_shared<ReceiverRandomWalkFactor>(
        previous, e.x, layout_, positionProcessSigma_m(in.dt_s),
        sigmaOf(zwdProcessVariance_m2(in.dt_s)),
        sigmaOf(model_.troposphere_gradient.processVariance_m2(in.dt_s))));
    for (const GnssSystem system : layout_.clockSystems())
      e.factors.push_back(std::make_shared<ClockPriorFactor>(e.x, layout_.clock(system), predicted.clock_m(system),
                                                             sigmaOf(model_.clock.processVariance_m2(in.dt_s))));
  }
  addInertialFactors(in, e.index, e.factors, e.values, e.inertial_keys);
}

double PppSmoother::positionProcessSigma_m(double dt_s) const {
  return sigmaOf(model_.position.processVariance_m2(dt_s));
}

// Step 2
void PppSmoother::addMeasurementFactors(SolveEpoch& e) const {
  const EpochSolveInput& in = e.in;
  // The code sigmas carry the correlation of the code errors over dt (stochastic_model.h).
  const double code_sigma_factor = std::sqrt(model_.codeVarianceFactor(in.dt_s));
  e.newest = KeyVector{e.x};
  e.newest.insert(e.newest.end(), e.inertial_keys.begin(), e.inertial_keys.end());
  for (std::size_t k = 0; k < e.n_sat; ++k) {
    const SatelliteMeasurement& m = in.screened[k].m;
    auto it = e.arcs.find(m.arc);
    if (it == e.arcs.end()) {  // new arc: the front end's initial value, a priori sigma
      const Key b = biasKey(m.satellite, m.arc);
      const double b0 = in.screened[k].new_arc_bias_m;
      if (isam2().exists(b)) {  // the arc left the active set earlier (stale) and returns
        it = e.arcs.emplace(m.arc, ArcSlot{m.satellite, b, e.index, isam2().calculateEstimate(b)(0),
                                           model_.phase_bias.initialVariance_m2()})
                 .first;
      } else {
        e.values.insert(b, Vector::Constant(1, b0));
        e.factors.push_back(std::make_shared<smoother::PriorFactor>(
            b, Vector::Constant(1, b0), NoiseModel::isotropic(1, model_.phase_bias.initial_sigma_m)));
        it = e.arcs.emplace(m.arc, ArcSlot{m.satellite, b, e.index, b0, model_.phase_bias.initialVariance_m2()}).first;
        e.new_arc[k] = true;
        ++e.diag.new_biases;
      }
    }
    ArcSlot& slot = it->second;
    slot.last_state = e.index;
    e.bias_of[k] = slot.key;
    e.phase_prefit[k] = m.phaseResidualWithoutBias_m() - slot.filtered_m;
    e.newest.push_back(slot.key);
    SatellitePrediction prediction(m, in.predicted, options_.exact_range);
    e.code_factor[k] = e.factors.size();
    e.factors.push_back(
        std::make_shared<PppCodeFactor>(e.x, prediction, measurementNoise(m.code_sigma_m * code_sigma_factor)));
    e.factors.push_back(std::make_shared<PppPhaseFactor>(e.x, slot.key, prediction, measurementNoise(m.phase_sigma_m)));
  }
}

// Step 3
bool PppSmoother::updateWithNewFactors(SolveEpoch& e, EstimatorEpochResult& result) {
  SmootherEpochDiagnostics& diag = e.diag;
  e.bias_last_state = bias_last_state_;
  for (Key b : e.bias_of) e.bias_last_state[b] = e.index;
  e.t_update = SteadyClock::now();
  try {
    if (lag_) {
      std::unordered_map<Key, double> stamps{{e.x, time_origin_ ? lagStamp_s(e.in.time) : 0.0}};
      for (Key k : e.inertial_keys) stamps.emplace(k, stamps.at(e.x));
      const smoother::FixedLagResult r = lag_->update(e.factors, e.values, stamps, e.newest);
      addStepTimes(r.isam2, diag);
      diag.variables_relinearized = r.isam2.variables_relinearized;
      diag.variables_reeliminated = r.isam2.variables_reeliminated;
      diag.factors_relinearized = r.isam2.factors_relinearized;
      diag.cliques_touched = r.isam2.cliquesTouched();
      diag.variables_marginalized = r.variables_marginalized;
      e.graph_index = r.isam2.new_factor_indices;
      e.marginalized = r.marginalized_estimates;
    } else {
      smoother::ISAM2UpdateParams up;
      up.newest_keys = e.newest;
      up.ordering_group = orderingByLastState(e.bias_last_state);
      const smoother::ISAM2Result r = isam_->update(e.factors, e.values, up);
      addStepTimes(r, diag);
      diag.variables_relinearized = r.variables_relinearized;
      diag.variables_reeliminated = r.variables_reeliminated;
      diag.factors_relinearized = r.factors_relinearized;
      diag.cliques_touched = r.cliquesTouched();
      e.graph_index = r.new_factor_indices;
    }
  } catch (const std::exception& ex) {
    diag.update_time_s = secondsSince(e.t_update);
    return fail(result, EpochStatus::Failed, NoSolutionReason::SmootherUpdateFailed,
                std::string("smoother update failed: ") + ex.what());
  }
  return true;
}

// Step 4 (postfit_screening.h, as the EKF): the worst satellite's code and phase
// factors are removed from the graph and the estimate updated again, never below
// min_satellites. A removed new arc keeps only its bias prior (a detached
// variable) and is not active; it starts afresh when seen again.
bool PppSmoother::postfitCheck(SolveEpoch& e, EstimatorEpochResult& result) {
  const smoother::ISAM2& isam = isam2();
  auto postfitPair = [&](std::size_t k, const Vector& x_est) {
    const SatelliteMeasurement& m = e.in.screened[k].m;
    const SatellitePrediction prediction(m, e.in.predicted, options_.exact_range);
    return PostfitResidualPair{m.observed_code_m - prediction.code_m(x_est, nullptr),
                               m.observed_phase_m - prediction.phase_m(x_est, nullptr) -
                                   isam.calculateEstimate(e.bias_of[k])(0),
                               m.code_sigma_m, m.phase_sigma_m};
  };
  const ScreeningOptions& sc = options_.screening;
  while (sc.postfit_check && result.postfit_rejections < sc.postfit_max_rejections &&
         static_cast<int>(e.n_kept) > sc.min_satellites && e.graph_index.size() == e.factors.size()) {
    const Vector x_now = isam.calculateEstimate(e.x);
    std::vector<PostfitResidualPair> pairs;
    std::vector<std::size_t> of_pair;
    for (std::size_t k = 0; k < e.n_sat; ++k)
      if (e.kept[k]) {
        pairs.push_back(postfitPair(k, x_now));
        of_pair.push_back(k);
      }
    const auto worst = worstPostfitResidual(pairs, sc.postfit_sigmas);
    if (!worst) break;
    const std::size_t k = of_pair[worst->index];
    const SatelliteMeasurement& m = e.in.screened[k].m;
    result.rejected.push_back(postfitRejection(m.satellite, *worst, sc.postfit_sigmas));
    ++result.postfit_rejections;
    if (!removeSatellite(e, k, result)) return false;
  }
  return true;
}

bool PppSmoother::removeSatellite(SolveEpoch& e, std::size_t k, EstimatorEpochResult& result) {
  const SatelliteMeasurement& m = e.in.screened[k].m;
  e.kept[k] = false;
  --e.n_kept;
  if (e.new_arc[k]) {
    e.arcs.erase(m.arc);
    --e.diag.new_biases;
  }
  const std::vector<smoother::FactorIndex> remove{e.graph_index[e.code_factor[k]],
                                                  e.graph_index[e.code_factor[k] + 1]};
  e.removed_factors.insert(e.removed_factors.end(), remove.begin(), remove.end());
  KeyVector kept_newest{e.x};
  kept_newest.insert(kept_newest.end(), e.inertial_keys.begin(), e.inertial_keys.end());
  for (std::size_t j = 0; j < e.n_sat; ++j)
    if (e.kept[j]) kept_newest.push_back(e.bias_of[j]);
  try {
    if (lag_) {
      addStepTimes(lag_->update({}, {}, {}, kept_newest, remove).isam2, e.diag);
    } else {
      smoother::ISAM2UpdateParams up;
      up.newest_keys = kept_newest;
      up.remove_factor_indices = remove;
      up.ordering_group = orderingByLastState(e.bias_last_state);
      addStepTimes(isam_->update({}, {}, up), e.diag);
    }
  } catch (const std::exception& ex) {
    e.diag.update_time_s = secondsSince(e.t_update);
    return fail(result, EpochStatus::Failed, NoSolutionReason::SmootherUpdateFailed,
                std::string("smoother update failed (postfit removal of ") + m.satellite.toString() + "): " +
                    ex.what());
  }
  return true;
}

// Step 5
bool PppSmoother::filteredMarginals(SolveEpoch& e, EstimatorEpochResult& result) const {
  const smoother::ISAM2& isam = isam2();
  const int kRx = layout_.dim();
  KeyVector marginal_keys{e.x};
  e.marginal_of.assign(e.n_sat, -1);
  for (std::size_t k = 0; k < e.n_sat; ++k)
    if (e.kept[k]) {
      e.marginal_of[k] = kRx + static_cast<int>(marginal_keys.size()) - 1;
      marginal_keys.push_back(e.bias_of[k]);
    }
  e.joint = isam.jointMarginalCovariance(marginal_keys);
  e.x_est = isam.calculateEstimate(e.x);
  e.solution.state = ReceiverState::fromVector(e.x_est, layout_);
  e.solution.covariance = e.joint.topLeftCorner(kRx, kRx);
  if (!e.x_est.allFinite() || !e.solution.covariance.allFinite())
    return fail(result, EpochStatus::Failed, NoSolutionReason::NonFiniteFilteredEstimate,
                "non-finite filtered estimate or covariance");
  return true;
}

// Step 6
void PppSmoother::commitEpoch(SolveEpoch& e) {
  const smoother::ISAM2& isam = isam2();
  joint_ = FilteredJoint{};
  joint_.P = e.joint;
  joint_.x = Eigen::VectorXd::Zero(e.joint.rows());
  joint_.x.head(layout_.dim()) = e.x_est;
  for (std::size_t k = 0; k < e.n_sat; ++k)
    if (e.kept[k]) {
      joint_.arcs.push_back(e.in.screened[k].m.arc);
      joint_.x(e.marginal_of[k]) = isam.calculateEstimate(e.bias_of[k])(0);
    }
  for (std::size_t k = 0; k < e.n_sat; ++k) {
    if (!e.kept[k]) continue;
    ArcSlot& slot = e.arcs.at(e.in.screened[k].m.arc);
    slot.filtered_m = isam.calculateEstimate(slot.key)(0);
    slot.filtered_variance_m2 = e.joint(e.marginal_of[k], e.marginal_of[k]);
    e.diag.biases.push_back({e.in.screened[k].m.arc, slot.satellite, slot.filtered_m,
                             std::sqrt(std::max(0.0, slot.filtered_variance_m2))});
  }
  arcs_ = std::move(e.arcs);
  bias_last_state_ = std::move(e.bias_last_state);
  if (!time_origin_) time_origin_ = e.in.time;
  states_.push_back({e.in.time, e.index, e.solution.state});
  if (options_.record_graph) recordEpochGraph(e);
  if (lag_) forgetMarginalized(e.marginalized);
  releaseLeftStates();
  filtered_ = e.solution;
}

void PppSmoother::recordEpochGraph(const SolveEpoch& e) {
  for (std::size_t i = 0; i < e.factors.size(); ++i) {
    const bool removed = i < e.graph_index.size() && std::find(e.removed_factors.begin(), e.removed_factors.end(),
                                                                e.graph_index[i]) != e.removed_factors.end();
    if (!removed) recorded_factors_.push_back(e.factors[i]);
  }
  for (Key key : e.values.keys())
    if (!recorded_values_.exists(key)) recorded_values_.insertFrom(e.values, key);
}

// Fixed lag: the marginalized states keep their estimate at marginalization (O(marginalized)).
void PppSmoother::forgetMarginalized(const smoother::Values& marginalized) {
  const smoother::ISAM2& isam = isam2();
  for (const auto& [key, value] : marginalized) {
    if (smoother::keySymbol(key) != 'x' || states_.empty()) continue;
    const std::uint32_t i = static_cast<std::uint32_t>(smoother::keyIndex(key));
    const std::uint32_t first = states_.front().index;
    if (i < first || i - first >= states_.size() || states_[i - first].index != i) continue;
    states_[i - first].last_estimate = ReceiverState::fromVector(value, layout_);
  }
  for (auto it = bias_last_state_.begin(); it != bias_last_state_.end();)
    it = isam.exists(it->first) ? std::next(it) : bias_last_state_.erase(it);
  // A held fix on a marginalized bias now lives in the marginal prior: permanent.
  held_.erase(std::remove_if(held_.begin(), held_.end(),
                             [&](const HeldFix& h) {
                               for (Key k : h.factor->keys())
                                 if (!isam.exists(k)) return true;
                               return false;
                             }),
              held_.end());
}

// Step 7
std::vector<PppEstimator::SolvedMeasurement> PppSmoother::residualRows(const SolveEpoch& e) const {
  std::vector<SolvedMeasurement> rows;
  for (std::size_t k = 0; k < e.n_sat; ++k) {
    if (!e.kept[k]) continue;
    const SatelliteMeasurement& m = e.in.screened[k].m;
    const SatellitePrediction prediction(m, e.in.predicted, options_.exact_range);
    SolvedMeasurement r;
    r.screened_index = k;
    r.m = m;
    r.new_arc = e.new_arc[k];
    r.phase_prefit_m = e.phase_prefit[k];
    r.code_postfit_m = m.observed_code_m - prediction.code_m(e.x_est, nullptr);
    r.phase_postfit_m = m.observed_phase_m - prediction.phase_m(e.x_est, nullptr) - arcs_.at(m.arc).filtered_m;
    rows.push_back(std::move(r));
  }
  return rows;
}

bool PppSmoother::recoverAfterFailure(EstimatorEpochResult& result) {
  // The failed update may have left its factors in the graph: start a new graph
  // from the last good state.
  keepReadableEstimates();
  newGraph();
  bias_last_state_.clear();
  held_.clear();  // the restart's priors carry the fixed estimates, not the factors
  joint_ = FilteredJoint{};
  if (states_.empty()) {  // failed at the first epoch: the next one starts afresh
    arcs_.clear();
    result.reason += "; smoother restarted (empty graph)";
    return true;
  }
  const StateRecord& last = states_.back();
  const Key x = stateKey(last.index);
  smoother::NonlinearFactorGraph factors;
  smoother::Values values;
  values.insert(x, filtered_.state.vector());
  factors.push_back(std::make_shared<smoother::PriorFactor>(x, filtered_.state.vector(),
                                                            NoiseModel::covariance(filtered_.covariance)));
  KeyVector newest{x};
  addRestartInertialFactors(last.index, factors, values, newest);
  const KeyVector stamped(newest.begin(), newest.end());  // the state and its inertial variables
  for (auto& [arc, slot] : arcs_) {
    values.insert(slot.key, Vector::Constant(1, slot.filtered_m));
    factors.push_back(std::make_shared<smoother::PriorFactor>(
        slot.key, Vector::Constant(1, slot.filtered_m), NoiseModel::isotropic(1, sigmaOf(slot.filtered_variance_m2))));
    slot.last_state = last.index;
    bias_last_state_[slot.key] = last.index;
    newest.push_back(slot.key);
  }
  try {
    if (lag_) {
      std::unordered_map<Key, double> stamps;
      for (Key k : stamped) stamps.emplace(k, lagStamp_s(last.time));
      lag_->update(factors, values, stamps, newest);
    } else {
      smoother::ISAM2UpdateParams up;
      up.newest_keys = newest;
      isam_->update(factors, values, up);
    }
  } catch (const std::exception& e) {
    result.reason += std::string("; smoother restart failed: ") + e.what();
    return false;
  }
  result.reason += "; smoother restarted from the last filtered state";
  return true;
}

void PppSmoother::keepReadableEstimates() {
  if (states_.empty()) return;
  try {
    const smoother::Values estimate = isam2().calculateBestEstimate();
    bool finite = true;
    for (const auto& s : states_) {
      if (!estimate.exists(stateKey(s.index))) continue;
      const Vector v = estimate.at(stateKey(s.index));
      finite = finite && v.allFinite();
    }
    if (finite)
      for (auto& s : states_)
        if (estimate.exists(stateKey(s.index)))
          s.last_estimate = ReceiverState::fromVector(estimate.at(stateKey(s.index)), layout_);
  } catch (const std::exception&) {
    // keep the last estimates
  }
}

std::vector<smoother::FactorIndex> PppSmoother::updateGraph(const smoother::NonlinearFactorGraph& add,
                                                            const std::vector<smoother::FactorIndex>& remove) {
  KeyVector newest;
  if (!states_.empty()) newest.push_back(stateKey(states_.back().index));
  for (ArcId arc : joint_.arcs)
    if (auto it = arcs_.find(arc); it != arcs_.end()) newest.push_back(it->second.key);
  std::vector<smoother::FactorIndex> indices;
  if (lag_) {
    indices = lag_->update(add, {}, {}, newest, remove).isam2.new_factor_indices;
  } else {
    smoother::ISAM2UpdateParams up;
    up.newest_keys = newest;
    up.remove_factor_indices = remove;
    up.ordering_group = orderingByLastState(bias_last_state_);
    indices = isam_->update(add, {}, up).new_factor_indices;
  }
  if (options_.record_graph) {
    for (const auto& f : add) recorded_factors_.push_back(f);
    for (const smoother::FactorIndex i : remove) {
      const auto h = std::find_if(held_.begin(), held_.end(), [i](const HeldFix& x) { return x.index == i; });
      if (h == held_.end()) continue;
      recorded_factors_.erase(std::remove(recorded_factors_.begin(), recorded_factors_.end(), h->factor),
                              recorded_factors_.end());
    }
  }
  return indices;
}

void PppSmoother::refreshFiltered() {
  if (states_.empty()) return;
  const smoother::ISAM2& isam = isam2();
  const int kRx = layout_.dim();
  const Key x = stateKey(states_.back().index);
  KeyVector keys{x};
  for (ArcId arc : joint_.arcs) keys.push_back(arcs_.at(arc).key);
  const smoother::Matrix P = isam.jointMarginalCovariance(keys);
  joint_.P = P;
  joint_.x = Eigen::VectorXd::Zero(P.rows());
  joint_.x.head(kRx) = isam.calculateEstimate(x);
  for (std::size_t j = 0; j < joint_.arcs.size(); ++j) {
    const int i = kRx + static_cast<int>(j);
    ArcSlot& slot = arcs_.at(joint_.arcs[j]);
    slot.filtered_m = isam.calculateEstimate(slot.key)(0);
    slot.filtered_variance_m2 = P(i, i);
    joint_.x(i) = slot.filtered_m;
  }
  filtered_.state = ReceiverState::fromVector(joint_.x.head(kRx), layout_);
  filtered_.covariance = P.topLeftCorner(kRx, kRx);
  states_.back().last_estimate = filtered_.state;
}

int PppSmoother::holdIntegerConstraints(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  return updateFixes({}, A, y).added;
}

int PppSmoother::releaseFixes(const std::vector<std::pair<ArcId, ArcId>>& pairs) {
  return updateFixes(pairs, Eigen::MatrixXd(0, joint_.x.size()), Eigen::VectorXd(0)).removed;
}

PppSmoother::FixChanges PppSmoother::updateFixes(const std::vector<std::pair<ArcId, ArcId>>& release,
                                                 const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  const int kRx = layout_.dim();
  if (A.rows() != y.size() || (A.rows() > 0 && A.cols() != joint_.x.size()))
    throw std::invalid_argument("updateFixes: constraint rows do not match the filtered joint (" +
                                std::to_string(A.rows()) + "x" + std::to_string(A.cols()) + ", " +
                                std::to_string(y.size()) + " values; joint " + std::to_string(joint_.x.size()) + ")");
  // The held fixes on the released single differences (either order) leave the graph.
  std::vector<smoother::FactorIndex> remove;
  for (const HeldFix& h : held_) {
    if (h.arcs.size() != 2) continue;
    for (const auto& [a, b] : release)
      if ((h.arcs[0] == a && h.arcs[1] == b) || (h.arcs[0] == b && h.arcs[1] == a)) {
        remove.push_back(h.index);
        break;
      }
  }
  const auto removed = [&remove](const HeldFix& h) {
    return std::find(remove.begin(), remove.end(), h.index) != remove.end();
  };
  const double sigma = options_.fixed_ambiguity_sigma_cycles;
  smoother::NonlinearFactorGraph add;
  std::vector<std::vector<ArcId>> add_arcs;
  for (int r = 0; r < A.rows(); ++r) {
    const Eigen::RowVectorXd a = A.row(r);
    KeyVector keys;
    std::vector<double> coefficients;
    std::vector<ArcId> arcs;
    for (int j = kRx; j < A.cols(); ++j) {
      if (a(j) == 0.0) continue;
      const ArcId arc = joint_.arcs[static_cast<std::size_t>(j - kRx)];
      keys.push_back(arcs_.at(arc).key);
      coefficients.push_back(a(j));
      arcs.push_back(arc);
    }
    if (keys.empty()) continue;
    std::vector<ArcId> sorted = arcs;
    std::sort(sorted.begin(), sorted.end());
    const bool held = std::any_of(held_.begin(), held_.end(),
                                  [&](const HeldFix& h) { return h.sorted_arcs == sorted && !removed(h); });
    if (held) continue;  // already held in the graph
    add.push_back(std::make_shared<IntegerAmbiguityFactor>(keys, coefficients, y(r), sigma));
    add_arcs.push_back(std::move(arcs));
  }
  if (add.empty() && remove.empty()) return {};
  const std::vector<smoother::FactorIndex> indices = updateGraph(add, remove);
  held_.erase(std::remove_if(held_.begin(), held_.end(), removed), held_.end());
  fixes_removed_ += remove.size();
  for (std::size_t i = 0; i < add.size() && i < indices.size(); ++i) {
    std::vector<ArcId> sorted = add_arcs[i];
    std::sort(sorted.begin(), sorted.end());
    held_.push_back(HeldFix{indices[i], add_arcs[i], add[i], std::move(sorted)});
  }
  refreshFiltered();
  return {static_cast<int>(remove.size()), static_cast<int>(add.size())};
}

std::optional<PppSmoother::FilteredJoint> PppSmoother::floatJoint() const {
  // The held fixes whose arcs are all in the joint are factors on joint variables
  // only, so their information comes out of the joint marginal exactly:
  // P_float^-1 = P^-1 - A^T W A, i.e. (Woodbury) P_float = P + P A^T S^-1 A P with
  // S = W^-1 - A P A^T (positive: the fixed variance of A x is below its factor's),
  // and x_float = x + P_float A^T W (A x - y) = x + P A^T S^-1 (A x - y)
  // (P_float A^T W = P A^T W + P A^T S^-1 (W^-1 - S) W = P A^T S^-1).
  const int kRx = layout_.dim();
  std::map<ArcId, int> column;
  for (std::size_t j = 0; j < joint_.arcs.size(); ++j) column[joint_.arcs[j]] = kRx + static_cast<int>(j);
  std::vector<const HeldFix*> in_joint;
  for (const HeldFix& h : held_) {
    bool all = true;
    for (ArcId a : h.arcs) all = all && column.count(a) > 0;
    if (all) in_joint.push_back(&h);
  }
  const int k = static_cast<int>(in_joint.size());
  if (k == 0) return joint_;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(k, joint_.x.size());
  Eigen::VectorXd y(k), w(k);
  for (int i = 0; i < k; ++i) {
    const HeldFix& h = *in_joint[static_cast<std::size_t>(i)];
    const auto* f = static_cast<const IntegerAmbiguityFactor*>(h.factor.get());
    for (std::size_t j = 0; j < h.arcs.size(); ++j) A(i, column.at(h.arcs[j])) += f->coefficients_per_m()[j];
    y(i) = f->value_cycles();
    w(i) = 1.0 / (f->sigma_cycles() * f->sigma_cycles());
  }
  const Eigen::MatrixXd PAt = joint_.P * A.transpose();
  Eigen::MatrixXd S = -A * PAt;
  S.diagonal() += w.cwiseInverse();
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (S + S.transpose()));
  if (llt.info() != Eigen::Success) return std::nullopt;
  FilteredJoint out;
  out.arcs = joint_.arcs;
  out.P = joint_.P + PAt * llt.solve(PAt.transpose());
  out.P = 0.5 * (out.P + out.P.transpose());
  out.x = joint_.x + PAt * llt.solve(A * joint_.x - y);
  return out;
}


}  // namespace ppp

namespace ppp {

void PppSmoother::resolveAmbiguities(const EstimatorEpochInput& input, EstimatorEpochResult& r) {
  // The EKF's decision path (resolveAndHold) on the smoother's float joint; the
  // held integers are factors of the graph, a wrong one released is removed.
  AmbiguityResolver& ambiguity = resolver();
  if (r.estimator_reset) ambiguity.releaseAll();  // a restart drops the graph's fixes
  if (input.observations && input.arcs) ambiguity.addEpoch(*input.observations, *input.arcs, input.phase_biases);
  AmbiguityFixSummary summary;
  if (r.status == EpochStatus::Ok && r.solution) {
    bool changed = false;
    try {
      changed = resolveOnFloatJoint(input, r, summary);
    } catch (const std::exception& e) {
      summary.float_reason = AmbiguityFloatReason::NumericalFailure;
      r.reason += std::string("; ambiguity fix not applied: ") + e.what();
    }
    if (changed) {
      r.solution->state = filteredSolution().state;
      r.solution->covariance = filteredSolution().covariance;
    }
    if (summary.fixed()) r.ambiguities = AmbiguityState::Fixed;
  }
  r.ambiguity_fix = summary;
}

bool PppSmoother::resolveOnFloatJoint(const EstimatorEpochInput& input, const EstimatorEpochResult& r,
                                      AmbiguityFixSummary& summary) {
  const std::optional<FilteredJoint> joint = floatJoint();
  if (!joint) {
    summary.float_reason = AmbiguityFloatReason::NumericalFailure;
    return false;
  }
  const int receiver_dim = r.solution->state.layout.dim();
  std::map<ArcId, double> elevation_rad;
  for (const auto& res : r.residuals) elevation_rad[res.arc] = res.elevation_rad;
  const auto fixed = resolver().resolveAndHold(joint->x, joint->P, receiver_dim, joint->arcs, input.phase_biases,
                                               summary, &elevation_rad);
  std::vector<std::pair<ArcId, ArcId>> wrong;
  for (const AmbiguityRelease& rel : summary.released)
    if (rel.reason != AmbiguityReleaseReason::ArcEnded) wrong.emplace_back(rel.arc, rel.reference_arc);
  // Removals and additions in one graph update.
  const Eigen::MatrixXd none(0, joint->x.size());
  const FixChanges c = updateFixes(wrong, fixed ? fixed->constraint_rows : none,
                                   fixed ? fixed->constraint_values : Eigen::VectorXd(0));
  return c.removed > 0 || c.added > 0;
}

}  // namespace ppp
