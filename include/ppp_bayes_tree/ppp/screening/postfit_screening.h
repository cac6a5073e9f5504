#pragma once
// Postfit checks shared by the EKF (ppp_ekf.h) and the smoother (ppp_smoother.h),
// so that both estimators judge a solution's residuals alike:
//  - the postfit residual test: the code or phase residual with the largest
//    normalised value |r| / sigma above `postfit_sigmas` marks its satellite as an
//    outlier (the estimator removes it and solves again: the EKF redoes the update
//    from the prediction, the smoother removes the satellite's factors from the
//    graph);
//  - the epoch consistency test: the weighted sum of squares of the postfit
//    residuals, T = sum (r_code / sigma_code)^2 + (r_phase / sigma_phase)^2, against
//    the chi-square quantile of m = 2 n (n satellites) degrees of freedom at the
//    false-alarm probability. For the linear(ised) update with the prior
//    (x_pred, P_pred), the normalised innovation squared is
//      NIS = y' S^-1 y = r' R^-1 r + (x - x_pred)' P_pred^-1 (x - x_pred) >= T,
//    and NIS ~ chi2(m) when the data fit their covariance (Bar-Shalom, Li,
//    Kirubarajan, "Estimation with applications to tracking and navigation", 2001,
//    ch. 5.4); T needs no prior covariance (the smoother has none in closed form),
//    so T > chi2_m(1 - alpha) flags an inconsistent epoch with a false-alarm
//    probability at most alpha (a conservative test).
// A flagged solution is not published as consistent (SolutionIntegrity): its
// covariance is inflated by the variance factor T / m, or it is withheld
// (ConsistencyAction, screening_options.h).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/model/chi_square_quantile.h"
#include "ppp_bayes_tree/ppp/model/satellite_measurement.h"

namespace ppp {

/// Postfit residuals of one used satellite and their sigmas [m].
struct PostfitResidualPair {
  double code_m = 0.0;
  double phase_m = 0.0;
  double code_sigma_m = 0.0;
  double phase_sigma_m = 0.0;
};

/// The worst postfit residual of an epoch.
struct PostfitOutlier {
  std::size_t index = 0;  // into the residual pairs
  bool code = true;       // the code residual (else the phase one)
  double residual_m = 0.0;
  double normalised = 0.0;  // |residual| / sigma
};

/// The residual with the largest |r| / sigma over all pairs (code before phase,
/// the first on ties) when it exceeds `sigmas`, else nullopt.
std::optional<PostfitOutlier> worstPostfitResidual(const std::vector<PostfitResidualPair>& pairs, double sigmas);
/// The rejection of the outlier's satellite (PostfitCode / PostfitPhase) with its values.
RejectedSatellite postfitRejection(const SatelliteId& satellite, const PostfitOutlier& outlier, double sigmas);

/// The epoch consistency test of a solution's postfit residuals.
struct ConsistencyTest {
  double statistic = 0.0;  // T, the weighted postfit sum of squares
  int dof = 0;             // m, the number of measurements
  double threshold = 0.0;  // chi2_m(1 - alpha)
  bool consistent() const { return !(statistic > threshold); }
  /// a posteriori variance factor T / m (>= 1 when inconsistent)
  double varianceFactor() const { return dof > 0 ? statistic / dof : 1.0; }
  /// "postfit chi-square 412.3 > 58.4 (16 measurements; false alarm 1e-06)" (no comma: a CSV field).
  std::string describe(double alpha) const;
};
ConsistencyTest postfitConsistency(const std::vector<PostfitResidualPair>& pairs, double alpha);
/// The same test with the quantiles of one false-alarm probability computed ahead.
ConsistencyTest postfitConsistency(const std::vector<PostfitResidualPair>& pairs,
                                   const ChiSquareUpperQuantile& quantile);

}  // namespace ppp
