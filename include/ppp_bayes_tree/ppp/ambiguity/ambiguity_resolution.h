#pragma once
// AmbiguityResolver: PPP integer ambiguity resolution (PPP-AR) for a filter
// whose state holds one ionosphere-free (IF) phase bias [m] per arc, with
// satellite phase biases consistent with the clocks (phase_bias_consistency.h).
// Per epoch: wide lanes from Melbourne-Wuebbena means, rounded, against one
// reference arc per system (wide_lane_ambiguity.h); narrow-lane single
// differences searched by LAMBDA with the ratio test, the bootstrapped success
// rate and partial fixing (integer_least_squares.h); the accepted integers
// applied as exact conditioning of a COPY of the float state, so the float
// filter is never changed (resolve()). resolveAndHold() adds what the EKF and
// the smoother use: a consistency window and a candidate gate before the
// search, validation across epochs, and the hold and release of integers.
// The steps, their keys and the user's view: doc/ppp_ar.md.
//
// References: Ge M. et al. (2008) J Geod 82:389-399 (wide lane then narrow lane,
// single differences between satellites); Laurichesse D. et al. (2009)
// Navigation 56(2) (integer clocks, the GRG convention); Schaer S. et al. (2021)
// J Geod 95:81 (the OSB convention); Teunissen P.J.G. (1998) J Geod 72:606-612
// (bootstrapped success rate); Teunissen P.J.G., Verhagen S. (2009) Survey
// Review 41(312):138-151 (the ratio test as a validation).
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Core>

#include "ppp_bayes_tree/models/bias_provider.h"
#include "ppp_bayes_tree/ppp/ambiguity/integer_least_squares.h"
#include "ppp_bayes_tree/ppp/ambiguity/wide_lane_ambiguity.h"
#include "ppp_bayes_tree/ppp/model/arc_tracker.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

/// Validation across epochs and hold (resolveAndHold()).
struct AmbiguityHoldOptions {
  /// Epochs of float history a single difference needs before it is searched,
  /// and over which its float may spread by at most max_float_spread_cycles.
  int consistency_epochs = 10;
  double max_float_spread_cycles = 0.2;
  /// A float that spreads by more is still steady when every value i of the
  /// window lies within max_float_drift_sigmas sigmas of the change its
  /// covariance explains, |x_i - x_first| <= k sqrt(sigma_first^2 - sigma_i^2):
  /// the filtered estimate of a constant (a single difference of ambiguities)
  /// changes only by gains times innovations, which are independent of the
  /// earlier estimate (Kailath 1968, IEEE Trans. Autom. Control 13(6):646-655;
  /// Teunissen 2001, Dynamic data processing, Delft University Press), so
  /// x_i - x_first has the variance sigma_first^2 - sigma_i^2. A converging
  /// float moves that much and is steady; a float that moves more (or moves
  /// while its sigma stays) carries an error its covariance does not hold.
  /// 0 = the raw spread alone. 3: a 3-sigma test, as the candidate gate
  /// (measured: doc/studies/config_defaults.md).
  double max_float_drift_sigmas = 3.0;
  /// Candidate gate (Ge et al. 2008: a narrow lane is fixed only with a small
  /// fractional part and sigma; PRIDE PPP-AR applies it so): a
  /// single difference is offered to the search only when its float,
  /// conditioned on the held integers, lies within max_fraction_cycles or 3
  /// of its sigmas of an integer and its sigma is below max_sigma_cycles; and
  /// an integer the search returns is accepted by the same rule (the
  /// search may otherwise pick, through the correlations, an integer 0.5 cycle
  /// away when all floats share a bias the covariance does not hold).
  /// PRIDE PPP-AR uses 0.15 / 0.15 in its batch; here 0.25 cycle and 1 cycle
  /// (LAMBDA's success rate covers the sigma; doc/studies/ar_real_data.md, "ESBC
  /// day, kinematic").
  double max_fraction_cycles = 0.25;
  double max_sigma_cycles = 1.0;
  /// A float further than max_fraction_cycles from its integer still passes
  /// the gate when it lies within this many of its sigmas (0 = the fraction
  /// alone). 1: a float 0.35 cycle from its integer at a sigma of 0.14 is not
  /// an integer yet (measured: doc/studies/config_defaults.md).
  double max_fraction_sigmas = 1.0;
  /// Every subset the search accepts (the first fix as well as what partial
  /// fixing adds) must reach the bootstrapped success rate (Teunissen 1998)
  /// narrow_lane.min_success_rate, computed from the float covariance times
  /// narrow_lane.success_rate_variance_factor, as well as the ratio test
  /// (Teunissen, Joosten & Tiberius 1999: the subset is chosen by its success
  /// rate; the ratio test alone does not bound the failure rate, Verhagen &
  /// Teunissen 2013). false: the ratio test alone decides subsets larger than
  /// small_subset_max_size (measured: doc/studies/ar_real_data.md, "Restarts").
  bool require_subset_success_rate = true;
  /// Subsets of at most this many integers must reach the bootstrapped success
  /// rate narrow_lane.min_success_rate as well as the ratio test, whatever
  /// require_subset_success_rate says (0 = none). The ratio test is a weak test
  /// in few dimensions (Verhagen & Teunissen 2013: its failure rate at a fixed
  /// threshold grows as the dimension drops): for one integer, ratio 3 accepts any
  /// float within 0.37 cycle of an integer, whatever its sigma. Such small subsets
  /// are what partial fixing adds to an existing held set (min_fixed - held),
  /// while the first fix needs min_fixed integers together and keeps the ratio
  /// test alone, so this costs no time to first fix (doc/studies/ar_real_data.md).
  int small_subset_max_size = 3;
  /// Consecutive searches giving the same integer before it is held.
  int validation_epochs = 5;
  /// Fewer of them for a well-determined subset: when the bootstrapped success
  /// rate (Teunissen 1998, a sharp lower bound of the integer least-squares
  /// success rate) of the subset the search accepted this epoch is at least
  /// fast_validation_success_rate, its integers are held after
  /// fast_validation_epochs consecutive equal searches (the success rate says
  /// the integer is determined; the repetition still guards against a float
  /// that jumps). 1 = never (the default): a success rate does not know the
  /// constant narrow-lane offsets of satellite antennas of another model than
  /// the products' (measured: doc/studies/config_defaults.md).
  double fast_validation_success_rate = 1.0;
  int fast_validation_epochs = 2;
  /// A held integer is released when its float (conditioned on the other held
  /// ones) departs by more than both of these.
  double release_cycles = 0.4;
  double release_sigma = 4.0;
  /// When an arc ends, the held integers through it are re-expressed between
  /// the arcs it linked (N(a - e) - N(b - e) = N(a - b), the same for the wide
  /// lanes), so that the held set survives the end of its reference arc instead
  /// of being validated again from nothing.
  bool rereference_on_arc_end = true;
};

/// What `ambiguity_resolution.enabled` asks for (product_assembly.h decides Auto).
enum class AmbiguityResolutionMode {
  Off,   // false: float
  On,    // true: fix with whatever consistent phase information there is
  Auto,  // auto (default): fix only where it is sound (consistent phase information, the products' antennas)
};
std::string toString(AmbiguityResolutionMode mode);  // "false", "true", "auto"

/// The narrow-lane search options PPP-AR starts from (see narrow_lane below).
inline IlsOptions pppNarrowLaneOptions() {
  IlsOptions o;
  o.success_rate_variance_factor = 2.0;
  return o;
}

struct AmbiguityResolutionOptions {
  /// What the configuration asks for. The product assembly (product_assembly.h)
  /// turns it into `enabled` for the run: Off -> false, On -> true, Auto -> the
  /// gate's verdict.
  AmbiguityResolutionMode mode = AmbiguityResolutionMode::Auto;
  /// Whether the estimator's resolver runs. Code that sets it true without the
  /// assembly gets the resolver as before (`mode` is then read as On).
  bool enabled = false;
  /// Arcs below this elevation are not fixed (their float biases carry the
  /// multipath and mapping errors of low satellites) [rad]; 0 = all. 15 deg.
  double min_elevation_rad = 15.0 * kDegToRad;
  WideLaneOptions wide_lane;
  /// The narrow-lane search, with its success rate computed from the float
  /// covariance times 2 (sigmas x 1.41; measured: doc/studies/config_defaults.md).
  IlsOptions narrow_lane = pppNarrowLaneOptions();
  AmbiguityHoldOptions hold;
  /// Fix even when the satellite antenna model of the products (SP3/clock header)
  /// differs from the ANTEX's, or (auto) is not known (antenna_model_consistency.h);
  /// false: such a run stays float with the reason named. Off by default: a PCO difference leaves a
  /// constant narrow-lane offset per satellite (doc/ppp_ar.md, "When a run fixes").
  bool allow_antenna_model_mismatch = false;
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
  Validating,               // resolveAndHold: too few integers held yet (validation across epochs)
  FloatsDrifting,           // resolveAndHold: no single difference passed the float consistency window
  FloatsOffInteger,         // resolveAndHold: the steady floats all failed the candidate gate
  IntegerFarFromFloat,      // resolveAndHold: the search's integers failed the candidate gate (last subset tried)
};
std::string toString(AmbiguityFloatReason reason);

/// One narrow-lane single difference of an epoch (diagnostics).
struct NarrowLaneFloat {
  ArcId arc = 0, reference_arc = 0;
  SatelliteId satellite, reference_satellite;
  long wide_lane_cycles = 0;
  double float_cycles = 0.0;  // dN1 from the float state
  double sigma_cycles = 0.0;
  std::optional<long> held_cycles;  // set when held this epoch
};

/// Why a held integer was released.
enum class AmbiguityReleaseReason { FloatDeparted, WideLaneChanged, ArcEnded };
std::string toString(AmbiguityReleaseReason reason);

struct AmbiguityRelease {
  SatelliteId satellite, reference_satellite;
  ArcId arc = 0, reference_arc = 0;  // the single difference's arcs (a smoother removes its factor by them)
  AmbiguityReleaseReason reason = AmbiguityReleaseReason::FloatDeparted;
  double departure_cycles = 0.0;  // float - held (FloatDeparted)
};

/// One system's part of an epoch's ambiguity resolution (each system has its
/// own reference arc).
struct SystemAmbiguitySummary {
  GnssSystem system = GnssSystem::GPS;
  SatelliteId reference_satellite;
  int wide_lane_candidates = 0;
  int wide_lanes_fixed = 0;
  int narrow_lane_candidates = 0;  // resolveAndHold: offered to the search
  int held = 0;                    // resolveAndHold: integers held after this epoch
};

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
  /// The reference of the first system with one (GPS before Galileo); every
  /// system's reference is in `systems`.
  std::optional<SatelliteId> reference_satellite;
  std::vector<SystemAmbiguitySummary> systems;  // the systems with a wide-lane reference this epoch
  double search_time_s = 0.0;  // decorrelation + search + validation
  // resolveAndHold() only:
  std::vector<NarrowLaneFloat> narrow_lanes;  // this epoch's single differences
  int held = 0;                               // integers held after this epoch
  int newly_held = 0;                         // of them, validated this epoch
  /// The held integers' residual test: T = r^T (A P A^T)^-1 r, r = the held
  /// single differences' floats minus their integers [cycles], m = their number;
  /// under the model T ~ chi-square(m) (Teunissen 1998, the ambiguity residual).
  double held_residual_statistic = 0.0;
  int held_residual_dof = 0;
  std::vector<AmbiguityRelease> released;     // released this epoch
  bool fixed() const { return float_reason == AmbiguityFloatReason::None; }
  /// "fixed 7/9 ratio 5.3 (ref G22 E05, WL 8/9)" or "float: ratio test failed (ratio 1.8)".
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
  /// r^T (A P A^T)^-1 r with r = A x - y: the constraints' residual statistic
  /// against the float state (chi-square with A.rows() degrees of freedom under
  /// the model; applyIntegerConstraints() computes it with the same factorisation).
  double constraint_residual_statistic = 0.0;
};

class AmbiguityResolver {
 public:
  explicit AmbiguityResolver(AmbiguityResolutionOptions options = {}) : options_(std::move(options)) {}

  /// Feeds one epoch's usable observations with their arcs (same order).
  /// `biases` nullptr: nothing is accumulated (float).
  void addEpoch(const std::vector<DualFrequencyObservation>& observations, const std::vector<ArcId>& arcs,
                const BiasProvider* biases);
  void arcsEnded(const std::vector<EndedArc>& ended);
  /// The arc's Melbourne-Wubbena mean starts again (WideLaneResolver::restartArc): its
  /// phases were repaired with a wide lane that may be off by a slip common to its
  /// system. Its held integers stay; whether its wide lane changed is asked again once
  /// the new mean rounds.
  void restartWideLane(ArcId arc) { wide_lane_.restartArc(arc); }

  /// Resolves against the float filter state x, P whose entries from
  /// `receiver_dim` on are the IF biases [m] of `bias_arcs` (in that order).
  /// With `elevation_rad` (this epoch's elevation per arc), arcs below
  /// min_elevation_rad or without an elevation are left float (nor reference).
  /// Returns the fixed copy when fixed; `summary` says what happened.
  std::optional<AmbiguityFixedState> resolve(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, int receiver_dim,
                                             const std::vector<ArcId>& bias_arcs, const BiasProvider* biases,
                                             AmbiguityFixSummary& summary,
                                             const std::map<ArcId, double>* elevation_rad = nullptr) const;

  /// resolve() with validation across epochs and hold (steps 5-8 above): keeps
  /// the float history, the integers being validated and the held integers.
  /// The fixed copy is returned when at least narrow_lane.min_fixed integers
  /// are held. Its named steps:
  ///  1. slotArcs: the state index of every bias arc, and the arcs high enough
  ///     for new candidates (min_elevation_rad);
  ///  2. keepPresentHeld: held integers whose arc ended or whose wide lane
  ///     changed are released;
  ///  3. conditionOnHeld: each held integer against its float conditioned on
  ///     the other held ones (hold, step 8 above); the worst offender is
  ///     released; the float is conditioned on the rest;
  ///  4. recordHeld: the held single differences into the summary;
  ///  5. gatherCandidates: wide-lane fixed pairs, steady in the float history,
  ///     through the candidate gate (step 5 above);
  ///  6. searchBestSubset: partial fixing (step 6 above);
  ///  7. validateAndHold: validation across epochs (step 7 above), then hold;
  ///  8. applyHeld: the held integers applied to a copy of the float state, or
  ///     the reason it stays float.
  std::optional<AmbiguityFixedState> resolveAndHold(const Eigen::VectorXd& x, const Eigen::MatrixXd& P,
                                                    int receiver_dim, const std::vector<ArcId>& bias_arcs,
                                                    const BiasProvider* biases, AmbiguityFixSummary& summary,
                                                    const std::map<ArcId, double>* elevation_rad = nullptr);
  /// Releases every held integer (e.g. after a filter reset); counted.
  void releaseAll();
  /// Holds an integer decided outside the search (dN1 of `arc` against
  /// `reference_arc` with that wide lane), e.g. one restored after a restart,
  /// or a deliberately wrong one in a wrong-fix injection test. From the next
  /// resolveAndHold() on it is validated and released like a searched one.
  void holdInteger(ArcId arc, ArcId reference_arc, long wide_lane_cycles, long narrow_lane_cycles);
  int heldCount() const { return static_cast<int>(held_.size()); }
  long releasesTotal() const { return releases_total_; }

  const AmbiguityResolutionOptions& options() const { return options_; }

 private:
  /// A single difference: the arc, its reference arc and its wide lane.
  struct PairKey {
    ArcId arc = 0, reference_arc = 0;
    long wide_lane_cycles = 0;
    bool operator<(const PairKey& o) const {
      return std::tie(arc, reference_arc, wide_lane_cycles) < std::tie(o.arc, o.reference_arc, o.wide_lane_cycles);
    }
  };
  struct PairRow {
    PairKey key;
    SatelliteId satellite, reference_satellite;
    Eigen::RowVectorXd d;  // dN1 = d x - offset
    double offset = 0.0;
  };
  struct Pending {
    long integer = 0;
    int count = 0;
  };
  /// The row of a single difference (nullopt when an arc has no slot, no
  /// observation or no phase bias).
  std::optional<PairRow> rowOf(const PairKey& key, int dim, const std::map<ArcId, int>& slot,
                               const BiasProvider* biases) const;
  /// The rows of the wide-lane fixed single differences of `per_system` (resolve()).
  std::vector<PairRow> wideLaneFixedRows(const std::vector<WideLaneResolution>& per_system, int dim,
                                         const std::map<ArcId, int>& slot, const BiasProvider* biases) const;
  /// The wide lanes of each system among the `slot` arcs against that system's
  /// best-determined arc (resolve()).
  std::vector<WideLaneResolution> wideLanesPerSystem(const std::map<ArcId, int>& slot) const;
  /// The same, keeping each system's reference of the last epoch while it is
  /// eligible and fixes as many wide lanes (resolveAndHold()).
  std::vector<WideLaneResolution> wideLanesPerSystemKeepingReferences(const std::map<ArcId, int>& slot);
  std::optional<GnssSystem> systemOf(ArcId arc) const;

  /// The state carried between the steps of resolveAndHold (defined with them).
  struct HoldEpoch;
  void slotArcs(int receiver_dim, const std::vector<ArcId>& bias_arcs, const std::map<ArcId, double>* elevation_rad,
                HoldEpoch& e) const;
  void keepPresentHeld(HoldEpoch& e);
  bool conditionOnHeld(HoldEpoch& e);
  void recordHeld(HoldEpoch& e) const;
  void gatherCandidates(HoldEpoch& e);
  void searchBestSubset(HoldEpoch& e) const;
  void validateAndHold(HoldEpoch& e);
  std::optional<AmbiguityFixedState> applyHeld(HoldEpoch& e) const;
  AmbiguityFloatReason floatReason(const HoldEpoch& e) const;
  /// Releases a held integer (counted unless its arc ended) into the summary.
  std::map<PairKey, long>::iterator release(std::map<PairKey, long>::iterator it, AmbiguityReleaseReason why,
                                            double departure, const SatelliteId& sat, const SatelliteId& ref,
                                            AmbiguityFixSummary& summary);
  SatelliteId satelliteOf(ArcId arc) const;

  AmbiguityResolutionOptions options_;
  WideLaneResolver wide_lane_{options_.wide_lane};
  std::map<ArcId, DualFrequencyObservation> last_observation_;  // signals and frequencies of each arc
  struct FloatSample {
    double value_cycles = 0.0, sigma_cycles = 0.0;
  };
  std::map<PairKey, std::vector<FloatSample>> float_history_;  // recent float dN1 and its sigma per pair
  std::map<PairKey, Pending> pending_;
  std::map<PairKey, long> held_;
  std::map<GnssSystem, ArcId> reference_arcs_;  // one per system, kept while eligible
  long releases_total_ = 0;
};

/// The constraints A x = y applied to a copy of (x, P) by exact conditioning
/// (with constraint_residual_statistic; constraint_rows/values are left empty);
/// nullopt when A P A^T is not positive definite.
std::optional<AmbiguityFixedState> applyIntegerConstraints(const Eigen::VectorXd& x, const Eigen::MatrixXd& P,
                                                           const Eigen::MatrixXd& A, const Eigen::VectorXd& y);

}  // namespace ppp
