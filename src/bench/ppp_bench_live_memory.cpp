// Memory and update time of the PPP smoother over a long live-like run
// ("bounded memory, hours at 10 Hz"), in the core without ROS: a simulated flight
// (simulation/gnss_simulator.h, nominal GPS constellation of --satellites, all
// error terms of the default error model) is run through the offline pipeline
// (PppPipeline, in-memory inputs) into the smoother, fixed lag or full. Prints,
// every --report-s of flight time, the process RSS (/proc/self/status VmRSS), the
// smoother's structure sizes (graph variables, factors, Bayes-tree cliques, states
// kept) and the update-time median/p99/max of that interval; at the end the whole
// run's figures and the 3D error of the filtered and of the lag-final (written)
// states against the truth. The simulated flight itself is made before the run and
// its size is printed (the "input" RSS): a live run would not hold it, so the
// growth figures are taken from the run's start.
//
// Usage: ppp_bench_live_memory [--hours H] [--rate HZ] [--lag S] [--report-s S]
//          [--satellites N] [--profile loiter|survey|figure8|climb] [--seed N]
//          [--csv PATH] [--keep-states] [--config YAML] [--wildfire-m M]
//   --lag 0 runs the full smoother. With a lag, the states leaving the window go
//   to a SmoothedTrajectoryWriter (--csv PATH, else /dev/null) and are dropped from
//   memory, as in live use; --keep-states keeps them instead (no sink).
//   --config: a YAML over the defaults (e.g. config/live.yaml; its lag unless --lag
//   is given); the simulation's physics replace its measurement model as in the
//   Monte Carlo study (flightPppConfig). --wildfire-m: smoother.wildfire_threshold_m.
//   Defaults: 24 h at 1 Hz, lag 300 s, report every 3600 s, 30 satellites, loiter.
// Prints figures, asserts nothing.
#include <malloc.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/evaluation/quantile.h"
#include "ppp_bayes_tree/evaluation/smoothed_trajectory_writer.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/types/thread_cpu_time.h"

using namespace ppp;

namespace {

double rss_mb() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;
  return -1.0;
}

/// Per-epoch figures of the bench itself, in storage sized and touched before the run,
/// so that the RSS measured during the run is the estimator's, not these records'.
template <class T>
struct Record {
  std::vector<T> v;
  std::size_t n = 0;
  void presize(std::size_t size) { v.assign(size, T{}); }
  void push_back(const T& x) {
    if (n < v.size()) v[n] = x;
    else v.push_back(x);
    ++n;
  }
  std::vector<T> values() const { return {v.begin(), v.begin() + static_cast<long>(n)}; }
};

struct Args {
  double hours = 24.0, rate_hz = 1.0, lag_s = -1.0, report_s = 3600.0;  // lag < 0: the config's (else 300 s)
  int satellites = 30;
  std::string profile = "loiter", csv;
  std::uint64_t seed = 14;
  bool keep_states = false;
  std::string config;                 // YAML over the defaults (e.g. config/live.yaml)
  std::optional<double> wildfire_m;   // smoother.wildfire_threshold_m
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", k.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (k == "--hours") a.hours = std::atof(next().c_str());
    else if (k == "--rate") a.rate_hz = std::atof(next().c_str());
    else if (k == "--lag") a.lag_s = std::atof(next().c_str());
    else if (k == "--report-s") a.report_s = std::atof(next().c_str());
    else if (k == "--satellites") a.satellites = std::atoi(next().c_str());
    else if (k == "--profile") a.profile = next();
    else if (k == "--seed") a.seed = std::strtoull(next().c_str(), nullptr, 10);
    else if (k == "--csv") a.csv = next();
    else if (k == "--keep-states") a.keep_states = true;
    else if (k == "--config") a.config = next();
    else if (k == "--wildfire-m") a.wildfire_m = std::atof(next().c_str());
    else {
      std::fprintf(stderr, "unknown argument %s (see the header of ppp_bench_live_memory.cpp)\n", k.c_str());
      std::exit(2);
    }
  }
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  const Args a = parse(argc, argv);
  using Clock = std::chrono::steady_clock;
  SimulationConfig sim;
  sim.profile = parseFlightProfile(a.profile);
  sim.rate_hz = a.rate_hz;
  sim.duration_s = a.hours * 3600.0;
  sim.satellites = a.satellites;
  std::printf("simulating %.2f h at %.1f Hz (%s, %d satellites, seed %llu) ...\n", a.hours, a.rate_hz,
              a.profile.c_str(), a.satellites, static_cast<unsigned long long>(a.seed));
  std::fflush(stdout);
  const double rss_start = rss_mb();
  auto t0 = Clock::now();
  SimulatedFlight f = simulateFlight(sim, a.seed);
  // Keep what the run needs (observations, products) and the truth positions.
  std::vector<Eigen::Vector3d> truth(f.truth.size());
  for (std::size_t k = 0; k < f.truth.size(); ++k) truth[k] = f.truth[k].trajectory.position_ecef_m;
  std::vector<TruthEpoch>().swap(f.truth);
  std::string().swap(f.truth_sp3_text);
  std::string().swap(f.truth_clk_text);
  std::string().swap(f.products_sp3_text);
  std::string().swap(f.products_clk_text);
  malloc_trim(0);
  const double rss_input = rss_mb();
  std::size_t tracked = 0;
  for (const auto& e : f.epochs) tracked += e.satellites.size();
  std::printf("simulated %zu epochs in %.1f s, %.1f tracked satellites per epoch; RSS %.1f MB before, %.1f MB "
              "with the simulated input\n",
              f.epochs.size(), std::chrono::duration<double>(Clock::now() - t0).count(),
              static_cast<double>(tracked) / static_cast<double>(std::max<std::size_t>(1, f.epochs.size())),
              rss_start, rss_input);

  PppConfig config = flightPppConfig(a.config.empty() ? PppConfig{} : loadPppConfig(a.config), f);
  if (a.lag_s >= 0.0) config.smoother.fixed_lag_s = a.lag_s;
  else if (a.config.empty()) config.smoother.fixed_lag_s = 300.0;
  const double lag_s = config.smoother.fixed_lag_s;
  if (a.wildfire_m) config.smoother.wildfire_threshold_m = *a.wildfire_m;
  std::printf("smoother: fixed_lag_s %.1f, wildfire_threshold_m %g, relinearize_position_m %g\n",
              config.smoother.fixed_lag_s, config.smoother.wildfire_threshold_m,
              config.smoother.relinearize_position_m);
  PppInMemoryInputs in;
  in.header = &f.header;
  in.epochs = &f.epochs;
  in.products = &f.products;
  in.name = "simulated";
  PppPipeline pipeline(in, config);
  const std::unique_ptr<PppSmoother> sm_made = makeEstimatorAs<PppSmoother>("smoother", config);
  PppSmoother& sm = *sm_made;

  const GnssTime t_first = f.epochs.front().time;
  auto epochIndex = [&](const GnssTime& t) {
    const double k = std::round((t - t_first) * a.rate_hz);
    return k < 0 ? truth.size() : static_cast<std::size_t>(k);
  };
  std::unique_ptr<SmoothedTrajectoryWriter> writer;
  Record<double> final_err_m;
  final_err_m.presize(f.epochs.size() + 16);
  std::size_t handed_out = 0;
  if (lag_s > 0.0 && !a.keep_states) {
    writer = std::make_unique<SmoothedTrajectoryWriter>(a.csv.empty() ? std::string("/dev/null") : a.csv);
    sm.setMarginalizedStateSink([&](const SmoothedEpoch& e) {
      writer->write(e);
      ++handed_out;
      const std::size_t k = epochIndex(e.time);
      if (k < truth.size()) final_err_m.push_back((e.state.position_ecef_m - truth[k]).norm());
    });
  }

  std::printf("%s smoother%s; flight time [h], RSS [MB], RSS growth since the run's start [MB], graph variables, "
              "factors, cliques, states kept, update median/p99/max [ms] in the interval\n",
              lag_s > 0 ? "fixed-lag" : "full", lag_s > 0 ? (" (lag " + std::to_string(lag_s) + " s)").c_str() : "");
  std::vector<double> interval_ms;
  interval_ms.reserve(static_cast<std::size_t>(a.report_s * a.rate_hz) + 16);
  Record<double> update_ms, filtered_err_m, epoch_cpu_ms;
  for (auto* r : {&update_ms, &filtered_err_m, &epoch_cpu_ms}) r->presize(f.epochs.size() + 16);
  double cpu_last_s = threadCpu_s();
  struct Slow {
    double ms;
    std::size_t reelim, relin, marg, touched;
  };
  Record<Slow> per_epoch_record;
  per_epoch_record.presize(f.epochs.size() + 16);
  std::vector<double> rss_at_report;
  const double rss_run_start = rss_mb();  // the records above included
  double next_report_s = a.report_s;
  std::size_t epochs = 0, solved = 0;
  t0 = Clock::now();
  auto report = [&](double flight_s) {
    const double rss = rss_mb();
    rss_at_report.push_back(rss);
    const smoother::ISAM2& isam = sm.isam2();
    std::printf("  %6.2f h  RSS %7.1f  +%7.1f  vars %6zu  factors %7zu  cliques %6zu  states %7zu  update %.3f / "
                "%.3f / %.3f\n",
                flight_s / 3600.0, rss, rss - rss_run_start, isam.linearizationPoint().size(), isam.numFactors(),
                isam.bayesTree().numCliques(), sm.storedStateCount(), quantile(interval_ms, 0.5),
                quantile(interval_ms, 0.99), quantile(interval_ms, 1.0));
    std::fflush(stdout);
    interval_ms.clear();
  };
  pipeline.run(sm, [&](const PppEpochRecord& rec) {
    if (rec.refused) return;
    ++epochs;
    const double cpu_now_s = threadCpu_s();
    epoch_cpu_ms.push_back(1e3 * (cpu_now_s - cpu_last_s));
    if (rec.smoother && rec.status == EpochStatus::Ok) {
      ++solved;
      update_ms.push_back(1e3 * rec.smoother->update_time_s);
      interval_ms.push_back(1e3 * rec.smoother->update_time_s);
      per_epoch_record.push_back({1e3 * rec.smoother->update_time_s, rec.smoother->variables_reeliminated,
                           rec.smoother->variables_relinearized, rec.smoother->variables_marginalized,
                           rec.smoother->cliques_touched});
      const std::size_t k = epochIndex(rec.solution.time);
      if (rec.solution.position_ecef_m && k < truth.size())
        filtered_err_m.push_back((*rec.solution.position_ecef_m - truth[k]).norm());
    }
    const double flight_s = rec.solution.time - t_first;
    if (flight_s + 0.5 / a.rate_hz >= next_report_s) {
      report(flight_s);
      next_report_s += a.report_s;
    }
    cpu_last_s = threadCpu_s();  // the next epoch's CPU time starts here (the reports excluded)
  });
  const double run_s = std::chrono::duration<double>(Clock::now() - t0).count();
  if (!interval_ms.empty()) report(f.epochs.back().time - t_first);
  if (writer) sm.finishTrajectory();

  std::printf("run: %zu epochs (%zu solved) in %.1f s (%.0f epochs/s, %.1fx real time at %.1f Hz)\n", epochs, solved,
              run_s, static_cast<double>(epochs) / run_s,
              static_cast<double>(epochs) / a.rate_hz / run_s, a.rate_hz);
  std::printf("update time over the run (wall clock): median %.3f ms, p99 %.3f ms, max %.3f ms\n",
              quantile(update_ms.values(), 0.5), quantile(update_ms.values(), 0.99), quantile(update_ms.values(), 1.0));
  std::printf("whole epoch step, CPU time of the thread (model + screening + update + marginalization): median "
              "%.3f ms, p99 %.3f ms, max %.3f ms\n",
              quantile(epoch_cpu_ms.values(), 0.5), quantile(epoch_cpu_ms.values(), 0.99), quantile(epoch_cpu_ms.values(), 1.0));
  {
    // What the slowest 1 % of the updates did (medians), against all updates.
    auto med = [](std::vector<Slow> v, std::size_t Slow::*m) {
      std::vector<double> x;
      for (const auto& e : v) x.push_back(static_cast<double>(e.*m));
      return quantile(x, 0.5);
    };
    const std::vector<Slow> per_epoch = per_epoch_record.values();
    std::vector<Slow> sorted = per_epoch;
    std::sort(sorted.begin(), sorted.end(), [](const Slow& l, const Slow& r) { return l.ms > r.ms; });
    sorted.resize(std::max<std::size_t>(1, sorted.size() / 100));
    std::printf("per update (median), all / slowest 1 %%: re-eliminated %.0f / %.0f, relinearized %.0f / %.0f, "
                "marginalized %.0f / %.0f, cliques touched %.0f / %.0f\n",
                med(per_epoch, &Slow::reelim), med(sorted, &Slow::reelim), med(per_epoch, &Slow::relin),
                med(sorted, &Slow::relin), med(per_epoch, &Slow::marg), med(sorted, &Slow::marg),
                med(per_epoch, &Slow::touched), med(sorted, &Slow::touched));
  }
  if (rss_at_report.size() >= 2) {
    // Flatness after the first hour: the reports from flight time >= 1 h.
    const std::size_t first = std::min<std::size_t>(rss_at_report.size() - 1,
                                                    static_cast<std::size_t>(std::ceil(3600.0 / a.report_s)) - 1);
    const auto [lo, hi] = std::minmax_element(rss_at_report.begin() + static_cast<long>(first), rss_at_report.end());
    std::printf("RSS after the first hour: min %.1f MB, max %.1f MB (spread %.1f %% of min); total growth over the "
                "run %.1f MB = %.2f KB per epoch\n",
                *lo, *hi, 100.0 * (*hi - *lo) / *lo, rss_at_report.back() - rss_run_start,
                1024.0 * (rss_at_report.back() - rss_run_start) / static_cast<double>(std::max<std::size_t>(1, epochs)));
  }
  std::printf("3D error vs truth: filtered median %.3f m, p95 %.3f m", quantile(filtered_err_m.values(), 0.5),
              quantile(filtered_err_m.values(), 0.95));
  if (writer)
    std::printf("; lag-final (written) median %.3f m, p95 %.3f m; rows written %zu, refused %zu", quantile(final_err_m.values(), 0.5),
                quantile(final_err_m.values(), 0.95), writer->rowsWritten(), writer->rowsRefused());
  if (lag_s <= 0.0) {  // the full smoother's smoothed trajectory (all data), the reference
    std::vector<double> smoothed_err_m;
    for (const auto& e : sm.smoothedTrajectory()) {
      const std::size_t k = epochIndex(e.time);
      if (k < truth.size()) smoothed_err_m.push_back((e.state.position_ecef_m - truth[k]).norm());
    }
    std::printf("; full smoothed median %.3f m, p95 %.3f m", quantile(smoothed_err_m, 0.5),
                quantile(smoothed_err_m, 0.95));
  }
  std::printf("\n");
  return 0;
}
