#include "ppp_bayes_tree/ppp/model/doppler_velocity.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace ppp {

std::string DopplerVelocityOptions::validate() const {
  if (!(sigma_zenith_mps > 0.0)) return "Doppler sigma must be > 0";
  if (!(elevation_cutoff_rad >= 0.0)) return "Doppler elevation cutoff must be >= 0";
  if (!(outlier_threshold > 0.0)) return "Doppler outlier threshold must be > 0";
  if (min_satellites < 5) return "Doppler minimum satellites must be >= 5";
  if (!(innovation_chi2 > 0.0)) return "Doppler innovation chi-square must be > 0";
  return {};
}

const char* dopplerVelocityStatusText(DopplerVelocityStatus status) {
  switch (status) {
    case DopplerVelocityStatus::Ok: return "ok";
    case DopplerVelocityStatus::TooFewSatellites: return "too few satellites with Doppler";
    case DopplerVelocityStatus::Singular: return "singular geometry";
    case DopplerVelocityStatus::UnresolvedOutlier: return "an outlier among the fewest satellites";
  }
  return "unknown";
}

namespace {

/// One satellite's row: y = g.v + drift, y the range rate minus the geometry at v = 0
/// plus the satellite clock rate.
struct VelocityRow {
  SatelliteId satellite;
  Eigen::Matrix<double, 1, 4> a;
  double y = 0.0;
  double sigma_mps = 0.0;
};

std::vector<VelocityRow> velocityRows(const std::vector<DopplerObservation>& observations,
                                      const Eigen::Vector3d& receiver_ecef_m, const DopplerVelocityOptions& o,
                                      int& below_cutoff) {
  std::vector<VelocityRow> rows;
  for (const DopplerObservation& d : observations) {
    const RangeRatePrediction p = predictRangeRate(d.satellite_position_ecef_m, d.satellite_velocity_ecef_mps,
                                                   receiver_ecef_m, Eigen::Vector3d::Zero());
    if (p.elevation_rad < o.elevation_cutoff_rad) {
      ++below_cutoff;
      continue;
    }
    VelocityRow r;
    r.satellite = d.satellite;
    r.a << p.d_receiver_velocity.transpose(), 1.0;
    r.y = d.range_rate_mps - p.range_rate_mps + d.satellite_clock_rate_mps;
    r.sigma_mps = o.sigma_zenith_mps / std::sin(std::max(p.elevation_rad, 0.05));
    rows.push_back(r);
  }
  return rows;
}

/// The weighted least squares of the rows; the index of the worst normalised
/// residual above the threshold (-1: none).
int leastSquares(const std::vector<VelocityRow>& rows, const DopplerVelocityOptions& o, DopplerVelocitySolution& s) {
  const int n = static_cast<int>(rows.size());
  Eigen::MatrixXd A(n, 4);
  Eigen::VectorXd y(n), w(n);
  for (int i = 0; i < n; ++i) {
    A.row(i) = rows[i].a;
    y(i) = rows[i].y;
    w(i) = 1.0 / (rows[i].sigma_mps * rows[i].sigma_mps);
  }
  const Eigen::Matrix4d N = A.transpose() * w.asDiagonal() * A;
  const Eigen::LDLT<Eigen::Matrix4d> ldlt(N);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12 * ldlt.vectorD().maxCoeff())) {
    s.status = DopplerVelocityStatus::Singular;
    return -1;
  }
  const Eigen::Matrix4d Q = ldlt.solve(Eigen::Matrix4d::Identity());
  const Eigen::Vector4d x = Q * A.transpose() * w.asDiagonal() * y;
  const Eigen::VectorXd r = y - A * x;
  s.status = DopplerVelocityStatus::Ok;
  s.velocity_ecef_mps = x.head<3>();
  s.clock_drift_mps = x(3);
  s.variance_factor = r.dot(w.asDiagonal() * r) / (n - 4);
  s.velocity_covariance = Q.topLeftCorner<3, 3>() * std::max(1.0, s.variance_factor);
  int worst = -1;
  double worst_w = o.outlier_threshold;
  for (int i = 0; i < n; ++i) {
    const double q_r = 1.0 / w(i) - A.row(i) * Q * A.row(i).transpose();
    if (!(q_r > 0.0)) continue;
    const double normalised = std::abs(r(i)) / std::sqrt(q_r);
    if (normalised > worst_w) {
      worst_w = normalised;
      worst = i;
    }
  }
  return worst;
}

}  // namespace

DopplerVelocitySolution solveDopplerVelocity(const std::vector<DopplerObservation>& observations,
                                             const Eigen::Vector3d& receiver_ecef_m,
                                             const DopplerVelocityOptions& options) {
  DopplerVelocitySolution s;
  std::vector<VelocityRow> rows = velocityRows(observations, receiver_ecef_m, options, s.below_cutoff);
  for (;;) {
    if (static_cast<int>(rows.size()) < options.min_satellites) {
      s.status = DopplerVelocityStatus::TooFewSatellites;
      return s;
    }
    const int worst = leastSquares(rows, options, s);
    if (!s.ok()) return s;
    if (worst < 0) break;
    if (static_cast<int>(rows.size()) == options.min_satellites) {  // an outlier none can be spared for
      s.status = DopplerVelocityStatus::UnresolvedOutlier;
      return s;
    }
    s.rejected.push_back(rows[static_cast<std::size_t>(worst)].satellite);
    rows.erase(rows.begin() + worst);
  }
  for (const VelocityRow& r : rows) s.used.push_back(r.satellite);
  return s;
}

}  // namespace ppp
