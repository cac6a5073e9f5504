#pragma once
// Monte Carlo evaluation over simulated UAV flights: the method's study. Each
// flight is simulated in process (simulateFlight) and run through the offline
// pipeline by the EKF and by the smoother, with the SAME PppConfig; the smoother
// gives a filtered and a smoothed solution. A flight depends only on the study's
// seed and its index (not on the number of flights or threads). Scored: the 3D
// position error per epoch, the phase-bias error against the simulator's truth in
// the estimator's convention, and tables over all epochs, the first window and the
// representative flight. How flights are drawn and scored: doc/evaluation.md,
// "The Monte Carlo study". Reference: Watson R.M., Gross J.N. (2018), IEEE/ION
// PLANS (arXiv:1804.04197), the study it repeats.
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ppp_bayes_tree/evaluation/position_error_statistics.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/simulation/simulation_config.h"

namespace ppp {

// The estimators the study compares are the registry's kMonteCarloStudy
// (estimator_registry.h: the rows marked monte_carlo_study), each made by the
// registry and run through the same pipeline (PppEstimator): the first, the
// EKF, is the reference that chooses the representative flight; an estimator
// that smooths (the smoother) is compared with it epoch by epoch
// (filtered_minus_ekf_m), and its smoothed solution is
// SmoothedTrajectoryProvider::finalSmoothedSolution().

/// The number of solutions of the studied estimators (the columns of the tables).
constexpr int monteCarloSolutionCount() {
  int n = 0;
  for (const std::string_view name : kMonteCarloStudy)
    for (const EstimatorEntry& e : kEstimators)
      if (e.name == name) n += e.solutionCount();
  return n;
}
constexpr int kMonteCarloEstimators = monteCarloSolutionCount();
static_assert(kMonteCarloEstimators == 3, "the study's columns: EKF, smoother filtered, smoother smoothed");

/// The studied estimators' solutions in order (solutionOutputs of each): keys
/// 0 "ekf", 1 "smoother_filtered", 2 "smoother_smoothed" (keys of the outputs).
std::string monteCarloEstimatorKey(int estimator);
/// "EKF", "smoother filtered", "smoother smoothed".
std::string monteCarloEstimatorLabel(int estimator);

/// The estimators' configuration of the study unless one is given: the method's
/// preset (methodTablePppConfig, config/method_table.yaml) with the estimator
/// override of config/ppp_simulated.yaml (test_simulation_start_prior checks
/// that they agree; the measurement model is the simulator's, flightPppConfig).
/// The estimators' override: stochastic.position.initial_sigma_m 30 m instead of the
/// method's 1 m (the value of the real-data defaults as well). Both
/// estimators start at a code least-squares solution of the first-epoch codes;
/// a 1 m prior around it counts those codes twice and claims 1 m where the
/// simulated first-epoch IF code (multipath 0.4 m / sin(el) per frequency, x3 for
/// IF) leaves metres. Through the phase arcs the whole trajectory hangs on that
/// first position, so the smoothed solution keeps the start error as a flat
/// offset where the code cannot separate height and ZWD (figure8, phase breaks
/// in every turn). Seed 1, figure8, 25 min (ppp_sim_error_budget): smoothed mean
/// 3D 186 -> 59 cm (Up -180 -> -44 cm, ZWD error 39 -> 1 cm), EKF 359 -> 128 cm;
/// 30 m and 1000 m agree to 0.2 cm. With matched white code noise the smoothed
/// spread over 20 noise draws then equals the formal sigmas (Up 19.6 vs 22 cm;
/// with 1 m: 35 vs 21 cm).
/// The solver's override: smoother.relinearize_position_m 0.5 m instead of
/// 0.01 m (as config/live.yaml). The study runs without the Huber kernel, so
/// the factors are nonlinear in the position only through the range, linear
/// to 0.25 / 4e7 m = 6e-9 m over 0.5 m; at 0.01 m the whole lag window was
/// relinearized and re-eliminated at one update in eight. Seed 1, GE, 12
/// flights: smoother CPU 10.8 -> 6.1 s, the summary the same to the last
/// printed digit (test_monte_carlo: a flight's smoothed errors within 1e-6 m,
/// its filtered ones within 1 mm; measured 6e-8 m and 0.17 mm).
PppConfig monteCarloDefaultPppConfig();

struct MonteCarloOptions {
  int flights = 100;
  /// The index of the first flight: a shard of a larger study runs the flights
  /// first_flight .. first_flight + flights - 1 (each flight depends only on the
  /// seed and its index, so shards merge into the whole study exactly:
  /// evaluation/monte_carlo_records.h).
  int first_flight = 0;
  std::uint64_t seed = 1;
  double duration_s = 1800.0;
  double rate_hz = 1.0;
  std::vector<FlightProfile> profiles = {FlightProfile::Loiter, FlightProfile::Survey, FlightProfile::Figure8,
                                         FlightProfile::Climb};
  unsigned threads = 0;  // 0: std::thread::hardware_concurrency()
  /// Base simulation (error model, constellation); profile, rate, duration, start
  /// and origin are set per flight.
  SimulationConfig simulation;
  PppConfig ppp = monteCarloDefaultPppConfig();  // both estimators
  /// 0: one full iSAM2 smoother gives the filtered (during the run) and the
  /// smoothed solution (smoothedTrajectory() at the end). > 0: the filtered
  /// solution comes from the fixed-lag smoother with this lag (bounded cost per
  /// epoch) and the smoothed solution from the batch solve of ALL its factors
  /// (PppSmoother::batchSmoothedValues: the full smoother's MAP estimate).
  double smoother_filtered_lag_s = 0.0;
  bool randomize_start = true;
  bool randomize_origin = true;
  double first_window_s = 900.0;  // "first 15 minutes"
  double time_bin_s = 10.0;       // error-versus-time curves
  double bias_bin_s = 10.0;       // bias convergence: one sample per arc and bin
  std::vector<double> convergence_thresholds_m = {0.5, 0.2, 0.1};
};

/// What defines flight `index` (deterministic in options.seed and index).
struct MonteCarloFlightSetup {
  int index = 0;
  std::uint64_t seed = 0;
  FlightProfile profile = FlightProfile::Loiter;
  GnssTime start;
  Geodetic origin;
};
MonteCarloFlightSetup monteCarloFlightSetup(const MonteCarloOptions& options, int index);
/// The estimators' configuration for a simulated flight: the flight's physics
/// (its model options: which corrections the simulator applied) with the
/// weights and cutoff of `ppp`, and the flight's systems (one receiver clock each).
PppConfig flightPppConfig(const PppConfig& ppp, const SimulatedFlight& f);
/// The pipeline's in-memory inputs of flight `f` (number `index`: its name "flight N"); `f`
/// must outlive them.
PppInMemoryInputs simulatedFlightInputs(const SimulatedFlight& f, int index);
/// The simulation configuration of a flight.
SimulationConfig monteCarloSimulationConfig(const MonteCarloOptions& options, const MonteCarloFlightSetup& setup);

struct BiasErrorSample {
  float age_s = 0.0f;    // since the estimator arc's first solved epoch
  float error_m = 0.0f;  // estimate - truth (estimator convention, see above)
};

/// PPP-AR against the simulator's integers, for one estimator (on one flight or
/// summed over flights). Each held single difference (arc, reference arc, wide
/// lane and narrow-lane integer, as AmbiguityFixSummary::narrow_lanes reports it;
/// counted once however long it is held) is compared with the truth of the
/// simulated arcs behind its two estimator arcs:
///  * wide lane: dN_WL = (N1 - N2)_s - (N1 - N2)_ref (the wind-up is the same
///    whole cycles on both frequencies and cancels);
///  * narrow lane: the resolver's dN1 = (B'_s - B'_ref - k_WL dN_WL) / lambda_NL
///    (ambiguity_resolution.h; k_WL and lambda_NL of the satellite's pair)
///    evaluated on the TRUE IF biases B' in the estimator's convention
///    (TruthArc::bias_if_m plus lambda_NL times the wind-up integer, as the
///    phase-bias errors above; the satellite UPD is the published OSB).
/// For two satellites of one system this is the integer N1_s - N1_ref; across
/// systems (other wavelengths, e.g. a Galileo satellite against a GPS reference)
/// it is in general not an integer. A hold is WRONG when its wide lane differs
/// from the truth or its narrow-lane integer is more than
/// kWrongHoldThresholdCycles from the true dN1 (a wrong integer of one system is
/// a whole cycle off; a cross-system hold is as wrong as its distance).
constexpr double kWrongHoldThresholdCycles = 0.25;
/// One wrong hold as it was first judged (diagnostics: which stage erred, and
/// what the float and the search said at that epoch).
struct WrongHold {
  double time_s = 0.0;  // since the flight's first epoch
  SatelliteId satellite, reference_satellite;
  long wide_lane_cycles = 0, true_wide_lane_cycles = 0;
  long held_cycles = 0;
  double true_cycles = 0.0;  // the true dN1 with the held wide lane (what the held integer should be)
  double float_cycles = 0.0, sigma_cycles = 0.0;  // the held pair's float dN1 and sigma at that epoch
  double ratio = 0.0, bootstrap_success_rate = 0.0;  // of that epoch's search (AmbiguityFixSummary)
};
struct HeldIntegerCheck {
  std::size_t held = 0;           // distinct held single differences compared with the truth
  std::size_t wrong = 0;          // of them, wrong (see above)
  std::size_t cross_system = 0;   // of `held`, between satellites of different systems
  std::size_t not_compared = 0;   // an arc ran into another simulated arc (a missed slip)
  std::size_t fixed_epochs = 0;   // epochs with a fixed solution
  std::size_t fixed_epochs_with_wrong_hold = 0;  // of them, holding at least one wrong integer
  double max_abs_error_cycles = 0.0;  // |held - true dN1| over the holds with the right wide lane
  std::vector<WrongHold> wrong_holds;  // each of the `wrong`, in the order judged
  void add(const HeldIntegerCheck& other);
};

struct MonteCarloFlightRun {
  MonteCarloFlightSetup setup;
  std::vector<std::string> drawn;  // DrawnParameters::describe()
  std::string failure;             // non-empty: the flight failed (left out of all statistics)
  std::size_t epochs = 0, simulated_arcs = 0, phase_breaks = 0;
  std::size_t estimator_arcs = 0, slips_detected = 0;  // arc tracker (the same front end in every run)
  std::vector<double> time_s;  // per epoch, since the first epoch
  /// Per estimator and epoch: 3D error [m], NaN when that epoch has no solution.
  std::array<std::vector<double>, kMonteCarloEstimators> error_3d_m;
  std::array<std::vector<BiasErrorSample>, kMonteCarloEstimators> bias;
  /// Per studied estimator (kMonteCarloStudy) and epoch: its filtered solution FIXED (PPP-AR) [0, 1].
  std::array<std::vector<char>, kMonteCarloStudy.size()> fixed;
  /// Per studied estimator: the held integers against the truth (PPP-AR on).
  std::array<HeldIntegerCheck, kMonteCarloStudy.size()> held_check;
  /// Per epoch |x_EKF - x_smoother filtered| [m], NaN unless both have a solution.
  std::vector<double> filtered_minus_ekf_m;
  std::size_t bias_arcs_compared = 0;      // estimator arcs with samples (smoothed solution)
  std::size_t bias_arcs_missed_slip = 0;   // ran into another simulated arc (compared up to it)
  double simulate_s = 0.0;  // wall time of the simulation
  /// Wall time of each studied estimator's run (kMonteCarloStudy order) [s].
  std::array<double, kMonteCarloStudy.size()> estimator_s{};

  /// Statistics of one estimator on this flight (epochs with a solution).
  ErrorSummary summary(int estimator, double window_s = -1.0) const;
};

/// Simulates flight `index` and runs the studied estimators on it, their
/// solutions in kMonteCarloEstimators columns (never throws: a failure is
/// reported in `failure`).
MonteCarloFlightRun runMonteCarloFlight(const MonteCarloOptions& options, int index);

/// One estimator's run on a simulated flight through the offline pipeline, epoch
/// by epoch (index = the flight's epochs), with its held integers checked against
/// the truth (HeldIntegerCheck): what a study beside the Monte Carlo's own
/// estimators (e.g. the GNSS/INS filter with the flight's IMU) records.
struct FlightEstimatorTrack {
  std::vector<std::optional<Eigen::Vector3d>> position_ecef_m;  // nullopt: no solution
  std::vector<char> fixed;  // the solution is fixed (PPP-AR)
  HeldIntegerCheck held_check;
  std::size_t arcs = 0, slips = 0;  // the arc tracker's
};
/// Runs estimator `name` with `config` (flightPppConfig of the flight) on `f`;
/// the flight's IMU readings (f.imu) are given to the pipeline. `on_epoch(k,
/// record, estimator)` is called after epoch k. Throws as the pipeline does.
FlightEstimatorTrack trackEstimatorOnFlight(
    const SimulatedFlight& f, const PppConfig& config, const std::string& name,
    const std::function<void(std::size_t, const PppEpochRecord&, const PppEstimator&)>& on_epoch = {});

struct QuantileBin {
  double t_s = 0.0;  // bin start
  std::size_t count = 0;
  double p05 = 0.0, p50 = 0.0, p95 = 0.0;  // of the signed value
  double abs_p50 = 0.0, abs_p90 = 0.0;     // of |value|
};

struct MonteCarloSummary {
  int flights = 0, failed = 0;
  std::vector<std::string> failures;
  int representative = -1;  // index into the flights (see above); -1 when none
  /// [estimator]: all epochs, first window, representative flight.
  std::array<ErrorSummary, kMonteCarloEstimators> all, first_window, representative_flight;
  /// [estimator]: the epochs after the first window ("after convergence").
  std::array<ErrorSummary, kMonteCarloEstimators> after_window;
  std::array<std::size_t, kMonteCarloEstimators> epochs_without_solution{};
  /// Per estimator and threshold: median over flights of the convergence time
  /// (stays below the threshold; a flight that never converges counts as +inf),
  /// and the number of flights that never converge.
  std::array<std::vector<double>, kMonteCarloEstimators> convergence_median_s;
  std::array<std::vector<int>, kMonteCarloEstimators> convergence_never;
  /// PPP-AR, [0] EKF, [1] smoother (filtered; its fixes are in the smoothed
  /// solution too): fixed epochs / epochs with a solution, the median over flights
  /// of the time to the first fixed epoch (a flight never fixed counts as +inf),
  /// and the flights never fixed.
  std::array<double, kMonteCarloStudy.size()> fixed_share{};
  std::array<double, kMonteCarloStudy.size()> first_fix_median_s{};
  std::array<int, kMonteCarloStudy.size()> never_fixed{};
  /// The held integers against the truth, summed over flights.
  std::array<HeldIntegerCheck, kMonteCarloStudy.size()> held_check;
  /// 3D error versus time since the flight start, over flights [m].
  std::array<std::vector<QuantileBin>, kMonteCarloEstimators> error_vs_time;
  /// Bias error versus arc age [m].
  std::array<std::vector<QuantileBin>, kMonteCarloEstimators> bias_vs_age;
  std::size_t bias_arcs_compared = 0, bias_arcs_missed_slip = 0;
  /// |x_EKF - x_smoother filtered| over all epochs, and versus time since the start [m].
  ErrorSummary filtered_minus_ekf;
  std::vector<QuantileBin> filtered_minus_ekf_vs_time;
  /// Error quantiles for the CDF figures: cdf_levels[j] -> 3D error [m].
  std::vector<double> cdf_levels;
  std::array<std::vector<double>, kMonteCarloEstimators> cdf_all_m, cdf_first_window_m;
  /// Sums of the per-flight wall times (CPU-ish cost per stage) [s].
  double simulate_s = 0.0;
  std::array<double, kMonteCarloStudy.size()> estimator_s{};  // kMonteCarloStudy order
};

MonteCarloSummary summarizeMonteCarlo(const std::vector<MonteCarloFlightRun>& flights,
                                      const MonteCarloOptions& options);

struct MonteCarloResult {
  MonteCarloOptions options;
  unsigned threads_used = 0;
  std::vector<MonteCarloFlightRun> flights;  // in index order
  MonteCarloSummary summary;
  double wall_s = 0.0;
};

/// Runs the study on a pool of threads (each flight independent; results do not
/// depend on the thread count). `progress(done, total)` is called after each
/// flight, serialised (never concurrently).
MonteCarloResult runMonteCarlo(const MonteCarloOptions& options,
                               const std::function<void(int done, int total)>& progress = {});

/// One configuration of the float / PPP-AR comparison (ppp_monte_carlo
/// --configurations): the simulated and processed systems, and PPP-AR in both
/// estimators or not. Every configuration simulates the satellite phase biases
/// (errors.ambiguity.satellite_phase_biases, published as phase OSBs), so that
/// the float and the AR study of a system set run on the SAME observations
/// (the float biases absorb the constant UPDs) and differ only in the fixing.
/// The products are the truth (errors.products off) unless their errors are
/// drawn as an analysis centre's (errors.products.model analysis_centre: the
/// clocks absorb the radial orbit error, so code and phase see the same small
/// range error and the published phase biases stay consistent). The independent
/// model's errors (orbit and clock drawn apart per satellite, 5 cm each) are not
/// consistent with the published phase biases: with them the true
/// single-difference narrow lanes are off integers by up to half a cycle and
/// more, and the resolver holds wrong integers (seed 7, 4 flights of 30 min,
/// gps_ar with those errors: 6 of 6 holds wrong by 1-4 cycles; without: 0 of 40).
struct MonteCarloConfiguration {
  std::string name;  // gps_float, gps_ar, gps_galileo_float, gps_galileo_ar
  std::vector<GnssSystem> systems;
  bool ambiguity_resolution = false;
};
/// The four configurations, in that order.
const std::vector<MonteCarloConfiguration>& monteCarloConfigurations();
/// The configuration of that name; nullptr when none.
const MonteCarloConfiguration* findMonteCarloConfiguration(const std::string& name);
/// `options` with the configuration's systems, phase biases and PPP-AR switch.
MonteCarloOptions withConfiguration(MonteCarloOptions options, const MonteCarloConfiguration& configuration);

/// The method's published Monte Carlo figures (its Table 3: 3D error over the
/// first 15 min of its flights, median / mean [cm], as published), printed beside ours.
/// The method: Watson and Gross (2018), "Evaluation of kinematic precise point
/// positioning convergence with an incremental graph optimizer", IEEE/ION PLANS 2018,
/// arXiv:1804.04197.
struct MethodTableRow {
  const char* estimator;
  double first_window_median_cm, first_window_mean_cm;
};
constexpr MethodTableRow kMethodTable3[] = {{"graph (smoother)", 117.76, 188.79}, {"Kalman filter", 295.15, 665.35}};

/// One table over several studies of the same flights (e.g. the four
/// configurations): per configuration and estimator the first-window median and
/// mean 3D error, the median time to stay below 10 cm, and with PPP-AR the fixed
/// share, the median time to first fix and the wrong holds; then the method's
/// Table 3 rows.
std::string monteCarloComparisonMarkdown(const std::vector<std::pair<std::string, MonteCarloResult>>& studies);

/// One cell of the convergence table: "12.5 min (never: 3)", or, when the
/// median itself is never reached (more than half of the flights never stay
/// below the threshold), "never (7 of 10 flights)" instead of "inf min".
std::string convergenceTimeText(double median_s, int never, int flights_compared);

/// The tables (figures in cm) as Markdown, and everything as one JSON document.
std::string monteCarloMarkdown(const MonteCarloResult& result);
std::string monteCarloJson(const MonteCarloResult& result);

/// Writes into `dir` (created): summary.md, summary.json, flights.csv,
/// representative_flight.csv, error_vs_time.csv, bias_convergence.csv, error_cdf.csv.
/// Throws std::runtime_error when a file cannot be written.
void writeMonteCarloOutputs(const MonteCarloResult& result, const std::string& dir);

}  // namespace ppp
