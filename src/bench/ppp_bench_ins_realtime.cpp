// Real-time benchmark of the GNSS/INS path (no ROS): a simulated flight with the
// readings of an industrial MEMS IMU (GPS + Galileo with phase biases, PPP-AR on,
// white code noise: evaluation/ins_ar_flights.h; default 200 Hz IMU, 10 Hz GNSS,
// 5 min, seed 7) is fed in time order
//  1. to ekf_ins with the odometry at the IMU rate, per reading what the PPP node
//     does per IMU message (ros/ppp_node.cpp onImu): the input screen
//     (ImuInputScreen::push, the time base checked at the first reading after each
//     epoch), the node's buffer, and InsOdometry::step (the mechanization and the
//     15-state covariance); after each GNSS epoch the odometry restart from the
//     filter (restartInsOdometry);
//  2. to smoother_ins with the fixed lag; --smoother-config YAML takes the smoother
//     section of a configuration (scripts/bench_ins_realtime.sh gives config/live.yaml:
//     lag 60 s, wildfire threshold 1 mm, relinearization thresholds), else the Monte
//     Carlo study's with a 60 s lag.
// Measured (wall, steady clock):
//  - odometry latency: per reading that gives an odometry state, from the reading
//    handed to the screen to the state (pose, twist, covariance) available; the
//    ROS message filling (a few 3 x 3 products) is not included;
//  - per GNSS epoch: the whole epoch step of the offline pipeline (reading the
//    in-memory epoch, signal selection, arcs, model, estimator: what the node
//    times as its update), the estimator step alone, and for the smoother its
//    iSAM2 update; for ekf_ins the odometry restart after the epoch.
// Prints p50 / p90 / p99 / max and counts, the fixed share of each estimator and
// whether the targets (odometry p99 < 2 ms, smoother_ins epoch step p99 < 10 ms)
// are met. Asserts nothing. scripts/bench_ins_realtime.sh builds and runs it.
// Usage: ppp_bench_ins_realtime [--minutes 5] [--seed 7] [--flight 0] [--profile loiter]
//          [--smoother-config YAML] [--lag-s 60] [--gnss-rate-hz 10] [--imu-rate-hz 200] [--csv FILE]
//          [--ekf-only]
//   --csv: per smoother_ins epoch its step times, the iSAM2 steps and counts.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/evaluation/ins_ar_flights.h"
#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/navigation/imu_input_screen.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/estimators/ins_odometry.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_ins_ekf.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/simulation/simulated_imu.h"
#include "ppp_bayes_tree/smoother/isam2_result.h"
#include "ppp_bayes_tree/types/thread_cpu_time.h"

using namespace ppp;

namespace {

using Clock = std::chrono::steady_clock;
double secondsBetween(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

constexpr double kOdometryTarget_s = 2e-3;
constexpr double kSmootherTarget_s = 10e-3;
constexpr double kNodeImuBuffer_s = 10.0;  // ros.imu.buffer_s default (config/ppp.yaml)

struct BenchOptions {
  double minutes = 5.0, gnss_rate_hz = 10.0, imu_rate_hz = 200.0;
  std::optional<double> lag_s;  // default: the smoother configuration's, else 60 s
  std::string smoother_config;  // YAML whose smoother section is used (e.g. config/live.yaml)
  std::uint64_t seed = 7;
  int flight = 0;
  std::string profile = "loiter";
  std::string csv;  // per smoother_ins epoch: times and the iSAM2 update's figures
  bool ekf_only = false;
};

/// The times of one run [s] and its fixes.
struct RunFigures {
  std::vector<double> epoch_step_s, epoch_step_cpu_s, estimator_s, isam2_s, restart_s, odometry_s;
  /// smoother_ins: the iSAM2 steps (ISAM2Result::Step order), the rest of the update
  /// (marginalization, postfit check) and the estimator step outside the update.
  std::array<std::vector<double>, 5> isam2_step_s;
  std::vector<double> update_rest_s, outside_update_s;
  std::size_t epochs = 0, solved = 0, fixed = 0, readings = 0;
  std::optional<double> first_fix_s;
  double run_s = 0.0;
};

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a.empty() ? "unknown" : a + " " + b + " " + c + " (1, 5, 15 min)";
}

void printTimes(const char* what, const std::vector<double>& times_s) {
  const TimingSummary s = summarizeTimes(times_s);
  std::printf("  %-46s n %7zu  p50 %8.3f  p90 %8.3f  p99 %8.3f  max %8.3f ms\n", what, s.count, 1e3 * s.median_s,
              1e3 * s.p90_s, 1e3 * s.p99_s, 1e3 * s.max_s);
}

/// Counts the epoch's solution and fix into `r`.
void countEpoch(const PppEpochRecord& rec, const SimulatedFlight& f, RunFigures& r) {
  ++r.epochs;
  if (rec.solution.position_ecef_m) ++r.solved;
  if (rec.solution.status != SolutionStatus::PppFixed) return;
  ++r.fixed;
  if (!r.first_fix_s) r.first_fix_s = rec.solution.time - f.epochs.front().time;
}

/// The node's IMU input and odometry (ros/node_imu_input.cpp, ros/ins_odometry.h) with the core calls only.
class OdometryPath {
 public:
  explicit OdometryPath(const InsEkfOptions& ins) : odometry_(ins) {}

  /// One reading handed over (onImu): screen, buffer, odometry step. True when a state came out.
  bool receive(const ImuSample& reading, const std::optional<GnssTime>& newest_epoch) {
    std::optional<GnssTime> check;
    if (newest_epoch && (!checked_ || *newest_epoch - *checked_ != 0.0)) check = checked_ = newest_epoch;
    bool state = false;
    for (const ImuSample& r : screen_.push(reading, check)) {
      pending_.push_back(r);
      while (pending_.back().time - pending_.front().time > kNodeImuBuffer_s) pending_.pop_front();
      if (odometry_.step(r)) state = true;
    }
    return state;
  }
  /// After an epoch at `time` (processObsEpoch): its readings leave the buffer, the
  /// odometry restarts from the filter (restartInsOdometry).
  void restart(const GnssTime& time, const PppInsEkf& filter) {
    while (!pending_.empty() && pending_.front().time - time <= 0.0) {
      last_taken_ = pending_.front();
      pending_.pop_front();
    }
    if (!filter.navTime()) return;
    InsState state;
    state.time = *filter.navTime();
    state.nav = filter.navState();
    state.bias = filter.imuBias();
    state.covariance = filter.covarianceMatrix().topLeftCorner<kInsErrorStateSize, kInsErrorStateSize>();
    odometry_.restart(state, last_taken_, pending_);
  }

 private:
  ImuInputScreen screen_;
  InsOdometry odometry_;
  std::deque<ImuSample> pending_;
  std::optional<ImuSample> last_taken_;
  std::optional<GnssTime> checked_;
};

/// The readings up to and including `until` from `next` on, each handed to the odometry and timed.
void feedReadings(const SimulatedFlight& f, const GnssTime& until, const std::optional<GnssTime>& newest_epoch,
                  std::size_t& next, OdometryPath& path, RunFigures& r) {
  for (; next < f.imu.samples.size() && f.imu.samples[next].time - until <= 0.0; ++next) {
    const auto t0 = Clock::now();
    const bool state = path.receive(f.imu.samples[next], newest_epoch);
    const auto t1 = Clock::now();
    ++r.readings;
    if (state) r.odometry_s.push_back(secondsBetween(t0, t1));
  }
}

/// ekf_ins with the odometry at the IMU rate, in time order.
RunFigures runEkfIns(const SimulatedFlight& f, const PppConfig& config) {
  PppPipeline pipeline(simulatedFlightInputs(f, 0), config);
  pipeline.setImu(f.imu.samples);
  const std::unique_ptr<PppInsEkf> filter = makeEstimatorAs<PppInsEkf>("ekf_ins", config);
  OdometryPath path(config.ins);
  RunFigures r;
  std::size_t next = 0, k = 0;
  feedReadings(f, f.epochs.front().time, std::nullopt, next, path, r);  // before the first epoch: no state yet
  const auto start = Clock::now();
  auto step_start = Clock::now();
  pipeline.run(*filter, [&](const PppEpochRecord& rec) {
    r.epoch_step_s.push_back(secondsBetween(step_start, Clock::now()));
    r.estimator_s.push_back(rec.estimator_time_s);
    countEpoch(rec, f, r);
    const auto t0 = Clock::now();
    path.restart(rec.solution.time, *filter);
    r.restart_s.push_back(secondsBetween(t0, Clock::now()));
    const GnssTime until = ++k < f.epochs.size() ? f.epochs[k].time : f.imu.samples.back().time;
    feedReadings(f, until, rec.solution.time, next, path, r);
    step_start = Clock::now();
  });
  r.run_s = secondsBetween(start, Clock::now());
  return r;
}

/// One CSV row of a smoother_ins epoch (the header: kSmootherCsvHeader).
constexpr const char* kSmootherCsvHeader =
    "k,epoch_step_ms,estimator_ms,isam2_ms,add_factors_ms,relinearize_ms,remove_top_ms,reeliminate_ms,"
    "backsubstitute_ms,relinearized,reeliminated,cliques_touched,marginalized,model_rejections,new_biases,"
    "active_biases,fixed\n";
void writeSmootherRow(std::FILE* csv, std::size_t k, double step_s, const PppEpochRecord& rec) {
  const SmootherEpochDiagnostics d = rec.smoother.value_or(SmootherEpochDiagnostics{});
  const auto& st = d.isam2_step_time_s;
  std::fprintf(csv, "%zu,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%zu,%zu,%zu,%zu,%d,%d,%d,%d\n", k, 1e3 * step_s,
               1e3 * rec.estimator_time_s, 1e3 * d.update_time_s, 1e3 * st[0], 1e3 * st[1], 1e3 * st[2], 1e3 * st[3],
               1e3 * st[4], d.variables_relinearized, d.variables_reeliminated, d.cliques_touched,
               d.variables_marginalized, static_cast<int>(std::count_if(rec.rejected.begin(), rec.rejected.end(),
                   [](const EpochRejection& x) { return x.stage == RejectionStage::Model; })),
               d.new_biases, rec.active_biases, rec.solution.status == SolutionStatus::PppFixed ? 1 : 0);
}

/// The smoother's update split into its steps.
void addUpdateSteps(const SmootherEpochDiagnostics& d, double estimator_s, RunFigures& r) {
  r.isam2_s.push_back(d.update_time_s);
  double steps_s = 0.0;
  for (std::size_t i = 0; i < d.isam2_step_time_s.size(); ++i) {
    r.isam2_step_s[i].push_back(d.isam2_step_time_s[i]);
    steps_s += d.isam2_step_time_s[i];
  }
  r.update_rest_s.push_back(d.update_time_s - steps_s);
  r.outside_update_s.push_back(estimator_s - d.update_time_s);
}

/// smoother_ins (fixed lag), each epoch with its readings (the pipeline's); per epoch a
/// row into `csv` when given.
RunFigures runSmootherIns(const SimulatedFlight& f, const PppConfig& config, std::FILE* csv) {
  PppPipeline pipeline(simulatedFlightInputs(f, 0), config);
  pipeline.setImu(f.imu.samples);
  const std::unique_ptr<PppEstimator> smoother = makeEstimator("smoother_ins", config);
  RunFigures r;
  const auto start = Clock::now();
  auto step_start = Clock::now();
  double step_cpu_start_s = threadCpu_s();
  pipeline.run(*smoother, [&](const PppEpochRecord& rec) {
    r.epoch_step_s.push_back(secondsBetween(step_start, Clock::now()));
    r.epoch_step_cpu_s.push_back(threadCpu_s() - step_cpu_start_s);
    if (csv) writeSmootherRow(csv, r.epochs, r.epoch_step_s.back(), rec);
    r.estimator_s.push_back(rec.estimator_time_s);
    if (rec.smoother) addUpdateSteps(*rec.smoother, rec.estimator_time_s, r);
    countEpoch(rec, f, r);
    step_cpu_start_s = threadCpu_s();
    step_start = Clock::now();
  });
  r.run_s = secondsBetween(start, Clock::now());
  return r;
}

void printFixes(const char* name, const RunFigures& r) {
  char first[32] = "never";
  if (r.first_fix_s) std::snprintf(first, sizeof first, "%.1f s", *r.first_fix_s);
  std::printf("  %s: %zu epochs, %zu solved, %zu fixed (%.1f %% of the epochs), first fix at %s; run %.1f s wall\n",
              name, r.epochs, r.solved, r.fixed, r.epochs ? 100.0 * r.fixed / r.epochs : 0.0, first, r.run_s);
}

const char* verdict(const std::vector<double>& times_s, double target_s) {
  if (times_s.empty()) return "NOT MEASURED";
  return summarizeTimes(times_s).p99_s < target_s ? "MET" : "MISSED";
}

int usage(const char* why) {
  std::fprintf(stderr,
               "ppp_bench_ins_realtime: %s\nusage: ppp_bench_ins_realtime [--minutes 5] [--seed 7] [--flight 0] "
               "[--profile loiter|survey|figure8|climb] [--smoother-config YAML] [--lag-s 60] [--gnss-rate-hz 10] "
               "[--imu-rate-hz 200] "
               "[--csv FILE] [--ekf-only]\n",
               why);
  return 2;
}

/// Parses the arguments into `o`; returns the usage message's reason, empty when fine.
std::string parse(int argc, char** argv, BenchOptions& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--ekf-only") {
      o.ekf_only = true;
      continue;
    }
    if (i + 1 >= argc) return a + " needs a value";
    const std::string v = argv[++i];
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    const bool number = end && *end == '\0' && !v.empty();
    if (a == "--profile") o.profile = v;
    else if (a == "--csv") o.csv = v;
    else if (a == "--smoother-config") o.smoother_config = v;
    else if (!number) return a + ": not a number: " + v;
    else if (a == "--minutes" && x > 0.0) o.minutes = x;
    else if (a == "--seed" && x >= 0.0) o.seed = static_cast<std::uint64_t>(x);
    else if (a == "--flight" && x >= 0.0) o.flight = static_cast<int>(x);
    else if (a == "--lag-s" && x > 0.0) o.lag_s = x;
    else if (a == "--gnss-rate-hz" && x > 0.0) o.gnss_rate_hz = x;
    else if (a == "--imu-rate-hz" && x > 0.0) o.imu_rate_hz = x;
    else return "unknown argument or value out of range: " + a + " " + v;
  }
  return "";
}

/// The estimators' configuration: the flight's (both start from the true attitude and
/// velocity), the smoother section of --smoother-config (its screening stays the
/// estimator's), the lag of --lag-s.
PppConfig benchConfig(const MonteCarloOptions& o, const SimulatedFlight& f, const BenchOptions& b) {
  PppConfig config = flightPppConfig(o.ppp, f);
  const TrajectorySample& start = f.truth.front().trajectory;
  config.ins.noise = f.imu.noise;
  config.ins.initial_rotation_ecef_body = ecefFromBody(start);
  config.ins.initial_velocity_ecef_mps = start.velocity_ecef_mps;
  if (!b.smoother_config.empty()) {
    const ScreeningOptions screening = config.smoother.screening;
    config.smoother = loadPppConfig(b.smoother_config).smoother;
    config.smoother.screening = screening;
  } else {
    config.smoother.fixed_lag_s = 60.0;
  }
  if (b.lag_s) config.smoother.fixed_lag_s = *b.lag_s;
  return config;
}

/// The figures and the targets' verdicts.
void printReport(const RunFigures& ekf, const RunFigures& sm, bool ekf_only) {
  std::printf("fixes (PPP-AR on):\n");
  printFixes("ekf_ins", ekf);
  if (!ekf_only) printFixes("smoother_ins", sm);
  std::printf("latencies (wall):\n");
  printTimes("odometry per IMU reading (screen + step)", ekf.odometry_s);
  printTimes("ekf_ins GNSS epoch step (whole pipeline)", ekf.epoch_step_s);
  printTimes("ekf_ins estimator step", ekf.estimator_s);
  printTimes("ekf_ins odometry restart after the epoch", ekf.restart_s);
  if (!ekf_only) {
    printTimes("smoother_ins GNSS epoch step (whole pipeline)", sm.epoch_step_s);
    printTimes("smoother_ins epoch step, thread CPU", sm.epoch_step_cpu_s);
    printTimes("smoother_ins estimator step", sm.estimator_s);
    printTimes("smoother_ins update (iSAM2 + fixed lag)", sm.isam2_s);
    std::printf("  where the smoother_ins update goes:\n");
    for (std::size_t i = 0; i < sm.isam2_step_s.size(); ++i)
      printTimes(("  iSAM2 " + std::string(smoother::ISAM2Result::kStepNames[i])).c_str(), sm.isam2_step_s[i]);
    printTimes("  marginalization + postfit check", sm.update_rest_s);
    printTimes("  estimator step outside the update", sm.outside_update_s);
  }
  std::printf("targets: odometry p99 < 2 ms: %s; smoother_ins epoch step p99 < 10 ms: %s\n",
              verdict(ekf.odometry_s, kOdometryTarget_s), ekf_only ? "NOT RUN" : verdict(sm.epoch_step_s, kSmootherTarget_s));
}

}  // namespace

int main(int argc, char** argv) {
  BenchOptions b;
  if (const std::string why = parse(argc, argv, b); !why.empty()) return usage(why.c_str());
  FlightProfile profile = FlightProfile::Loiter;
  try {
    profile = parseFlightProfile(b.profile);
  } catch (const std::exception& e) {
    return usage(("--profile: " + std::string(e.what())).c_str());
  }
  MonteCarloOptions o = insArFlightOptions({profile}, 60.0 * b.minutes);
  o.seed = b.seed;
  o.rate_hz = b.gnss_rate_hz;
  o.simulation.imu.rate_hz = b.imu_rate_hz;
  std::printf("ppp_bench_ins_realtime: %s, %.1f min, seed %llu flight %d, GNSS %.0f Hz (GPS + Galileo, PPP-AR on), "
              "industrial MEMS IMU %.0f Hz\n",
              b.profile.c_str(), b.minutes, static_cast<unsigned long long>(b.seed), b.flight, b.gnss_rate_hz,
              b.imu_rate_hz);
  std::printf("load average at the start: %s\n", loadAverage().c_str());
  const MonteCarloFlightSetup setup = monteCarloFlightSetup(o, b.flight);
  const auto t0 = Clock::now();
  const SimulatedFlight f = simulateFlight(monteCarloSimulationConfig(o, setup), setup.seed);
  std::printf("simulated %zu epochs and %zu IMU readings in %.1f s\n", f.epochs.size(), f.imu.samples.size(),
              secondsBetween(t0, Clock::now()));
  PppConfig config;
  try {
    config = benchConfig(o, f, b);
  } catch (const std::exception& e) {
    return usage(("--smoother-config " + b.smoother_config + ": " + e.what()).c_str());
  }
  std::printf("smoother_ins: fixed lag %.0f s, wildfire threshold %g m, relinearization position %g m, ZWD %g m "
              "(%s)\n",
              config.smoother.fixed_lag_s, config.smoother.wildfire_threshold_m,
              config.smoother.relinearize_position_m, config.smoother.relinearize_zwd_m,
              b.smoother_config.empty() ? "the Monte Carlo study's" : b.smoother_config.c_str());

  const RunFigures ekf = runEkfIns(f, config);
  std::FILE* csv = b.csv.empty() ? nullptr : std::fopen(b.csv.c_str(), "w");
  if (!b.csv.empty() && !csv) return usage(("--csv: cannot write " + b.csv).c_str());
  if (csv) std::fputs(kSmootherCsvHeader, csv);
  const RunFigures sm = b.ekf_only ? RunFigures{} : runSmootherIns(f, config, csv);
  if (csv) std::fclose(csv);
  std::printf("load average at the end: %s\n", loadAverage().c_str());
  printReport(ekf, sm, b.ekf_only);
  return 0;
}
