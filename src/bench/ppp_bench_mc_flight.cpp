// One Monte Carlo flight (evaluation/monte_carlo.h), EKF against the smoother's
// filtered solution epoch by epoch: where and why they differ. Prints the epochs
// where the positions differ by more than 0.3 m or the used satellites differ,
// with the model/screening rejections of each; writes a CSV (k, time_s, 3D error
// of each, satellites used by each, 0 = no solution) for
// scripts/plot_monte_carlo.py --flight-csv. Also prints the wall time of each run,
// the smoother's per-epoch iSAM2 update median / p99 / max and the time of the final
// smoothed trajectory (LAG_S = 0: the full smoother). Asserts nothing.
// usage: ppp_bench_mc_flight SEED INDEX [OUT.csv] [LAG_S=60]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"

using namespace ppp;

namespace {

struct Epoch {
  std::optional<Eigen::Vector3d> position;
  int used = 0;
  std::string rejections;
};

void record(const PppEpochRecord& r, std::vector<Epoch>& out) {
  Epoch e;
  e.position = r.solution.position_ecef_m;
  e.used = e.position ? static_cast<int>(r.used.size()) : 0;
  for (const auto& x : r.rejected)
    if (x.stage == RejectionStage::Model) e.rejections += x.satellite.toString() + ": " + x.detail.substr(0, 40) + "; ";
  out.push_back(e);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: ppp_bench_mc_flight SEED INDEX [OUT.csv] [LAG_S=60]\n");
    return 2;
  }
  MonteCarloOptions o;
  o.seed = std::strtoull(argv[1], nullptr, 10);
  const int index = std::atoi(argv[2]);
  const MonteCarloFlightSetup setup = monteCarloFlightSetup(o, index);
  const SimulatedFlight f = simulateFlight(monteCarloSimulationConfig(o, setup), setup.seed);
  // The same configuration as runMonteCarloFlight: the flight's physics, the config's weights.
  PppConfig c = flightPppConfig(o.ppp, f);
  PppInMemoryInputs in;
  in.header = &f.header;
  in.epochs = &f.epochs;
  in.products = &f.products;
  using Clock = std::chrono::steady_clock;
  auto since = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  std::vector<Epoch> ekf, filtered;
  double ekf_s = 0, smoother_s = 0, smoothed_s = 0;
  std::vector<double> updates;
  const double lag_s = argc > 4 ? std::atof(argv[4]) : 60.0;
  {
    const auto t0 = Clock::now();
    PppPipeline p(in, c);
    const std::unique_ptr<PppEstimator> e_made = makeEstimator("ekf", c);
    PppEstimator& e = *e_made;
    p.run(e, [&](const PppEpochRecord& r) { record(r, ekf); });
    ekf_s = since(t0);
  }
  {
    const auto t0 = Clock::now();
    PppConfig cs = c;
    cs.smoother.fixed_lag_s = lag_s;
    PppPipeline p(in, cs);
    const std::unique_ptr<PppEstimator> e_made = makeEstimator("smoother", cs);
    PppEstimator& e = *e_made;
    p.run(e, [&](const PppEpochRecord& r) {
      record(r, filtered);
      if (!r.refused && e.lastResult().status == EpochStatus::Ok)
        updates.push_back(e.lastResult().smoother->update_time_s);
    });
    smoother_s = since(t0);
    const auto t1 = Clock::now();
    const auto trajectory = e.smoothing()->smoothedTrajectory(true);
    smoothed_s = since(t1);
  }
  const TimingSummary u = summarizeTimes(updates);
  std::printf("wall time: EKF run %.2f s; smoother (%s) run %.2f s, iSAM2 update median %.2f ms, p99 %.2f ms, "
              "max %.2f ms over %zu updates; final smoothed trajectory with covariances %.3f s\n",
              ekf_s, lag_s > 0 ? ("lag " + std::to_string(static_cast<int>(lag_s)) + " s").c_str() : "full",
              smoother_s, u.median_s * 1e3, u.p99_s * 1e3, u.max_s * 1e3, u.count, smoothed_s);
  std::printf("flight %d (%s, seed %llu): %zu epochs, %zu phase breaks\n", index, flightProfileName(setup.profile),
              static_cast<unsigned long long>(setup.seed), f.epochs.size(), f.breaks.size());
  FILE* csv = argc > 3 ? std::fopen(argv[3], "w") : nullptr;
  if (csv) std::fprintf(csv, "k,time_s,ekf_3d_m,smoother_filtered_3d_m,ekf_used,smoother_filtered_used\n");
  auto err = [&](const Epoch& e, std::size_t k) {
    return e.position ? (*e.position - f.truth[k].trajectory.position_ecef_m).norm() : -1.0;
  };
  int shown = 0;
  for (std::size_t k = 0; k < ekf.size() && k < filtered.size(); ++k) {
    const double t = f.epochs[k].time - f.epochs.front().time;
    if (csv)
      std::fprintf(csv, "%zu,%.1f,%s,%s,%d,%d\n", k, t, ekf[k].position ? std::to_string(err(ekf[k], k)).c_str() : "",
                   filtered[k].position ? std::to_string(err(filtered[k], k)).c_str() : "", ekf[k].used,
                   filtered[k].used);
    const double d = ekf[k].position && filtered[k].position ? (*ekf[k].position - *filtered[k].position).norm() : -1.0;
    if ((d > 0.3 || ekf[k].used != filtered[k].used) && shown++ < 60)
      std::printf("k=%zu |dx|=%.3f m err EKF %.2f filtered %.2f used %d/%d\n  EKF rejects: %s\n  smoother rejects: %s\n", k,
                  d, err(ekf[k], k), err(filtered[k], k), ekf[k].used, filtered[k].used, ekf[k].rejections.c_str(),
                  filtered[k].rejections.c_str());
  }
  if (csv) std::fclose(csv);
  return 0;
}
