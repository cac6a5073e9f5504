// The cost of the smoother node's smoothed outputs (ros/ppp_node.h) on a simulated
// flight (default: 30 min loiter at 1 Hz, seed 7), through the node's chain
// (PppEpochProcessor + PppSmoother, config/ppp.yaml with the flight's physics):
//  - the epoch update (what ppp/status update_time_s reports),
//  - ppp/path/smoothed: smoothedTrajectory() without covariance, every 60 epochs
//    and repeatedly at the end (the node calls it at ros.smoothed.path_publish_rate_hz),
//  - ppp/odometry/smoothed: smoothedEpochAt(t - delay) with its marginal covariance
//    per epoch, full smoother (delay 0, 10 s, 60 s) and fixed lag 60 s (lag boundary).
// Prints figures; asserts nothing.
// usage: ppp_bench_smoothed_outputs [CONFIG=config/ppp.yaml] [DURATION_MIN=30] [RATE_HZ=1]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_epoch_processor.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"

using namespace ppp;

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

struct Figures {
  std::vector<double> ms;
  void add(double v) { ms.push_back(v); }
  void print(const char* what) {
    if (ms.empty()) return;
    std::sort(ms.begin(), ms.end());
    double sum = 0.0;
    for (double v : ms) sum += v;
    std::printf("  %-58s mean %8.3f ms  median %8.3f  p99 %8.3f  max %8.3f  (n=%zu)\n", what, sum / ms.size(),
                ms[ms.size() / 2], ms[std::min(ms.size() - 1, ms.size() * 99 / 100)], ms.back(), ms.size());
  }
};

void run(const SimulatedFlight& f, PppConfig c, double lag_s) {
  c.smoother.fixed_lag_s = lag_s;
  const std::unique_ptr<PppEstimator> est_made = makeEstimator("smoother", c);
  PppEstimator& est = *est_made;
  PppEpochProcessor processor(f.header, c, f.products, {}, nullptr, nullptr);
  est.setApproximatePosition(*f.header.approx_position_ecef_m);
  Figures update, newest, delay10, delay60, trajectory_periodic;
  std::size_t k = 0;
  for (const auto& e : f.epochs) {
    auto t0 = Clock::now();
    const auto rec = processor.process(e, est);
    update.add(msSince(t0));
    ++k;
    if (!rec.solution.position_ecef_m) continue;
    const SmoothedTrajectoryProvider& s = *est.smoothing();
    t0 = Clock::now();
    (void)s.smoothedEpochAt(e.time - lag_s, true);  // lag 0: the newest state
    newest.add(msSince(t0));
    if (lag_s == 0.0) {
      t0 = Clock::now();
      (void)s.smoothedEpochAt(e.time - 10.0, true);
      delay10.add(msSince(t0));
      t0 = Clock::now();
      (void)s.smoothedEpochAt(e.time - 60.0, true);
      delay60.add(msSince(t0));
    }
    if (k % 60 == 0) {
      t0 = Clock::now();
      (void)s.smoothedTrajectory(false);
      trajectory_periodic.add(msSince(t0));
    }
  }
  Figures trajectory_end;
  std::size_t states = 0;
  for (int i = 0; i < 20; ++i) {
    const auto t0 = Clock::now();
    states = est.smoothing()->smoothedTrajectory(false).size();
    trajectory_end.add(msSince(t0));
  }
  if (lag_s > 0) std::printf("fixed lag %.0f s (%zu epochs, %zu states):\n", lag_s, f.epochs.size(), states);
  else std::printf("full smoother (%zu epochs, %zu states):\n", f.epochs.size(), states);
  update.print("epoch update (processor + smoother)");
  newest.print(lag_s > 0 ? "smoothed odometry: lag boundary + marginal" : "smoothed odometry: newest state + marginal");
  delay10.print("smoothed odometry: delay 10 s + marginal");
  delay60.print("smoothed odometry: delay 60 s + marginal");
  trajectory_periodic.print("smoothed path: smoothedTrajectory() every 60 epochs");
  trajectory_end.print("smoothed path: smoothedTrajectory() at the end (x20)");
}

}  // namespace

int main(int argc, char** argv) {
  const std::string config_path = argc > 1 ? argv[1] : "config/ppp.yaml";
  SimulationConfig sc;
  sc.profile = FlightProfile::Loiter;
  sc.duration_s = 60.0 * (argc > 2 ? std::atof(argv[2]) : 30.0);
  sc.rate_hz = argc > 3 ? std::atof(argv[3]) : 1.0;
  const SimulatedFlight f = simulateFlight(sc, 7);
  PppConfig c = flightPppConfig(loadPppConfig(config_path), f);
  run(f, c, 0.0);
  run(f, c, 60.0);
  return 0;
}
