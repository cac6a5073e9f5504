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

}  // namespace

int main(int argc, char** argv) {
  PppInputFiles files;
  std::string extra_yaml, csv_path, nl_csv_path;
  std::vector<std::string> ar_keys;
  bool static_runs = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](std::string& v) {
      if (i + 1 >= argc) return false;
      v = argv[++i];
      return true;
    };
    std::string v;
    if (a == "--static") {
      static_runs = true;
    } else if (a == "--obs" || a == "--sp3" || a == "--clk" || a == "--atx" || a == "--ar" || a == "--yaml" ||
               a == "--csv" || a == "--nl-csv" || a == "--bia" || a == "--blq") {
      if (!value(v)) return usage(a + " needs a value");
      if (a == "--obs") files.obs = v;
      if (a == "--sp3") files.sp3.push_back(v);
      if (a == "--clk") files.clk.push_back(v);
      if (a == "--atx") files.atx.push_back(v);
      if (a == "--bia") files.bias = v;
      if (a == "--blq") files.blq = v;
      if (a == "--yaml") extra_yaml = v + "\n";
      if (a == "--csv") csv_path = v;
      if (a == "--nl-csv") nl_csv_path = v;
      if (a == "--ar") {
        const auto eq = v.find('=');
        if (eq == std::string::npos) return usage("--ar needs key=value");
        ar_keys.push_back("  " + v.substr(0, eq) + ": " + v.substr(eq + 1) + "\n");
      }
    } else {
      return usage("unknown argument " + a);
    }
  }
  if (files.obs.empty() || files.sp3.empty() || files.clk.empty() || files.atx.empty())
    return usage("--obs, --sp3, --clk and --atx are required");
  const std::string static_yaml = "stochastic:\n  position:\n    process_noise_m_per_sqrt_s: 0.0\n";
  const std::string dyn_yaml = extra_yaml + (static_runs ? static_yaml : "");
  std::string ar_yaml = dyn_yaml + "ambiguity_resolution:\n  enabled: true\n";
  for (const auto& k : ar_keys) ar_yaml += k;
  try {
    const std::vector<EpochOut> reference_run = runEkf(files, extra_yaml + static_yaml, "float static");
    const std::vector<EpochOut> floats = runEkf(files, dyn_yaml, "float");
    const std::vector<EpochOut> fixes = runEkf(files, ar_yaml, "PPP-AR");
    std::optional<Eigen::Vector3d> reference;
    for (const auto& e : reference_run)
      if (e.position) reference = e.position;
    if (!reference) return usage("the float static run solved no epoch");
    std::map<long long, const EpochOut*> float_at;  // by time [ms]
    auto key = [](const GnssTime& t) { return std::llround(t.toGpsSecondsDouble() * 1000.0); };
    for (const auto& e : floats)
      if (e.position) float_at[key(e.time)] = &e;

    std::ofstream csv, nl_csv;
    if (!csv_path.empty()) {
      csv.open(csv_path);
      csv.precision(12);  // GPS seconds to the millisecond
      csv << "time_s,fixed,ar_e_m,ar_n_m,ar_u_m,float_e_m,float_n_m,float_u_m,held,T,m,reason\n";
    }
    if (!nl_csv_path.empty()) {
      nl_csv.open(nl_csv_path);
      nl_csv.precision(12);
      nl_csv << "time_s,satellite,reference,wide_lane,float_cycles,sigma_cycles,held_cycles\n";
    }
    const std::size_t first_hour = 120;  // solved epochs (30 s)
    std::size_t solved = 0, after = 0, fixed_after = 0, wrong = 0, wrong_float_too = 0, wrong_float_good = 0, moved = 0,
                float_wrong = 0;
    std::optional<double> first_fix_s;
    std::optional<GnssTime> first_time;
    std::vector<Eigen::Vector3d> fixed_enu, float_enu;
    std::vector<double> t_over_m;
    struct PairStats {
      int n = 0;
      double sum = 0.0, sum2 = 0.0;
    };
    std::map<std::string, PairStats> per_pair;
    std::map<int, PairStats> per_hour;
    std::map<GnssSystem, std::array<int, 5>> bins;  // per system: |float - integer| in 0.1-cycle bins
    std::map<GnssSystem, std::size_t> fixed_epochs_with_system;  // fixed epochs (after 1 h) holding its integers
    for (const auto& e : fixes) {
      if (!e.position) continue;
      if (!first_time) first_time = e.time;
      const std::size_t index = solved++;
      const Eigen::Vector3d enu = ecefToEnu(*e.position, *reference);
      const auto f = float_at.find(key(e.time));
      const std::optional<Eigen::Vector3d> float_enu_now =
          f == float_at.end() ? std::nullopt : std::optional<Eigen::Vector3d>(ecefToEnu(*f->second->position, *reference));
      if (e.fixed && !first_fix_s) first_fix_s = e.time - *first_time;
      const double hour = std::fmod(e.time.toGpsSecondsDouble(), 86400.0) / 3600.0;
      if (e.fix) {
        for (const auto& nl : e.fix->narrow_lanes) {
          if (nl_csv.is_open())
            nl_csv << e.time.toGpsSecondsDouble() << ',' << nl.satellite.toString() << ',' << nl.reference_satellite.toString()
                   << ',' << nl.wide_lane_cycles << ',' << nl.float_cycles << ',' << nl.sigma_cycles << ','
                   << (nl.held_cycles ? std::to_string(*nl.held_cycles) : std::string()) << '\n';
          if (!nl.held_cycles || index < first_hour) continue;
          const double r = nl.float_cycles - static_cast<double>(*nl.held_cycles);
          ++bins[nl.satellite.system][static_cast<std::size_t>(std::min(4, static_cast<int>(std::abs(r) * 10.0)))];
          PairStats& p = per_pair[nl.satellite.toString() + "-" + nl.reference_satellite.toString()];
          ++p.n, p.sum += r, p.sum2 += r * r;
          PairStats& h = per_hour[static_cast<int>(hour)];
          ++h.n, h.sum += std::abs(r), h.sum2 += r * r;
        }
      }
      if (csv.is_open()) {
        csv << e.time.toGpsSecondsDouble() << ',' << (e.fixed ? 1 : 0) << ',' << enu.x() << ',' << enu.y() << ',' << enu.z();
        if (float_enu_now)
          csv << ',' << float_enu_now->x() << ',' << float_enu_now->y() << ',' << float_enu_now->z();
        else
          csv << ",,,";
        csv << ',' << (e.fix ? e.fix->held : 0) << ',' << (e.fix ? e.fix->held_residual_statistic : 0.0) << ','
            << (e.fix ? e.fix->held_residual_dof : 0) << ",\"" << (e.fix ? e.fix->text() : std::string()) << "\"\n";
      }
      if (index < first_hour) continue;
      ++after;
      if (float_enu_now) {
        float_enu.push_back(*float_enu_now);
        if (float_enu_now->norm() > 0.10) ++float_wrong;
      }
      if (!e.fixed) continue;
      ++fixed_after;
      fixed_enu.push_back(enu);
      if (enu.norm() > 0.10) ++wrong;
      if (enu.norm() > 0.10 && float_enu_now && float_enu_now->norm() > 0.10) ++wrong_float_too;
      if (enu.norm() > 0.10 && float_enu_now && float_enu_now->norm() <= 0.10) ++wrong_float_good;
      if (e.fix)
        for (const SystemAmbiguitySummary& sys : e.fix->systems)
          if (sys.held > 0) ++fixed_epochs_with_system[sys.system];
      if (float_enu_now && (enu - *float_enu_now).norm() > 0.05) ++moved;
      if (e.fix && e.fix->held_residual_dof > 0)
        t_over_m.push_back(e.fix->held_residual_statistic / e.fix->held_residual_dof);
    }
    const Eigen::Vector3d rms_fixed = rmsAboutMean(fixed_enu), rms_float = rmsAboutMean(float_enu);
    char first_fix_buf[32] = "never";
    if (first_fix_s) std::snprintf(first_fix_buf, sizeof first_fix_buf, "%.1f", *first_fix_s / 60.0);
    const std::string first_fix_text = first_fix_buf;
    std::printf("reference (float static, last solved epoch) ECEF %.4f %.4f %.4f m\n", reference->x(), reference->y(),
                reference->z());
    std::printf("solved %zu epochs, after the first hour %zu\n", solved, after);
    std::printf("float: %zu epochs > 10 cm after the first hour; RMS E/N/U about the mean %.2f / %.2f / %.2f cm\n",
                float_wrong, 100 * rms_float.x(), 100 * rms_float.y(), 100 * rms_float.z());
    std::printf("PPP-AR: first fix %s min; fixed after the first hour %zu (%.1f %%); fixed > 10 cm: %zu (float too: %zu, "
                "float within 10 cm: %zu); moved > 5 cm from the float: %zu; fixed RMS E/N/U %.2f / %.2f / %.2f cm\n",
                first_fix_text.c_str(), fixed_after,
                after ? 100.0 * static_cast<double>(fixed_after) / static_cast<double>(after) : 0.0, wrong, wrong_float_too,
                wrong_float_good, moved, 100 * rms_fixed.x(), 100 * rms_fixed.y(), 100 * rms_fixed.z());
    for (const auto& [system, n] : fixed_epochs_with_system)
      std::printf("  %s: integers held in %zu of the fixed epochs after the first hour\n",
                  std::string(systemName(system)).c_str(), n);
    std::printf("held set T/m over the fixed epochs after the first hour: 10/50/90/99 %% = %.1f / %.1f / %.1f / %.1f\n",
                quantile(t_over_m, 0.10), quantile(t_over_m, 0.50), quantile(t_over_m, 0.90),
                quantile(t_over_m, 0.99));
    for (const auto& [system, b] : bins) {
      const int total = b[0] + b[1] + b[2] + b[3] + b[4];
      std::printf("held NL |float - integer| %s (after the first hour, %d values) 0-0.1 / 0.1-0.2 / 0.2-0.3 / 0.3-0.4 / "
                  "0.4-0.5: %.1f / %.1f / %.1f / %.1f / %.1f %%\n",
                  std::string(systemName(system)).c_str(), total, 100.0 * b[0] / std::max(1, total),
                  100.0 * b[1] / std::max(1, total), 100.0 * b[2] / std::max(1, total),
                  100.0 * b[3] / std::max(1, total), 100.0 * b[4] / std::max(1, total));
    }
    std::printf("per single difference (held epochs, mean / RMS of float - integer [cycles]):\n");
    for (const auto& [pair, p] : per_pair)
      if (p.n >= 20)
        std::printf("  %-8s n %5d mean %+.3f rms %.3f\n", pair.c_str(), p.n, p.sum / p.n, std::sqrt(p.sum2 / p.n));
    std::printf("per hour (mean |float - integer|, RMS [cycles]):\n");
    for (const auto& [h, p] : per_hour)
      std::printf("  %02d h n %5d mean|r| %.3f rms %.3f\n", h, p.n, p.sum / p.n, std::sqrt(p.sum2 / p.n));
  } catch (const std::exception& e) {
    std::cerr << "ppp_ar_study: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
