#pragma once
// The GNSS/INS outage study: simulated flights of the Monte Carlo study
// (monte_carlo.h: the same flight setup from the seed and the index) with the
// readings of a simulated IMU (simulated_imu.h) and GNSS outages of outage_s
// every outage_every_s after the first fix (the simulator tracks nothing during
// an outage and reacquires every satellite afterwards with new ambiguities, or,
// with outage_keeps_lock, goes on with the same arcs and ambiguities,
// simulation_config.h), run on the same data by the estimators chosen
// (InsOutageStudyOptions::estimators, registry names; by default the GNSS EKF
// "ekf", the GNSS/INS filter "ekf_ins", ppp_ins_ekf.h, and the GNSS/INS smoother
// "smoother_ins", ppp_ins_smoother.h). An estimator with inertial
// states (the registry's EstimatedState::GnssInertial: ekf_ins, smoother_ins)
// takes the flight's IMU readings and starts from the study's attitude and
// velocity. Every estimator is scored on its FILTERED solution, the real-time one
// of each epoch: a smoother's estimate of the newest state when that epoch was
// solved (with the Monte Carlo study's fixed lag, MonteCarloOptions::
// smoother_filtered_lag_s), never its smoothed one. The first fix is ekf_ins's
// on the same flight simulated without outages (the simulation before the first
// outage does not depend on them); a flight it never fixes has no outage. An
// outage counts for an estimator when it starts after that estimator's first
// fixed epoch.
//
// Per estimator, over all counted outages of all flights:
//  * horizontal error at the outage end: an estimator with inertial states, its
//    coasting position at the first epoch after the outage (the INS prediction
//    before the update: PppEstimator::predictedAntennaPosition); a GNSS-only one (ekf), which has
//    no motion model, the last position it had before the outage (its
//    prediction) against the truth at that epoch; the median;
//  * with inertial states: the IMU's own share of that error: the coast through
//    the same readings from the true state and bias of the last epoch before the
//    outage (ins_coast_from_truth.h), against the truth at the first epoch after
//    (the same for every such estimator on the same outage); the median;
//  * re-fix time: from the first epoch after the outage to the next fixed epoch;
//    the median (an outage never re-fixed before the next one or the end counts
//    as +inf and is counted);
//  * fix kept: outages after which the first epoch is fixed;
//  * with inertial states: RMS of the roll, pitch and heading errors (ZYX Euler
//    angles of R_ned_body, ins_alignment.h) of the estimator's inertial state
//    after each epoch (PppEstimator::inertialState) over the epochs after alignment_s;
//  * the held integers against the truth (HeldIntegerCheck), and the fixed
//    epochs more than kWrongFixThreshold_m (3D) from the truth.
// INS-aided re-fixing after an outage (the literature this follows): the INS
// prediction bridges the outage and constrains the position when the new arcs'
// biases enter, so that their floats converge from the predicted position rather
// than from the code alone: Du S., Gao Y. (2012), Inertial aided cycle slip
// detection and identification for integrated PPP GPS and INS, Sensors
// 12(11):14344-14362; Rabbou M.A., El-Rabbany A. (2015), Tightly coupled
// integration of GPS precise point positioning and MEMS-based inertial systems,
// GPS Solutions 19:601-609.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/navigation/imu_noise.h"

namespace ppp {

/// A fixed epoch further than this from the truth (3D) is a wrong fix (as on
/// real data, doc/ppp_ar.md) [m].
constexpr double kWrongFixThreshold_m = 0.10;

/// The estimators the study runs unless told otherwise, in order: the GNSS EKF and
/// both GNSS/INS estimators. smoother_ins (fixed lag 60 s) adds half the time of the
/// other two with the simulation (20 industrial flights of 30 min on one thread: 159 s
/// against 106 s; doc/studies/ins_outages.md, "smoother_ins in the outage study").
inline const std::vector<std::string>& insOutageDefaultEstimators() {
  static const std::vector<std::string> names = {"ekf", "ekf_ins", "smoother_ins"};
  return names;
}

/// Empty when the study can run `names`: one or more registered estimators
/// (estimator_registry.h), none twice; else the problem, naming the value and
/// the registered names.
std::string insOutageEstimatorsProblem(const std::vector<std::string>& names);

struct InsOutageStudyOptions {
  /// The flights (count, seed, duration, profiles, simulation, estimators'
  /// configuration with its ambiguity resolution), as the Monte Carlo study's.
  MonteCarloOptions flights;
  ImuGrade grade = ImuGrade::IndustrialMems;
  double imu_rate_hz = 100.0;
  /// false: the true readings (no noise, no bias; SimulationConfig::Imu::errors),
  /// the filter still weighting them with the grade's noise: what the estimator's
  /// own state at the outage start costs, without the sensor's errors.
  bool imu_errors = true;
  double outage_s = 30.0;
  /// Outages at first fix + k outage_every_s, k >= 1, each with its whole period
  /// before the flight's end (outage_every_s - outage_s to re-fix).
  double outage_every_s = 300.0;
  /// The outages keep the receiver's lock (SimulationConfig::Outage::keeps_lock:
  /// same arcs and ambiguities after them) instead of new arcs.
  bool outage_keeps_lock = false;
  double alignment_s = 120.0;     // attitude errors are scored after this time
  /// The GNSS/INS filter's start: the true attitude and velocity of the first
  /// epoch moved by these errors (each axis) [rad], [m/s].
  double start_attitude_error_rad = 0.005;
  double start_velocity_error_mps = 0.1;
  /// The estimators run, by registry name, in the table's order (see above;
  /// insOutageEstimatorsProblem says whether they can run).
  std::vector<std::string> estimators = insOutageDefaultEstimators();
};

/// One estimator's figures on one flight or summed over flights.
struct InsOutageFigures {
  std::vector<double> outage_end_horizontal_m;  // one per counted outage
  /// With inertial states: the coast from the truth through the outage, one per counted outage
  /// (empty for a GNSS-only estimator)
  std::vector<double> truth_coast_horizontal_m;
  std::vector<double> refix_s;                  // one per counted outage, +inf when never re-fixed
  int outages_counted = 0, fix_kept = 0, first_fixes = 0;
  double roll_sq_sum_rad2 = 0.0, pitch_sq_sum_rad2 = 0.0, heading_sq_sum_rad2 = 0.0;
  std::size_t attitude_epochs = 0;
  HeldIntegerCheck held_check;
  std::size_t fixed_epochs_over_threshold = 0;  // fixed epochs > kWrongFixThreshold_m (3D) from the truth
  void add(const InsOutageFigures& other);
};

struct InsOutageFlight {
  MonteCarloFlightSetup setup;
  std::string failure;  // non-empty: the flight failed (left out)
  std::optional<double> first_fix_s;  // ekf_ins's first fix without outages, since the start
  std::vector<InsOutageFigures> estimators;  // options.estimators order
  double wall_s = 0.0;
};

/// Simulates flight `index` with its IMU and outages and runs the study's estimators
/// (never throws: a failure, e.g. an estimator that cannot run, is in `failure`).
InsOutageFlight runInsOutageFlight(const InsOutageStudyOptions& options, int index);

struct InsOutageStudy {
  InsOutageStudyOptions options;
  std::vector<InsOutageFlight> flights;
  std::vector<InsOutageFigures> total;  // options.estimators order
  int failed = 0;
  double wall_s = 0.0;
};
/// All flights on options.flights.threads threads (0: the hardware's). Throws
/// std::invalid_argument when the estimators cannot run (insOutageEstimatorsProblem).
InsOutageStudy runInsOutageStudy(const InsOutageStudyOptions& options);

/// The table (one row per estimator) as Markdown.
std::string insOutageMarkdown(const InsOutageStudy& study);
/// Every wrong hold of every flight (HeldIntegerCheck::wrong_holds) as CSV, one
/// line each: flight, estimator, time [s], satellites, wide lane held and true,
/// narrow lane held and true [cycles], float and sigma [cycles], ratio, success rate.
std::string insOutageWrongHoldsCsv(const InsOutageStudy& study);

}  // namespace ppp
