#pragma once
// Options of the PPP smoother (section `smoother` of config/ppp.yaml; the screening
// values are the EKF's, taken from section `estimator`, so that both estimators
// screen alike).
#include <optional>
#include <string>

#include "ppp_bayes_tree/ppp/screening/screening_options.h"
#include "ppp_bayes_tree/smoother/elimination.h"

namespace ppp {

struct PppSmootherOptions {
  /// The cliques' factorization of the PPP smoother when `factorization` is unset.
  static constexpr smoother::Factorization kDefaultFactorization = smoother::Factorization::Cholesky;

  /// Screening and bookkeeping: the EKF's (screening_options.h).
  ScreeningOptions screening;
  /// Huber kernel on the code and phase factors, width in sigmas (robust = false: Gaussian).
  bool robust = false;
  double huber_width_sigmas = 3.0;
  /// Relinearization thresholds on |delta| per component [m].
  double relinearize_position_m = 0.01;
  double relinearize_zwd_m = 0.001;
  double relinearize_clock_m = 1.0;
  /// Only with `robust` (Huber weights depend on the residual): otherwise the phase
  /// factors are affine in the bias and iSAM2 never relinearizes it (skip_affine_variables).
  double relinearize_bias_m = 0.01;
  /// Check relinearization every this many updates (iSAM2's relinearize_skip).
  int relinearize_skip = 1;
  /// Partial back-substitution threshold [m] (iSAM2's wildfire threshold).
  double wildfire_threshold_m = 1e-4;
  /// Factors re-evaluate the geometric range exactly at new states (ppp_factors.h);
  /// false: linear factors (linearised once; the EKF-equivalence test).
  bool exact_range = true;
  /// Dense factorization of the cliques; unset: the estimator's own (the PPP smoother
  /// Cholesky, kDefaultFactorization; QR slower, for reference checks). The GNSS/INS
  /// smoother factorizes by QR only and refuses another (ppp_ins_smoother.h "Numerics").
  /// Not a configuration key.
  std::optional<smoother::Factorization> factorization;
  /// 0: full smoother (every state kept); > 0: fixed-lag smoother with this lag [s].
  double fixed_lag_s = 0.0;
  /// Keep a copy of every factor and new variable of the successful updates besides
  /// the lag window, so that batchSmoothedValues() / finalSmoothedSolution() is the
  /// batch solve of all the data. Memory
  /// O(epochs). Not a configuration key: the Monte Carlo study's fast mode (a fixed
  /// lag for the filtered run, the exact smoothed solution at the end).
  bool record_graph = false;
  /// Ambiguity resolution (when enabled in the PPP config): sigma of each fixed
  /// ambiguity's factor [narrow-lane cycles] (integer_ambiguity_factor.h). Which
  /// fixes are held and when one is released is the AmbiguityResolver's decision
  /// (resolveAndHold, the EKF's path; its hold options).
  double fixed_ambiguity_sigma_cycles = 0.01;

  /// Empty when valid, else the first problem.
  std::string validate() const;
};

}  // namespace ppp
