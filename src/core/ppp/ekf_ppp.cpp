#include "ppp_bayes_tree/ppp/ekf_ppp.h"

#include "ppp_bayes_tree/ppp/prefit_screening.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace ppp {
namespace {

constexpr int kRx = ReceiverState::kDim;

std::string fmt(double v, int precision = 3) {
  std::ostringstream os;
  os.precision(precision);
  os << std::fixed << v;
  return os.str();
}

/// Symmetrise P and check it is finite and positive definite; empty when fine.
std::string checkCovariance(Eigen::MatrixXd& P) {
  if (!P.allFinite()) return "non-finite covariance";
  P = 0.5 * (P + P.transpose()).eval();
  Eigen::LLT<Eigen::MatrixXd> llt(P);
  if (llt.info() != Eigen::Success) return "covariance not positive definite";
  return {};
}

}  // namespace

std::string toString(EpochStatus status) {
  switch (status) {
    case EpochStatus::Ok: return "ok";
    case EpochStatus::NoSolution: return "no_solution";
    case EpochStatus::Failed: return "failed";
  }
  return "unknown";
}

std::string EkfOptions::validate() const {
  if (auto problem = screening.validate(); !problem.empty()) return problem;
  if (iterations_per_epoch < 1) return "iterations_per_epoch must be >= 1";
  if (!(postfit_sigmas > 0.0)) return "postfit_sigmas must be > 0";
  if (postfit_max_rejections < 0) return "postfit_max_rejections must be >= 0";
  return {};
}

// One row pair (code, phase) of the update.
struct EkfPpp::Row {
  SatelliteMeasurement m;  // linearised at the current point
  int bias_index = 0;      // state index of the arc's bias
  bool new_arc = false;
  double code_prefit_m = 0.0;
  double phase_prefit_m = 0.0;
};

EkfPpp::EkfPpp(StochasticModel model, EkfOptions options, CodeLeastSquaresOptions start_options)
    : model_(model), options_(options), start_options_(start_options) {}

void EkfPpp::initialise(const GnssTime& time, const ReceiverState& state) {
  f_.x = state.vector();
  f_.P = Eigen::MatrixXd::Zero(kRx, kRx);
  for (int i = 0; i < 3; ++i) f_.P(i, i) = model_.position.initialVariance_m2();
  f_.P(3, 3) = model_.zwd.initialVariance_m2();
  f_.P(4, 4) = model_.clock.initialVariance_m2();
  f_.biases.clear();
  last_time_ = time;
  initialised_ = true;
  fresh_ = true;
}

ReceiverState EkfPpp::receiverState() const {
  if (!initialised_) return {};
  return ReceiverState::fromVector(f_.x.head<kRx>());
}

ReceiverCovariance EkfPpp::receiverCovariance() const {
  if (!initialised_) return ReceiverCovariance::Zero();
  return f_.P.topLeftCorner<kRx, kRx>();
}

std::vector<ArcId> EkfPpp::activeArcs() const {
  std::vector<ArcId> arcs;
  for (const auto& b : f_.biases) arcs.push_back(b.arc);
  return arcs;
}

int EkfPpp::findBias(const Filter& f, ArcId arc) {
  for (std::size_t i = 0; i < f.biases.size(); ++i)
    if (f.biases[i].arc == arc) return static_cast<int>(i);
  return -1;
}

std::optional<double> EkfPpp::biasEstimate_m(ArcId arc) const {
  const int i = findBias(f_, arc);
  if (i < 0) return std::nullopt;
  return f_.x(kRx + i);
}

std::optional<double> EkfPpp::biasSigma_m(ArcId arc) const {
  const int i = findBias(f_, arc);
  if (i < 0) return std::nullopt;
  return std::sqrt(f_.P(kRx + i, kRx + i));
}

void EkfPpp::removeBias(Filter& f, std::size_t slot) {
  const int n = static_cast<int>(f.x.size());
  const int k = kRx + static_cast<int>(slot);
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

void EkfPpp::removeArc(ArcId arc) {
  const int i = findBias(f_, arc);
  if (i >= 0) removeBias(f_, static_cast<std::size_t>(i));
}

void EkfPpp::predict(Filter& f, double dt_s, bool first) const {
  if (first) return;  // freshly initialised at this very time: the a priori covariance stands
  const double q_pos = model_.position.processVariance_m2(dt_s);
  for (int i = 0; i < 3; ++i) f.P(i, i) += q_pos;
  f.P(3, 3) += model_.zwd.processVariance_m2(dt_s);
  // White clock: no memory, correlations removed, variance reset.
  f.P.row(4).setZero();
  f.P.col(4).setZero();
  f.P(4, 4) = model_.clock.processVariance_m2(dt_s);
  const double q_bias = model_.phase_bias.processVariance_m2(dt_s);
  for (Eigen::Index i = kRx; i < f.P.rows(); ++i) f.P(i, i) += q_bias;
}

Eigen::MatrixXd EkfPpp::predictedCovariance(double dt_s) const {
  Filter f = f_;
  if (initialised_) predict(f, dt_s, false);
  return f.P;
}

EkfEpochResult EkfPpp::processEpoch(const GnssTime& time, const MeasurementFunction& evaluate) {
  EkfEpochResult result;
  result.time = time;
  const bool was_initialised = initialised_;
  const bool was_fresh = fresh_;
  const GnssTime was_last_time = last_time_;
  const Filter before = f_;
  auto giveUp = [&](EpochStatus status, std::string reason) {
    f_ = before;  // nothing of this epoch is kept
    initialised_ = was_initialised;
    fresh_ = was_fresh;
    last_time_ = was_last_time;
    result.status = status;
    result.reason = std::move(reason);
    result.solution.reset();
    result.active_biases = activeBiasCount();
    return result;
  };

  // Start: single-epoch code least squares.
  if (!initialised_) {
    ReceiverState start;
    start.position_ecef_m = approx_position_ecef_m_.value_or(Eigen::Vector3d::Zero());
    start.zwd_m = model_.initial_zwd_m;
    const CodeLeastSquaresResult ls = codeLeastSquares(evaluate, start, start_options_);
    result.iterations += ls.iterations;
    if (!ls.ok) {
      result.rejected = ls.rejected;
      return giveUp(EpochStatus::NoSolution, "no initial position: " + ls.reason);
    }
    initialise(time, ls.state);
  }
  const double dt = time - last_time_;
  result.dt_s = dt;
  const bool first = fresh_ && dt == 0.0;
  if (!std::isfinite(dt) || dt < 0.0 || (dt == 0.0 && !first))
    return giveUp(EpochStatus::Failed, "epoch " + time.toString() + " is not after the last solved epoch " +
                                           last_time_.toString());

  // 1. Prediction.
  Filter fp = f_;
  predict(fp, dt, first);

  // 2. Linearise at the prediction; keep finite, unique measurements.
  const EpochMeasurements epoch0 = evaluate(ReceiverState::fromVector(fp.x.head<kRx>()));
  result.iterations += 1;
  result.rejected = epoch0.rejected;
  std::vector<SatelliteMeasurement> cand = usableMeasurements(epoch0.used, result.rejected);
  if (options_.screening.clock_from_code_median) {
    if (const auto shift = medianCodeClockShift_m(cand)) {
      fp.x(4) += *shift;
      applyClockShift(cand, *shift);
    }
  }

  // Arc bookkeeping: a new arc of a satellite replaces its bias; stale arcs go.
  for (const auto& m : cand) {
    for (std::size_t i = 0; i < fp.biases.size(); ++i) {
      if (fp.biases[i].satellite == m.satellite && fp.biases[i].arc != m.arc) {
        removeBias(fp, i);
        break;
      }
    }
  }
  for (std::size_t i = fp.biases.size(); i-- > 0;) {
    if (time - fp.biases[i].last_used > options_.screening.stale_arc_timeout_s) removeBias(fp, i);
  }

  // 3. Prefit screening.
  PrefitScreeningResult screening =
      screenPrefit(cand, options_.screening, [&fp](ArcId arc) -> std::optional<ArcBiasPrior> {
        const int slot = findBias(fp, arc);
        if (slot < 0) return std::nullopt;
        return ArcBiasPrior{fp.x(kRx + slot), fp.P(kRx + slot, kRx + slot)};
      });
  result.prefit_rejections += static_cast<int>(screening.rejected.size());
  result.rejected.insert(result.rejected.end(), screening.rejected.begin(), screening.rejected.end());
  const std::vector<SatelliteMeasurement>& screened = screening.kept;

  // 4-6. Update, with postfit rejections (each one restarts from the prediction).
  std::set<SatelliteId> excluded;
  for (;;) {
    std::vector<Row> rows;
    Filter fa = fp;
    for (const auto& m : screened) {
      if (excluded.count(m.satellite)) continue;
      Row row;
      row.m = m;
      row.code_prefit_m = m.codeResidual_m();
      int slot = findBias(fa, m.arc);
      if (slot < 0) {  // new arc: bias from phase minus code, a priori sigma
        const double b0 = m.phaseResidualWithoutBias_m() - m.codeResidual_m();
        const Eigen::Index n = fa.x.size();
        fa.x.conservativeResize(n + 1);
        fa.x(n) = b0;
        fa.P.conservativeResizeLike(Eigen::MatrixXd::Zero(n + 1, n + 1));
        fa.P(n, n) = model_.phase_bias.initialVariance_m2();
        fa.biases.push_back({m.arc, m.satellite, time});
        slot = static_cast<int>(fa.biases.size()) - 1;
        row.new_arc = true;
      }
      row.bias_index = kRx + slot;
      row.phase_prefit_m = m.phaseResidualWithoutBias_m() - fa.x(row.bias_index);
      rows.push_back(row);
    }
    const int n_sat = static_cast<int>(rows.size());
    if (n_sat < options_.screening.min_satellites)
      return giveUp(EpochStatus::NoSolution, std::to_string(n_sat) + " satellites usable after screening, at least " +
                                                 std::to_string(options_.screening.min_satellites) + " needed");

    // Iterated update: x_{i+1} = x_pred + K_i (z - h(x_i) - H_i (x_pred - x_i)).
    const Eigen::Index dim = fa.x.size();
    Eigen::VectorXd x_lin = fa.x, x_new = fa.x;
    Eigen::MatrixXd H, K;
    Eigen::VectorXd R, y_lin;  // R diagonal; y_lin = z - h(x_lin)
    bool restart = false;
    for (int it = 0; it < options_.iterations_per_epoch && !restart; ++it) {
      if (it > 0) {
        x_lin = x_new;
        const EpochMeasurements again = evaluate(ReceiverState::fromVector(x_lin.head<kRx>()));
        result.iterations += 1;
        for (auto& row : rows) {
          auto found = std::find_if(again.used.begin(), again.used.end(),
                                    [&](const SatelliteMeasurement& m) { return m.satellite == row.m.satellite; });
          std::string problem = found == again.used.end() ? "left out by the model at re-linearisation"
                                                         : measurementProblem(*found);
          if (problem.empty() && found->arc != row.m.arc) problem = "arc changed at re-linearisation";
          if (!problem.empty()) {
            excluded.insert(row.m.satellite);
            result.rejected.push_back({row.m.satellite, problem});
            restart = true;
            break;
          }
          row.m = *found;
        }
        if (restart) break;
      }
      H = Eigen::MatrixXd::Zero(2 * n_sat, dim);
      R.resize(2 * n_sat);
      y_lin.resize(2 * n_sat);
      for (int k = 0; k < n_sat; ++k) {
        const auto& row = rows[k];
        H.block(2 * k, 0, 1, kRx) = row.m.jacobian;
        H.block(2 * k + 1, 0, 1, kRx) = row.m.jacobian;
        H(2 * k + 1, row.bias_index) = 1.0;
        R(2 * k) = row.m.code_sigma_m * row.m.code_sigma_m;
        R(2 * k + 1) = row.m.phase_sigma_m * row.m.phase_sigma_m;
        y_lin(2 * k) = row.m.codeResidual_m();
        y_lin(2 * k + 1) = row.m.phaseResidualWithoutBias_m() - x_lin(row.bias_index);
      }
      const Eigen::VectorXd y = y_lin - H * (fa.x - x_lin);
      const Eigen::MatrixXd PHt = fa.P * H.transpose();
      Eigen::MatrixXd S = H * PHt;
      S.diagonal() += R;
      Eigen::LDLT<Eigen::MatrixXd> ldlt(S);
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive())
        return giveUp(EpochStatus::Failed, "innovation covariance not positive definite");
      K = ldlt.solve(PHt.transpose()).transpose();
      x_new = fa.x + K * y;
      if (!x_new.allFinite()) return giveUp(EpochStatus::Failed, "non-finite state after the update");
    }
    if (restart) continue;

    // Joseph form: P = (I - KH) P (I - KH)^T + K R K^T.
    const Eigen::MatrixXd IKH = Eigen::MatrixXd::Identity(dim, dim) - K * H;
    Eigen::MatrixXd P = IKH * fa.P * IKH.transpose() + K * R.asDiagonal() * K.transpose();
    if (auto problem = checkCovariance(P); !problem.empty())
      return giveUp(EpochStatus::Failed, problem + " after the update");

    // Postfit residuals at the updated state; optional check.
    const Eigen::VectorXd postfit = y_lin - H * (x_new - x_lin);
    if (options_.postfit_check && result.postfit_rejections < options_.postfit_max_rejections) {
      Eigen::Index worst = 0;
      const double worst_ratio = (postfit.array() / R.array().sqrt()).abs().maxCoeff(&worst);
      if (worst_ratio > options_.postfit_sigmas) {
        const auto& row = rows[static_cast<std::size_t>(worst / 2)];
        excluded.insert(row.m.satellite);
        result.rejected.push_back({row.m.satellite, std::string("postfit ") + (worst % 2 == 0 ? "code" : "phase") +
                                                        " residual " + fmt(postfit(worst)) + " m = " +
                                                        fmt(worst_ratio, 1) + " sigma > " +
                                                        fmt(options_.postfit_sigmas, 1) + " sigma"});
        ++result.postfit_rejections;
        continue;
      }
    }

    // Commit.
    fa.x = x_new;
    fa.P = std::move(P);
    for (auto& row : rows) fa.biases[static_cast<std::size_t>(row.bias_index - kRx)].last_used = time;
    f_ = std::move(fa);
    last_time_ = time;
    fresh_ = false;
    result.status = EpochStatus::Ok;
    EpochSolution solution;
    solution.state = receiverState();
    solution.covariance = receiverCovariance();
    result.solution = solution;
    result.active_biases = activeBiasCount();
    for (int k = 0; k < n_sat; ++k) {
      const auto& row = rows[k];
      result.used.push_back(row.m.satellite);
      MeasurementResidual r;
      r.satellite = row.m.satellite;
      r.arc = row.m.arc;
      r.new_arc = row.new_arc;
      r.elevation_rad = row.m.elevation_rad;
      r.azimuth_rad = row.m.azimuth_rad;
      r.code_prefit_m = row.code_prefit_m;
      r.phase_prefit_m = row.phase_prefit_m;
      r.code_postfit_m = postfit(2 * k);
      r.phase_postfit_m = postfit(2 * k + 1);
      r.code_sigma_m = row.m.code_sigma_m;
      r.phase_sigma_m = row.m.phase_sigma_m;
      result.residuals.push_back(r);
    }
    return result;
  }
}

}  // namespace ppp
