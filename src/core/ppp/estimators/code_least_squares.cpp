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

}  // namespace

CodeLeastSquaresResult codeLeastSquares(const MeasurementFunction& evaluate, const ReceiverState& start,
                                        const CodeLeastSquaresOptions& options) {
  CodeLeastSquaresResult result;
  result.state = start;
  const ReceiverStateLayout& layout = start.layout;
  std::set<SatelliteId> outliers;
  std::vector<RejectedSatellite> outlier_reasons;
  int total_iterations = 0;
  const int iteration_budget = options.max_iterations * 4;

  for (int iteration = 0; iteration < options.max_iterations && total_iterations < iteration_budget;
       ++iteration, ++total_iterations) {
    const EpochMeasurements epoch = evaluate(result.state);
    std::vector<const SatelliteMeasurement*> rows;
    result.rejected = epoch.rejected;
    for (const auto& m : epoch.used) {
      if (outliers.count(m.satellite)) continue;
      if (!finiteCode(m)) {
        result.rejected.push_back(
            {m.satellite, RejectionReason::NonFiniteModel, "non-finite code value, Jacobian or sigma"});
        continue;
      }
      rows.push_back(&m);
    }
    result.rejected.insert(result.rejected.end(), outlier_reasons.begin(), outlier_reasons.end());
    // Unknowns: position, and the clock of each system with satellites (the
    // clock of a system without satellites this epoch stays at its start value).
    std::vector<int> columns;
    for (int i = 0; i < ReceiverStateLayout::kPositionSize; ++i) columns.push_back(layout.position() + i);
    for (const GnssSystem system : layout.clockSystems())
      for (const SatelliteMeasurement* m : rows)
        if (m->satellite.system == system) {
          columns.push_back(layout.clock(system));
          break;
        }
    const int unknowns = static_cast<int>(columns.size());
    const int needed = std::max(options.min_satellites, unknowns);
    const int n = static_cast<int>(rows.size());
    if (n < needed) {
      result.ok = false;
      result.reason =
          std::to_string(n) + " satellites with usable code, at least " + std::to_string(needed) + " needed";
      result.iterations = total_iterations + 1;
      return result;
    }
    Eigen::MatrixXd H(n, unknowns);
    Eigen::VectorXd v(n), w(n);
    for (int i = 0; i < n; ++i) {
      const auto& m = *rows[i];
      for (int c = 0; c < unknowns; ++c) H(i, c) = m.jacobian(columns[static_cast<std::size_t>(c)]);
      v(i) = m.codeResidual_m();
      w(i) = 1.0 / (m.code_sigma_m * m.code_sigma_m);
    }
    const Eigen::MatrixXd N = H.transpose() * w.asDiagonal() * H;
    Eigen::LDLT<Eigen::MatrixXd> ldlt(N);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || ldlt.rcond() < 1e-14) {
      result.ok = false;
      result.reason = "singular code geometry";
      result.iterations = total_iterations + 1;
      return result;
    }
    const Eigen::VectorXd dx = ldlt.solve(H.transpose() * (w.asDiagonal() * v));
    if (!dx.allFinite()) {
      result.ok = false;
      result.reason = "non-finite least-squares step";
      result.iterations = total_iterations + 1;
      return result;
    }
    for (int c = 0; c < unknowns; ++c) {
      const int column = columns[static_cast<std::size_t>(c)];
      if (layout.isPosition(column)) {
        result.state.position_ecef_m(column - layout.position()) += dx(c);
      } else {
        const GnssSystem system = layout.clockSystem(column);
        result.state.setClock_m(system, result.state.clock_m(system) + dx(c));
      }
    }
    if (dx.norm() > options.convergence_m) continue;

    // Converged: residuals at the solution; reject the worst outlier and go on.
    const Eigen::VectorXd r = v - H * dx;
    int worst = 0;
    r.cwiseAbs().maxCoeff(&worst);
    if (std::abs(r(worst)) > options.outlier_threshold_m && n > needed) {
      outliers.insert(rows[worst]->satellite);
      outlier_reasons.push_back({rows[worst]->satellite, RejectionReason::CodeLeastSquaresOutlier,
                                 "code least-squares residual " + fixedDecimals(r(worst)) + " m > " +
                                     fixedDecimals(options.outlier_threshold_m) + " m"});
      iteration = -1;  // restart the iteration count with the outlier removed
      continue;
    }
    result.ok = true;
    result.iterations = total_iterations + 1;
    result.covariance = ldlt.solve(Eigen::MatrixXd::Identity(unknowns, unknowns));
    result.covariance_components = columns;
    result.used.clear();
    result.residuals_m.clear();
    for (int i = 0; i < n; ++i) {
      result.used.push_back(rows[i]->satellite);
      result.residuals_m.push_back(r(i));
    }
    return result;
  }
  result.ok = false;
  result.reason = "code least squares did not converge in " + std::to_string(total_iterations) + " iterations";
  result.iterations = total_iterations;
  return result;
}

}  // namespace ppp
