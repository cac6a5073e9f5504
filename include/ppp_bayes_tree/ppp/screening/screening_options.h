#pragma once
// Prefit and postfit screening, the epoch consistency test and arc bookkeeping
// options shared by the EKF (EkfOptions) and the smoother (PppSmootherOptions), so
// that both estimators accept and reject the same observations. YAML: section `estimator` of config/ppp.yaml
// (the smoother takes the same values).
#include <string>

namespace ppp {

/// What is published for a solution whose postfit residuals fail the epoch
/// consistency test (postfit_screening.h): it is flagged inconsistent either way.
enum class ConsistencyAction {
  Inflate,   // published with its covariance times the variance factor T / m (> 1)
  Withhold,  // not published: a "no solution" epoch (the estimator keeps its state)
};
std::string toString(ConsistencyAction action);  // "inflate", "withhold"

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
  /// Postfit check (postfit_screening.h): after the update, the satellite with the
  /// largest normalised postfit residual |r| / sigma above postfit_sigmas is
  /// rejected and the epoch solved again without it (EKF: the update redone from
  /// the prediction; smoother: its factors removed from the graph), at most
  /// postfit_max_rejections times per epoch (the smoother never below min_satellites).
  bool postfit_check = true;
  double postfit_sigmas = 5.0;
  int postfit_max_rejections = 3;
  /// Epoch consistency test (postfit_screening.h): the weighted postfit sum of
  /// squares against the chi-square quantile of the measurement count at this
  /// false-alarm probability; a failed epoch is flagged inconsistent and handled
  /// by consistency_action.
  bool consistency_check = true;
  double consistency_false_alarm = 1.0e-6;
  ConsistencyAction consistency_action = ConsistencyAction::Inflate;
  /// A bias whose arc has not been used for longer than this is removed [s].
  /// (A new arc of the same satellite always replaces the old bias at once.)
  double stale_arc_timeout_s = 300.0;

  /// Empty when valid, else the first problem.
  std::string validate() const;
};

}  // namespace ppp
