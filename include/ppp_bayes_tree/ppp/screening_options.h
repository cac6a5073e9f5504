#pragma once
// Prefit screening and arc bookkeeping options shared by the EKF (EkfOptions)
// and the smoother (PppSmootherOptions), so that both estimators accept and
// reject the same observations. YAML: section `estimator` of config/ppp.yaml
// (the smoother takes the same values).
#include <string>

namespace ppp {

struct ScreeningOptions {
  /// Fewest satellites with code and phase after screening for a solution;
  /// fewer gives an explicit NoSolution epoch (state kept, not propagated).
  int min_satellites = 5;
  /// Prefit code screening: residual left after a robust single-epoch code fit
  /// of position and clock (worst first) above this is an outlier [m].
  double prefit_code_threshold_m = 30.0;
  /// Prefit phase screening (arcs that already have a bias): the phase-minus-code
  /// innovation (phase residual - bias estimate - code residual; geometry, clock
  /// and troposphere cancel) is rejected above this many of its sigmas
  /// sqrt(P_bias + sigma_code^2 + sigma_phase^2).
  double prefit_phase_sigmas = 5.0;
  /// Before screening, shift the predicted (white) clock by the median code
  /// residual, so that residuals and screening do not see receiver clock jumps.
  bool clock_from_code_median = true;
  /// A bias whose arc has not been used for longer than this is removed [s].
  /// (A new arc of the same satellite always replaces the old bias at once.)
  double stale_arc_timeout_s = 300.0;

  /// Empty when valid, else the first problem.
  std::string validate() const;
};

}  // namespace ppp
