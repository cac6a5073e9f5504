#pragma once
// ArcTracker: carrier-phase preprocessing. Fed one epoch at a time, it assigns
// every satellite the id of its continuous phase arc (ArcId) and starts a new
// arc on a new satellite, a receiver loss-of-lock flag, a data gap or a cycle
// slip detected by the Melbourne-Wuebbena test (N1 != N2 slips) or the
// geometry-free phase test (a threshold growing with the interval, raised on
// noisy arcs). Epochs that go backwards or repeat refuse with a reason and change
// no state. The tests, thresholds and gap rule: doc/measurement_model.md, "Arcs
// and cycle slips".
// References: Blewitt G. (1990) An automatic editing algorithm for GPS data,
// GRL 17(3); Teunissen & Montenbruck (eds.) (2017) Springer Handbook of GNSS,
// sec. 20.3.1.
// Across a gap the estimator bridges, an arc whose slip tests fail may go on with
// its phase repaired (slip_repair.h): SatelliteArcStatus::phase_correction1_cycles
// and phase_correction2_cycles are then subtracted from its phases from that epoch on,
// here only: SatelliteArcStatus::phase1_cycles and phase2_cycles are the corrected
// phases the tracker's tests and the estimator use.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/model/dual_frequency_observation.h"
#include "ppp_bayes_tree/ppp/model/slip_repair.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

struct CycleSlipOptions {
  // Melbourne-Wuebbena test.
  double mw_sigma_factor = 5.0;           // k in k * sigma
  double mw_min_threshold_cycles = 1.0;   // absolute floor of the threshold [wide-lane cycles]
  double mw_initial_sigma_cycles = 0.5;   // sigma used before mw_min_samples samples
  int mw_min_samples = 5;
  int mw_window = 60;                     // forgetting length of the running mean/variance
  // Geometry-free test (threshold = base + rate * dt, capped).
  double gf_threshold_base_m = 0.030;
  double gf_threshold_rate_mps = 0.0006;
  double gf_threshold_max_m = 0.15;
  int gf_fit_points = 5;                  // epochs in the linear prediction
  double gf_drift_allowance_mps = 0.002;  // added when only one previous epoch is known
  double gf_sigma_factor = 4.0;           // adaptive threshold: k * RMS of prediction residuals
  int gf_min_samples = 5;
  // Data gaps.
  std::optional<double> max_gap_s;        // explicit maximum gap [s]
  double max_gap_intervals = 3.0;         // otherwise: this many data intervals
  double default_interval_s = 30.0;       // interval assumed before two epochs are seen
  // Gaps an estimator bridges (set by the pipeline for an estimator that verifies
  // them, PppEstimator::gapBridgeMax_s): an arc back after a gap longer than the
  // maximum gap but at most this is not ended by the gap; it goes through the
  // slip tests and is marked (SatelliteArcStatus::bridged_gap_s). Unset: every
  // gap longer than the maximum ends the arc.
  std::optional<double> bridge_max_gap_s;
  // Repair of a slip across a bridged gap (slip_repair.h): an arc whose slip tests
  // fail after a bridged gap goes on with its phase corrected by the identified
  // integer slip when the repair is accepted; otherwise a new arc starts. Only
  // with bridge_max_gap_s set (an estimator that verifies bridged arcs).
  SlipRepairOptions slip_repair;
  // Receiver loss-of-lock indicator (RINEX LLI bit 0) starts a new arc.
  bool use_loss_of_lock = true;

  /// GF threshold [m] for a prediction over dt seconds.
  double geometryFreeThreshold_m(double dt_s) const;
};

/// Why an arc started at this epoch.
enum class ArcStartReason {
  None,                   // arc continues
  NewSatellite,
  LossOfLock,             // receiver LLI bit 0
  DataGap,
  MelbourneWuebbenaJump,
  GeometryFreeJump,
};
const char* arcStartReasonName(ArcStartReason reason);

struct SatelliteArcStatus {
  SatelliteId satellite;
  /// Arc id (> 0) when usable; 0 when the observation was refused (see reason).
  ArcId arc = 0;
  bool usable = true;
  bool new_arc = false;
  ArcStartReason start_reason = ArcStartReason::None;
  /// Readable reason, e.g. "Melbourne-Wubbena jump 3.2 cycles > 1.0",
  /// "data gap 95 s > 90 s", "LLI set on L1"; empty when the arc continues.
  std::string reason;
  /// The gap [s] an arc that goes on was bridged over (longer than the maximum
  /// gap, at most bridge_max_gap_s); 0 otherwise.
  double bridged_gap_s = 0.0;
  /// A bridged arc's geometry-free phase minus its prediction from the arc's
  /// fit [m] (the ionosphere's drift through the gap removed); nullopt when the
  /// arc has fewer than two geometry-free samples.
  std::optional<double> bridged_gf_jump_m;
  /// This epoch's phases with the arc's corrections subtracted [cycles] (the
  /// observed ones without a repair): the phases of the arc.
  double phase1_cycles = 0.0, phase2_cycles = 0.0;
  double mw_cycles = 0.0;  // this epoch's MW [wide-lane cycles] of the corrected phases
  double gf_m = 0.0;       // this epoch's GF phase [m] of the corrected phases
  /// The repair attempted at this epoch after a bridged gap (accepted or refused);
  /// nullopt when none was attempted.
  std::optional<SlipRepair> slip_repair;
  /// The arc's integer phase corrections so far [cycles]: the slips repaired,
  /// to be subtracted from the observed phases (0 without a repair).
  long phase_correction1_cycles = 0, phase_correction2_cycles = 0;
};

struct EndedArc {
  SatelliteId satellite;
  ArcId arc = 0;
  GnssTime first_time, last_time;
  std::size_t epochs = 0;
  std::string reason;  // "cycle slip: ...", "not observed for 120 s > 90 s", "end of data"
};

struct ArcEpochResult {
  GnssTime time;
  bool accepted = true;
  std::string refusal_reason;  // "time goes backwards by 30 s", "duplicate epoch"
  /// One entry per input observation, in input order.
  std::vector<SatelliteArcStatus> satellites;
  /// Arcs that ended at this epoch (replaced after a slip/gap, or gone longer than the max gap).
  std::vector<EndedArc> ended;
  std::size_t newArcCount() const;
};

class ArcTracker {
 public:
  explicit ArcTracker(CycleSlipOptions options = {});

  /// Processes one epoch. Never throws on bad data: non-finite observations and
  /// repeated satellites are marked unusable, bad epoch times refuse the epoch.
  ArcEpochResult process(const GnssTime& time, const std::vector<DualFrequencyObservation>& observations);
  /// Ends all open arcs (end of data) and returns them.
  std::vector<EndedArc> finish();

  /// Current open arc of a satellite.
  std::optional<ArcId> currentArc(const SatelliteId& satellite) const;
  /// Data interval in use [s] (estimated or default).
  double interval_s() const;
  double maxGap_s() const;
  const CycleSlipOptions& options() const { return options_; }
  /// Sets the longest gap an estimator bridges (CycleSlipOptions::bridge_max_gap_s).
  void setBridgeMaxGap_s(std::optional<double> seconds) { options_.bridge_max_gap_s = seconds; }
  /// The longest absence after which an arc may still go on [s].
  double arcKeepGap_s(double max_gap_s) const;
  /// Applies another candidate of a repair made at the last epoch (one of its
  /// SlipRepair::alternatives, chosen by the estimator's gap bridge) in place of the
  /// one applied: the arc's state is that epoch's again with this slip. Returns the
  /// satellite's status with the phases so corrected; nullopt when the satellite had
  /// no repair with alternatives at the last epoch or the candidate is not one of them.
  std::optional<SatelliteArcStatus> chooseRepairCandidate(const SatelliteId& satellite,
                                                          const SlipCandidate& candidate);
  /// Ends the satellite's arc at the last epoch and starts a new one there (a new id,
  /// its phases as observed): for an arc that went on across a bridged gap and that
  /// the estimator's gap bridge ended. Returns the new arc's status; nullopt when the
  /// satellite had no open arc continued at the last epoch.
  std::optional<SatelliteArcStatus> restartArc(const SatelliteId& satellite, const std::string& reason);

 private:
  struct ArcState {
    ArcId id = 0;
    bool open = false;
    GnssTime first_time, last_time;
    std::size_t epochs = 0;
    // MW running statistics.
    double mw_mean = 0.0, mw_var = 0.0;
    int mw_count = 0;
    // Recent GF samples (time since first_time [s], GF [m]).
    std::vector<std::pair<double, double>> gf_history;
    // Running mean square of the GF prediction residuals (from >= 2 fit points).
    double gf_res_ms = 0.0;
    int gf_res_count = 0;
    // Slips repaired so far [cycles] (subtracted from the phases).
    long correction1_cycles = 0, correction2_cycles = 0;
    // GF samples of the last SlipRepairOptions::gf_fit_window_s (time since
    // first_time [s], GF [m]); kept only when repairs can be attempted.
    std::vector<std::pair<double, double>> repair_gf_history;
  };

  void startArc(ArcState& state, const GnssTime& time, double mw, double gf);
  void updateArc(ArcState& state, const GnssTime& time, double mw, double gf,
                 std::optional<double> gf_residual) const;
  std::optional<double> predictGeometryFree(const ArcState& state, const GnssTime& time) const;
  double geometryFreeThreshold_m(const ArcState& state, double dt_s) const;
  EndedArc endArc(const SatelliteId& sat, ArcState& state, std::string reason) const;
  /// Why an epoch at `time` is refused (time backwards, duplicate); nullopt when accepted.
  std::optional<std::string> refuseEpoch(const GnssTime& time);
  /// One satellite's combinations; its arc goes on, or a new one starts.
  void trackSatellite(const GnssTime& time, const DualFrequencyObservation& obs, double max_gap,
                      SatelliteArcStatus& status, ArcEpochResult& result);
  /// Why a new arc starts (None: the arc goes on), with its text and the GF prediction residual.
  ArcStartReason arcStart(const ArcState& state, bool inserted, const DualFrequencyObservation& obs,
                          const SatelliteArcStatus& status, const GnssTime& time, double max_gap, std::string& text,
                          std::optional<double>& gf_residual) const;
  /// The Melbourne-Wubbena and geometry-free tests of an open arc.
  ArcStartReason slipTest(const ArcState& state, const SatelliteArcStatus& status, const GnssTime& time, double dt,
                          std::string& text, std::optional<double>& gf_residual) const;

  /// Repairs are attempted (a bridging estimator, repair enabled).
  bool repairActive() const;
  /// This epoch's phases of `obs` with the arc's corrections subtracted (the one
  /// place they are applied), and the MW and GF of those phases.
  static void correctedCombinations(const DualFrequencyObservation& obs, long correction1_cycles,
                                    long correction2_cycles, SatelliteArcStatus& status);
  /// Appends a GF sample to the repair history and drops those older than the fit window.
  void recordRepairSample(ArcState& state, double t_s, double gf_m) const;
  /// The slip repair of an arc whose slip tests failed after a bridged gap.
  SlipRepair attemptRepair(const ArcState& state, const DualFrequencyObservation& obs,
                           const SatelliteArcStatus& status, const GnssTime& time) const;
  /// An accepted repair applied: corrections, combinations, the GF jump left [m].
  double applyRepair(ArcState& state, const DualFrequencyObservation& obs, const SlipRepair& repair,
                     SatelliteArcStatus& status) const;

  /// An arc that went on across a bridged gap at the last epoch: what restartArc and
  /// chooseRepairCandidate need.
  struct BridgedAtLastEpoch {
    DualFrequencyObservation observation;
    SatelliteArcStatus status;                 // as returned
    std::optional<ArcState> before_repair;     // a repair with alternatives: the state before it
  };

  CycleSlipOptions options_;
  std::map<SatelliteId, ArcState> arcs_;
  std::map<SatelliteId, BridgedAtLastEpoch> bridged_;
  std::optional<GnssTime> last_epoch_;
  std::optional<double> interval_s_;
  ArcId next_id_ = 1;
};

}  // namespace ppp
