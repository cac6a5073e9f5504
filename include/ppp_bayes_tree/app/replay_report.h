#pragma once
// The ROS-free part of ppp_bag_report (src/ros/tools/ppp_bag_report.cpp): the
// solutions a replay recorded from the nodes (EKF, smoother filtered, smoother
// smoothed), matched to the truth by time and summarised with the SAME core
// statistics as ppp_solve (position_error_statistics.h), plus each node's
// update-time figures, as one comparison table, one JSON document and one
// per-estimator CSV (SolutionCsvWriter, the format ppp_solve writes and
// scripts/plot_solutions.py reads).
//
// Truth: a fixed point (a static station) or a trajectory of time-tagged ECEF
// positions (a simulated flight: truth.csv of writeTruthEpochsCsv). A solution
// epoch takes the truth sample within `tolerance_s` of its time, else the linear
// interpolation of the two samples around it when they are at most `max_gap_s`
// apart; an epoch with neither is UNMATCHED: counted and left out of the
// statistics and the CSV (never compared with a far-away truth).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ppp_bayes_tree/evaluation/position_error_statistics.h"
#include "ppp_bayes_tree/ppp/pipeline/solution_epoch.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/app/ppp_solve_run.h"

namespace ppp {

struct TruthMatchOptions {
  double tolerance_s = 0.01;  // a sample this close is the truth of the epoch
  double max_gap_s = 2.0;     // longest span between two samples to interpolate across
};

struct TruthTrajectory {
  std::optional<Eigen::Vector3d> fixed_point_ecef_m;  // set: the truth of every epoch
  std::vector<GnssTime> time;                         // strictly increasing
  std::vector<Eigen::Vector3d> position_ecef_m;       // one per time

  static TruthTrajectory fixedPoint(const Eigen::Vector3d& position_ecef_m);
  bool empty() const { return !fixed_point_ecef_m && time.empty(); }
  /// The truth at `t` (see the top of this file), nullopt when unmatched.
  std::optional<Eigen::Vector3d> at(const GnssTime& t, const TruthMatchOptions& options = {}) const;
};

/// Reads a truth CSV: a header row naming the columns, then one row per epoch.
/// Needs gps_week, seconds_of_week (or tow_s, as ppp_solve's CSV), x_m, y_m, z_m
/// (ECEF, GPST); other columns are ignored. A header without them -> ParseError;
/// a malformed row, or one not after the previous row in time -> skipped and
/// report.addProblem. Empty position fields (a "no solution" row) are skipped
/// and counted as "rows without position".
TruthTrajectory readTruthCsv(LineSource& source, ParseReport& report);
TruthTrajectory readTruthCsv(const std::string& path, ParseReport& report);

/// One epoch as a node's status reports it (ppp/status, ROS-free).
struct ReplayStatusSample {
  GnssTime time;
  bool solved = false;
  int satellites_used = 0, satellites_rejected = 0;
  std::optional<double> zwd_m, receiver_clock_m;
  std::optional<double> update_time_s;  // absent for an epoch the node did not process (empty epoch)
  /// The epoch's solution is conditioned on held integer ambiguities (PPP-AR).
  bool ambiguities_fixed = false;
  // the node's counters since start
  std::size_t epochs_processed = 0, epochs_duplicate = 0, epochs_out_of_order = 0, estimator_resets = 0;
};

/// One position of a solution (a fix, an odometry or a path pose), in ECEF.
struct ReplayPositionSample {
  GnssTime time;
  Eigen::Vector3d position_ecef_m = Eigen::Vector3d::Zero();
  std::optional<Eigen::Matrix3d> covariance_ecef_m2;
};

struct AssembledSolution {
  std::vector<SolutionEpoch> epochs;        // in time order
  std::size_t solved_without_position = 0;  // status solved, no position at its time: left out
  std::size_t positions_without_status = 0; // kept, without the status fields
};

/// The per-epoch solution of a node: one epoch per status (the positions
/// matched by time within tolerance_s; a later sample at the same time replaces
/// an earlier one, as a re-published smoothed state does); "no solution" for a
/// status that says so; plus the positions no status covers. Without any
/// status, just the positions.
AssembledSolution assembleReplaySolution(const std::vector<ReplayStatusSample>& status,
                                         std::vector<ReplayPositionSample> positions, double tolerance_s = 0.01);

/// A node's figures from its status messages.
struct NodeFigures {
  std::string name;                   // "ekf", "smoother"
  std::size_t status_messages = 0;
  TimingSummary update_time;          // of update_time_s over the processed epochs
  std::size_t epochs_processed = 0;   // the node's counter in its last status
  std::size_t epochs_duplicate = 0, epochs_out_of_order = 0, estimator_resets = 0;
  std::optional<std::size_t> input_epochs;  // observation epochs in the replayed bag, when known
  /// Input epochs the node never processed (input - processed), or, without the
  /// input count, the duplicate + out-of-order epochs it dropped.
  std::size_t dropped() const;
};

/// The figures of the node named `name` from its status samples.
NodeFigures replayNodeFigures(const std::string& name, const std::vector<ReplayStatusSample>& status,
                              std::optional<std::size_t> input_epochs = std::nullopt);

/// PPP-AR figures of a solution: the epochs with a position, those fixed
/// (SolutionStatus::PppFixed), and the time from the first epoch with a
/// position to the first fixed one (nullopt when none is fixed).
struct ReplayFixFigures {
  std::size_t solved_epochs = 0, fixed_epochs = 0;
  std::optional<double> time_to_first_fix_s;
  double fixedShare() const;  // fixed / solved, 0 without solved epochs
};
ReplayFixFigures replayFixFigures(const std::vector<SolutionEpoch>& solution);

struct ReplayReportRow {
  std::string label;    // "EKF", "smoother filtered", "smoother smoothed"
  std::string key;      // "ekf", "smoother_filtered", "smoother_smoothed" (file names)
  std::string missing;  // non-empty: why there is no solution (no statistics)
  std::vector<SolutionEpoch> solution;        // the epochs matched to the truth, in time order
  std::vector<Eigen::Vector3d> truth_ecef_m;  // the truth of each of them
  std::size_t unmatched_epochs = 0;           // left out: no truth at their time
  PositionErrorStatistics statistics;
  ReplayFixFigures fix;  // of `solution`
  std::optional<NodeFigures> node;
};

/// Matches `solution` (sorted by time here) to the truth and computes the
/// statistics. Epochs without a position stay (they count as "no solution").
ReplayReportRow buildReplayReportRow(const std::string& label, const std::string& key,
                                     std::vector<SolutionEpoch> solution, const TruthTrajectory& truth,
                                     const StatisticsOptions& statistics = {}, const TruthMatchOptions& match = {});
/// A row for a solution that is absent (a missing topic), with the reason.
ReplayReportRow missingReplayReportRow(const std::string& label, const std::string& key, const std::string& why);

/// The comparison table: one line per row (3D error median, mean, sigma, max in
/// cm over all epochs and over the first window; time to stay below each
/// convergence threshold; PPP-AR: fixed share of the solved epochs [%] and time
/// to first fix [min]; node update time median/p99 in ms; epochs processed /
/// dropped), then one line per missing row with its reason.
std::string formatReplayReport(const std::vector<ReplayReportRow>& rows);
/// {"rows": [{label, key, missing, unmatched_epochs, statistics (statisticsToJson), node}]}.
std::string replayReportJson(const std::vector<ReplayReportRow>& rows);
/// The row's CSV text (SolutionCsvWriter header with the error columns, one row per epoch).
std::string replayReportCsv(const ReplayReportRow& row);

/// The datum (ECEF origin of the ENU map frame) from one epoch known in both
/// frames: position_ecef_m = datum + R(datum)^T enu_m (the node's map frame,
/// axes at the datum). Iterated from datum = position - R(position)^T enu: the
/// rotation changes by |enu| / R_earth per step, so a few steps reach 0.1 mm
/// for any map within 100 km of its datum.
Eigen::Vector3d mapDatumFromPair(const Eigen::Vector3d& position_ecef_m, const Eigen::Vector3d& enu_m);

}  // namespace ppp
