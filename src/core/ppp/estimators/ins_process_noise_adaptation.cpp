#include "ppp_bayes_tree/ppp/estimators/ins_process_noise_adaptation.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {

std::string ProcessNoiseAdaptationOptions::validate() const {
  if (!(false_alarm > 0.0 && false_alarm < 0.5)) return "process noise adaptation: false alarm must be in (0, 0.5)";
  if (!(max_scale >= 1.0) || !std::isfinite(max_scale)) return "process noise adaptation: max scale must be >= 1";
  return {};
}

PhaseInnovationRow phaseInnovationRow(const SatelliteMeasurement& m, const ReceiverStateLayout& layout, double bias_m) {
  PhaseInnovationRow row;
  row.satellite = m.satellite;
  row.d_antenna_m = m.jacobian.segment<3>(layout.position()).transpose();
  row.clock_system = m.satellite.system;
  row.innovation_m = m.phaseResidualWithoutBias_m() - bias_m;
  row.variance_m2 = m.phase_sigma_m * m.phase_sigma_m;
  return row;
}

Matrix12d accelerometerNoiseDensity(const Matrix12d& density) {
  Matrix12d accel = Matrix12d::Zero();
  accel.topLeftCorner<3, 3>() = density.topLeftCorner<3, 3>();
  return accel;
}

ImuNoise accelerometerNoise(const ImuNoise& noise) {
  ImuNoise accel;
  accel.name = noise.name;
  accel.source = noise.source;
  accel.accel_noise_density_mps2_per_sqrthz = noise.accel_noise_density_mps2_per_sqrthz;
  return accel;
}

Matrix15d relativeInsErrorCovariance(const InsDiscreteModel& since, const Matrix15d& covariance) {
  const Matrix15d A_minus_I = since.transition - Matrix15d::Identity();
  const Matrix15d D = A_minus_I * covariance * A_minus_I.transpose() + since.process_noise;
  return 0.5 * (D + D.transpose());
}

std::string ProcessNoiseScale::text() const {
  if (dof == 0) return "not tested";
  std::string s = format("phase innovations T = %.1f %s %.1f (%d dof)", statistic, statistic > quantile ? ">" : "<=",
                         quantile, dof);
  if (left_out) s += ", " + left_out->toString() + " left out";
  if (inflated()) s += format(": process noise x %.3g", scale);
  return s;
}

namespace {

/// The rows' innovations, their covariance at a process-noise scale, and T with the
/// receiver clocks free.
class InnovationSquare {
 public:
  InnovationSquare(const std::vector<PhaseInnovationRow>& rows, const Eigen::Matrix3d& relative_cov_m2,
                   const Eigen::Matrix3d& process_cov_m2) {
    const int m = static_cast<int>(rows.size());
    Eigen::MatrixXd G(m, 3);
    y_.resize(m);
    r_.resize(m);
    std::vector<GnssSystem> systems;
    for (const auto& row : rows)
      if (std::find(systems.begin(), systems.end(), row.clock_system) == systems.end())
        systems.push_back(row.clock_system);
    clocks_ = Eigen::MatrixXd::Zero(m, static_cast<Eigen::Index>(systems.size()));
    for (int i = 0; i < m; ++i) {
      const PhaseInnovationRow& row = rows[static_cast<std::size_t>(i)];
      G.row(i) = row.d_antenna_m.transpose();
      y_(i) = row.innovation_m;
      r_(i) = row.variance_m2;
      const auto c = std::find(systems.begin(), systems.end(), row.clock_system) - systems.begin();
      clocks_(i, c) = 1.0;
    }
    relative_ = G * relative_cov_m2 * G.transpose();
    process_ = G * process_cov_m2 * G.transpose();
  }

  int dof() const { return static_cast<int>(y_.size() - clocks_.cols()); }

  /// T at the scale (the receiver clocks estimated: the clock-free part of the square).
  double at(double scale) const {
    Eigen::MatrixXd S = relative_ + (scale - 1.0) * process_;
    S.diagonal() += r_;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(S);
    const Eigen::VectorXd Si_y = ldlt.solve(y_);
    const Eigen::MatrixXd Si_C = ldlt.solve(clocks_);
    const Eigen::VectorXd Ct_Si_y = clocks_.transpose() * Si_y;
    const Eigen::MatrixXd M = clocks_.transpose() * Si_C;
    return y_.dot(Si_y) - Ct_Si_y.dot(M.ldlt().solve(Ct_Si_y));
  }

 private:
  Eigen::VectorXd y_, r_;
  Eigen::MatrixXd clocks_, relative_, process_;
};

std::vector<PhaseInnovationRow> without(const std::vector<PhaseInnovationRow>& rows, std::size_t k) {
  std::vector<PhaseInnovationRow> out = rows;
  out.erase(out.begin() + static_cast<std::ptrdiff_t>(k));
  return out;
}

/// The lambda in [1, max_scale] with T(lambda) = its degrees of freedom (T falls with lambda).
double scaleToExpectation(const InnovationSquare& square, double max_scale) {
  const double target = square.dof();
  if (square.at(max_scale) > target) return max_scale;
  double lo = 0.0, hi = std::log(max_scale);  // log lambda
  for (int it = 0; it < 50 && hi - lo > 1e-3; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (square.at(std::exp(mid)) > target)
      lo = mid;
    else
      hi = mid;
  }
  return std::exp(hi);
}

}  // namespace

ProcessNoiseScale processNoiseScale(const std::vector<PhaseInnovationRow>& rows, const Eigen::Matrix3d& relative_cov_m2,
                                    const Eigen::Matrix3d& process_cov_m2, const ProcessNoiseAdaptationOptions& options,
                                    const ChiSquareUpperQuantile& quantile) {
  ProcessNoiseScale result;
  if (!options.enabled) return result;
  if (InnovationSquare(rows, relative_cov_m2, process_cov_m2).dof() < 1) return result;
  // 1. The satellite whose leaving lowers T's excess over its expectation most (a row takes a
  // degree of freedom with it) is left out, when a degree of freedom is left.
  std::vector<PhaseInnovationRow> kept = rows;
  double best_excess = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < rows.size(); ++k) {
    std::vector<PhaseInnovationRow> others = without(rows, k);
    const InnovationSquare square(others, relative_cov_m2, process_cov_m2);
    if (square.dof() < 1) continue;
    const double excess = square.at(1.0) - square.dof();
    if (!(excess < best_excess)) continue;
    best_excess = excess;
    kept = std::move(others);
    result.left_out = rows[k].satellite;
  }
  // 2. The test of what is kept, and the scale that brings T to its expectation.
  const InnovationSquare square(kept, relative_cov_m2, process_cov_m2);
  result.dof = square.dof();
  result.quantile = quantile(result.dof);
  result.statistic = square.at(1.0);
  if (!(result.statistic > result.quantile)) return result;
  result.scale = scaleToExpectation(square, options.max_scale);
  return result;
}

}  // namespace ppp
