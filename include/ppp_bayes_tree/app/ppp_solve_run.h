#pragma once
// One ppp_solve run: the pipeline with one estimator, written to a directory.
// Each solution (the EKF's; the smoother's filtered and smoothed ones) is written
// under its tag as <name>_<tag>.csv, .pos (RTKLIB format) and _summary.json; once
// per run, under the estimator's name, the per-epoch diagnostics (_epochs.csv),
// the residuals (_residuals.csv) and, for the smoother, the phase biases
// (_biases.csv). The tool src/tools/ppp_solve.cpp only parses arguments and
// calls this; the end-to-end test calls it too. The files and their columns:
// doc/offline_tools.md, "The output files in detail".
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/position_error_statistics.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"

namespace ppp {

struct PppSolveRequest {
  PppInputFiles files;
  PppConfig config;
  std::string estimator = std::string(kDefaultEstimator);  // a registered name or "both" (estimator_registry.h)
  /// IMU readings for an estimator with inertial states ("ekf_ins"; it needs them,
  /// the others ignore them). Its options: config.ins.
  std::vector<ImuSample> imu;
  std::optional<Eigen::Vector3d> truth_ecef_m;
  /// A moving truth instead (a simulated flight's true antenna path, e.g.
  /// TruthTrajectory::at of app/replay_report.h): the truth at an epoch, nullopt
  /// when it has none (the epoch is left out of the statistics). Empty: no truth.
  std::function<std::optional<Eigen::Vector3d>(const GnssTime&)> truth_at;
  std::string out_dir;
  /// Output file prefix; empty = the station name in lower case ("zim2").
  std::string name;
  /// false: the run's outputs hold no wall-clock figures (processing_time_s and
  /// the smoother's update/epoch times are left out of the summary JSON, their
  /// epochs-CSV cells empty), so that two runs of the same inputs write the same
  /// bytes (campaigns: app/campaign_job.h). The outcome still carries them.
  bool write_timings = true;
  /// When set, the run's pipeline comes from it (given the request's config)
  /// instead of `files`: other inputs than files, e.g. the epochs and corrections
  /// of a ROS bag (the ROS tool ppp_bag_solve). `files.obs` still names the data
  /// in the outputs.
  std::function<std::unique_ptr<PppPipeline>(const PppConfig&)> make_pipeline;
  /// Called after each epoch with the fraction of the observation file read.
  std::function<void(double fraction, const PppEpochRecord&)> on_epoch;
};

/// One written solution of a run.
struct PppSolutionOutput {
  std::string label;  // "ekf", "smoother filtered", "smoother smoothed"
  std::string tag;    // file-name part: "ekf", "smoother_filtered", "smoother_smoothed"
  std::vector<SolutionEpoch> solution;                // one per processed epoch
  std::optional<PositionErrorStatistics> statistics;  // with a truth only
  std::string csv_path, pos_path, json_path;
};

/// Median, p90, p99 and max of per-epoch times [s] (the percentiles by nearest rank),
/// count of epochs.
struct TimingSummary {
  std::size_t count = 0;
  double median_s = 0.0, p90_s = 0.0, p99_s = 0.0, max_s = 0.0;
};
TimingSummary summarizeTimes(std::vector<double> times_s);

struct PppSolveOutcome {
  std::string name;
  PppRunSummary run;
  /// EKF: {ekf}; smoother: {smoother filtered, smoother smoothed}.
  std::vector<PppSolutionOutput> outputs;
  // The first output's solution, statistics and files (the causal solution).
  std::vector<SolutionEpoch> solution;
  std::optional<PositionErrorStatistics> statistics;
  std::string csv_path, pos_path, json_path;
  std::string epochs_path, residuals_path;
  std::string biases_path;  // smoother only
  /// Smoother only: iSAM2 update time and whole estimator step of every solved epoch.
  std::optional<TimingSummary> update_time, epoch_time;
};

/// Runs and writes. Throws std::invalid_argument (unknown or unavailable
/// estimator: "both" is run by solvePppEstimators), FileOpenError / ParseError
/// (inputs), std::runtime_error (output directory not writable).
PppSolveOutcome solvePpp(const PppSolveRequest& request);
/// As solvePpp, with "both" = "ekf" then "smoother" (one pipeline run each).
std::vector<PppSolveOutcome> solvePppEstimators(const PppSolveRequest& request);

/// Readable report: notes, epoch counts, rejection counts, per-satellite residuals.
std::string formatRunReport(const PppRunSummary& run);
/// The summary JSON document of one output (as written to <name>_<tag>_summary.json).
/// `timings` false: without the wall-clock figures (PppSolveRequest::write_timings).
std::string runSummaryToJson(const PppSolveOutcome& outcome, const PppSolutionOutput& output, bool timings = true);
/// The same for the first output.
std::string runSummaryToJson(const PppSolveOutcome& outcome);

}  // namespace ppp
