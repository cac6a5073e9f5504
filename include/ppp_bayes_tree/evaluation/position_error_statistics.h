#pragma once
// Position error statistics of a solution against a fixed truth point (or a
// truth trajectory, one position per epoch): the
// method's RSOS metrics, computed exactly as ../shared/peers/poserr.py does
// (which produced the RTKLIB figures of ../shared/data/README.md), so that our solutions and
// RTKLIB's are summarised by the same definitions:
//  * 3D error per epoch = |x - truth| (root sum of squares of the ECEF errors);
//  * median (mean of the two middle values for an even count), mean, population
//    standard deviation (divided by n) and maximum, over all epochs and over the
//    epochs with t - t0 < convergence_window_s (t0 = first solution epoch);
//  * convergence time below a threshold: the time since t0 of the first epoch
//    after the last epoch whose 3D error is >= the threshold (the error STAYS
//    below from then on); 0 when no epoch is at or above it; "never" when the
//    last epoch is at or above it;
//  * final error: 3D error of the last epoch;
//  * ENU RMS over the epochs with t >= t_last - tail_window_s, axes at the truth;
//  * empirical CDF: sorted 3D errors with fractions k/n.
// Epochs without a position (SolutionStatus::NoSolution) are counted and left out.
// All functions are pure.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ppp_bayes_tree/ppp/pipeline/solution_epoch.h"

namespace ppp {

struct StatisticsOptions {
  double convergence_window_s = 15.0 * 60.0;  // the "first 15 minutes"
  std::vector<double> convergence_thresholds_m = {0.10, 0.05};
  double tail_window_s = 30.0 * 60.0;         // ENU RMS over the last 30 minutes
};

struct ErrorSummary {
  std::size_t count = 0;
  // NaN when count == 0.
  double median_m = 0.0, mean_m = 0.0, std_m = 0.0, max_m = 0.0;
};

struct ConvergenceTime {
  double threshold_m = 0.0;
  std::optional<double> time_s;  // since the first epoch; nullopt = never
};

struct PositionErrorStatistics {
  std::size_t epochs = 0;                 // epochs with a position
  std::size_t epochs_without_solution = 0;
  double span_s = 0.0;                    // last - first epoch with a position
  StatisticsOptions options;
  std::vector<double> time_s;             // per epoch with a position, since the first
  std::vector<double> error_3d_m;         // per epoch with a position
  ErrorSummary all, first_window;
  std::vector<ConvergenceTime> convergence;  // one per options.convergence_thresholds_m
  double final_error_m = 0.0;             // NaN when no epoch
  Eigen::Vector3d tail_enu_rms_m = Eigen::Vector3d::Zero();
  std::size_t tail_epochs = 0;
  /// Empirical CDF: (3D error [m], fraction of epochs with error <= it).
  std::vector<std::pair<double, double>> cdf;
  /// The error below which `fraction` of the epochs lie (nearest rank), NaN when empty.
  double percentile_m(double fraction) const;
};

/// Summary statistics of a set of values (median, mean, population std, max).
ErrorSummary summarizeErrors(std::vector<double> values_m);

/// Convergence time of a time series (times since the first epoch): see above.
std::optional<double> convergenceTime_s(const std::vector<double>& time_s, const std::vector<double>& error_m,
                                        double threshold_m);

PositionErrorStatistics computePositionErrorStatistics(const std::vector<SolutionEpoch>& solution,
                                                       const Eigen::Vector3d& truth_ecef_m,
                                                       const StatisticsOptions& options = {});
/// The same against a moving truth (a simulated flight): truth_ecef_m[i] is the
/// true position at solution[i]'s epoch; ENU errors use the axes at each truth
/// position. Throws std::invalid_argument when the sizes differ.
PositionErrorStatistics computePositionErrorStatistics(const std::vector<SolutionEpoch>& solution,
                                                       const std::vector<Eigen::Vector3d>& truth_ecef_m,
                                                       const StatisticsOptions& options = {});

/// Text table of one solution's statistics (figures in cm, times in minutes).
std::string formatStatisticsTable(const PositionErrorStatistics& stats, const std::string& label);
/// Side-by-side table of several solutions (e.g. "RTKLIB" and "ours"), one column each.
std::string formatStatisticsComparison(
    const std::vector<std::pair<std::string, PositionErrorStatistics>>& columns);
/// JSON object with all figures (metres and seconds; "never" convergence is null).
std::string statisticsToJson(const PositionErrorStatistics& stats, const std::string& label = "");

}  // namespace ppp
