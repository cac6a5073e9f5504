#pragma once
// The GNSS/INS outage study: simulated flights of the Monte Carlo study
// (monte_carlo.h: the same flight setup from the seed and the index) with the
// readings of a simulated IMU (simulated_imu.h) and GNSS outages of outage_s
// every outage_every_s after the first fix (the simulator tracks nothing during
// an outage and reacquires every satellite afterwards with new ambiguities, or,
// with outage_keeps_lock, goes on with the same arcs and ambiguities,
// simulation_config.h), run by the GNSS EKF ("ekf") and the GNSS/INS filter
// ("ekf_ins", ppp_ins_ekf.h) on the same data. The first fix is ekf_ins's on the
// same flight simulated without outages (the simulation before the first outage
// does not depend on them); a flight it never fixes has no outage. An outage
// counts for an estimator when it starts after that estimator's first fixed epoch.
//
// Per estimator, over all counted outages of all flights:
//  * horizontal error at the outage end: ekf_ins, its coasting position at the
//    first epoch after the outage (the INS prediction before the update,
//    PppInsEkf::predictedAntennaPosition); ekf, which has no motion model, the
//    last position it had before the outage (its prediction) against the truth
//    at that epoch; the median;
//  * ekf_ins: the IMU's own share of that error: the coast through the same
//    readings from the true state and bias of the last epoch before the outage
//    (ins_coast_from_truth.h), against the truth at the first epoch after; the median;
//  * re-fix time: from the first epoch after the outage to the next fixed epoch;
//    the median (an outage never re-fixed before the next one or the end counts
//    as +inf and is counted);
//  * fix kept: outages after which the first epoch is fixed;
//  * ekf_ins: RMS of the roll, pitch and heading errors (ZYX Euler angles of
//    R_ned_body, ins_alignment.h) over the epochs after alignment_s;
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
};

/// The two estimators of the study, in order.
inline const std::vector<std::string>& insOutageEstimators() {
  static const std::vector<std::string> names = {"ekf", "ekf_ins"};
  return names;
}

/// One estimator's figures on one flight or summed over flights.
struct InsOutageFigures {
  std::vector<double> outage_end_horizontal_m;  // one per counted outage
  /// ekf_ins: the coast from the truth through the outage, one per counted outage (empty for ekf)
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
  std::vector<InsOutageFigures> estimators;  // insOutageEstimators() order
  double wall_s = 0.0;
};

/// Simulates flight `index` with its IMU and outages and runs both estimators
/// (never throws: a failure is in `failure`).
InsOutageFlight runInsOutageFlight(const InsOutageStudyOptions& options, int index);

struct InsOutageStudy {
  InsOutageStudyOptions options;
  std::vector<InsOutageFlight> flights;
  std::vector<InsOutageFigures> total;  // insOutageEstimators() order
  int failed = 0;
  double wall_s = 0.0;
};
/// All flights on options.flights.threads threads (0: the hardware's).
InsOutageStudy runInsOutageStudy(const InsOutageStudyOptions& options);

/// The table (one row per estimator) as Markdown.
std::string insOutageMarkdown(const InsOutageStudy& study);
/// Every wrong hold of every flight (HeldIntegerCheck::wrong_holds) as CSV, one
/// line each: flight, estimator, time [s], satellites, wide lane held and true,
/// narrow lane held and true [cycles], float and sigma [cycles], ratio, success rate.
std::string insOutageWrongHoldsCsv(const InsOutageStudy& study);

}  // namespace ppp
