#pragma once
// Options of the EKF-PPP estimator (section `estimator` of config/ppp.yaml).
#include <string>

#include "ppp_bayes_tree/ppp/screening_options.h"

namespace ppp {

struct EkfOptions {
  /// Prefit screening, minimum satellites, clock shift, stale arcs (shared with the smoother).
  ScreeningOptions screening;
  /// Measurement updates per epoch; each one after the first re-linearises the
  /// model at the updated state (iterated EKF). >= 1.
  int iterations_per_epoch = 2;
  /// Postfit check: after the update, the satellite with the largest normalised
  /// postfit residual |r|/sigma above postfit_sigmas is rejected and the update
  /// redone from the prediction, at most postfit_max_rejections times per epoch.
  bool postfit_check = true;
  double postfit_sigmas = 5.0;
  int postfit_max_rejections = 3;

  /// Empty when valid, else the first problem.
  std::string validate() const;
};

}  // namespace ppp
