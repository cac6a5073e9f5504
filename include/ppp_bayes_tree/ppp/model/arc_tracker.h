#pragma once
// ArcTracker: carrier-phase preprocessing. Fed one epoch at a time, it assigns
// every satellite the id of its continuous phase arc (ArcId) and starts a new
// arc on a new satellite, a receiver loss-of-lock flag, a data gap or a
// detected cycle slip.
//
// Cycle-slip tests (Blewitt 1990, "An automatic editing algorithm for GPS
// data", GRL 17(3); Springer Handbook of GNSS 2017, sec. 20.3.1):
//  * Melbourne-Wuebbena (MW, wide-lane cycles): free of geometry, clocks,
//    troposphere and ionosphere, so it is flat within an arc up to code noise and
//    multipath. A running mean and standard deviation are kept per arc
//    (exponentially forgetting after `mw_window` samples); a slip is declared
//    when |MW - mean| > max(mw_sigma_factor * sigma, mw_min_threshold_cycles).
//    Until `mw_min_samples` samples are in, sigma is `mw_initial_sigma_cycles`.
//    Catches every slip with N1 - N2 != 0 of about one wide-lane cycle or more,
//    e.g. (1,0), (0,1), (9,7). It is insensitive to N1 = N2 slips.
//  * Geometry-free phase (GF = L1 - L2 in metres): only the ionosphere (and
//    the constant ambiguities) remain. The value at this epoch is compared with
//    a linear least-squares fit through the last `gf_fit_points` epochs of the
//    arc, extrapolated to this epoch. A (1,1) slip moves GF by lambda1 - lambda2
//    = -5.4 cm on GPS L1/L2; (1,0) by 19 cm.
//
// Interval scaling of the GF threshold: the prediction error is phase noise
// plus multipath (a constant part) plus the unmodelled change of the
// ionospheric drift over the prediction interval dt (seconds since the
// satellite's previous epoch), which grows with dt. We use the linear law
//     threshold_m = gf_threshold_base_m + gf_threshold_rate_mps * dt
// with defaults 0.030 m + 0.0006 m/s: 3.1 cm at 1 s, 4.8 cm at 30 s (just below
// the 5.4 cm of a (1,1) slip; RTKLIB's fixed default is 5 cm), capped at
// gf_threshold_max_m for longer intervals. With a single previous epoch the
// drift cannot be predicted, so gf_drift_allowance_mps * dt is added (6 cm at
// 30 s, 2 mm at 1 s). Low-elevation arcs whose ionosphere fluctuates faster than
// a line can follow (seen on ZIM2 G05 at 30 s: 2 cm scatter of the prediction
// residuals) raise their own threshold: the running RMS of the arc's GF
// prediction residuals times gf_sigma_factor is used when larger (after
// gf_min_samples residuals). Such arcs then need MW (N1 != N2) to see small
// slips. The MW threshold is not scaled: MW holds no time-varying geometric or
// ionospheric term.
//
// Data gaps: a satellite whose previous epoch is more than max_gap_s ago starts
// a new arc. When max_gap_s is not set, it is max_gap_intervals times the data
// interval, estimated as the smallest spacing between accepted epochs.
//
// Epochs that go backwards in time or repeat the previous time are refused with
// a reason and change no state.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/model/dual_frequency_observation.h"
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
  double mw_cycles = 0.0;  // this epoch's MW [wide-lane cycles]
  double gf_m = 0.0;       // this epoch's GF phase [m]
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

  CycleSlipOptions options_;
  std::map<SatelliteId, ArcState> arcs_;
  std::optional<GnssTime> last_epoch_;
  std::optional<double> interval_s_;
  ArcId next_id_ = 1;
};

}  // namespace ppp
