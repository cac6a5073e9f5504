#pragma once
// AmbiguityResolver: PPP ambiguity resolution (PPP-AR) for a filter whose state
// holds one ionosphere-free (IF) phase bias [m] per arc, with satellite phase
// OSBs consistent with the clocks (phase_bias_consistency.h).
//
// Per epoch:
//  1. Wide lane: Melbourne-Wuebbena means per arc with the satellite OSBs
//     removed, single-differenced against a reference arc and fixed by rounding
//     (wide_lane_ambiguity.h).
//  2. Narrow lane: with the OSB-corrected IF bias B'_s = B_s - b_s (b_s the IF
//     combination of the satellite's phase OSBs of the selected phases) and the
//     IF ambiguity written as lambda_NL N1 + c f2 / (f1^2 - f2^2) N_WL
//     (models/ionosphere_free.h), the between-satellite single difference
//         dN1_s = (B'_s - B'_ref - k_WL dN_WL_s) / lambda_NL
//     is a float integer free of the receiver biases (the receiver clock and
//     the receiver phase bias are common to all satellites and cancel; this is
//     why single differences against a reference arc are fixed, not undifferenced
//     ambiguities). The reference arc is the wide lane's. dN1 is linear in the
//     filter state, dN1 = D x - o, so its covariance is D P D^T.
//  3. LAMBDA with ratio test and partial fixing on the dN1 (integer_least_squares.h):
//     the accepted integer constraints C dN1 = z become C D x = z + C o.
//  4. The constraints are applied, as exact conditioning, to a COPY of the float
//     state and covariance: x_fix = x + P A^T (A P A^T)^-1 (y - A x),
//     P_fix = P - P A^T (A P A^T)^-1 A P. The float filter itself is never
//     changed, so a wrong fix does not propagate: the next epoch resolves anew
//     from the float state (no hold yet).
//
// References: Ge M., Gendt G., Rothacher M., Shi C., Liu J. (2008) Resolution of
// GPS carrier-phase ambiguities in precise point positioning (PPP) with daily
// observations. J Geod 82:389-399 (wide lane then narrow lane with satellite
// fractional biases, single differences between satellites); Laurichesse D.,
// Mercier F., Berthias J.-P., Broca P., Cerri L. (2009) Integer ambiguity
// resolution on undifferenced GPS phase measurements and its application to
// PPP and satellite precise orbit determination. Navigation 56(2) (integer
// clocks, the GRG convention); Schaer S. et al. (2021) The CODE ambiguity-fixed
// clock and phase bias analysis products. J Geod 95:81 (the OSB convention).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ppp_bayes_tree/models/bias_provider.h"
#include "ppp_bayes_tree/ppp/arc_tracker.h"
#include "ppp_bayes_tree/ppp/integer_least_squares.h"
#include "ppp_bayes_tree/ppp/wide_lane_ambiguity.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

struct AmbiguityResolutionOptions {
  bool enabled = false;
  /// Arcs below this elevation are not fixed (their float biases carry the
  /// multipath and mapping errors of low satellites) [rad]; 0 = all. 15 deg.
  double min_elevation_rad = 15.0 * kDegToRad;
  WideLaneOptions wide_lane;
  IlsOptions narrow_lane;
  /// "" when valid, else the reason.
  std::string validate() const;
};

/// Why an epoch stayed float (None when fixed).
enum class AmbiguityFloatReason {
  None,
  Disabled,
  NoConsistentPhaseBiases,  // products: see phase_bias_consistency.h
  NoWideLaneReference,      // no arc with enough MW samples
  TooFewWideLanes,          // fewer fixed wide lanes with a bias state than narrow_lane.min_fixed
  NarrowLane,               // LAMBDA refused (see ils_reason)
  NumericalFailure,         // the constrained covariance was not positive
};
std::string toString(AmbiguityFloatReason reason);

/// What one epoch's ambiguity resolution did (diagnostics, CSV, summaries).
struct AmbiguityFixSummary {
  AmbiguityFloatReason float_reason = AmbiguityFloatReason::Disabled;
  IlsFloatReason ils_reason = IlsFloatReason::None;
  int wide_lane_candidates = 0;  // single differences with enough samples
  int wide_lanes_fixed = 0;
  int narrow_lane_candidates = 0;  // dN1 offered to LAMBDA
  int narrow_lanes_fixed = 0;      // integer constraints applied
  double ratio = 0.0;
  double bootstrap_success_rate = 0.0;
  std::optional<SatelliteId> reference_satellite;
  double search_time_s = 0.0;  // decorrelation + search + validation
  bool fixed() const { return float_reason == AmbiguityFloatReason::None; }
  /// "fixed 7/9 ratio 5.3 (ref G22)" or "float: ratio test failed (ratio 1.8)".
  std::string text() const;
};

struct AmbiguityFixedState {
  Eigen::VectorXd x;
  Eigen::MatrixXd P;
  /// The accepted integer constraints A x = y on the float state (A [1/m] over
  /// the whole state, zero on the receiver part; y [cycles]): what a smoother
  /// adds to its graph (integer_ambiguity_factor.h) instead of conditioning a copy.
  Eigen::MatrixXd constraint_rows;
  Eigen::VectorXd constraint_values;
};

class AmbiguityResolver {
 public:
  explicit AmbiguityResolver(AmbiguityResolutionOptions options = {}) : options_(std::move(options)) {}

  /// Feeds one epoch's usable observations with their arcs (same order).
  /// `biases` nullptr: nothing is accumulated (float).
  void addEpoch(const std::vector<DualFrequencyObservation>& observations, const std::vector<ArcId>& arcs,
                const BiasProvider* biases);
  void arcsEnded(const std::vector<EndedArc>& ended);

  /// Resolves against the float filter state x, P whose entries from
  /// `receiver_dim` on are the IF biases [m] of `bias_arcs` (in that order).
  /// With `elevation_rad` (this epoch's elevation per arc), arcs below
  /// min_elevation_rad or without an elevation are left float (nor reference).
  /// Returns the fixed copy when fixed; `summary` says what happened.
  std::optional<AmbiguityFixedState> resolve(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, int receiver_dim,
                                             const std::vector<ArcId>& bias_arcs, const BiasProvider* biases,
                                             AmbiguityFixSummary& summary,
                                             const std::map<ArcId, double>* elevation_rad = nullptr) const;

  const AmbiguityResolutionOptions& options() const { return options_; }

 private:
  AmbiguityResolutionOptions options_;
  WideLaneResolver wide_lane_{options_.wide_lane};
  std::map<ArcId, DualFrequencyObservation> last_observation_;  // signals and frequencies of each arc
};

/// The constraints A x = y applied to a copy of (x, P) by exact conditioning;
/// nullopt when A P A^T is not positive definite.
std::optional<AmbiguityFixedState> applyIntegerConstraints(const Eigen::VectorXd& x, const Eigen::MatrixXd& P,
                                                           const Eigen::MatrixXd& A, const Eigen::VectorXd& y);

}  // namespace ppp
