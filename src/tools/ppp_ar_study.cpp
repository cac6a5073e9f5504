// ppp_ar_study: what integer ambiguity resolution (PPP-AR) does on a real day,
// judged against the day's own float static position (the ESBC
// criterion: there is no external truth there).
//
// Three EKF runs of the same inputs: float static (the reference: its last
// solved position), float with the chosen dynamics, and PPP-AR with the chosen
// dynamics. Printed: the time to first fix, the share of fixed epochs after the
// first hour, the fixed epochs further than 10 cm from the reference (wrong
// fixes), the fixed epochs more than 5 cm from the float of the same epoch,
// the RMS E/N/U about their mean of the fixed (and the float) positions after
// the first hour, the held set's residual statistic T/m (chi-square(m)/m under
// the model, AmbiguityFixSummary::held_residual_statistic) and the held narrow
// lanes' integer residuals (float - integer) per system (histogram), per single
// difference and per hour, and each system's held integers and reference.
//
// Usage:
//   ppp_ar_study --obs O --sp3 S --clk C --atx A [--atx A2] [--bia B] [--blq L] [--static]
//                [--ar key=value]... [--yaml TEXT] [--csv FILE] [--nl-csv FILE]
//   --bia B          Bias-SINEX OSB file (phase OSBs of the clocks' analysis centre)
//   --blq L          ocean loading BLQ file
//   --ar key=value   an ambiguity_resolution key for the AR run (config/ppp.yaml)
//   --yaml TEXT      further YAML for all three runs (not stochastic.position)
//   --static         the float and AR runs static as well (else kinematic)
//   --csv FILE       per epoch: time, fixed, E/N/U of AR and float [m], T, m, reason
//   --nl-csv FILE    per epoch and single difference: float, sigma, held integer
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/types/frames.h"

namespace {

using namespace ppp;

struct EpochOut {
  GnssTime time;
  std::optional<Eigen::Vector3d> position;
  bool fixed = false;
  std::optional<AmbiguityFixSummary> fix;
};

/// The EKF estimator recording each epoch's ambiguity summary.
std::vector<EpochOut> runEkf(const PppInputFiles& files, const std::string& yaml, const std::string& name) {
  const PppConfig config = parsePppConfig(yaml, name);
  PppPipeline pipeline(files, config);
  if (config.ambiguity_resolution.mode != AmbiguityResolutionMode::Off)  // the products' verdicts
    for (const auto& n : pipeline.notes())
      if (n.find("ambiguity resolution") != std::string::npos || n.find("antenna model") != std::string::npos ||
          n.rfind("systems:", 0) == 0 || n.rfind("satellite antennas:", 0) == 0)
        std::cout << name << ": " << n << "\n";
  // The systems and the AR switch the products decided.
  const std::unique_ptr<PppEstimator> ekf = makeEstimator("ekf", pipeline.config());
  std::vector<EpochOut> out;
  pipeline.run(*ekf, [&](const PppEpochRecord& r) {
    EpochOut e;
    e.time = r.solution.time;
    e.position = r.solution.position_ecef_m;
    e.fixed = r.solution.status == SolutionStatus::PppFixed;
    e.fix = r.ambiguity_fix;
    out.push_back(std::move(e));
  });
  return out;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto i = static_cast<std::size_t>(pos);
  const double f = pos - static_cast<double>(i);
  return i + 1 < v.size() ? v[i] * (1.0 - f) + v[i + 1] * f : v[i];
}

/// RMS of E/N/U about their mean [m].
Eigen::Vector3d rmsAboutMean(const std::vector<Eigen::Vector3d>& enu) {
  if (enu.empty()) return Eigen::Vector3d::Constant(std::nan(""));
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& e : enu) mean += e;
  mean /= static_cast<double>(enu.size());
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (const auto& e : enu) s += (e - mean).cwiseAbs2();
  return (s / static_cast<double>(enu.size())).cwiseSqrt();
}

int usage(const std::string& why) {
  std::cerr << "ppp_ar_study: " << why
            << "\nusage: ppp_ar_study --obs O --sp3 S --clk C --atx A [--atx A2] [--bia B] [--blq L] [--static]"
               " [--ar key=value]... [--yaml TEXT] [--csv FILE] [--nl-csv FILE]\n";
  return 2;
}

// The command line: input files, YAML for the runs, CSV outputs and the AR keys.
struct StudyArguments {
  PppInputFiles files;
  std::string extra_yaml, csv_path, nl_csv_path;
  std::vector<std::string> ar_keys;  // YAML lines under ambiguity_resolution
  bool static_runs = false;
};

// The YAML of the three runs: float static (reference), float and PPP-AR with the chosen dynamics.
struct StudyYaml {
  std::string reference, dynamics, ar;
};

// Mean and mean square of a set of residuals [cycles].
struct PairStats {
  int n = 0;
  double sum = 0.0, sum2 = 0.0;
};

// What the PPP-AR run's epochs add up to, against the reference and the float run.
struct StudyTallies {
  std::size_t solved = 0, after = 0, fixed_after = 0, wrong = 0, wrong_float_too = 0, wrong_float_good = 0,
              moved = 0, float_wrong = 0;
  std::optional<double> first_fix_s;
  std::optional<GnssTime> first_time;
  std::vector<Eigen::Vector3d> fixed_enu, float_enu;  // [m] about the reference
  std::vector<double> t_over_m;
  std::map<std::string, PairStats> per_pair;
  std::map<int, PairStats> per_hour;
  std::map<GnssSystem, std::array<int, 5>> bins;  // per system: |float - integer| in 0.1-cycle bins
  std::map<GnssSystem, std::size_t> fixed_epochs_with_system;  // fixed epochs (after 1 h) holding its integers
};

constexpr std::size_t kFirstHourEpochs = 120;  // solved epochs (30 s)

// Step 1: the arguments read; an exit code (2) on a usage error.
std::optional<int> parseStudyArguments(int argc, char** argv, StudyArguments& args) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](std::string& v) {
      if (i + 1 >= argc) return false;
      v = argv[++i];
      return true;
    };
    std::string v;
    if (a == "--static") {
      args.static_runs = true;
    } else if (a == "--obs" || a == "--sp3" || a == "--clk" || a == "--atx" || a == "--ar" || a == "--yaml" ||
               a == "--csv" || a == "--nl-csv" || a == "--bia" || a == "--blq") {
      if (!value(v)) return usage(a + " needs a value");
      if (a == "--obs") args.files.obs = v;
      if (a == "--sp3") args.files.sp3.push_back(v);
      if (a == "--clk") args.files.clk.push_back(v);
      if (a == "--atx") args.files.atx.push_back(v);
      if (a == "--bia") args.files.bias = v;
      if (a == "--blq") args.files.blq = v;
      if (a == "--yaml") args.extra_yaml = v + "\n";
      if (a == "--csv") args.csv_path = v;
      if (a == "--nl-csv") args.nl_csv_path = v;
      if (a == "--ar") {
        const auto eq = v.find('=');
        if (eq == std::string::npos) return usage("--ar needs key=value");
        args.ar_keys.push_back("  " + v.substr(0, eq) + ": " + v.substr(eq + 1) + "\n");
      }
    } else {
      return usage("unknown argument " + a);
    }
  }
  if (args.files.obs.empty() || args.files.sp3.empty() || args.files.clk.empty() || args.files.atx.empty())
    return usage("--obs, --sp3, --clk and --atx are required");
  return std::nullopt;
}

// Step 2: the YAML of the three runs.
StudyYaml studyYaml(const StudyArguments& args) {
  const std::string static_yaml = "stochastic:\n  position:\n    process_noise_m_per_sqrt_s: 0.0\n";
  StudyYaml yaml;
  yaml.reference = args.extra_yaml + static_yaml;
  yaml.dynamics = args.extra_yaml + (args.static_runs ? static_yaml : "");
  yaml.ar = yaml.dynamics + "ambiguity_resolution:\n  enabled: true\n";
  for (const auto& k : args.ar_keys) yaml.ar += k;
  return yaml;
}

// An epoch's time as a map key [ms].
long long epochKey_ms(const GnssTime& t) { return std::llround(t.toGpsSecondsDouble() * 1000.0); }

// The last solved position of a run [m, ECEF].
std::optional<Eigen::Vector3d> lastSolvedPosition_m(const std::vector<EpochOut>& run) {
  std::optional<Eigen::Vector3d> reference;
  for (const auto& e : run)
    if (e.position) reference = e.position;
  return reference;
}

// The solved epochs of a run by time [ms].
std::map<long long, const EpochOut*> solvedByTime_ms(const std::vector<EpochOut>& run) {
  std::map<long long, const EpochOut*> at;
  for (const auto& e : run)
    if (e.position) at[epochKey_ms(e.time)] = &e;
  return at;
}

// The per-epoch and per-narrow-lane CSV files opened with their headers, when asked for.
void openCsvFiles(const StudyArguments& args, std::ofstream& csv, std::ofstream& nl_csv) {
  if (!args.csv_path.empty()) {
    csv.open(args.csv_path);
    csv.precision(12);  // GPS seconds to the millisecond
    csv << "time_s,fixed,ar_e_m,ar_n_m,ar_u_m,float_e_m,float_n_m,float_u_m,held,T,m,reason\n";
  }
  if (!args.nl_csv_path.empty()) {
    nl_csv.open(args.nl_csv_path);
    nl_csv.precision(12);
    nl_csv << "time_s,satellite,reference,wide_lane,float_cycles,sigma_cycles,held_cycles\n";
  }
}

// An epoch's narrow lanes written to the CSV; the held ones after the first hour binned per system,
// single difference and hour of day [cycles].
void addNarrowLanes(const EpochOut& e, std::size_t index, double hour, std::ofstream& nl_csv, StudyTallies& t) {
  for (const auto& nl : e.fix->narrow_lanes) {
    if (nl_csv.is_open())
      nl_csv << e.time.toGpsSecondsDouble() << ',' << nl.satellite.toString() << ',' << nl.reference_satellite.toString()
             << ',' << nl.wide_lane_cycles << ',' << nl.float_cycles << ',' << nl.sigma_cycles << ','
             << (nl.held_cycles ? std::to_string(*nl.held_cycles) : std::string()) << '\n';
    if (!nl.held_cycles || index < kFirstHourEpochs) continue;
    const double r = nl.float_cycles - static_cast<double>(*nl.held_cycles);
    ++t.bins[nl.satellite.system][static_cast<std::size_t>(std::min(4, static_cast<int>(std::abs(r) * 10.0)))];
    PairStats& p = t.per_pair[nl.satellite.toString() + "-" + nl.reference_satellite.toString()];
    ++p.n, p.sum += r, p.sum2 += r * r;
    PairStats& h = t.per_hour[static_cast<int>(hour)];
    ++h.n, h.sum += std::abs(r), h.sum2 += r * r;
  }
}

// One CSV row: time, fixed, E/N/U of AR and float [m], held count, T, m and the fix summary.
void writeEpochRow(std::ofstream& csv, const EpochOut& e, const Eigen::Vector3d& enu,
                   const std::optional<Eigen::Vector3d>& float_enu_now) {
  csv << e.time.toGpsSecondsDouble() << ',' << (e.fixed ? 1 : 0) << ',' << enu.x() << ',' << enu.y() << ',' << enu.z();
  if (float_enu_now)
    csv << ',' << float_enu_now->x() << ',' << float_enu_now->y() << ',' << float_enu_now->z();
  else
    csv << ",,,";
  csv << ',' << (e.fix ? e.fix->held : 0) << ',' << (e.fix ? e.fix->held_residual_statistic : 0.0) << ','
      << (e.fix ? e.fix->held_residual_dof : 0) << ",\"" << (e.fix ? e.fix->text() : std::string()) << "\"\n";
}

// An epoch after the first hour counted: float and fixed positions [m] against the reference (10 cm)
// and each other (5 cm), the systems holding integers and the held set's T/m.
void tallyAfterFirstHour(const EpochOut& e, const Eigen::Vector3d& enu,
                         const std::optional<Eigen::Vector3d>& float_enu_now, StudyTallies& t) {
  ++t.after;
  if (float_enu_now) {
    t.float_enu.push_back(*float_enu_now);
    if (float_enu_now->norm() > 0.10) ++t.float_wrong;
  }
  if (!e.fixed) return;
  ++t.fixed_after;
  t.fixed_enu.push_back(enu);
  if (enu.norm() > 0.10) ++t.wrong;
  if (enu.norm() > 0.10 && float_enu_now && float_enu_now->norm() > 0.10) ++t.wrong_float_too;
  if (enu.norm() > 0.10 && float_enu_now && float_enu_now->norm() <= 0.10) ++t.wrong_float_good;
  if (e.fix)
    for (const SystemAmbiguitySummary& sys : e.fix->systems)
      if (sys.held > 0) ++t.fixed_epochs_with_system[sys.system];
  if (float_enu_now && (enu - *float_enu_now).norm() > 0.05) ++t.moved;
  if (e.fix && e.fix->held_residual_dof > 0)
    t.t_over_m.push_back(e.fix->held_residual_statistic / e.fix->held_residual_dof);
}

// Step 3 (per PPP-AR epoch): positions about the reference [m], narrow lanes, CSV rows and counts.
void tallyEpoch(const EpochOut& e, const Eigen::Vector3d& reference, const std::map<long long, const EpochOut*>& float_at,
                std::ofstream& csv, std::ofstream& nl_csv, StudyTallies& t) {
  if (!e.position) return;
  if (!t.first_time) t.first_time = e.time;
  const std::size_t index = t.solved++;
  const Eigen::Vector3d enu = ecefToEnu(*e.position, reference);
  const auto f = float_at.find(epochKey_ms(e.time));
  const std::optional<Eigen::Vector3d> float_enu_now =
      f == float_at.end() ? std::nullopt : std::optional<Eigen::Vector3d>(ecefToEnu(*f->second->position, reference));
  if (e.fixed && !t.first_fix_s) t.first_fix_s = e.time - *t.first_time;
  const double hour = std::fmod(e.time.toGpsSecondsDouble(), 86400.0) / 3600.0;
  if (e.fix) addNarrowLanes(e, index, hour, nl_csv, t);
  if (csv.is_open()) writeEpochRow(csv, e, enu, float_enu_now);
  if (index < kFirstHourEpochs) return;
  tallyAfterFirstHour(e, enu, float_enu_now, t);
}

// Step 4a: the reference, the float and the PPP-AR position figures, the systems holding integers.
void printPositionSummary(const Eigen::Vector3d& reference, const StudyTallies& t) {
  const Eigen::Vector3d rms_fixed = rmsAboutMean(t.fixed_enu), rms_float = rmsAboutMean(t.float_enu);
  char first_fix_buf[32] = "never";
  if (t.first_fix_s) std::snprintf(first_fix_buf, sizeof first_fix_buf, "%.1f", *t.first_fix_s / 60.0);
  const std::string first_fix_text = first_fix_buf;
  std::printf("reference (float static, last solved epoch) ECEF %.4f %.4f %.4f m\n", reference.x(), reference.y(),
              reference.z());
  std::printf("solved %zu epochs, after the first hour %zu\n", t.solved, t.after);
  std::printf("float: %zu epochs > 10 cm after the first hour; RMS E/N/U about the mean %.2f / %.2f / %.2f cm\n",
              t.float_wrong, 100 * rms_float.x(), 100 * rms_float.y(), 100 * rms_float.z());
  std::printf("PPP-AR: first fix %s min; fixed after the first hour %zu (%.1f %%); fixed > 10 cm: %zu (float too: %zu, "
              "float within 10 cm: %zu); moved > 5 cm from the float: %zu; fixed RMS E/N/U %.2f / %.2f / %.2f cm\n",
              first_fix_text.c_str(), t.fixed_after,
              t.after ? 100.0 * static_cast<double>(t.fixed_after) / static_cast<double>(t.after) : 0.0, t.wrong,
              t.wrong_float_too, t.wrong_float_good, t.moved, 100 * rms_fixed.x(), 100 * rms_fixed.y(),
              100 * rms_fixed.z());
  for (const auto& [system, n] : t.fixed_epochs_with_system)
    std::printf("  %s: integers held in %zu of the fixed epochs after the first hour\n",
                std::string(systemName(system)).c_str(), n);
}

// Step 4b: the held set's T/m quantiles and the held narrow lanes' residuals [cycles] per system,
// single difference and hour.
void printNarrowLaneSummary(const StudyTallies& t) {
  std::printf("held set T/m over the fixed epochs after the first hour: 10/50/90/99 %% = %.1f / %.1f / %.1f / %.1f\n",
              quantile(t.t_over_m, 0.10), quantile(t.t_over_m, 0.50), quantile(t.t_over_m, 0.90),
              quantile(t.t_over_m, 0.99));
  for (const auto& [system, b] : t.bins) {
    const int total = b[0] + b[1] + b[2] + b[3] + b[4];
    std::printf("held NL |float - integer| %s (after the first hour, %d values) 0-0.1 / 0.1-0.2 / 0.2-0.3 / 0.3-0.4 / "
                "0.4-0.5: %.1f / %.1f / %.1f / %.1f / %.1f %%\n",
                std::string(systemName(system)).c_str(), total, 100.0 * b[0] / std::max(1, total),
                100.0 * b[1] / std::max(1, total), 100.0 * b[2] / std::max(1, total),
                100.0 * b[3] / std::max(1, total), 100.0 * b[4] / std::max(1, total));
  }
  std::printf("per single difference (held epochs, mean / RMS of float - integer [cycles]):\n");
  for (const auto& [pair, p] : t.per_pair)
    if (p.n >= 20)
      std::printf("  %-8s n %5d mean %+.3f rms %.3f\n", pair.c_str(), p.n, p.sum / p.n, std::sqrt(p.sum2 / p.n));
  std::printf("per hour (mean |float - integer|, RMS [cycles]):\n");
  for (const auto& [h, p] : t.per_hour)
    std::printf("  %02d h n %5d mean|r| %.3f rms %.3f\n", h, p.n, p.sum / p.n, std::sqrt(p.sum2 / p.n));
}

}  // namespace

int main(int argc, char** argv) {
  StudyArguments args;
  if (const auto exit_code = parseStudyArguments(argc, argv, args)) return *exit_code;  // 1. arguments
  const StudyYaml yaml = studyYaml(args);                                                // 2. the runs' YAML
  try {
    const std::vector<EpochOut> reference_run = runEkf(args.files, yaml.reference, "float static");
    const std::vector<EpochOut> floats = runEkf(args.files, yaml.dynamics, "float");
    const std::vector<EpochOut> fixes = runEkf(args.files, yaml.ar, "PPP-AR");
    const std::optional<Eigen::Vector3d> reference = lastSolvedPosition_m(reference_run);
    if (!reference) return usage("the float static run solved no epoch");
    const std::map<long long, const EpochOut*> float_at = solvedByTime_ms(floats);
    std::ofstream csv, nl_csv;
    openCsvFiles(args, csv, nl_csv);
    StudyTallies tallies;
    for (const auto& e : fixes) tallyEpoch(e, *reference, float_at, csv, nl_csv, tallies);  // 3. each AR epoch
    printPositionSummary(*reference, tallies);                                               // 4. summary
    printNarrowLaneSummary(tallies);
  } catch (const std::exception& e) {
    std::cerr << "ppp_ar_study: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
