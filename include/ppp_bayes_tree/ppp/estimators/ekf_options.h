#pragma once
// Options of the EKF-PPP estimator (section `estimator` of config/ppp.yaml).
#include <string>

#include "ppp_bayes_tree/ppp/screening/screening_options.h"

namespace ppp {

struct EkfOptions {
  /// Prefit and postfit screening, consistency test, minimum satellites, clock
  /// shift, stale arcs (shared with the smoother).
  ScreeningOptions screening;
  /// Measurement updates per epoch; each one after the first re-linearises the
  /// model at the updated state (iterated EKF). >= 1.
  int iterations_per_epoch = 2;

  /// Empty when valid, else the first problem.
  std::string validate() const;
};

}  // namespace ppp
