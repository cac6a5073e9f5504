#pragma once
// EstimatorEpochResult: what any PPP estimator (EKF, smoother) reports for one
// epoch: status and the reason of a missing solution, the receiver solution
// (float or fixed), the satellites used and rejected with their reasons, the
// residuals, and the smoother's own diagnostics when the estimator is one.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/ppp/ambiguity/ambiguity_resolution.h"
#include "ppp_bayes_tree/ppp/model/rejection_reason.h"
#include "ppp_bayes_tree/ppp/model/satellite_measurement.h"
#include "ppp_bayes_tree/ppp/screening/solution_integrity.h"

namespace ppp {

enum class EpochStatus { Ok, NoSolution, Failed };
std::string toString(EpochStatus status);  // "ok", "no_solution", "failed"

/// Whether the phase biases of a solution are float or fixed to integers.
enum class AmbiguityState { Float, Fixed };
std::string toString(AmbiguityState state);  // "float", "fixed"

/// Covariance of a receiver state, in the state's layout order [m^2].
using ReceiverCovariance = Eigen::MatrixXd;

struct EpochSolution {
  ReceiverState state;
  ReceiverCovariance covariance;  // layout.dim() square
  Eigen::Matrix3d positionCovariance_m2() const {
    const int p = state.layout.position();
    return covariance.block<ReceiverStateLayout::kPositionSize, ReceiverStateLayout::kPositionSize>(p, p);
  }
  double zwdVariance_m2() const { return covariance(state.layout.zwd(), state.layout.zwd()); }
  double clockVariance_m2(GnssSystem system) const {
    const int c = state.layout.clock(system);
    return covariance(c, c);
  }
};

/// Residuals of one used satellite [m]. Prefit: at the prediction (after the
/// clock shift), phase minus the bias estimate (or its initial value for a new
/// arc). Postfit: at the updated state.
struct MeasurementResidual {
  SatelliteId satellite;
  ArcId arc = 0;
  bool new_arc = false;
  double elevation_rad = 0.0;
  double azimuth_rad = 0.0;
  double code_prefit_m = 0.0;
  double phase_prefit_m = 0.0;
  double code_postfit_m = 0.0;
  double phase_postfit_m = 0.0;
  double code_sigma_m = 0.0;
  double phase_sigma_m = 0.0;
};

/// Filtered estimate of one arc's IF phase bias right after an update.
struct ArcBiasEstimate {
  ArcId arc = 0;
  SatelliteId satellite;
  double bias_m = 0.0;
  double sigma_m = 0.0;  // sqrt of the marginal variance
};

/// The smoother's own per-epoch diagnostics (iSAM2 update).
struct SmootherEpochDiagnostics {
  int new_biases = 0;
  std::vector<ArcBiasEstimate> biases;  // filtered biases of the arcs observed this epoch (when Ok)
  std::size_t variables_relinearized = 0;
  std::size_t variables_reeliminated = 0;
  std::size_t factors_relinearized = 0;
  std::size_t cliques_touched = 0;
  std::size_t variables_marginalized = 0;  // fixed-lag only
  double update_time_s = 0.0;              // the iSAM2 (or fixed-lag) update
  /// Wall time of the iSAM2 steps summed over the epoch's updates (the update and any
  /// postfit removals) [s], in smoother::ISAM2Result::Step order: add factors,
  /// relinearize, remove top, re-eliminate, back-substitute. The rest of update_time_s is
  /// the fixed lag's marginalization and the postfit check's own work.
  std::array<double, 5> isam2_step_time_s{};
};

struct EstimatorEpochResult {
  GnssTime time;
  EpochStatus status = EpochStatus::NoSolution;
  NoSolutionReason no_solution_reason = NoSolutionReason::None;  // None when Ok
  std::string reason;                     // readable, with values; empty when Ok
  std::optional<EpochSolution> solution;  // only when Ok (the smoother: FILTERED)
  AmbiguityState ambiguities = AmbiguityState::Float;
  double dt_s = 0.0;                      // elapsed since the last solved epoch (0 at the first)
  std::vector<SatelliteId> used;
  std::vector<RejectedSatellite> rejected;  // the model's rejections, then the estimator's
  int prefit_rejections = 0;
  int postfit_rejections = 0;
  /// The epoch consistency test of the solution (postfit_screening.h): Inconsistent
  /// means the covariance was inflated by consistency_variance_factor (or, withheld,
  /// status NoSolution with InconsistentSolution); the test's sentence is in
  /// `consistency`. Unchecked without a solution or with the test off.
  SolutionIntegrity integrity = SolutionIntegrity::Unchecked;
  double consistency_statistic = 0.0;      // T, weighted postfit sum of squares
  int consistency_dof = 0;                 // m, measurements
  double consistency_variance_factor = 1.0;  // T / m when inflated, else 1
  std::string consistency;                 // readable test result, empty when unchecked
  int active_biases = 0;  // bias states after the epoch
  /// Arcs back after a bridged gap (PppEstimator::gapBridgeMax_s): kept, and
  /// ended by the slip test; one readable line per arc.
  int bridged_arcs_kept = 0, bridged_arcs_ended = 0;
  /// Of them, the arcs whose slip the arc tracker repaired (BridgedArc::repair):
  /// kept (the repair confirmed), ended (refused by the slip test).
  int repaired_arcs_kept = 0, repaired_arcs_ended = 0;
  /// Of the repaired arcs kept, those whose slip the gap bridge chose among the
  /// repair's candidates in place of the one applied (SlipRepair::alternatives).
  int repair_candidates_chosen = 0;
  std::vector<std::string> gap_bridge;
  int iterations = 0;     // measurement-model evaluations
  std::vector<MeasurementResidual> residuals;  // same order as `used`
  /// The estimator restarted from its last good state after this (failed) epoch.
  bool estimator_reset = false;
  double epoch_time_s = 0.0;  // the whole estimator step (model evaluations included)
  std::optional<SmootherEpochDiagnostics> smoother;  // set by the smoother
  /// Ambiguity resolution of this epoch (set when it is enabled); the solution
  /// is the fixed one when ambiguity_fix->fixed() (ambiguities == Fixed).
  std::optional<AmbiguityFixSummary> ambiguity_fix;
  /// The attitude's alignment, sigmas and whether it is good enough to publish
  /// (estimators with inertial states, once started).
  std::optional<InsAttitudeQuality> attitude;
};

}  // namespace ppp
