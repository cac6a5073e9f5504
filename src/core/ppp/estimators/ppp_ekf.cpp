#include "ppp_bayes_tree/ppp/estimators/ppp_ekf.h"

#include "ppp_bayes_tree/ppp/screening/postfit_screening.h"
#include "ppp_bayes_tree/ppp/screening/prefit_screening.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace ppp {
namespace {

/// Symmetrise P and check it is finite and positive definite; empty when fine.
std::string checkCovariance(Eigen::MatrixXd& P) {
  if (!P.allFinite()) return "non-finite covariance";
  P = 0.5 * (P + P.transpose()).eval();
  Eigen::LLT<Eigen::MatrixXd> llt(P);
  if (llt.info() != Eigen::Success) return "covariance not positive definite";
  return {};
}

}  // namespace

std::string EkfOptions::validate() const {
  if (auto problem = screening.validate(); !problem.empty()) return problem;
  if (iterations_per_epoch < 1) return "iterations_per_epoch must be >= 1";
  return {};
}

// One row pair (code, phase) of the update.
struct PppEkf::Row {
  std::size_t screened_index = 0;
  SatelliteMeasurement m;  // linearised at the current point
  int bias_index = 0;      // state index of the arc's bias
  bool new_arc = false;
  double phase_prefit_m = 0.0;
};

PppEkf::PppEkf(StochasticModel model, EkfOptions options, CodeLeastSquaresOptions start_options,
               ReceiverStateLayout layout)
    : PppEstimator(model, options.screening, start_options, layout), options_(options) {}

PppEkf::PppEkf(const EstimatorOptions& options)
    : PppEstimator(options.stochastic, options.ekf.screening, options.start,
                   ReceiverStateLayout(options.systems, options.troposphere_gradients), options.ambiguity_resolution),
      options_(options.ekf) {}

void PppEkf::resolveAmbiguities(const EstimatorEpochInput& input, EstimatorEpochResult& r) {
  // The filter stays float; the fixed solution is a constrained copy of it,
  // conditioned on the integers validated across epochs and held.
  AmbiguityResolver& ambiguity = resolver();
  if (r.estimator_reset) ambiguity.releaseAll();
  if (input.observations && input.arcs) ambiguity.addEpoch(*input.observations, *input.arcs, input.phase_biases);
  AmbiguityFixSummary summary;
  if (r.status == EpochStatus::Ok && r.solution) {
    const std::vector<ArcId> arcs = activeArcs();
    std::map<ArcId, double> elevation_rad;
    for (const auto& res : r.residuals) elevation_rad[res.arc] = res.elevation_rad;
    // The biases follow the core (coreDim()); the fixed receiver state is read
    // from the fixed core through the same seam as the float one.
    const auto fixed = ambiguity.resolveAndHold(stateVector(), covarianceMatrix(), coreDim(), arcs,
                                                input.phase_biases, summary, &elevation_rad);
    if (fixed) {
      r.solution->state = receiverStateAt(fixed->x);
      r.solution->covariance = receiverCovarianceAt(fixed->x, fixed->P);
      r.ambiguities = AmbiguityState::Fixed;
      fixedSolutionFound(*fixed);
    }
  }
  r.ambiguity_fix = summary;
}

PppEkf::Filter PppEkf::initialFilter(const ReceiverState& state) const {
  ReceiverState s(layout_);
  s.position_ecef_m = state.position_ecef_m;
  s.zwd_m = state.zwd_m;
  for (const GnssSystem system : layout_.clockSystems()) s.setClock_m(system, state.clock_m(system));
  s.gradient_north_m = state.gradient_north_m;
  s.gradient_east_m = state.gradient_east_m;
  Filter f;
  f.x = s.vector();
  const int n = layout_.dim();
  f.P = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < ReceiverStateLayout::kPositionSize; ++i)
    f.P(layout_.position() + i, layout_.position() + i) = model_.position.initialVariance_m2();
  f.P(layout_.zwd(), layout_.zwd()) = model_.zwd.initialVariance_m2();
  for (const GnssSystem system : layout_.clockSystems())
    f.P(layout_.clock(system), layout_.clock(system)) = model_.clock.initialVariance_m2();
  if (layout_.hasGradients()) {
    for (const int g : {layout_.gradientNorth(), layout_.gradientEast()})
      f.P(g, g) = model_.troposphere_gradient.initialVariance_m2();
  }
  return f;
}

void PppEkf::initialise(const GnssTime& time, const ReceiverState& state) {
  f_ = initialFilter(state);
  last_time_ = time;
  initialised_ = true;
  fresh_ = true;
}

ReceiverState PppEkf::receiverState() const {
  if (!initialised_) return ReceiverState(layout_);
  return receiverStateAt(f_.x);
}

ReceiverCovariance PppEkf::receiverCovariance() const {
  if (!initialised_) return ReceiverCovariance::Zero(layout_.dim(), layout_.dim());
  return receiverCovarianceAt(f_.x, f_.P);
}

ReceiverState PppEkf::receiverStateAt(const Eigen::VectorXd& x) const {
  return ReceiverState::fromVector(x.head(layout_.dim()), layout_);
}

ReceiverCovariance PppEkf::receiverCovarianceAt(const Eigen::VectorXd& /*x*/, const Eigen::MatrixXd& P) const {
  return P.topLeftCorner(layout_.dim(), layout_.dim());
}

Eigen::RowVectorXd PppEkf::coreJacobian(const SatelliteMeasurement& m, const Eigen::VectorXd& /*x*/) const {
  return m.jacobian;
}

std::vector<ArcId> PppEkf::activeArcs() const {
  std::vector<ArcId> arcs;
  for (const auto& b : f_.biases) arcs.push_back(b.arc);
  return arcs;
}

int PppEkf::findBias(const Filter& f, ArcId arc) {
  for (std::size_t i = 0; i < f.biases.size(); ++i)
    if (f.biases[i].arc == arc) return static_cast<int>(i);
  return -1;
}

std::optional<double> PppEkf::biasEstimate_m(ArcId arc) const {
  const int i = findBias(f_, arc);
  if (i < 0) return std::nullopt;
  return f_.x(coreDim() + i);
}

std::optional<double> PppEkf::biasSigma_m(ArcId arc) const {
  const int i = findBias(f_, arc);
  if (i < 0) return std::nullopt;
  const int k = coreDim() + i;
  return std::sqrt(f_.P(k, k));
}

void PppEkf::removeBias(Filter& f, std::size_t slot, int receiver_dim) {
  const int n = static_cast<int>(f.x.size());
  const int k = receiver_dim + static_cast<int>(slot);
  const int tail = n - k - 1;
  Eigen::VectorXd x(n - 1);
  x << f.x.head(k), f.x.tail(tail);
  Eigen::MatrixXd P(n - 1, n - 1);
  P.topLeftCorner(k, k) = f.P.topLeftCorner(k, k);
  P.topRightCorner(k, tail) = f.P.topRightCorner(k, tail);
  P.bottomLeftCorner(tail, k) = f.P.bottomLeftCorner(tail, k);
  P.bottomRightCorner(tail, tail) = f.P.bottomRightCorner(tail, tail);
  f.x = std::move(x);
  f.P = std::move(P);
  f.biases.erase(f.biases.begin() + static_cast<std::ptrdiff_t>(slot));
}

void PppEkf::arcRemoved(ArcId arc) {
  const int i = findBias(f_, arc);
  if (i >= 0) removeBias(f_, static_cast<std::size_t>(i), coreDim());
  // An arc ended between the prediction and the update (a bridged gap) leaves the prediction too.
  const int w = findBias(work_, arc);
  if (w >= 0) removeBias(work_, static_cast<std::size_t>(w), coreDim());
}

void PppEkf::predictFilter(Filter& f, double dt_s, bool first) const {
  if (first) return;  // freshly initialised at this very time: the a priori covariance stands
  const double q_pos = model_.position.processVariance_m2(dt_s);
  for (int i = 0; i < ReceiverStateLayout::kPositionSize; ++i)
    f.P(layout_.position() + i, layout_.position() + i) += q_pos;
  predictDelaysClocksBiases(f, dt_s);
}

void PppEkf::predictDelaysClocksBiases(Filter& f, double dt_s) const {
  const int zwd = coreIndex(layout_.zwd());
  f.P(zwd, zwd) += zwdProcessVariance_m2(dt_s);
  if (layout_.hasGradients()) {
    for (const int g : {coreIndex(layout_.gradientNorth()), coreIndex(layout_.gradientEast())})
      f.P(g, g) += model_.troposphere_gradient.processVariance_m2(dt_s);
  }
  // White clocks: no memory, correlations removed, variance reset.
  for (const GnssSystem system : layout_.clockSystems()) {
    const int c = clockIndex(system);
    f.P.row(c).setZero();
    f.P.col(c).setZero();
    f.P(c, c) = model_.clock.processVariance_m2(dt_s);
  }
  const double q_bias = model_.phase_bias.processVariance_m2(dt_s);
  for (Eigen::Index i = coreDim(); i < f.P.rows(); ++i) f.P(i, i) += q_bias;
}

Eigen::MatrixXd PppEkf::predictedCovariance(double dt_s) const {
  Filter f = f_;
  if (initialised_) predictFilter(f, dt_s, false);
  return f.P;
}

ReceiverState PppEkf::predict(double dt_s, bool first, const std::optional<ReceiverState>& start) {
  if (start) {
    work_ = initialFilter(*start);
  } else {
    work_ = f_;
    predictFilter(work_, dt_s, first);
  }
  return receiverStateAt(work_.x);
}

std::optional<ArcBiasPrior> PppEkf::predictedBias(ArcId arc) const {
  const int slot = findBias(work_, arc);
  if (slot < 0) return std::nullopt;
  const int k = coreDim() + slot;
  return ArcBiasPrior{work_.x(k), work_.P(k, k)};
}

// One update attempt: the prediction with this attempt's new biases, its rows
// and the iterated update's linear system.
struct PppEkf::Attempt {
  Filter f;
  std::vector<Row> rows;
  Eigen::VectorXd x_lin, x_new;
  Eigen::MatrixXd H, K;
  Eigen::VectorXd R, y_lin;  // R diagonal; y_lin = z - h(x_lin)
  Eigen::MatrixXd P;         // the updated covariance (Joseph form)
  Eigen::VectorXd postfit;   // postfit residuals at x_new (code, phase per row)
  int satellites() const { return static_cast<int>(rows.size()); }
};

bool PppEkf::solve(const EpochSolveInput& in, EpochSolveOutput& out, EstimatorEpochResult& result) {
  // 1. The prediction with the front end's clock shifts, without the arcs that leave.
  const Filter fp = shiftedPrediction(in);
  // Each rejection (re-linearisation, postfit) restarts from the prediction without the satellite.
  std::set<SatelliteId> excluded;
  for (;;) {
    // 2. The rows of the satellites still in, a bias at the front end's value for each new arc.
    Attempt a;
    a.f = fp;
    a.rows = updateRows(in, excluded, a.f);
    if (a.satellites() < options_.screening.min_satellites)
      return fail(result, EpochStatus::NoSolution, NoSolutionReason::TooFewSatellites,
                  std::to_string(a.satellites()) + " satellites usable after screening, at least " +
                      std::to_string(options_.screening.min_satellites) + " needed");
    // 3. The iterated update, re-linearising through the measurement function.
    const UpdateStep step = iterateUpdate(in, a, excluded, result);
    if (step == UpdateStep::Failed) return false;
    if (step == UpdateStep::Restart) continue;
    // 4. The covariance in Joseph form, checked.
    if (!josephCovariance(a, result)) return false;
    // 5. The postfit check at the updated state.
    if (postfitRejects(a, excluded, result)) continue;
    // 6. Commit the filter; the solution and its rows.
    commitUpdate(in, std::move(a), out);
    return true;
  }
}

PppEkf::Filter PppEkf::shiftedPrediction(const EpochSolveInput& in) const {
  const int kRx = coreDim();
  Filter fp = work_;
  for (const GnssSystem system : layout_.clockSystems()) fp.x(clockIndex(system)) = in.predicted.clock_m(system);
  for (const ArcId arc : in.dropped_arcs) {
    const int slot = findBias(fp, arc);
    if (slot >= 0) removeBias(fp, static_cast<std::size_t>(slot), kRx);
  }
  return fp;
}

std::vector<PppEkf::Row> PppEkf::updateRows(const EpochSolveInput& in, const std::set<SatelliteId>& excluded,
                                            Filter& fa) const {
  const int kRx = coreDim();
  std::vector<Row> rows;
  for (std::size_t k = 0; k < in.screened.size(); ++k) {
    const SatelliteMeasurement& m = in.screened[k].m;
    if (excluded.count(m.satellite)) continue;
    Row row;
    row.screened_index = k;
    row.m = m;
    int slot = findBias(fa, m.arc);
    if (slot < 0) {  // new arc: the front end's initial value, a priori sigma
      const Eigen::Index n = fa.x.size();
      fa.x.conservativeResize(n + 1);
      fa.x(n) = in.screened[k].new_arc_bias_m;
      fa.P.conservativeResizeLike(Eigen::MatrixXd::Zero(n + 1, n + 1));
      fa.P(n, n) = model_.phase_bias.initialVariance_m2();
      fa.biases.push_back({m.arc, m.satellite});
      slot = static_cast<int>(fa.biases.size()) - 1;
      row.new_arc = true;
    }
    row.bias_index = kRx + slot;
    row.phase_prefit_m = m.phaseResidualWithoutBias_m() - fa.x(row.bias_index);
    rows.push_back(row);
  }
  return rows;
}

PppEkf::UpdateStep PppEkf::iterateUpdate(const EpochSolveInput& in, Attempt& a, std::set<SatelliteId>& excluded,
                                         EstimatorEpochResult& result) const {
  // Iterated update: x_{i+1} = x_pred + K_i (z - h(x_i) - H_i (x_pred - x_i)).
  // The code variances carry the correlation of the code errors over dt (stochastic_model.h).
  const double code_variance_factor = model_.codeVarianceFactor(in.dt_s);
  a.x_lin = a.f.x;
  a.x_new = a.f.x;
  for (int it = 0; it < options_.iterations_per_epoch; ++it) {
    if (it > 0) {
      a.x_lin = a.x_new;
      if (!relinearise(in, a, excluded, result)) return UpdateStep::Restart;
    }
    linearSystem(a, code_variance_factor);
    if (!kalmanGain(a, result)) return UpdateStep::Failed;
  }
  return UpdateStep::Done;
}

bool PppEkf::relinearise(const EpochSolveInput& in, Attempt& a, std::set<SatelliteId>& excluded,
                         EstimatorEpochResult& result) const {
  const EpochMeasurements again = (*in.evaluate)(receiverStateAt(a.x_lin));
  result.iterations += 1;
  for (auto& row : a.rows) {
    auto found = std::find_if(again.used.begin(), again.used.end(),
                              [&](const SatelliteMeasurement& m) { return m.satellite == row.m.satellite; });
    std::string problem =
        found == again.used.end() ? "left out by the model at re-linearisation" : measurementProblem(*found);
    if (problem.empty() && found->arc != row.m.arc) problem = "arc changed at re-linearisation";
    if (problem.empty() && !matchesLayout(*found, layout_)) problem = "Jacobian outside the state layout";
    if (!problem.empty()) {
      excluded.insert(row.m.satellite);
      result.rejected.push_back({row.m.satellite, RejectionReason::Relinearisation, problem});
      return false;
    }
    row.m = *found;
  }
  return true;
}

void PppEkf::linearSystem(Attempt& a, double code_variance_factor) const {
  const int kRx = coreDim();
  const int n_sat = a.satellites();
  a.H = Eigen::MatrixXd::Zero(2 * n_sat, a.f.x.size());
  a.R.resize(2 * n_sat);
  a.y_lin.resize(2 * n_sat);
  for (int k = 0; k < n_sat; ++k) {
    const auto& row = a.rows[k];
    const Eigen::RowVectorXd jacobian = coreJacobian(row.m, a.x_lin);
    a.H.block(2 * k, 0, 1, kRx) = jacobian;
    a.H.block(2 * k + 1, 0, 1, kRx) = jacobian;
    a.H(2 * k + 1, row.bias_index) = 1.0;
    a.R(2 * k) = row.m.code_sigma_m * row.m.code_sigma_m * code_variance_factor;
    a.R(2 * k + 1) = row.m.phase_sigma_m * row.m.phase_sigma_m;
    a.y_lin(2 * k) = row.m.codeResidual_m();
    a.y_lin(2 * k + 1) = row.m.phaseResidualWithoutBias_m() - a.x_lin(row.bias_index);
  }
}

bool PppEkf::kalmanGain(Attempt& a, EstimatorEpochResult& result) const {
  const Eigen::VectorXd y = a.y_lin - a.H * (a.f.x - a.x_lin);
  const Eigen::MatrixXd PHt = a.f.P * a.H.transpose();
  Eigen::MatrixXd S = a.H * PHt;
  S.diagonal() += a.R;
  Eigen::LDLT<Eigen::MatrixXd> ldlt(S);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive())
    return fail(result, EpochStatus::Failed, NoSolutionReason::InnovationNotPositiveDefinite,
                "innovation covariance not positive definite");
  a.K = ldlt.solve(PHt.transpose()).transpose();
  a.x_new = a.f.x + a.K * y;
  if (!a.x_new.allFinite())
    return fail(result, EpochStatus::Failed, NoSolutionReason::NonFiniteState, "non-finite state after the update");
  return true;
}

bool PppEkf::josephCovariance(Attempt& a, EstimatorEpochResult& result) const {
  // Joseph form: P = (I - KH) P (I - KH)^T + K R K^T.
  const Eigen::Index dim = a.f.x.size();
  const Eigen::MatrixXd IKH = Eigen::MatrixXd::Identity(dim, dim) - a.K * a.H;
  Eigen::MatrixXd P = IKH * a.f.P * IKH.transpose() + a.K * a.R.asDiagonal() * a.K.transpose();
  if (auto problem = checkCovariance(P); !problem.empty())
    return fail(result, EpochStatus::Failed, NoSolutionReason::CovarianceNotPositiveDefinite,
                problem + " after the update");
  a.P = std::move(P);
  return true;
}

bool PppEkf::postfitRejects(Attempt& a, std::set<SatelliteId>& excluded, EstimatorEpochResult& result) const {
  // Postfit residuals at the updated state; optional check (postfit_screening.h).
  const Eigen::VectorXd postfit = a.y_lin - a.H * (a.x_new - a.x_lin);
  a.postfit = postfit;
  const ScreeningOptions& sc = options_.screening;
  if (!sc.postfit_check || result.postfit_rejections >= sc.postfit_max_rejections) return false;
  const int n_sat = a.satellites();
  std::vector<PostfitResidualPair> pairs(static_cast<std::size_t>(n_sat));
  for (int k = 0; k < n_sat; ++k)
    pairs[static_cast<std::size_t>(k)] = {postfit(2 * k), postfit(2 * k + 1), std::sqrt(a.R(2 * k)),
                                          std::sqrt(a.R(2 * k + 1))};
  const auto worst = worstPostfitResidual(pairs, sc.postfit_sigmas);
  if (!worst) return false;
  const auto& row = a.rows[worst->index];
  excluded.insert(row.m.satellite);
  result.rejected.push_back(postfitRejection(row.m.satellite, *worst, sc.postfit_sigmas));
  ++result.postfit_rejections;
  return true;
}

void PppEkf::commitUpdate(const EpochSolveInput& in, Attempt a, EpochSolveOutput& out) {
  a.f.x = a.x_new;
  a.f.P = std::move(a.P);
  closeLoop(a.f);
  f_ = std::move(a.f);
  last_time_ = in.time;
  initialised_ = true;
  fresh_ = false;
  out.solution.state = receiverState();
  out.solution.covariance = receiverCovariance();
  out.ambiguities = AmbiguityState::Float;
  for (int k = 0; k < a.satellites(); ++k) {
    const auto& row = a.rows[k];
    SolvedMeasurement s;
    s.screened_index = row.screened_index;
    s.m = row.m;
    s.new_arc = row.new_arc;
    s.phase_prefit_m = row.phase_prefit_m;
    s.code_postfit_m = a.postfit(2 * k);
    s.phase_postfit_m = a.postfit(2 * k + 1);
    out.rows.push_back(std::move(s));
  }
}

}  // namespace ppp
