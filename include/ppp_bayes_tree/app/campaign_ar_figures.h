#pragma once
// PPP-AR figures of one solution of a campaign job (app/campaign_job.h), and
// their distribution over many jobs (app/campaign_summary.h):
//  * fixed epochs: epochs with a position whose status is PppFixed;
//  * wrong fixed epochs: fixed epochs more than kWrongFixThreshold_m 3D from the
//    job's truth, whatever the float solution was;
//  * time to first fix: from the first epoch with a position to the first fixed
//    one (app/replay_report.h replayFixFigures);
//  * time below 10 cm for good: the convergence time of
//    evaluation/position_error_statistics.h at 0.10 m (the error stays below);
//  * mean 3D error of the epochs with a position.
// The errors need a truth (NaN without one); the time origin is the first epoch
// with a position (the window's start for a restart). "Never" is +infinity: no fixed
// epoch, or an error still at or above 10 cm at the last epoch.
#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/position_error_statistics.h"
#include "ppp_bayes_tree/ppp/pipeline/solution_epoch.h"

namespace ppp {

/// A fixed epoch further than this from the truth (3D) is a wrong fix.
inline constexpr double kWrongFixThreshold_m = 0.10;
/// The convergence threshold of the figures (below it for good).
inline constexpr double kArConvergenceThreshold_m = 0.10;

struct CampaignArFigures {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::string solution;  // "ekf", "smoother_filtered", "smoother_smoothed"
  std::size_t solved_epochs = 0, fixed_epochs = 0, wrong_fixed_epochs = 0;
  double first_fix_s = kNaN;        // +inf: never fixed
  double below_10cm_s = kNaN;       // +inf: never for good; NaN without a truth
  double mean_3d_m = kNaN;          // NaN without a truth
  double worst_wrong_fix_m = kNaN;  // the largest error of a wrong fixed epoch, NaN when none
};

/// The figures of one solution (epochs in time order) with its error statistics
/// (evaluation/position_error_statistics.h: one error per epoch with a position,
/// as ppp_solve computes them against its truth); without them, or when they do
/// not cover every epoch with a position (a moving truth that leaves some out),
/// only the fix figures.
CampaignArFigures campaignArFigures(const std::string& solution_tag, const std::vector<SolutionEpoch>& solution,
                                    const std::optional<PositionErrorStatistics>& statistics);
/// The same against a fixed truth point.
CampaignArFigures campaignArFigures(const std::string& solution_tag, const std::vector<SolutionEpoch>& solution,
                                    const Eigen::Vector3d& truth_ecef_m);

/// Median, 90th percentile (nearest rank, evaluation/quantile.h) and maximum of
/// a figure over runs, a run that never reached the event counted as +inf (so the
/// median is +inf, "never", when most runs never did), and how many never did.
struct CampaignArSpread {
  std::size_t count = 0, never = 0;
  double median = CampaignArFigures::kNaN, p90 = CampaignArFigures::kNaN, max = CampaignArFigures::kNaN;
};
/// The spread of `values`; +inf is never, NaN (not known) is left out.
CampaignArSpread campaignArSpread(const std::vector<double>& values);

/// The distribution of one solution's figures over a set of runs.
struct CampaignArDistribution {
  std::string station;   // a station, or "all"
  std::string runs;      // "restarts" (jobs with a start time) or "whole" (whole files)
  std::string solution;  // as CampaignArFigures::solution
  std::size_t run_count = 0, runs_with_wrong_fix = 0;
  std::size_t fixed_epochs = 0, wrong_fixed_epochs = 0, solved_epochs = 0;
  CampaignArSpread first_fix_s, below_10cm_s, mean_3d_m;
};
/// Adds one run's figures.
void addCampaignArRun(const CampaignArFigures& run, std::vector<double>& first_fix_s,
                      std::vector<double>& below_10cm_s, std::vector<double>& mean_3d_m,
                      CampaignArDistribution& distribution);

/// A figure as JSON: a number of `significant_digits`, "never" for +inf, null for NaN.
std::string campaignFigureJson(double value, int significant_digits);
/// The figures of several solutions as a JSON array of objects (done.json, summary.json).
std::string campaignArFiguresJson(const std::vector<CampaignArFigures>& list, int significant_digits);

}  // namespace ppp
