#pragma once
// One ppp_solve run: the pipeline with one estimator, written to a directory:
//   <name>_<estimator>.csv            per-epoch solution (SolutionCsvWriter)
//   <name>_<estimator>.pos            RTKLIB-compatible xyz .pos (RtklibPosWriter)
//   <name>_<estimator>_epochs.csv     per-epoch diagnostics: status, reason, counts,
//                                     rejected satellites with stage and reason
//   <name>_<estimator>_residuals.csv  per epoch and used satellite: elevation,
//                                     prefit/postfit code and phase residuals, sigmas
//   <name>_<estimator>_summary.json   statistics (with a truth), run counts,
//                                     rejection counts, per-satellite residual
//                                     statistics, notes
// The tool src/tools/ppp_solve.cpp only parses arguments and calls this; the
// end-to-end test calls it too.
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/position_error_statistics.h"
#include "ppp_bayes_tree/ppp/ppp_pipeline.h"

namespace ppp {

struct PppSolveRequest {
  PppInputFiles files;
  PppConfig config;
  std::string estimator = "ekf";
  std::optional<Eigen::Vector3d> truth_ecef_m;
  std::string out_dir;
  /// Output file prefix; empty = the station name in lower case ("zim2").
  std::string name;
  /// Called after each epoch with the fraction of the observation file read.
  std::function<void(double fraction, const PppEpochRecord&)> on_epoch;
};

struct PppSolveOutcome {
  std::string name;
  PppRunSummary run;
  std::vector<SolutionEpoch> solution;
  std::optional<PositionErrorStatistics> statistics;  // with a truth only
  std::string csv_path, pos_path, epochs_path, residuals_path, json_path;
};

/// Runs and writes. Throws std::invalid_argument (unknown or unavailable
/// estimator), FileOpenError / ParseError (inputs), std::runtime_error (output
/// directory not writable).
PppSolveOutcome solvePpp(const PppSolveRequest& request);

/// Readable report: notes, epoch counts, rejection counts, per-satellite residuals.
std::string formatRunReport(const PppRunSummary& run);
/// The summary JSON document (as written to <name>_<estimator>_summary.json).
std::string runSummaryToJson(const PppSolveOutcome& outcome);

}  // namespace ppp
