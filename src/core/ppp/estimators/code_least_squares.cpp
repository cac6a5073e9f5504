#include "ppp_bayes_tree/ppp/estimators/code_least_squares.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "ppp_bayes_tree/types/number_text.h"

namespace ppp {
namespace {

bool finiteCode(const SatelliteMeasurement& m) {
  return std::isfinite(m.observed_code_m) && std::isfinite(m.predicted_code_m) && m.jacobian.allFinite() &&
         std::isfinite(m.code_sigma_m) && m.code_sigma_m > 0.0;
}

/// The rows of one iteration: the finite code measurements not yet taken out as
/// outliers; the rejections of the epoch, the non-finite ones and the outliers so far.
std::vector<const SatelliteMeasurement*> usableRows(const EpochMeasurements& epoch,
                                                    const std::set<SatelliteId>& outliers,
                                                    const std::vector<RejectedSatellite>& outlier_reasons,
                                                    std::vector<RejectedSatellite>& rejected) {
  std::vector<const SatelliteMeasurement*> rows;
  rejected = epoch.rejected;
  for (const auto& m : epoch.used) {
    if (outliers.count(m.satellite)) continue;
    if (!finiteCode(m)) {
      rejected.push_back({m.satellite, RejectionReason::NonFiniteModel, "non-finite code value, Jacobian or sigma"});
      continue;
    }
    rows.push_back(&m);
  }
  rejected.insert(rejected.end(), outlier_reasons.begin(), outlier_reasons.end());
  return rows;
}

/// The unknowns' state columns: position, and the clock of each system with
/// satellites (the clock of a system without satellites this epoch stays at its
/// start value).
std::vector<int> estimatedColumns(const ReceiverStateLayout& layout,
                                  const std::vector<const SatelliteMeasurement*>& rows) {
  std::vector<int> columns;
  for (int i = 0; i < ReceiverStateLayout::kPositionSize; ++i) columns.push_back(layout.position() + i);
  for (const GnssSystem system : layout.clockSystems())
    for (const SatelliteMeasurement* m : rows)
      if (m->satellite.system == system) {
        columns.push_back(layout.clock(system));
        break;
      }
  return columns;
}

/// One weighted least-squares step over the rows: H dx = v with weights 1/sigma^2.
struct CodeStep {
  Eigen::MatrixXd H;
  Eigen::VectorXd v, w, dx;
  Eigen::LDLT<Eigen::MatrixXd> ldlt;
  std::string failure;  ///< empty when the step is usable

  CodeStep(const std::vector<const SatelliteMeasurement*>& rows, const std::vector<int>& columns) {
    const int n = static_cast<int>(rows.size()), unknowns = static_cast<int>(columns.size());
    H.resize(n, unknowns);
    v.resize(n);
    w.resize(n);
    for (int i = 0; i < n; ++i) {
      const auto& m = *rows[static_cast<std::size_t>(i)];
      for (int c = 0; c < unknowns; ++c) H(i, c) = m.jacobian(columns[static_cast<std::size_t>(c)]);
      v(i) = m.codeResidual_m();
      w(i) = 1.0 / (m.code_sigma_m * m.code_sigma_m);
    }
    ldlt.compute(H.transpose() * w.asDiagonal() * H);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || ldlt.rcond() < 1e-14) {
      failure = "singular code geometry";
      return;
    }
    dx = ldlt.solve(H.transpose() * (w.asDiagonal() * v));
    if (!dx.allFinite()) failure = "non-finite least-squares step";
  }
};

/// Adds the step to the position and the clocks of the state.
void applyStep(const std::vector<int>& columns, const Eigen::VectorXd& dx, ReceiverState& state) {
  const ReceiverStateLayout& layout = state.layout;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const int column = columns[c];
    const double d = dx(static_cast<Eigen::Index>(c));
    if (layout.isPosition(column)) {
      state.position_ecef_m(column - layout.position()) += d;
    } else {
      const GnssSystem system = layout.clockSystem(column);
      state.setClock_m(system, state.clock_m(system) + d);
    }
  }
}

/// The converged solution: covariance, used satellites and their residuals.
void acceptSolution(const CodeStep& step, const std::vector<const SatelliteMeasurement*>& rows,
                    const std::vector<int>& columns, const Eigen::VectorXd& residuals_m,
                    CodeLeastSquaresResult& result) {
  const auto unknowns = static_cast<Eigen::Index>(columns.size());
  result.ok = true;
  result.covariance = step.ldlt.solve(Eigen::MatrixXd::Identity(unknowns, unknowns));
  result.covariance_components = columns;
  result.used.clear();
  result.residuals_m.clear();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    result.used.push_back(rows[i]->satellite);
    result.residuals_m.push_back(residuals_m(static_cast<Eigen::Index>(i)));
  }
}

CodeLeastSquaresResult failed(CodeLeastSquaresResult& result, const std::string& reason, int iterations) {
  result.ok = false;
  result.reason = reason;
  result.iterations = iterations;
  return result;
}

}  // namespace

// Gauss-Newton on the code, as steps per iteration:
//   1. evaluate the model at the state; keep the finite rows not taken out;
//   2. the unknowns (position, the clocks of the systems seen); enough rows?
//   3. the weighted least-squares step, applied to the state;
//   4. once converged, take out the worst outlier over the threshold and start
//      the iteration count again; else the solution is accepted.
// The whole search is bounded by four times the iteration limit.
CodeLeastSquaresResult codeLeastSquares(const MeasurementFunction& evaluate, const ReceiverState& start,
                                        const CodeLeastSquaresOptions& options) {
  CodeLeastSquaresResult result;
  result.state = start;
  std::set<SatelliteId> outliers;
  std::vector<RejectedSatellite> outlier_reasons;
  int total_iterations = 0;
  const int iteration_budget = options.max_iterations * 4;

  for (int iteration = 0; iteration < options.max_iterations && total_iterations < iteration_budget;
       ++iteration, ++total_iterations) {
    const EpochMeasurements epoch = evaluate(result.state);  // 1
    const auto rows = usableRows(epoch, outliers, outlier_reasons, result.rejected);
    const std::vector<int> columns = estimatedColumns(start.layout, rows);  // 2
    const int needed = std::max(options.min_satellites, static_cast<int>(columns.size()));
    const int n = static_cast<int>(rows.size());
    if (n < needed)
      return failed(result,
                    std::to_string(n) + " satellites with usable code, at least " + std::to_string(needed) + " needed",
                    total_iterations + 1);
    const CodeStep step(rows, columns);  // 3
    if (!step.failure.empty()) return failed(result, step.failure, total_iterations + 1);
    applyStep(columns, step.dx, result.state);
    if (step.dx.norm() > options.convergence_m) continue;

    const Eigen::VectorXd r = step.v - step.H * step.dx;  // 4
    int worst = 0;
    r.cwiseAbs().maxCoeff(&worst);
    if (std::abs(r(worst)) > options.outlier_threshold_m && n > needed) {
      outliers.insert(rows[static_cast<std::size_t>(worst)]->satellite);
      outlier_reasons.push_back({rows[static_cast<std::size_t>(worst)]->satellite,
                                 RejectionReason::CodeLeastSquaresOutlier,
                                 "code least-squares residual " + fixedDecimals(r(worst)) + " m > " +
                                     fixedDecimals(options.outlier_threshold_m) + " m"});
      iteration = -1;  // restart the iteration count with the outlier removed
      continue;
    }
    result.iterations = total_iterations + 1;
    acceptSolution(step, rows, columns, r, result);
    return result;
  }
  return failed(result, "code least squares did not converge in " + std::to_string(total_iterations) + " iterations",
                total_iterations);
}

}  // namespace ppp
