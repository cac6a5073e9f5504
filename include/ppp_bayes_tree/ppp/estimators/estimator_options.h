#pragma once
// EstimatorOptions: what a PppEstimator (ppp_estimator.h) is built from:
// the stochastic model, the EKF options with the code least squares start, the
// smoother options, the GNSS/INS filter's options, the systems of the receiver state (and whether it carries
// the tropospheric gradients) and the PPP-AR options.
// The whole configuration (ppp/config/ppp_config.h, a part above the
// estimators) converts to it, so the estimators do not depend on it.
#include <vector>

#include "ppp_bayes_tree/ppp/ambiguity/ambiguity_resolution.h"
#include "ppp_bayes_tree/ppp/estimators/code_least_squares.h"
#include "ppp_bayes_tree/ppp/estimators/ekf_options.h"
#include "ppp_bayes_tree/ppp/estimators/ins_ekf_options.h"
#include "ppp_bayes_tree/ppp/estimators/smoother_options.h"
#include "ppp_bayes_tree/ppp/model/stochastic_model.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

struct EstimatorOptions {
  StochasticModel stochastic;                         // `stochastic:`
  EkfOptions ekf;                                     // `estimator:`
  CodeLeastSquaresOptions start;                      // `estimator.start:`
  PppSmootherOptions smoother;                        // `smoother:`
  std::vector<GnssSystem> systems{GnssSystem::GPS};   // the receiver state's systems (`signals.systems`)
  /// The receiver state carries the tropospheric gradients
  /// (`measurement_model.troposphere.estimate_gradients`).
  bool troposphere_gradients = false;
  AmbiguityResolutionOptions ambiguity_resolution;    // `ambiguity_resolution:`
  InsEkfOptions ins;                                  // the GNSS/INS filter's (ppp_solve --imu-grade, --lever-arm)
};

}  // namespace ppp
