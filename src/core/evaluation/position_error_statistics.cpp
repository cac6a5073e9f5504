#include "ppp_bayes_tree/evaluation/position_error_statistics.h"

#include "ppp_bayes_tree/evaluation/json_text.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string minutes(const std::optional<double>& t_s) { return t_s ? format("%.1f", *t_s / 60.0) : "never"; }

}  // namespace

ErrorSummary summarizeErrors(std::vector<double> v) {
  ErrorSummary s;
  s.count = v.size();
  if (v.empty()) {
    s.median_m = s.mean_m = s.std_m = s.max_m = kNaN;
    return s;
  }
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  s.median_m = n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  s.mean_m = std::accumulate(v.begin(), v.end(), 0.0) / n;
  double ss = 0.0;
  for (double x : v) ss += (x - s.mean_m) * (x - s.mean_m);
  s.std_m = std::sqrt(ss / n);  // population standard deviation (Python statistics.pstdev)
  s.max_m = v.back();
  return s;
}

std::optional<double> convergenceTime_s(const std::vector<double>& time_s, const std::vector<double>& error_m,
                                        double threshold_m) {
  std::optional<std::size_t> last_bad;
  for (std::size_t i = 0; i < error_m.size(); ++i)
    if (!(error_m[i] < threshold_m)) last_bad = i;
  if (!last_bad) return 0.0;
  if (*last_bad + 1 >= time_s.size()) return std::nullopt;
  return time_s[*last_bad + 1];
}

double PositionErrorStatistics::percentile_m(double fraction) const {
  if (cdf.empty()) return kNaN;
  const double rank = std::ceil(std::clamp(fraction, 0.0, 1.0) * cdf.size());
  const auto k = static_cast<std::size_t>(std::max(rank, 1.0)) - 1;
  return cdf[std::min(k, cdf.size() - 1)].first;
}

PositionErrorStatistics computePositionErrorStatistics(const std::vector<SolutionEpoch>& solution,
                                                       const Eigen::Vector3d& truth_ecef_m,
                                                       const StatisticsOptions& options) {
  return computePositionErrorStatistics(solution, std::vector<Eigen::Vector3d>(solution.size(), truth_ecef_m),
                                        options);
}

PositionErrorStatistics computePositionErrorStatistics(const std::vector<SolutionEpoch>& solution,
                                                       const std::vector<Eigen::Vector3d>& truth_ecef_m,
                                                       const StatisticsOptions& options) {
  if (truth_ecef_m.size() != solution.size())
    throw std::invalid_argument("computePositionErrorStatistics: " + std::to_string(truth_ecef_m.size()) +
                                " truth positions for " + std::to_string(solution.size()) + " epochs");
  PositionErrorStatistics st;
  st.options = options;
  std::optional<GnssTime> t0;
  std::vector<Eigen::Vector3d> enu;
  for (std::size_t i = 0; i < solution.size(); ++i) {
    const SolutionEpoch& e = solution[i];
    if (!e.position_ecef_m) {
      ++st.epochs_without_solution;
      continue;
    }
    if (!t0) t0 = e.time;
    st.time_s.push_back(e.time - *t0);
    st.error_3d_m.push_back((*e.position_ecef_m - truth_ecef_m[i]).norm());
    enu.push_back(ecefToEnu(*e.position_ecef_m, truth_ecef_m[i]));
  }
  st.epochs = st.error_3d_m.size();
  st.all = summarizeErrors(st.error_3d_m);
  std::vector<double> early;
  for (std::size_t i = 0; i < st.epochs; ++i)
    if (st.time_s[i] < options.convergence_window_s) early.push_back(st.error_3d_m[i]);
  st.first_window = summarizeErrors(early);
  for (double thr : options.convergence_thresholds_m)
    st.convergence.push_back({thr, st.epochs ? convergenceTime_s(st.time_s, st.error_3d_m, thr) : std::nullopt});
  if (st.epochs == 0) {
    st.final_error_m = kNaN;
    st.tail_enu_rms_m.setConstant(kNaN);
    return st;
  }
  st.span_s = st.time_s.back();
  st.final_error_m = st.error_3d_m.back();
  Eigen::Vector3d ss = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < st.epochs; ++i) {
    if (st.time_s[i] < st.span_s - options.tail_window_s) continue;
    ss += enu[i].cwiseAbs2();
    ++st.tail_epochs;
  }
  st.tail_enu_rms_m = (ss / static_cast<double>(st.tail_epochs)).cwiseSqrt();
  std::vector<double> sorted = st.error_3d_m;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t k = 0; k < sorted.size(); ++k)
    st.cdf.emplace_back(sorted[k], static_cast<double>(k + 1) / sorted.size());
  return st;
}

std::string formatStatisticsComparison(
    const std::vector<std::pair<std::string, PositionErrorStatistics>>& columns) {
  std::ostringstream os;
  int width = 12;  // widened to the longest label ("smoother filtered")
  for (const auto& c : columns) width = std::max(width, static_cast<int>(std::min<std::size_t>(c.first.size(), 40)));
  auto row = [&](const std::string& name, auto cell) {
    os << format("%-30s", name.c_str());
    for (const auto& [label, st] : columns) os << format(" %*s", width, cell(st).substr(0, 40).c_str());
    os << "\n";
  };
  auto cm = [](double m) { return std::isfinite(m) ? format("%.2f", m * 100.0) : std::string("-"); };
  row("", [&](const PositionErrorStatistics& st) {
    for (const auto& c : columns)
      if (&c.second == &st) return c.first;
    return std::string();
  });
  row("epochs (no solution)", [](const auto& st) {
    return std::to_string(st.epochs) + " (" + std::to_string(st.epochs_without_solution) + ")";
  });
  row("3D mean [cm]", [&](const auto& st) { return cm(st.all.mean_m); });
  row("3D median [cm]", [&](const auto& st) { return cm(st.all.median_m); });
  row("3D std [cm]", [&](const auto& st) { return cm(st.all.std_m); });
  row("3D max [cm]", [&](const auto& st) { return cm(st.all.max_m); });
  const std::string w = format("%g", columns.empty() ? 15.0 : columns.front().second.options.convergence_window_s / 60.0);
  row("first " + w + " min median [cm]", [&](const auto& st) { return cm(st.first_window.median_m); });
  row("first " + w + " min mean [cm]", [&](const auto& st) { return cm(st.first_window.mean_m); });
  row("first " + w + " min max [cm]", [&](const auto& st) { return cm(st.first_window.max_m); });
  const std::size_t n_thr = columns.empty() ? 0 : columns.front().second.convergence.size();
  for (std::size_t k = 0; k < n_thr; ++k) {
    const double thr = columns.front().second.convergence[k].threshold_m;
    row("< " + format("%g", thr * 100.0) + " cm from [min]", [&](const auto& st) {
      return k < st.convergence.size() && st.epochs ? minutes(st.convergence[k].time_s) : std::string("-");
    });
  }
  row("final 3D [cm]", [&](const auto& st) { return cm(st.final_error_m); });
  const std::string t = format("%g", columns.empty() ? 30.0 : columns.front().second.options.tail_window_s / 60.0);
  const char* axes[3] = {"E", "N", "U"};
  for (int a = 0; a < 3; ++a)
    row("last " + t + " min RMS " + axes[a] + " [cm]", [&](const auto& st) { return cm(st.tail_enu_rms_m(a)); });
  row("3D 95% [cm]", [&](const auto& st) { return cm(st.percentile_m(0.95)); });
  return os.str();
}

std::string formatStatisticsTable(const PositionErrorStatistics& stats, const std::string& label) {
  return formatStatisticsComparison({{label, stats}});
}

std::string statisticsToJson(const PositionErrorStatistics& st, const std::string& label) {
  std::ostringstream os;
  auto summary = [&](const ErrorSummary& s) {
    return "{\"count\": " + std::to_string(s.count) + ", \"median_m\": " + jsonNumber(s.median_m) +
           ", \"mean_m\": " + jsonNumber(s.mean_m) + ", \"std_m\": " + jsonNumber(s.std_m) +
           ", \"max_m\": " + jsonNumber(s.max_m) + "}";
  };
  os << "{\n";
  if (!label.empty()) os << "  \"label\": " << jsonString(label) << ",\n";
  os << "  \"epochs\": " << st.epochs << ",\n";
  os << "  \"epochs_without_solution\": " << st.epochs_without_solution << ",\n";
  os << "  \"span_s\": " << jsonNumber(st.span_s) << ",\n";
  os << "  \"all_epochs\": " << summary(st.all) << ",\n";
  os << "  \"convergence_window_s\": " << jsonNumber(st.options.convergence_window_s) << ",\n";
  os << "  \"first_window\": " << summary(st.first_window) << ",\n";
  os << "  \"convergence\": [";
  for (std::size_t k = 0; k < st.convergence.size(); ++k) {
    const auto& c = st.convergence[k];
    os << (k ? ", " : "") << "{\"threshold_m\": " << jsonNumber(c.threshold_m)
       << ", \"time_s\": " << (c.time_s ? jsonNumber(*c.time_s) : "null") << "}";
  }
  os << "],\n";
  os << "  \"final_error_m\": " << jsonNumber(st.final_error_m) << ",\n";
  os << "  \"tail_window_s\": " << jsonNumber(st.options.tail_window_s) << ",\n";
  os << "  \"tail_enu_rms_m\": [" << jsonNumber(st.tail_enu_rms_m(0)) << ", " << jsonNumber(st.tail_enu_rms_m(1))
     << ", " << jsonNumber(st.tail_enu_rms_m(2)) << "],\n";
  os << "  \"percentiles_m\": {\"p50\": " << jsonNumber(st.percentile_m(0.5))
     << ", \"p68\": " << jsonNumber(st.percentile_m(0.68)) << ", \"p95\": " << jsonNumber(st.percentile_m(0.95))
     << "},\n";
  os << "  \"cdf\": [";
  for (std::size_t k = 0; k < st.cdf.size(); ++k)
    os << (k ? ", " : "") << "[" << jsonNumber(st.cdf[k].first) << ", " << jsonNumber(st.cdf[k].second) << "]";
  os << "]\n}\n";
  return os.str();
}

}  // namespace ppp
