// Monte Carlo throughput in CPU time (evaluation/monte_carlo.h), for a machine
// shared with other work, where wall times say little: the study ppp_monte_carlo
// runs by default (30 min at 1 Hz, 60 s smoother lag) with GPS + Galileo unless
// --systems G, flights 0..N-1 of seed S, one after another on this thread.
// Prints, per flight and on average, the CPU time (this thread's, user + system)
//  * of the whole flight as the study runs it (runMonteCarloFlight), and from it
//    the flights per core-minute and the wall time of 1000 flights on 2 idle cores;
//  * of each stage measured on its own: the simulation (simulateFlight), the EKF
//    run, and the smoother run with its smoothed solution (the batch solve of the
//    fixed-lag smoother's factors), as runMonteCarloFlight runs them, without the
//    study's bookkeeping (error, bias and held-integer records).
// Uses the allocator setting of the batch tools (app/allocator_tuning.h). Asserts nothing.
// usage: ppp_bench_mc_throughput [--flights N=4] [--seed S=1] [--systems G|GE]
#include <time.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "ppp_bayes_tree/app/allocator_tuning.h"
#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"

using namespace ppp;

namespace {

/// CPU time of the calling thread [s].
double threadCpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct StageCpu {
  double flight_s = 0, simulate_s = 0, ekf_s = 0, smoother_s = 0;
  void add(const StageCpu& o) {
    flight_s += o.flight_s;
    simulate_s += o.simulate_s;
    ekf_s += o.ekf_s;
    smoother_s += o.smoother_s;
  }
};

/// The stages of flight `index` one by one (see the file comment).
StageCpu stages(const MonteCarloOptions& o, int index) {
  StageCpu cpu;
  const MonteCarloFlightSetup setup = monteCarloFlightSetup(o, index);
  double t0 = threadCpu_s();
  const SimulatedFlight f = simulateFlight(monteCarloSimulationConfig(o, setup), setup.seed);
  cpu.simulate_s = threadCpu_s() - t0;
  const PppConfig config = flightPppConfig(o.ppp, f);
  PppInMemoryInputs in;
  in.header = &f.header;
  in.epochs = &f.epochs;
  in.products = &f.products;
  if (!f.phase_biases.empty()) in.phase_biases = &f.phase_biases;
  t0 = threadCpu_s();
  {
    PppPipeline pipeline(in, config);
    const std::unique_ptr<PppEstimator> ekf_made = makeEstimator("ekf", config);
    PppEstimator& ekf = *ekf_made;
    pipeline.run(ekf, [](const PppEpochRecord&) {});
  }
  cpu.ekf_s = threadCpu_s() - t0;
  t0 = threadCpu_s();
  {
    PppConfig smoother_config = config;
    smoother_config.smoother.fixed_lag_s = o.smoother_filtered_lag_s;
    smoother_config.smoother.record_graph = true;
    PppPipeline pipeline(in, smoother_config);
    const std::unique_ptr<PppEstimator> sm_made = makeEstimator("smoother", smoother_config);
    PppEstimator& sm = *sm_made;
    pipeline.run(sm, [](const PppEpochRecord&) {});
    if (sm.smoothing()->finalSmoothedSolution().trajectory.empty())
      std::fprintf(stderr, "flight %d: no smoothed state\n", index);
  }
  cpu.smoother_s = threadCpu_s() - t0;
  return cpu;
}

int usage() {
  std::fprintf(stderr, "usage: ppp_bench_mc_throughput [--flights N=4] [--seed S=1] [--systems G|GE]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  ppp::useAllocatorWithoutFastBins();  // app/allocator_tuning.h
  MonteCarloOptions o;
  o.flights = 4;
  o.smoother_filtered_lag_s = 60.0;  // ppp_monte_carlo's default
  o.simulation.systems = {GnssSystem::GPS, GnssSystem::Galileo};
  for (int i = 1; i < argc; i += 2) {
    if (i + 1 >= argc) return usage();
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--flights") o.flights = std::atoi(v.c_str());
    else if (a == "--seed") o.seed = std::strtoull(v.c_str(), nullptr, 10);
    else if (a == "--systems" && v == "G") o.simulation.systems = {GnssSystem::GPS};
    else if (a == "--systems" && v == "GE") o.simulation.systems = {GnssSystem::GPS, GnssSystem::Galileo};
    else return usage();
  }
  if (o.flights < 1) return usage();
  StageCpu sum;
  std::printf("flight  CPU s: whole flight | simulation   EKF   smoother (stages on their own)\n");
  for (int i = 0; i < o.flights; ++i) {
    const double t0 = threadCpu_s();
    const MonteCarloFlightRun run = runMonteCarloFlight(o, i);
    const double flight_s = threadCpu_s() - t0;
    StageCpu cpu = stages(o, i);
    cpu.flight_s = flight_s;
    if (!run.failure.empty()) std::printf("flight %d failed: %s\n", i, run.failure.c_str());
    std::printf("%6d  %22.3f | %10.3f %5.3f %10.3f\n", i, cpu.flight_s, cpu.simulate_s, cpu.ekf_s, cpu.smoother_s);
    sum.add(cpu);
  }
  const double n = o.flights;
  const double per_flight_s = sum.flight_s / n;
  std::printf("mean CPU per flight: whole flight %.3f s; stages: simulation %.3f s, EKF %.3f s, smoother %.3f s\n",
              per_flight_s, sum.simulate_s / n, sum.ekf_s / n, sum.smoother_s / n);
  std::printf("throughput: %.1f flights per core-minute; 1000 flights on 2 idle cores: %.1f min (target < 10 min)\n",
              60.0 / per_flight_s, 1000.0 * per_flight_s / 2.0 / 60.0);
  return 0;
}
