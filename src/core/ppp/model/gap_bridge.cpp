#include "ppp_bayes_tree/ppp/model/gap_bridge.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {

namespace {

struct Solved {
  Eigen::VectorXd residual_m;  // per active row
  Eigen::VectorXd sigma_m;     // sigma of the predicted value plus the row's noise
};

/// Least squares of [dp(3); clocks] over the active rows, dp with the prior covariance.
Solved solveRows(const std::vector<GapBridgeRow>& rows, const std::vector<int>& active, int clocks,
                 const Eigen::Matrix3d& position_cov_m2) {
  const int n = static_cast<int>(active.size()), u = 3 + clocks;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, u);
  Eigen::VectorXd y(n), w(n);
  for (int i = 0; i < n; ++i) {
    const GapBridgeRow& r = rows[static_cast<std::size_t>(active[static_cast<std::size_t>(i)])];
    H.block<1, 3>(i, 0) = r.position_jacobian;
    H(i, 3 + r.clock) = 1.0;
    y(i) = r.residual_m;
    w(i) = 1.0 / (r.sigma_m * r.sigma_m);
  }
  Eigen::MatrixXd N = H.transpose() * w.asDiagonal() * H;
  N.topLeftCorner<3, 3>() += position_cov_m2.inverse();
  const Eigen::MatrixXd Q = N.ldlt().solve(Eigen::MatrixXd::Identity(u, u));
  const Eigen::VectorXd x = Q * (H.transpose() * w.asDiagonal() * y);
  Solved s;
  s.residual_m = y - H * x;
  s.sigma_m.resize(n);
  for (int i = 0; i < n; ++i) s.sigma_m(i) = std::sqrt(H.row(i) * Q * H.row(i).transpose() + 1.0 / w(i));
  return s;
}

/// Index (into `active`) of the worst failing row; -1 when all pass.
int worstFailing(const std::vector<GapBridgeRow>& rows, const std::vector<int>& active, const Solved& s,
                 const GapBridgeOptions& o, std::vector<GapBridgeVerdict>& out) {
  int worst = -1;
  double worst_excess = 0.0;
  for (std::size_t i = 0; i < active.size(); ++i) {
    const GapBridgeRow& r = rows[static_cast<std::size_t>(active[i])];
    GapBridgeVerdict& v = out[static_cast<std::size_t>(active[i])];
    v.slip_cycles = s.residual_m(static_cast<int>(i)) / r.wavelength_m;
    v.sigma_cycles = s.sigma_m(static_cast<int>(i)) / r.wavelength_m;
    const double excess = std::max(std::abs(v.slip_cycles) - o.max_fraction_cycles, v.sigma_cycles - o.max_sigma_cycles);
    if (excess > 0.0 && (worst < 0 || excess > worst_excess)) worst = static_cast<int>(i), worst_excess = excess;
  }
  return worst;
}

/// The prior covariance with each eigenvalue at least floor_sigma_m^2.
Eigen::Matrix3d flooredCovariance(const Eigen::Matrix3d& cov_m2, double floor_sigma_m) {
  if (!(floor_sigma_m > 0.0)) return cov_m2;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (cov_m2 + cov_m2.transpose()));
  const Eigen::Vector3d values = eig.eigenvalues().cwiseMax(floor_sigma_m * floor_sigma_m);
  return eig.eigenvectors() * values.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

std::vector<GapBridgeVerdict> bridgeGap(const std::vector<GapBridgeRow>& rows, const Eigen::Matrix3d& given_cov_m2,
                                        const GapBridgeOptions& options) {
  const Eigen::Matrix3d position_cov_m2 = flooredCovariance(given_cov_m2, options.min_position_sigma_m);
  std::vector<GapBridgeVerdict> out(rows.size());
  std::vector<int> active;
  int clocks = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    active.push_back(static_cast<int>(i));
    clocks = std::max(clocks, rows[i].clock + 1);
    out[i].slip_cycles = std::numeric_limits<double>::quiet_NaN();
  }
  while (static_cast<int>(active.size()) >= 3 + clocks + options.min_extra_rows) {
    const Solved s = solveRows(rows, active, clocks, position_cov_m2);
    const int worst = worstFailing(rows, active, s, options, out);
    if (worst < 0) {
      for (int i : active) out[static_cast<std::size_t>(i)].keep = true;
      return out;
    }
    GapBridgeVerdict& v = out[static_cast<std::size_t>(active[static_cast<std::size_t>(worst)])];
    v.reason = format("slip %.2f +- %.2f cycles (bounds %.2f, %.2f)", v.slip_cycles, v.sigma_cycles,
                      options.max_fraction_cycles, options.max_sigma_cycles);
    active.erase(active.begin() + worst);
  }
  for (int i : active)
    out[static_cast<std::size_t>(i)].reason = format("%d arcs back after the gap, too few to test the slips",
                                                    static_cast<int>(active.size()));
  return out;
}

}  // namespace ppp
