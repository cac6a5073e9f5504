#pragma once
// PppPipeline: the offline PPP processing chain of ppp_solve (no ROS):
//   RINEX obs (streamed, one epoch at a time)
//   -> signal selection (SignalSelector: IF pair, code priorities, Bias-SINEX OSB)
//   -> arc tracking (ArcTracker: cycle slips, LLI, gaps; ended arcs leave the estimator)
//   -> the measurement model (PppMeasurementModel, through a MeasurementFunction)
//   -> the estimator (PppEstimator: the EKF now, the smoother later)
//   -> one PppEpochRecord per epoch (SolutionEpoch + diagnostics) to a callback.
// Products: several SP3 and several CLK files are merged (PreciseEphemeris);
// several ANTEX files are searched in order, the first file holding an antenna
// wins (notes() says which antenna came from where); an optional Bias-SINEX
// file aligns the codes; an optional BLQ file gives ocean loading for the
// station found by the RINEX marker name.
// The chain itself takes an ObservationSource (file, in-memory epochs, later a
// decoded stream) and PppProducts (an EphemerisSource, antenna calibrations,
// biases, ocean loading): the file and in-memory constructors only build those.
// Bad input never crashes the run: epochs whose time goes backwards or repeats
// are refused and counted, data gaps are counted, satellites without products
// are rejected with the product's reason, and an epoch without enough
// satellites is an explicit "no solution" epoch (never a stale estimate).
#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/pipeline/solution_epoch.h"
#include "ppp_bayes_tree/io/rinex/observation_source.h"
#include "ppp_bayes_tree/io/rinex/time_window_source.h"
#include "ppp_bayes_tree/models/antex_calibrations.h"
#include "ppp_bayes_tree/models/bias_provider.h"
#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_estimator.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/model/ppp_measurement_model.h"
#include "ppp_bayes_tree/ppp/model/signal_selection.h"
#include "ppp_bayes_tree/ppp/pipeline/product_sources.h"

namespace ppp {

/// The format of PppInputFiles::obs: RINEX/CRX, an RTCM 3 recording
/// (io/rtcm/rtcm_observation_source.h; ppp_solve --rtcm) or a u-blox UBX recording
/// (io/ubx/ubx_observation_source.h; ppp_solve --ubx).
enum class ObservationFormat { Rinex, Rtcm3, Ubx };

/// The observation file, the orbit and clock files (OrbitClockFiles: which are
/// given selects the source, product_sources.h) and the other product files.
struct PppInputFiles : OrbitClockFiles {
  std::string obs;
  std::vector<std::string> atx;
  std::optional<std::string> bias, blq;
  ObservationFormat obs_format = ObservationFormat::Rinex;
  /// With an RTCM 3 `obs`: the approximate date that places its MSM times
  /// (ppp_solve --ref-date), when the stream itself cannot.
  std::optional<GnssTime> rtcm_reference_time;
  /// The product sanity checks of the SP3 and CLK files (product_sanity.h). Off
  /// only to measure what the estimators' own checks catch (test/integrity).
  bool check_products = true;
  /// Only the epochs inside this window [start, end) GPST are processed (ppp_solve
  /// --start/--end; io/rinex/time_window_source.h); the products are checked over it.
  ObservationWindow window;
};

/// The files of a run on precise products (SP3 + RINEX clock).
PppInputFiles preciseInputFiles(std::string obs, std::vector<std::string> sp3, std::vector<std::string> clk,
                                std::vector<std::string> atx, std::optional<std::string> bias = std::nullopt,
                                std::optional<std::string> blq = std::nullopt);

/// In-process inputs (e.g. a simulated flight, simulation/gnss_simulator.h): the
/// observation header and epochs and the products, used in place of files. All
/// referenced objects must outlive the pipeline; `antex` may be empty when the
/// measurement-model options use no antenna calibrations.
struct PppInMemoryInputs {
  const RinexObsHeader* header = nullptr;
  const std::vector<ObsEpoch>* epochs = nullptr;
  const PreciseEphemeris* products = nullptr;
  std::vector<AntexSource> antex;
  /// Satellite phase OSBs consistent with `products`' clocks (e.g. a simulated
  /// flight's); used by ambiguity resolution when enabled. nullptr: float.
  const BiasProvider* phase_biases = nullptr;
  std::string name = "in-memory";  // stands for the observation file name in notes
};

/// The products of a run, whatever they come from. `ephemeris` is required;
/// the others may be null / empty. `notes` go into the run's notes.
class ProductAssembly;

struct PppProducts {
  std::shared_ptr<const EphemerisSource> ephemeris;
  std::shared_ptr<const AntennaCalibrationProvider> antennas;
  std::shared_ptr<const BiasProvider> biases;
  std::optional<OceanLoadingCoefficients> ocean;
  std::vector<std::string> notes;
  /// The phase information for ambiguity resolution (the general constructor
  /// only; nullptr: float). A file run takes its product assembly's.
  std::shared_ptr<const BiasProvider> phase_biases;
};

/// The stage of the chain that left a satellite out.
enum class RejectionStage { Signals, Arcs, Model };  // model: the model and the estimator's screening
std::string toString(RejectionStage stage);           // "signals", "arcs", "model"

/// A satellite left out at some stage of an epoch: counted by stage and reason,
/// the detail is the readable sentence with its values.
struct EpochRejection {
  SatelliteId satellite;
  RejectionStage stage = RejectionStage::Model;
  RejectionReason reason = RejectionReason::NonFiniteModel;
  std::string detail;
  /// "model: elevation 4.2 deg below cutoff 7.0 deg".
  std::string text() const { return toString(stage) + ": " + (detail.empty() ? toString(reason) : detail); }
};

/// What rejections are counted by.
struct RejectionKey {
  RejectionStage stage = RejectionStage::Model;
  RejectionReason reason = RejectionReason::NonFiniteModel;
  bool operator<(const RejectionKey& o) const {
    return stage != o.stage ? stage < o.stage : reason < o.reason;
  }
  bool operator==(const RejectionKey& o) const { return stage == o.stage && reason == o.reason; }
};
std::string toString(const RejectionKey& key);  // "model: elevation below cutoff"

/// A slip repaired after a bridged gap (PppEpochRecord::slip_repairs).
struct ArcSlipRepair {
  SatelliteId satellite;
  ArcId arc = 0;
  SlipRepair repair;
};

/// One epoch of the run: the solution and what happened.
struct PppEpochRecord {
  SolutionEpoch solution;  // position (or explicitly none), sigmas, counts, ZWD, clock
  EpochStatus status = EpochStatus::NoSolution;
  NoSolutionReason no_solution_reason = NoSolutionReason::None;
  std::string reason;      // why there is no solution, readable ("" when ok)
  /// The epoch consistency test's sentence (solution.integrity holds its verdict).
  std::string consistency;
  bool refused = false;    // time backwards / repeated / special records: not processed at all
  std::optional<double> gap_s;  // set when this epoch follows a data gap (seconds since the previous)
  int satellites_observed = 0;  // satellites of the processed systems in the file
  int satellites_selected = 0;  // with a dual-frequency IF pair
  std::vector<SatelliteId> used;
  std::vector<EpochRejection> rejected;
  int new_arcs = 0;
  int slips = 0;  // new arcs started by a detected cycle slip or loss of lock
  /// Arc starts other than new satellites, e.g. "G17 arc 11: Melbourne-Wubbena jump 3.2 cycles > 1.0".
  std::vector<std::string> arc_events;
  /// Slips repaired after a bridged gap (slip_repair.h): the arcs go on with their
  /// phases corrected by them; and the repairs refused (those arcs started anew).
  std::vector<ArcSlipRepair> slip_repairs;
  int slip_repairs_refused = 0;
  std::vector<MeasurementResidual> residuals;  // per used satellite
  /// The receiver state's layout, and its covariance [m^2] when solved (empty otherwise).
  ReceiverStateLayout state_layout;
  ReceiverCovariance receiver_covariance;
  int active_biases = 0;  // phase-bias states of the estimator after the epoch
  /// The estimator restarted from its last good state after this (failed) epoch.
  bool estimator_reset = false;
  double estimator_time_s = 0.0;  // the estimator step of the epoch
  std::optional<SmootherEpochDiagnostics> smoother;  // the smoother's diagnostics
  /// Ambiguity resolution of the epoch (set when ambiguity_resolution is enabled);
  /// solution.status is PppFixed when ambiguity_fix->fixed().
  std::optional<AmbiguityFixSummary> ambiguity_fix;
};

/// Postfit residual statistics of one satellite over the run [m].
struct SatelliteResidualStatistics {
  SatelliteId satellite;
  std::size_t count = 0;
  double code_mean_m = 0.0, code_rms_m = 0.0;
  double phase_mean_m = 0.0, phase_rms_m = 0.0, phase_max_abs_m = 0.0;
  double min_elevation_deg = 90.0, max_elevation_deg = 0.0;
  std::size_t rejections = 0;  // epochs in which the model or estimator rejected it
};

struct PppRunSummary {
  std::string estimator;
  std::size_t epochs_read = 0;
  std::size_t epochs_solved = 0;
  std::size_t epochs_no_solution = 0;
  std::size_t epochs_failed = 0;
  std::size_t epochs_refused = 0;  // time backwards, duplicates, cycle-slip record epochs
  /// Epochs whose postfit residuals failed the consistency test (solved with an
  /// inflated covariance, or withheld: then also counted as no solution).
  std::size_t epochs_inconsistent = 0;
  std::size_t data_gaps = 0;
  std::size_t arcs = 0;
  std::size_t slips = 0;
  /// Slip repairs after bridged gaps: accepted (also those of no slip), refused.
  std::size_t slips_repaired = 0, slip_repairs_refused = 0;
  /// Rejections (satellite-epochs) by stage and reason.
  std::map<RejectionKey, std::size_t> rejection_counts;
  /// Epochs without a solution by reason.
  std::map<NoSolutionReason, std::size_t> no_solution_counts;
  /// Restarts of the estimator from its last good state after a failed update.
  std::size_t estimator_resets = 0;
  std::vector<SatelliteResidualStatistics> residual_statistics;
  /// Antenna sources, code reference, ocean loading, product notes.
  std::vector<std::string> notes;
  /// Problems of the observation file (malformed records skipped) and refusals.
  std::vector<std::string> problems;
  double processing_time_s = 0.0;
  /// Ambiguity resolution (PPP-AR): solved epochs with fixed ambiguities, and
  /// the time from the first solved epoch to the first fixed one [s].
  std::size_t epochs_fixed = 0;
  std::optional<double> time_to_first_fix_s;
};

class PppPipeline {
 public:
  /// Loads the products and opens the observation file (header only).
  /// Throws FileOpenError / ParseError (inputs) or std::runtime_error (no ANTEX).
  /// The products come from the product assembly (product_assembly.h): config()
  /// then holds the systems and the PPP-AR switch it resolved; make the
  /// estimator from config() (an estimator for other systems runs its own).
  PppPipeline(const PppInputFiles& files, PppConfig config);
  /// The product assembly of a file run (nullptr for the other constructors).
  const ProductAssembly* productAssembly() const;
  /// Runs over in-process epochs instead of files (throws std::invalid_argument
  /// when a pointer is null); no Bias-SINEX, no ocean loading.
  PppPipeline(const PppInMemoryInputs& inputs, PppConfig config);
  /// The general form: any observation source and any products (throws
  /// std::invalid_argument when the source or the ephemeris is null).
  PppPipeline(std::unique_ptr<ObservationSource> observations, PppProducts products, PppConfig config);
  ~PppPipeline();
  PppPipeline(const PppPipeline&) = delete;
  PppPipeline& operator=(const PppPipeline&) = delete;

  const RinexObsHeader& header() const;
  /// The 4-character station name (marker name, else the file name).
  std::string stationName() const;
  const PppConfig& config() const { return config_; }
  /// The GLONASS channel of a slot: the observation header's, else the configuration's
  /// (navigation records); nullopt when neither knows it.
  std::optional<int> glonassChannel(const SatelliteId& sat) const;
  /// Notes known before the run (antenna sources grow as satellites are seen).
  std::vector<std::string> notes() const;
  /// What the receiver antenna policy "warn" left out (once each; see PppMeasurementModel).
  const std::vector<std::string>& receiverAntennaWarnings() const;

  /// IMU readings for an estimator with inertial states (EstimatorEpochInput::imu),
  /// sorted by time here; each epoch gets those since the previous one. Set before run().
  void setImu(std::vector<ImuSample> readings);

  using EpochCallback = std::function<void(const PppEpochRecord&)>;
  /// Runs the whole observation file through `estimator` (once per pipeline:
  /// the file is streamed). `on_epoch` gets every epoch record, in order.
  PppRunSummary run(PppEstimator& estimator, const EpochCallback& on_epoch);
  /// Fraction of the observation file consumed (0..1), for progress bars.
  double progress() const;

 private:
  struct Impl;
  struct RunTally;
  // The steps of run() (numbered there).
  void adoptEstimatorSystems(const PppEstimator& estimator);
  void startRun(PppEstimator& estimator, PppRunSummary& summary);
  bool readEpoch(ObsEpoch& epoch);
  void processEpochs(PppEstimator& estimator, const EpochCallback& on_epoch, PppRunSummary& summary,
                     RunTally& tally);
  static void countEpoch(const PppEpochRecord& rec, PppRunSummary& summary, RunTally& tally);
  void reportInputProblems(const RunTally& tally, PppRunSummary& summary) const;
  void finishNotes(const RunTally& tally, PppRunSummary& summary) const;
  PppConfig config_;
  std::unique_ptr<Impl> impl_;
  std::vector<ImuSample> imu_;
};

}  // namespace ppp
