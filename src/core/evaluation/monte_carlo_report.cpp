// Outputs of the Monte Carlo study (monte_carlo.h): Markdown tables, JSON, CSV.
#include <algorithm>

#include "ppp_bayes_tree/evaluation/json_text.h"
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

std::string fmt(const char* printf_format, double v) {
  if (!std::isfinite(v)) return v > 0 ? "inf" : (v < 0 ? "-inf" : "nan");
  return format(printf_format, v);
}
std::string cm(double m) { return fmt("%.1f", 100.0 * m); }

/// JSON number (null for NaN/inf: JSON has neither).
std::string jsonSummary(const ErrorSummary& s) {
  return "{\"count\": " + std::to_string(s.count) + ", \"median_cm\": " + jsonNumber(100 * s.median_m, 10) +
         ", \"mean_cm\": " + jsonNumber(100 * s.mean_m, 10) + ", \"sigma_cm\": " + jsonNumber(100 * s.std_m, 10) +
         ", \"max_cm\": " + jsonNumber(100 * s.max_m, 10) + "}";
}
std::string jsonArray(const std::vector<double>& v) {
  std::string o = "[";
  for (std::size_t i = 0; i < v.size(); ++i) o += (i ? ", " : "") + jsonNumber(v[i], 10);
  return o + "]";
}

std::string profileList(const MonteCarloOptions& o) {
  std::string s;
  for (std::size_t i = 0; i < o.profiles.size(); ++i) s += (i ? "," : "") + std::string(flightProfileName(o.profiles[i]));
  return s;
}

void writeFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::string quantileCsv(const std::array<std::vector<QuantileBin>, kMonteCarloEstimators>& bins, const char* t_name) {
  // Union of the bin starts over the estimators.
  std::map<double, std::array<const QuantileBin*, kMonteCarloEstimators>> rows;
  for (int e = 0; e < kMonteCarloEstimators; ++e)
    for (const auto& b : bins[static_cast<std::size_t>(e)]) rows[b.t_s][static_cast<std::size_t>(e)] = &b;
  std::ostringstream o;
  o << t_name;
  for (int e = 0; e < kMonteCarloEstimators; ++e) {
    const std::string k = monteCarloEstimatorKey(e);
    o << ',' << k << "_count," << k << "_p05_m," << k << "_p50_m," << k << "_p95_m," << k << "_abs_p50_m," << k
      << "_abs_p90_m";
  }
  o << '\n';
  for (const auto& [t, r] : rows) {
    o << jsonNumber(t, 10);
    for (const QuantileBin* b : r) {
      if (b == nullptr) {
        o << ",0,,,,,";
      } else {
        o << ',' << b->count << ',' << jsonNumber(b->p05, 10) << ',' << jsonNumber(b->p50, 10) << ',' << jsonNumber(b->p95, 10) << ','
          << jsonNumber(b->abs_p50, 10) << ',' << jsonNumber(b->abs_p90, 10);
      }
    }
    o << '\n';
  }
  return o.str();
}

std::string systemsText(const MonteCarloOptions& o) {
  std::string t;
  for (GnssSystem sys : o.simulation.systems) t += systemLetter(sys);
  return t;
}

}  // namespace

std::string convergenceTimeText(double median_s, int never, int flights_compared) {
  if (std::isinf(median_s) && median_s > 0)
    return "never (" + std::to_string(never) + " of " + std::to_string(flights_compared) + " flights)";
  if (std::isnan(median_s)) return "no flights";
  return fmt("%.1f", median_s / 60.0) + " min (never: " + std::to_string(never) + ")";
}

std::string monteCarloMarkdown(const MonteCarloResult& r) {
  const MonteCarloSummary& s = r.summary;
  const MonteCarloOptions& o = r.options;
  std::ostringstream md;
  md << "# Monte Carlo: " << s.flights << " simulated flights\n\n";
  md << "Seed " << o.seed << ", " << fmt("%.1f", o.duration_s / 60.0) << " min at " << fmt("%g", o.rate_hz)
     << " Hz, profiles " << profileList(o) << ", systems " << systemsText(o) << ", ambiguity resolution "
     << (o.ppp.ambiguity_resolution.enabled ? "on" : "off") << "; " << s.failed << " failed. Wall time "
     << fmt("%.1f", r.wall_s) << " s on " << r.threads_used << " threads (per-flight sums: simulate "
     << fmt("%.1f", s.simulate_s) << " s";
  for (std::size_t i = 0; i < kMonteCarloStudy.size(); ++i)
    md << ", " << findEstimator(kMonteCarloStudy[i])->label << ' ' << fmt("%.1f", s.estimator_s[i]) << " s";
  md << ").\n\n";
  auto table = [&](const std::string& title, const std::array<ErrorSummary, kMonteCarloEstimators>& t) {
    md << "## " << title << "\n\n| estimator | epochs | median | mean | sigma | max |\n|---|---:|---:|---:|---:|---:|\n";
    for (int e = 0; e < kMonteCarloEstimators; ++e) {
      const ErrorSummary& x = t[static_cast<std::size_t>(e)];
      md << "| " << monteCarloEstimatorLabel(e) << " | " << x.count << " | " << cm(x.median_m) << " | "
         << cm(x.mean_m) << " | " << cm(x.std_m) << " | " << cm(x.max_m) << " |\n";
    }
    md << '\n';
  };
  md << "3D position error in cm.\n\n";
  table("All epochs of all flights", s.all);
  table("First " + fmt("%g", o.first_window_s / 60.0) + " minutes of each flight", s.first_window);
  table("After the first " + fmt("%g", o.first_window_s / 60.0) + " minutes (after convergence)", s.after_window);
  std::string rep = "Representative flight (none)";
  if (s.representative >= 0) {
    const auto& f = r.flights[static_cast<std::size_t>(s.representative)];
    rep = "Representative flight: #" + std::to_string(f.setup.index) + " (" + flightProfileName(f.setup.profile) +
          ", seed " + std::to_string(f.setup.seed) + "; the flight whose EKF mean is the median of the flights' EKF means)";
  }
  table(rep, s.representative_flight);

  md << "## Convergence: median over flights of the time after which the 3D error stays below a threshold\n\n"
        "| estimator |";
  for (double t : o.convergence_thresholds_m) md << " < " << cm(t) << " cm |";
  md << "\n|---|";
  for (std::size_t i = 0; i < o.convergence_thresholds_m.size(); ++i) md << "---:|";
  md << '\n';
  for (int e = 0; e < kMonteCarloEstimators; ++e) {
    const auto ei = static_cast<std::size_t>(e);
    md << "| " << monteCarloEstimatorLabel(e) << " |";
    for (std::size_t i = 0; i < o.convergence_thresholds_m.size(); ++i)
      md << ' ' << convergenceTimeText(s.convergence_median_s[ei][i], s.convergence_never[ei][i], s.flights - s.failed)
         << " |";
    md << '\n';
  }
  if (o.ppp.ambiguity_resolution.enabled) {
    md << "\n## Ambiguity resolution: fixed epochs, time to first fix, held integers against the truth\n\n"
          "Fixed share: fixed epochs / epochs with a solution. The smoothed solution is the smoother's graph "
          "after the last epoch, with the integers it holds then: its fix figures are the filtered run's. "
          "Held integers: distinct held single differences compared with the simulator's integers (cross-system: "
          "between satellites of two systems); wrong: wide lane off, or narrow lane more than "
       << fmt("%g", kWrongHoldThresholdCycles)
       << " cycle from the truth.\n\n"
          "| estimator | fixed share | median time to first fix | held integers (cross-system) | wrong | "
          "fixed epochs holding a wrong integer | max abs(held - truth) [cycles] |\n|---|---:|---:|---:|---:|---:|---:|\n";
    for (int e = 0; e < kMonteCarloEstimators; ++e) {
      const std::size_t i = e == 0 ? 0 : 1;  // the smoothed solution has the filtered run's fixes
      const HeldIntegerCheck& h = s.held_check[i];
      md << "| " << monteCarloEstimatorLabel(e) << " | " << fmt("%.1f %%", 100.0 * s.fixed_share[i]) << " | "
         << convergenceTimeText(s.first_fix_median_s[i], s.never_fixed[i], s.flights - s.failed) << " | " << h.held
         << " (" << h.cross_system << ") | " << h.wrong << " | " << h.fixed_epochs_with_wrong_hold << " of "
         << h.fixed_epochs << " | " << fmt("%.3f", h.max_abs_error_cycles) << " |\n";
    }
  }
  md << "\n## Phase-bias error |estimate - truth| by arc age (median / 90th percentile, cm)\n\n"
     << "Arcs compared: " << s.bias_arcs_compared << " (of which " << s.bias_arcs_missed_slip
     << " ran into another simulated arc: compared up to it).\n\n| age |";
  for (int e = 0; e < kMonteCarloEstimators; ++e) md << ' ' << monteCarloEstimatorLabel(e) << " |";
  md << "\n|---:|---:|---:|---:|\n";
  for (double age : {0.0, 60.0, 300.0, 600.0, 900.0, 1200.0, 1790.0}) {
    bool any = false;
    std::string row = "| " + fmt("%.0f", age) + " s |";
    for (int e = 0; e < kMonteCarloEstimators; ++e) {
      const QuantileBin* hit = nullptr;
      for (const auto& b : s.bias_vs_age[static_cast<std::size_t>(e)])
        if (b.t_s <= age + 1e-9 && age < b.t_s + o.bias_bin_s) hit = &b;
      row += hit ? " " + cm(hit->abs_p50) + " / " + cm(hit->abs_p90) + " |" : " - |";
      any |= hit != nullptr;
    }
    if (any) md << row << '\n';
  }
  md << "\n## Smoother filtered vs EKF: |x_EKF - x_filtered| over all epochs (same models and noise)\n\n"
     << "median " << cm(s.filtered_minus_ekf.median_m) << " cm, mean " << cm(s.filtered_minus_ekf.mean_m)
     << " cm, max " << cm(s.filtered_minus_ekf.max_m) << " cm over " << s.filtered_minus_ekf.count << " epochs.\n";
  md << "\nEpochs without a solution:";
  for (int e = 0; e < kMonteCarloEstimators; ++e)
    md << ' ' << monteCarloEstimatorLabel(e) << ' ' << s.epochs_without_solution[static_cast<std::size_t>(e)]
       << (e + 1 < kMonteCarloEstimators ? "," : ".\n");
  for (const auto& f : s.failures) md << "\n- failed: " << f;
  return md.str();
}

std::string monteCarloComparisonMarkdown(const std::vector<std::pair<std::string, MonteCarloResult>>& studies) {
  std::ostringstream md;
  md << "# Monte Carlo: float and PPP-AR, the same flights\n\n";
  if (!studies.empty()) {
    const MonteCarloOptions& o = studies.front().second.options;
    md << studies.front().second.summary.flights << " flights of " << fmt("%.1f", o.duration_s / 60.0) << " min at "
       << fmt("%g", o.rate_hz) << " Hz, seed " << o.seed << ", profiles " << profileList(o)
       << ". 3D error in cm over the first " << fmt("%g", o.first_window_s / 60.0)
       << " min of each flight; time to 10 cm: median over flights of the time after which the error stays "
          "below 10 cm. Fix figures of the smoothed solution: the filtered run's (the same graph).\n\n";
  }
  md << "| configuration | estimator | first-window median | first-window mean | time to < 10 cm | fixed share | "
        "median time to first fix | wrong holds / held |\n|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& [name, r] : studies) {
    const MonteCarloSummary& s = r.summary;
    const auto& thresholds = r.options.convergence_thresholds_m;
    const auto ten = std::find_if(thresholds.begin(), thresholds.end(), [](double t) { return std::abs(t - 0.1) < 1e-9; });
    const bool ar = r.options.ppp.ambiguity_resolution.enabled;
    for (int e = 0; e < kMonteCarloEstimators; ++e) {
      const auto ei = static_cast<std::size_t>(e);
      const std::size_t fi = e == 0 ? 0 : 1;
      md << "| " << name << " | " << monteCarloEstimatorLabel(e) << " | " << cm(s.first_window[ei].median_m) << " | "
         << cm(s.first_window[ei].mean_m) << " | ";
      if (ten != thresholds.end()) {
        const auto ti = static_cast<std::size_t>(ten - thresholds.begin());
        md << convergenceTimeText(s.convergence_median_s[ei][ti], s.convergence_never[ei][ti], s.flights - s.failed);
      } else {
        md << "-";
      }
      if (ar) {
        md << " | " << fmt("%.1f %%", 100.0 * s.fixed_share[fi]) << " | "
           << convergenceTimeText(s.first_fix_median_s[fi], s.never_fixed[fi], s.flights - s.failed) << " | "
           << s.held_check[fi].wrong << " / " << s.held_check[fi].held << " |\n";
      } else {
        md << " | - | - | - |\n";
      }
    }
  }
  for (const MethodTableRow& m : kMethodTable3)
    md << "| the method's Table 3 | " << m.estimator << " | " << fmt("%.2f", m.first_window_median_cm) << " | "
       << fmt("%.2f", m.first_window_mean_cm) << " | - | - | - | - |\n";
  return md.str();
}

std::string monteCarloJson(const MonteCarloResult& r) {
  const MonteCarloSummary& s = r.summary;
  const MonteCarloOptions& o = r.options;
  std::ostringstream j;
  j << "{\n  \"flights\": " << s.flights << ", \"failed\": " << s.failed << ", \"seed\": " << o.seed
    << ", \"duration_s\": " << jsonNumber(o.duration_s, 10) << ", \"rate_hz\": " << jsonNumber(o.rate_hz, 10)
    << ", \"profiles\": " << jsonString(profileList(o)) << ", \"first_window_s\": " << jsonNumber(o.first_window_s, 10)
    << ",\n  \"threads\": " << r.threads_used << ", \"wall_s\": " << jsonNumber(r.wall_s, 10)
    << ", \"simulate_s\": " << jsonNumber(s.simulate_s, 10);
  for (std::size_t i = 0; i < kMonteCarloStudy.size(); ++i)
    j << ", \"" << kMonteCarloStudy[i] << "_s\": " << jsonNumber(s.estimator_s[i], 10);
  j << ",\n  \"estimators\": [";
  for (int e = 0; e < kMonteCarloEstimators; ++e) j << (e ? ", " : "") << jsonString(monteCarloEstimatorKey(e));
  j << "],\n  \"representative_flight\": " << s.representative;
  if (s.representative >= 0) {
    const auto& f = r.flights[static_cast<std::size_t>(s.representative)];
    j << ", \"representative_profile\": " << jsonString(flightProfileName(f.setup.profile))
      << ", \"representative_seed\": " << f.setup.seed;
  }
  j << ",\n  \"representative_definition\": "
    << jsonString("the flight whose EKF mean 3D error is the median of the flights' EKF means (lower middle for an even count)");
  auto tables = [&](const char* name, const std::array<ErrorSummary, kMonteCarloEstimators>& t) {
    j << ",\n  " << jsonString(name) << ": {";
    for (int e = 0; e < kMonteCarloEstimators; ++e)
      j << (e ? ", " : "") << jsonString(monteCarloEstimatorKey(e)) << ": " << jsonSummary(t[static_cast<std::size_t>(e)]);
    j << "}";
  };
  tables("all_epochs", s.all);
  tables("first_window", s.first_window);
  tables("after_window", s.after_window);
  tables("representative", s.representative_flight);
  j << ",\n  \"filtered_minus_ekf\": " << jsonSummary(s.filtered_minus_ekf);
  j << ",\n  \"convergence_thresholds_m\": " << jsonArray(o.convergence_thresholds_m) << ",\n  \"convergence\": {";
  for (int e = 0; e < kMonteCarloEstimators; ++e) {
    const auto ei = static_cast<std::size_t>(e);
    std::vector<double> never(s.convergence_never[ei].begin(), s.convergence_never[ei].end());
    j << (e ? ", " : "") << jsonString(monteCarloEstimatorKey(e)) << ": {\"median_s\": " << jsonArray(s.convergence_median_s[ei])
      << ", \"never\": " << jsonArray(never) << "}";
  }
  j << "}";
  if (o.ppp.ambiguity_resolution.enabled) {  // fixed share and time to first fix (EKF, smoother)
    j << ",\n  \"ambiguity_resolution\": {";
    for (std::size_t e = 0; e < 2; ++e)
      j << (e ? ", " : "") << jsonString(kMonteCarloStudy[e]) << ": {\"fixed_share\": "
        << jsonNumber(s.fixed_share[e], 10) << ", \"first_fix_median_s\": " << jsonNumber(s.first_fix_median_s[e], 10)
        << ", \"never_fixed\": " << s.never_fixed[e] << ", \"held_integers\": " << s.held_check[e].held
        << ", \"held_cross_system\": " << s.held_check[e].cross_system << ", \"wrong_holds\": " << s.held_check[e].wrong
        << ", \"holds_not_compared\": " << s.held_check[e].not_compared
        << ", \"fixed_epochs\": " << s.held_check[e].fixed_epochs
        << ", \"fixed_epochs_with_wrong_hold\": " << s.held_check[e].fixed_epochs_with_wrong_hold
        << ", \"max_abs_hold_error_cycles\": " << jsonNumber(s.held_check[e].max_abs_error_cycles, 10) << "}";
    j << "}";
  }
  j << ",\n  \"epochs_without_solution\": {";
  for (int e = 0; e < kMonteCarloEstimators; ++e)
    j << (e ? ", " : "") << jsonString(monteCarloEstimatorKey(e)) << ": " << s.epochs_without_solution[static_cast<std::size_t>(e)];
  j << "},\n  \"bias_arcs_compared\": " << s.bias_arcs_compared
    << ", \"bias_arcs_missed_slip\": " << s.bias_arcs_missed_slip << ",\n  \"failures\": [";
  for (std::size_t i = 0; i < s.failures.size(); ++i) j << (i ? ", " : "") << jsonString(s.failures[i]);
  j << "],\n  \"flight_table\": [";
  for (std::size_t i = 0; i < r.flights.size(); ++i) {
    const auto& f = r.flights[i];
    j << (i ? "," : "") << "\n    {\"index\": " << f.setup.index << ", \"seed\": " << f.setup.seed
      << ", \"profile\": " << jsonString(flightProfileName(f.setup.profile)) << ", \"failed\": " << (f.failure.empty() ? "false" : "true")
      << ", \"epochs\": " << f.epochs << ", \"simulated_arcs\": " << f.simulated_arcs
      << ", \"phase_breaks\": " << f.phase_breaks << ", \"estimator_arcs\": " << f.estimator_arcs
      << ", \"slips_detected\": " << f.slips_detected;
    for (int e = 0; e < kMonteCarloEstimators; ++e)
      j << ", " << jsonString(std::string(monteCarloEstimatorKey(e)) + "_mean_cm") << ": " << jsonNumber(100 * f.summary(e).mean_m, 10);
    j << "}";
  }
  j << "\n  ]\n}\n";
  return j.str();
}

void writeMonteCarloOutputs(const MonteCarloResult& r, const std::string& dir) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  const fs::path d(dir);
  const MonteCarloSummary& s = r.summary;
  writeFile(d / "summary.md", monteCarloMarkdown(r));
  writeFile(d / "summary.json", monteCarloJson(r));

  std::ostringstream flights;
  flights << "index,seed,profile,start_gpst,latitude_deg,longitude_deg,height_m,epochs,simulated_arcs,phase_breaks,"
             "estimator_arcs,slips_detected,failed";
  for (int e = 0; e < kMonteCarloEstimators; ++e) {
    const std::string k = monteCarloEstimatorKey(e);
    flights << ',' << k << "_mean_cm," << k << "_median_cm," << k << "_max_cm," << k << "_first_window_mean_cm";
  }
  flights << ",filtered_minus_ekf_max_cm";
  for (const std::string_view name : kMonteCarloStudy) flights << ',' << name << "_held_integers," << name << "_wrong_holds";
  flights << ",simulate_s";
  for (const std::string_view name : kMonteCarloStudy) flights << ',' << name << "_s";
  flights << ",drawn\n";
  for (const auto& f : r.flights) {
    flights << f.setup.index << ',' << f.setup.seed << ',' << flightProfileName(f.setup.profile) << ','
            << f.setup.start.toString() << ',' << jsonNumber(f.setup.origin.latitude_rad * kRadToDeg, 10) << ','
            << jsonNumber(f.setup.origin.longitude_rad * kRadToDeg, 10) << ',' << jsonNumber(f.setup.origin.height_m, 10) << ','
            << f.epochs << ',' << f.simulated_arcs << ',' << f.phase_breaks << ',' << f.estimator_arcs << ','
            << f.slips_detected << ',' << (f.failure.empty() ? 0 : 1);
    for (int e = 0; e < kMonteCarloEstimators; ++e) {
      const ErrorSummary a = f.summary(e), w = f.summary(e, r.options.first_window_s);
      flights << ',' << jsonNumber(100 * a.mean_m, 10) << ',' << jsonNumber(100 * a.median_m, 10) << ',' << jsonNumber(100 * a.max_m, 10) << ','
              << jsonNumber(100 * w.mean_m, 10);
    }
    double diff_max = 0.0;
    for (double v : f.filtered_minus_ekf_m)
      if (std::isfinite(v)) diff_max = std::max(diff_max, v);
    flights << ',' << jsonNumber(100 * diff_max, 10);
    for (const HeldIntegerCheck& h : f.held_check) flights << ',' << h.held << ',' << h.wrong;
    std::string drawn;
    for (const auto& x : f.drawn) drawn += (drawn.empty() ? "" : "; ") + x;
    for (char& c : drawn)
      if (c == '"' || c == ',') c = (c == ',' ? ';' : '\'');
    flights << ',' << jsonNumber(f.simulate_s, 10);
    for (double t : f.estimator_s) flights << ',' << jsonNumber(t, 10);
    flights << ",\"" << drawn << "\"\n";
  }
  writeFile(d / "flights.csv", flights.str());

  std::ostringstream rep;
  rep << "time_s";
  for (int e = 0; e < kMonteCarloEstimators; ++e) rep << ',' << monteCarloEstimatorKey(e) << "_3d_m";
  rep << '\n';
  if (s.representative >= 0) {
    const auto& f = r.flights[static_cast<std::size_t>(s.representative)];
    for (std::size_t k = 0; k < f.time_s.size(); ++k) {
      rep << jsonNumber(f.time_s[k], 10);
      for (int e = 0; e < kMonteCarloEstimators; ++e) {
        const double v = f.error_3d_m[static_cast<std::size_t>(e)][k];
        rep << ',' << (std::isfinite(v) ? jsonNumber(v, 10) : "");
      }
      rep << '\n';
    }
  }
  writeFile(d / "representative_flight.csv", rep.str());
  writeFile(d / "error_vs_time.csv", quantileCsv(s.error_vs_time, "time_s"));
  writeFile(d / "bias_convergence.csv", quantileCsv(s.bias_vs_age, "age_s"));
  std::ostringstream diff;
  diff << "time_s,count,p50_m,p95_m,p90_m\n";
  for (const auto& b : s.filtered_minus_ekf_vs_time)
    diff << jsonNumber(b.t_s, 10) << ',' << b.count << ',' << jsonNumber(b.p50, 10) << ',' << jsonNumber(b.p95, 10) << ',' << jsonNumber(b.abs_p90, 10) << '\n';
  writeFile(d / "filtered_minus_ekf.csv", diff.str());

  std::ostringstream cdf;
  cdf << "fraction";
  for (int e = 0; e < kMonteCarloEstimators; ++e)
    cdf << ',' << monteCarloEstimatorKey(e) << "_all_m," << monteCarloEstimatorKey(e) << "_first_window_m";
  cdf << '\n';
  for (std::size_t i = 0; i < s.cdf_levels.size(); ++i) {
    cdf << jsonNumber(s.cdf_levels[i], 10);
    for (int e = 0; e < kMonteCarloEstimators; ++e) {
      const auto ei = static_cast<std::size_t>(e);
      cdf << ',' << (i < s.cdf_all_m[ei].size() ? jsonNumber(s.cdf_all_m[ei][i], 10) : "") << ','
          << (i < s.cdf_first_window_m[ei].size() ? jsonNumber(s.cdf_first_window_m[ei][i], 10) : "");
    }
    cdf << '\n';
  }
  writeFile(d / "error_cdf.csv", cdf.str());
}

}  // namespace ppp
