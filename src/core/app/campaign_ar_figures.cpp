#include "ppp_bayes_tree/app/campaign_ar_figures.h"

#include <algorithm>
#include <cmath>

#include "ppp_bayes_tree/app/replay_report.h"
#include "ppp_bayes_tree/evaluation/json_text.h"
#include "ppp_bayes_tree/evaluation/position_error_statistics.h"
#include "ppp_bayes_tree/evaluation/quantile.h"

namespace ppp {

namespace {

/// Wrong fixed epochs, the worst of them, the mean error and the convergence time, from
/// the per-epoch errors of `stats` (one per epoch with a position, in order).
void addErrorFigures(const std::vector<SolutionEpoch>& solution, const PositionErrorStatistics& stats,
                     CampaignArFigures& f) {
  std::size_t k = 0;
  for (const auto& e : solution) {
    if (!e.position_ecef_m) continue;
    const double err_m = stats.error_3d_m[k++];
    if (e.status != SolutionStatus::PppFixed || err_m <= kWrongFixThreshold_m) continue;
    ++f.wrong_fixed_epochs;
    f.worst_wrong_fix_m = std::isnan(f.worst_wrong_fix_m) ? err_m : std::max(f.worst_wrong_fix_m, err_m);
  }
  f.mean_3d_m = stats.all.mean_m;
  const std::optional<double> converged = convergenceTime_s(stats.time_s, stats.error_3d_m, kArConvergenceThreshold_m);
  f.below_10cm_s = converged ? *converged : std::numeric_limits<double>::infinity();
}

std::size_t epochsWithPosition(const std::vector<SolutionEpoch>& solution) {
  return static_cast<std::size_t>(
      std::count_if(solution.begin(), solution.end(), [](const SolutionEpoch& e) { return e.position_ecef_m.has_value(); }));
}

}  // namespace

CampaignArFigures campaignArFigures(const std::string& solution_tag, const std::vector<SolutionEpoch>& solution,
                                    const std::optional<PositionErrorStatistics>& statistics) {
  CampaignArFigures f;
  f.solution = solution_tag;
  const ReplayFixFigures fix = replayFixFigures(solution);
  f.solved_epochs = fix.solved_epochs;
  f.fixed_epochs = fix.fixed_epochs;
  f.first_fix_s = fix.time_to_first_fix_s ? *fix.time_to_first_fix_s : std::numeric_limits<double>::infinity();
  if (statistics && statistics->epochs > 0 && statistics->error_3d_m.size() == epochsWithPosition(solution))
    addErrorFigures(solution, *statistics, f);
  return f;
}

CampaignArFigures campaignArFigures(const std::string& solution_tag, const std::vector<SolutionEpoch>& solution,
                                    const Eigen::Vector3d& truth_ecef_m) {
  return campaignArFigures(solution_tag, solution, computePositionErrorStatistics(solution, truth_ecef_m));
}

CampaignArSpread campaignArSpread(const std::vector<double>& values) {
  CampaignArSpread s;
  std::vector<double> sorted;
  for (double v : values) {
    if (std::isnan(v)) continue;
    s.never += std::isinf(v);
    sorted.push_back(v);
  }
  s.count = sorted.size();
  if (sorted.empty()) return s;
  std::sort(sorted.begin(), sorted.end());
  s.median = quantileOfSorted(sorted, 0.5);
  s.p90 = quantileOfSorted(sorted, 0.9);
  s.max = sorted.back();
  return s;
}

std::string campaignFigureJson(double value, int significant_digits) {
  return std::isinf(value) ? "\"never\"" : jsonNumber(value, significant_digits);
}

std::string campaignArFiguresJson(const std::vector<CampaignArFigures>& list, int significant_digits) {
  auto number = [&](double v) { return campaignFigureJson(v, significant_digits); };
  std::string out = "[";
  for (std::size_t i = 0; i < list.size(); ++i) {
    const CampaignArFigures& f = list[i];
    out += std::string(i ? ", " : "") + "{\"solution\": " + jsonString(f.solution) +
           ", \"solved_epochs\": " + std::to_string(f.solved_epochs) + ", \"fixed_epochs\": " + std::to_string(f.fixed_epochs) +
           ", \"wrong_fixed_epochs\": " + std::to_string(f.wrong_fixed_epochs) + ", \"first_fix_s\": " + number(f.first_fix_s) +
           ", \"below_10cm_s\": " + number(f.below_10cm_s) + ", \"mean_3d_m\": " + number(f.mean_3d_m) +
           ", \"worst_wrong_fix_m\": " + number(f.worst_wrong_fix_m) + "}";
  }
  return out + "]";
}

void addCampaignArRun(const CampaignArFigures& run, std::vector<double>& first_fix_s,
                      std::vector<double>& below_10cm_s, std::vector<double>& mean_3d_m,
                      CampaignArDistribution& d) {
  ++d.run_count;
  d.runs_with_wrong_fix += run.wrong_fixed_epochs > 0;
  d.fixed_epochs += run.fixed_epochs;
  d.wrong_fixed_epochs += run.wrong_fixed_epochs;
  d.solved_epochs += run.solved_epochs;
  first_fix_s.push_back(run.first_fix_s);
  below_10cm_s.push_back(run.below_10cm_s);
  mean_3d_m.push_back(run.mean_3d_m);
}

}  // namespace ppp
