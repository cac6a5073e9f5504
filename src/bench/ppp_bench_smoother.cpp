// Benchmark and figures of the PPP smoother against the EKF on the real ZIM2 and
// CCJ2 hours (GPS only, kinematic), both through the offline pipeline: EKF,
// smoother filtered (causal), smoother smoothed (all data), with the method's
// statistics (position_error_statistics.h) and the per-epoch update times.
// Usage: ppp_bench_smoother [shared_data_dir] [config.yaml ...]
//   shared_data_dir defaults to $PPP_SHARED_DATA or ../shared/data; each config
//   (default: the method's table, config/method_table.yaml, then the defaults,
//   which are the real-data values)
//   gives one table per dataset. PPP_SMOOTHER_LAG_S=300 runs the fixed-lag smoother;
//   PPP_EKF_PLAIN=1 runs the EKF in the smoother's linearisation (1 iteration, no
//   postfit check). Prints figures, asserts nothing.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "ppp_smoother_run.h"

using namespace ppp;

namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())));
  return v[k];
}

std::string convergence(const PositionErrorStatistics& s, std::size_t i) {
  if (i >= s.convergence.size()) return "-";
  if (!s.convergence[i].time_s) return "never";
  char b[32];
  std::snprintf(b, sizeof b, "%.1f min", *s.convergence[i].time_s / 60.0);
  return b;
}

void row(const char* label, const PositionErrorStatistics& s) {
  std::printf("  %-20s %8.1f %8.1f %10.1f %10.1f %10s %10s %8.1f %8.1f\n", label, 100 * s.all.mean_m,
              100 * s.all.median_m, 100 * s.first_window.mean_m, 100 * s.first_window.median_m,
              convergence(s, 0).c_str(), convergence(s, 1).c_str(), 100 * s.final_error_m, 100 * s.all.max_m);
}

void report(const std::string& name, const bench::SmootherRunInputs& in, const PppConfig& config) {
  const bench::SmootherRunOutput out = bench::runSmootherAndEkf(in, config);
  std::printf("%s (%zu epochs; 3D errors in cm)\n", name.c_str(), out.filtered.size());
  std::printf("  %-20s %8s %8s %10s %10s %10s %10s %8s %8s\n", "solution", "mean", "median", "15min mean",
              "15min med", "<10cm", "<5cm", "final", "max");
  row("EKF", out.ekf_stats);
  row("smoother filtered", out.filtered_stats);
  row("smoother smoothed", out.smoothed_stats);
  if (std::getenv("PPP_BENCH_VERBOSE"))
    std::printf("%s", formatStatisticsComparison({{"EKF", out.ekf_stats},
                                                  {"smoother filtered", out.filtered_stats},
                                                  {"smoother smoothed", out.smoothed_stats}})
                          .c_str());
  std::vector<double> update, epoch, reelim, relin, biases;
  int no_solution = 0;
  for (const auto& r : out.smoother_epochs) {
    if (r.status != EpochStatus::Ok) {
      ++no_solution;
      continue;
    }
    update.push_back(1e3 * r.smoother->update_time_s);
    epoch.push_back(1e3 * r.epoch_time_s);
    reelim.push_back(static_cast<double>(r.smoother->variables_reeliminated));
    relin.push_back(static_cast<double>(r.smoother->variables_relinearized));
    biases.push_back(r.active_biases);
  }
  std::printf("  smoother per epoch: iSAM2 update median %.2f ms, p99 %.2f ms, max %.2f ms; estimator step "
              "(model evaluation included) median %.2f ms, p99 %.2f ms\n",
              percentile(update, 0.5), percentile(update, 0.99), percentile(update, 1.0), percentile(epoch, 0.5),
              percentile(epoch, 0.99));
  std::printf("  whole pipeline run: smoother %.2f s, EKF %.2f s; re-eliminated variables median %.0f, max %.0f; "
              "relinearized median %.0f, max %.0f; active biases median %.0f; no-solution epochs %d\n",
              out.smoother_run_s, out.ekf_run_s, percentile(reelim, 0.5), percentile(reelim, 1.0),
              percentile(relin, 0.5), percentile(relin, 1.0), percentile(biases, 0.5), no_solution);
}

void adjust(PppConfig& config) {
  if (const char* lag = std::getenv("PPP_SMOOTHER_LAG_S")) config.smoother.fixed_lag_s = std::atof(lag);
  if (std::getenv("PPP_SMOOTHER_ROBUST")) config.smoother.robust = true;
  if (std::getenv("PPP_EKF_PLAIN")) {
    config.estimator.iterations_per_epoch = 1;
    config.estimator.screening.postfit_check = false;
  }
  if (const char* c = std::getenv("PPP_CLOCK_SIGMA_M")) config.stochastic.clock.initial_sigma_m = std::atof(c);
}

}  // namespace

int main(int argc, char** argv) {
  const char* env = std::getenv("PPP_SHARED_DATA");
  const std::string d = argc > 1 ? argv[1] : (env ? env : "../shared/data");
  std::vector<std::pair<std::string, PppConfig>> configs;
  if (argc > 2) {
    for (int i = 2; i < argc; ++i) configs.emplace_back(argv[i], loadPppConfig(argv[i]));
  } else {
    configs.emplace_back("method table (config/method_table.yaml)", methodTablePppConfig());
    configs.emplace_back("defaults (the real-data values)", PppConfig{});
  }
  for (auto& [label, config] : configs) {
    adjust(config);
    std::printf("=== configuration: %s\n", label.c_str());
    report("ZIM2", bench::zim2Inputs(d), config);
    report("CCJ2", bench::ccj2Inputs(d), config);
  }
  return 0;
}
