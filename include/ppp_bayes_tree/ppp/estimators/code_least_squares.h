#pragma once
// Single-epoch least squares on the IF code: Gauss-Newton on position and the
// receiver clock of each system with satellites (zenith wet delay held at the
// start value; the clock of a configured system without satellites at the epoch
// is left out and keeps its start value, so it never makes the system singular;
// the estimators then hold it at their clock prior), weighted by the
// model's code sigmas, with worst-first rejection of code outliers. Used to
// start the EKF from a sensible position (from the RINEX approximate position,
// or from the Earth centre when the header has none).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/model/measurement_function.h"

namespace ppp {

struct CodeLeastSquaresOptions {
  int max_iterations = 20;
  double convergence_m = 1e-4;        // stop when the position+clock step is below [m]
  int min_satellites = 4;             // at least; and at least 3 + one per system with satellites
  double outlier_threshold_m = 30.0;  // reject the worst code residual above this [m] (needs a redundancy)
};

struct CodeLeastSquaresResult {
  bool ok = false;
  std::string reason;                 // why not ok ("3 satellites, at least 4 needed")
  ReceiverState state;                // position and clocks estimated, ZWD as given (start's layout)
  /// Covariance [m^2] of the estimated components (x, y, z, then the clocks of the
  /// systems with satellites), their state indices in `covariance_components`.
  Eigen::MatrixXd covariance;
  std::vector<int> covariance_components;
  int iterations = 0;
  std::vector<SatelliteId> used;
  std::vector<RejectedSatellite> rejected;  // the model's rejections plus code outliers
  std::vector<double> residuals_m;          // code residuals of `used`, same order
};

CodeLeastSquaresResult codeLeastSquares(const MeasurementFunction& evaluate, const ReceiverState& start,
                                        const CodeLeastSquaresOptions& options = {});

}  // namespace ppp
