#pragma once
// Options of the EKF-PPP estimator (section `estimator` of config/ppp.yaml).
#include <string>

namespace ppp {

struct EkfOptions {
  /// Fewest satellites with code and phase after screening for a solution;
  /// fewer gives an explicit NoSolution epoch (state kept, not propagated).
  int min_satellites = 5;
  /// Measurement updates per epoch; each one after the first re-linearises the
  /// model at the updated state (iterated EKF). >= 1.
  int iterations_per_epoch = 2;
  /// Prefit code screening: residual left after a robust single-epoch code fit
  /// of position and clock (worst first) above this is an outlier [m].
  double prefit_code_threshold_m = 30.0;
  /// Prefit phase screening (arcs that already have a bias): the phase-minus-code
  /// innovation (phase residual - bias estimate - code residual; geometry, clock
  /// and troposphere cancel) is rejected above this many of its sigmas
  /// sqrt(P_bias + sigma_code^2 + sigma_phase^2).
  double prefit_phase_sigmas = 5.0;
  /// Postfit check: after the update, the satellite with the largest normalised
  /// postfit residual |r|/sigma above postfit_sigmas is rejected and the update
  /// redone from the prediction, at most postfit_max_rejections times per epoch.
  bool postfit_check = true;
  double postfit_sigmas = 5.0;
  int postfit_max_rejections = 3;
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
