#pragma once
// Single-epoch least squares on the IF code: Gauss-Newton on position and
// receiver clock (zenith wet delay held at the start value), weighted by the
// model's code sigmas, with worst-first rejection of code outliers. Used to
// start the EKF from a sensible position (from the RINEX approximate position,
// or from the Earth centre when the header has none).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/measurement_function.h"

namespace ppp {

struct CodeLeastSquaresOptions {
  int max_iterations = 20;
  double convergence_m = 1e-4;        // stop when the position+clock step is below [m]
  int min_satellites = 4;             // unknowns: x, y, z, clock
  double outlier_threshold_m = 30.0;  // reject the worst code residual above this [m] (needs > 4 satellites)
};

struct CodeLeastSquaresResult {
  bool ok = false;
  std::string reason;                 // why not ok ("3 satellites, at least 4 needed")
  ReceiverState state;                // position and clock estimated, ZWD as given
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();  // (x, y, z, clock) [m^2]
  int iterations = 0;
  std::vector<SatelliteId> used;
  std::vector<RejectedSatellite> rejected;  // the model's rejections plus code outliers
  std::vector<double> residuals_m;          // code residuals of `used`, same order
};

CodeLeastSquaresResult codeLeastSquares(const MeasurementFunction& evaluate, const ReceiverState& start,
                                        const CodeLeastSquaresOptions& options = {});

}  // namespace ppp
