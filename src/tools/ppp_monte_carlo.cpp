// ppp_monte_carlo: the method's Monte Carlo study over simulated UAV flights
// (evaluation/monte_carlo.h documents what is computed).
//
// usage: ppp_monte_carlo --flights N --seed S --out DIR [--first-flight 0] [--duration-min 30] [--rate 1]
//                        [--profiles loiter,survey,figure8,climb] [--threads N]
//                        [--config PPP_YAML] [--sim-config SIMULATION_YAML]
//                        [--fixed-origin] [--fixed-start] [--smoother-lag 60]
//                        [--ambiguity-resolution] [--systems G|GE] [--configurations LIST]
// --systems GE: GPS L1/L2 and Galileo E1/E5a (nominal Walker 24/3/1), one
// receiver clock per system in both estimators (default G: GPS only).
// --ambiguity-resolution: integer ambiguity resolution (PPP-AR) on in both
// estimators, the flights simulated with satellite phase biases published as
// phase OSBs (errors.ambiguity.satellite_phase_biases).
// --smoother-lag L (default 60 s): the smoother's FILTERED solution comes from the
// fixed-lag smoother with lag L (bounded cost per epoch) and its SMOOTHED solution
// from the batch solve of all its factors (the full smoother's MAP estimate);
// 0 runs one full iSAM2 smoother for both (about 2x the smoother time at 1 Hz over
// 30 min: 2.4 s against 1.2 s per flight). On 10 flights of 30 min both
// modes agree to 0.1 cm in every per-flight mean (monte_carlo.h).
// --config: the estimators' configuration (config/ppp.yaml layout), the same for
// the EKF and the smoother, loaded over the built-in (real-data) defaults; it
// replaces the study's default (the method's preset config/method_table.yaml with
// the 30 m start prior of config/ppp_simulated.yaml, see monteCarloDefaultPppConfig),
// so pass a file that holds what you want of those; the measurement model is always
// the simulator's physics (flightPppConfig) with the file's weights and cutoff.
// --first-flight K: run flights K .. K + N - 1 of the seed (each flight depends only on
// the seed and its index, so one flight of a study can be run again alone).
// --sim-config: the simulation error model (config/simulation.yaml layout). Writes DIR/summary.md, summary.json and CSV
// files for scripts/plot_monte_carlo.py; prints the tables and the wall time.
// --configurations LIST (comma-separated, or "all"): gps_float, gps_ar,
// gps_galileo_float, gps_galileo_ar, one study each over the same flights (same
// seed; every configuration simulates the satellite phase biases, so float and AR
// see the same observations; monte_carlo.h MonteCarloConfiguration), written to
// DIR/<name>/, then DIR/comparison.md: one table of the first-15-min median and
// mean, the time to 10 cm, the fixed share, the time to first fix and the wrong
// holds per configuration and estimator, beside the method's Table 3. Replaces
// --systems and --ambiguity-resolution.
// --imu GRADE (consumer|industrial|tactical): the GNSS/INS outage study instead
// (evaluation/ins_outage_study.h): the flights with the readings of a simulated IMU
// of that grade and GNSS outages of --outage-s S (default 30) every
// --outage-every-s S (default 300) after the first fix (--outage-keeps-lock: the
// receiver keeps its lock through them, same ambiguities), readings at --imu-rate HZ
// (default 100; --ideal-imu: the true readings, no noise and no bias, to see what
// the filter's own state at an outage's start costs), run by the estimators of
// --outage-estimators LIST (comma-separated registry names, default
// ekf,ekf_ins,smoother_ins; each scored on its filtered solution, smoother_ins's
// from the fixed-lag smoother of --smoother-lag; ekf,ekf_ins takes two thirds of
// the time); writes
// DIR/ins_outages.md (horizontal error at the outage end, the coast from the truth
// through the same readings, re-fix time, fix kept,
// roll/pitch/heading RMS, held integers against the truth per estimator, fixed epochs
// more than 10 cm from the truth) and DIR/wrong_holds.csv (each wrong hold of each flight);
// --gap-bridge-max-s S: the GNSS/INS estimators' InsEkfOptions::gap_bridge_max_s (default 90 s).
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "ppp_bayes_tree/app/allocator_tuning.h"
#include "ppp_bayes_tree/evaluation/ins_outage_study.h"
#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "ppp_bayes_tree/types/number_text.h"

namespace {

int usage(const std::string& why) {
  std::cerr << "ppp_monte_carlo: " << why << "\n"
            << "usage: ppp_monte_carlo --flights N --seed S --out DIR [--first-flight 0] [--duration-min 30] [--rate 1]\n"
            << "                       [--profiles loiter,survey,figure8,climb] [--threads N]\n"
            << "                       [--config PPP_YAML] [--sim-config SIMULATION_YAML]\n"
            << "                       [--fixed-origin] [--fixed-start] [--smoother-lag 60]\n"
            << "                       [--ambiguity-resolution] [--systems G|GE]\n"
            << "                       [--configurations all|gps_float,gps_ar,gps_galileo_float,gps_galileo_ar]\n"
            << "                       [--imu consumer|industrial|tactical [--outage-s 30] [--outage-every-s 300]\n"
            << "                        [--outage-keeps-lock] [--ideal-imu] [--outage-estimators ekf,ekf_ins,smoother_ins]\n"
            << "                        [--imu-rate 100] [--gap-bridge-max-s 90]]\n";
  return 2;
}

bool parseNumber(const std::string& s, double& v) {
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return !s.empty() && end != s.c_str() && *end == '\0';
}

/// Progress on stderr: a bar redrawn in place on a terminal, else a line per 10 %.
class Progress {
 public:
  explicit Progress(int total) : total_(total), tty_(isatty(STDERR_FILENO) != 0), t0_(Clock::now()) {}
  void update(int done) {
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0_).count();
    const double left = done > 0 ? elapsed * (total_ - done) / done : 0.0;
    if (tty_) {
      const int width = 30, filled = total_ > 0 ? width * done / total_ : width;
      std::fprintf(stderr, "\r[%s%s] %d/%d flights, %s elapsed, ~%s left ", std::string(filled, '#').c_str(),
                   std::string(width - filled, '.').c_str(), done, total_, ppp::minutesSecondsText(elapsed).c_str(),
                   ppp::minutesSecondsText(left).c_str());
      if (done == total_) std::fprintf(stderr, "\n");
    } else {
      const int decile = total_ > 0 ? 10 * done / total_ : 10;
      if (decile > last_decile_) {
        last_decile_ = decile;
        std::fprintf(stderr, "%3d%% (%d/%d flights), %s elapsed, ~%s left\n", 10 * decile, done, total_,
                     ppp::minutesSecondsText(elapsed).c_str(), ppp::minutesSecondsText(left).c_str());
      }
    }
    std::fflush(stderr);
  }

 private:
  using Clock = std::chrono::steady_clock;
  int total_;
  bool tty_;
  Clock::time_point t0_;
  int last_decile_ = 0;
};

std::string allConfigurationNames() {
  std::string names;
  for (const auto& c : ppp::monteCarloConfigurations()) names += (names.empty() ? "" : ",") + c.name;
  return names;
}

/// Runs one study, writes its outputs into `dir` and prints its tables; false
/// when the outputs cannot be written or every flight failed.
bool runStudy(const ppp::MonteCarloOptions& options, const std::string& dir, ppp::MonteCarloResult* keep = nullptr) {
  Progress progress(options.flights);
  ppp::MonteCarloResult result = ppp::runMonteCarlo(options, [&](int done, int) { progress.update(done); });
  try {
    ppp::writeMonteCarloOutputs(result, dir);
  } catch (const std::exception& e) {
    std::cerr << "ppp_monte_carlo: " << e.what() << "\n";
    return false;
  }
  std::cout << ppp::monteCarloMarkdown(result) << "\n";
  std::printf("Wall time: %.1f s (%d flights, %u threads). Outputs in %s\n", result.wall_s, options.flights,
              result.threads_used, dir.c_str());
  std::fflush(stdout);
  const bool ok = result.summary.failed < options.flights;
  if (keep) *keep = std::move(result);
  return ok;
}

/// The GNSS/INS outage study: writes DIR/ins_outages.md and prints it.
bool runInsStudy(const ppp::InsOutageStudyOptions& options, const std::string& dir) {
  const ppp::InsOutageStudy study = ppp::runInsOutageStudy(options);
  const std::string md = ppp::insOutageMarkdown(study);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  std::ofstream file(dir + "/ins_outages.md", std::ios::binary);
  file << md;
  if (!file) {
    std::cerr << "ppp_monte_carlo: cannot write " << dir << "/ins_outages.md\n";
    return false;
  }
  std::ofstream csv(dir + "/wrong_holds.csv", std::ios::binary);
  csv << ppp::insOutageWrongHoldsCsv(study);
  if (!csv) {
    std::cerr << "ppp_monte_carlo: cannot write " << dir << "/wrong_holds.csv\n";
    return false;
  }
  std::cout << md << "\n";
  return study.failed < options.flights.flights;
}

bool parseGrade(const std::string& v, ppp::ImuGrade& grade) {
  const std::optional<ppp::ImuGrade> named = ppp::imuGradeFromName(v);
  if (named) grade = *named;
  return named.has_value();
}

}  // namespace

int main(int argc, char** argv) {
  ppp::useAllocatorWithoutFastBins();  // app/allocator_tuning.h
  ppp::MonteCarloOptions options;
  options.flights = 0;
  options.smoother_filtered_lag_s = 60.0;
  std::string out, config_path, sim_config_path, profiles;
  bool have_seed = false, ambiguity_resolution = false;
  std::string systems;  // empty: the simulation configuration's (default G)
  std::vector<ppp::MonteCarloConfiguration> configurations;
  double duration_min = 30.0;
  std::optional<ppp::ImuGrade> imu_grade;
  double outage_s = 30.0, outage_every_s = 300.0, imu_rate_hz = 100.0;
  bool outage_keeps_lock = false;
  bool ideal_imu = false;
  std::optional<double> gap_bridge_max_s;
  std::optional<std::vector<std::string>> outage_estimators;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--fixed-origin") {
      options.randomize_origin = false;
      continue;
    }
    if (a == "--ambiguity-resolution") {
      ambiguity_resolution = true;
      continue;
    }
    if (a == "--outage-keeps-lock") {
      outage_keeps_lock = true;
      continue;
    }
    if (a == "--ideal-imu") {
      ideal_imu = true;
      continue;
    }
    if (a == "--fixed-start") {
      options.randomize_start = false;
      continue;
    }
    if (i + 1 >= argc) return usage("missing value after " + a);
    const std::string v = argv[++i];
    double x = 0.0;
    if (a == "--out") out = v;
    else if (a == "--config") config_path = v;
    else if (a == "--sim-config") sim_config_path = v;
    else if (a == "--profiles") profiles = v;
    else if (a == "--configurations") {
      std::stringstream ss(v == "all" ? allConfigurationNames() : v);
      std::string name;
      while (std::getline(ss, name, ',')) {
        const ppp::MonteCarloConfiguration* c = ppp::findMonteCarloConfiguration(name);
        if (c == nullptr) return usage("unknown configuration '" + name + "' (expected all or " + allConfigurationNames() + ")");
        configurations.push_back(*c);
      }
      if (configurations.empty()) return usage("--configurations is empty");
    }
    else if (a == "--imu") {
      ppp::ImuGrade grade{};
      if (!parseGrade(v, grade)) return usage("--imu must be consumer, industrial or tactical");
      imu_grade = grade;
    }
    else if (a == "--outage-s") {
      if (!parseNumber(v, x) || !(x > 0.0)) return usage("--outage-s must be > 0 s");
      outage_s = x;
    }
    else if (a == "--imu-rate") {
      if (!parseNumber(v, x) || !(x >= 10.0) || x > 2000.0) return usage("--imu-rate must be in [10, 2000] Hz");
      imu_rate_hz = x;
    }
    else if (a == "--gap-bridge-max-s") {
      if (!parseNumber(v, x) || x < 0.0 || x > 3600.0) return usage("--gap-bridge-max-s must be in [0, 3600] s");
      gap_bridge_max_s = x;
    }
    else if (a == "--outage-estimators") {
      std::vector<std::string> names;
      std::stringstream ss(v);
      std::string name;
      while (std::getline(ss, name, ',')) names.push_back(name);
      if (const std::string why = ppp::insOutageEstimatorsProblem(names); !why.empty())
        return usage("--outage-estimators: " + why);
      outage_estimators = names;
    }
    else if (a == "--outage-every-s") {
      if (!parseNumber(v, x) || !(x > 0.0)) return usage("--outage-every-s must be > 0 s");
      outage_every_s = x;
    }
    else if (a == "--systems") {
      if (v != "G" && v != "GE") return usage("--systems must be G or GE");
      systems = v;
    }
    else if (a == "--smoother-lag") {
      if (!parseNumber(v, x) || x < 0.0) return usage("--smoother-lag must be >= 0 s");
      options.smoother_filtered_lag_s = x;
    }
    else if (a == "--flights") {
      if (!parseNumber(v, x) || x < 1 || x > 100000 || x != static_cast<int>(x)) return usage("--flights must be 1..100000");
      options.flights = static_cast<int>(x);
    } else if (a == "--first-flight") {
      if (!parseNumber(v, x) || x < 0 || x > 100000 || x != static_cast<int>(x)) return usage("--first-flight must be 0..100000");
      options.first_flight = static_cast<int>(x);
    } else if (a == "--threads") {
      if (!parseNumber(v, x) || x < 1 || x > 256 || x != static_cast<int>(x)) return usage("--threads must be 1..256");
      options.threads = static_cast<unsigned>(x);
    } else if (a == "--rate") {
      if (!parseNumber(v, x) || (x != 1.0 && x != 10.0)) return usage("--rate must be 1 or 10");
      options.rate_hz = x;
    } else if (a == "--duration-min") {
      if (!parseNumber(v, x) || !(x > 0.0) || x > 1440.0) return usage("--duration-min must be in (0, 1440]");
      duration_min = x;
    } else if (a == "--seed") {
      char* end = nullptr;
      options.seed = std::strtoull(v.c_str(), &end, 10);
      if (v.empty() || *end != '\0' || v[0] == '-') return usage("--seed must be a non-negative integer");
      have_seed = true;
    } else {
      return usage("unknown option " + a);
    }
  }
  if (out.empty()) return usage("--out DIR is required");
  if (options.flights == 0) return usage("--flights N is required");
  if (!have_seed) return usage("--seed S is required (explicit seeds only)");
  if (!configurations.empty() && (ambiguity_resolution || !systems.empty()))
    return usage("--configurations sets the systems and ambiguity resolution: leave out --systems and --ambiguity-resolution");
  options.duration_s = duration_min * 60.0;
  try {
    if (!profiles.empty()) {
      options.profiles.clear();
      std::stringstream ss(profiles);
      std::string p;
      while (std::getline(ss, p, ',')) options.profiles.push_back(ppp::parseFlightProfile(p));
      if (options.profiles.empty()) return usage("--profiles is empty");
    }
    if (!config_path.empty()) options.ppp = ppp::loadPppConfig(config_path);
    if (!sim_config_path.empty()) options.simulation = ppp::loadSimulationConfig(sim_config_path);
    if (systems == "G") options.simulation.systems = {ppp::GnssSystem::GPS};
    if (systems == "GE") options.simulation.systems = {ppp::GnssSystem::GPS, ppp::GnssSystem::Galileo};
    if (ambiguity_resolution) {  // PPP-AR in both estimators, on flights with published phase OSBs
      options.ppp.ambiguity_resolution.enabled = true;
      options.simulation.errors.ambiguity.satellite_phase_biases = true;
    }
  } catch (const std::exception& e) {
    std::cerr << "ppp_monte_carlo: " << e.what() << "\n";
    return 2;
  }
  if (const std::string why = options.ppp.smoother.validate(); !why.empty()) return usage("smoother options: " + why);

  if (ideal_imu && !imu_grade) return usage("--ideal-imu needs --imu");
  if (gap_bridge_max_s && !imu_grade) return usage("--gap-bridge-max-s needs --imu");
  if (outage_estimators && !imu_grade) return usage("--outage-estimators needs --imu");
  if (imu_grade) {
    if (configurations.size() > 1) return usage("--imu runs one configuration");
    ppp::InsOutageStudyOptions ins;
    ins.flights = configurations.empty() ? options : ppp::withConfiguration(options, configurations.front());
    ins.grade = *imu_grade;
    ins.outage_s = outage_s;
    ins.outage_every_s = outage_every_s;
    ins.outage_keeps_lock = outage_keeps_lock;
    ins.imu_errors = !ideal_imu;
    ins.imu_rate_hz = imu_rate_hz;
    if (gap_bridge_max_s) ins.flights.ppp.ins.gap_bridge_max_s = *gap_bridge_max_s;
    if (outage_estimators) ins.estimators = *outage_estimators;
    if (!(outage_s < outage_every_s)) return usage("--outage-s must be shorter than --outage-every-s");
    return runInsStudy(ins, out) ? 0 : 1;
  }
  if (configurations.empty()) return runStudy(options, out) ? 0 : 1;
  std::vector<std::pair<std::string, ppp::MonteCarloResult>> studies;
  bool ok = true;
  for (const auto& c : configurations) {
    std::cerr << "configuration " << c.name << "\n";
    studies.emplace_back(c.name, ppp::MonteCarloResult{});
    ok = runStudy(ppp::withConfiguration(options, c), out + "/" + c.name, &studies.back().second) && ok;
  }
  const std::string comparison = ppp::monteCarloComparisonMarkdown(studies);
  std::ofstream file(out + "/comparison.md", std::ios::binary);
  file << comparison;
  if (!file) {
    std::cerr << "ppp_monte_carlo: cannot write " << out << "/comparison.md\n";
    return 1;
  }
  std::cout << comparison << "\n";
  return ok ? 0 : 1;
}
