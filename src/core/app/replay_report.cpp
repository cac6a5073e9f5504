#include "ppp_bayes_tree/app/replay_report.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "ppp_bayes_tree/evaluation/json_text.h"
#include "ppp_bayes_tree/evaluation/solution_csv_writer.h"
#include "ppp_bayes_tree/io/fixed_width.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

std::string cm(double m) { return std::isfinite(m) ? format("%.2f", m * 100.0) : std::string("-"); }

}  // namespace

TruthTrajectory TruthTrajectory::fixedPoint(const Eigen::Vector3d& position_ecef_m) {
  TruthTrajectory t;
  t.fixed_point_ecef_m = position_ecef_m;
  return t;
}

std::optional<Eigen::Vector3d> TruthTrajectory::at(const GnssTime& t, const TruthMatchOptions& options) const {
  if (fixed_point_ecef_m) return fixed_point_ecef_m;
  if (time.empty()) return std::nullopt;
  // First sample at or after t.
  const auto it = std::lower_bound(time.begin(), time.end(), t);
  const std::size_t k = static_cast<std::size_t>(it - time.begin());
  if (k < time.size() && std::abs(time[k] - t) <= options.tolerance_s) return position_ecef_m[k];
  if (k > 0 && std::abs(t - time[k - 1]) <= options.tolerance_s) return position_ecef_m[k - 1];
  if (k == 0 || k == time.size()) return std::nullopt;  // outside the trajectory: no extrapolation
  const double span = time[k] - time[k - 1];
  if (!(span <= options.max_gap_s)) return std::nullopt;
  const double f = (t - time[k - 1]) / span;
  return position_ecef_m[k - 1] + f * (position_ecef_m[k] - position_ecef_m[k - 1]);
}

TruthTrajectory readTruthCsv(LineSource& source, ParseReport& report) {
  report.setFile(source.name());
  std::string line;
  while (source.next(line) && isBlank(line)) {
  }
  if (isBlank(line)) throw ParseError(source.name(), source.lineNumber(), "empty truth file (no header row)");
  const std::vector<std::string> header = splitCsvFields(line);
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < header.size(); ++i) col.emplace(header[i], i);
  const char* sow_name = col.count("seconds_of_week") ? "seconds_of_week" : "tow_s";
  for (const char* need : {"gps_week", sow_name, "x_m", "y_m", "z_m"})
    if (!col.count(need))
      throw ParseError(source.name(), source.lineNumber(),
                       std::string("truth CSV header has no '") + need +
                           "' column (needs gps_week, seconds_of_week or tow_s, x_m, y_m, z_m)");
  const std::size_t iw = col[std::string("gps_week")], is = col[sow_name];
  const std::size_t ix = col[std::string("x_m")], iy = col[std::string("y_m")], iz = col[std::string("z_m")];
  const std::size_t need_cols = std::max({iw, is, ix, iy, iz}) + 1;

  TruthTrajectory truth;
  while (source.next(line)) {
    if (isBlank(line)) continue;
    const std::vector<std::string> f = splitCsvFields(line);
    if (f.size() < need_cols) {
      report.addProblem(source.lineNumber(), "truth row with " + std::to_string(f.size()) + " fields, needs " +
                                                 std::to_string(need_cols));
      continue;
    }
    if (f[ix].empty() && f[iy].empty() && f[iz].empty()) {
      report.count("rows without position");
      continue;
    }
    long long week = 0;
    double sow = 0.0, x = 0.0, y = 0.0, z = 0.0;
    if (parseInt(f[iw], week) != FieldStatus::Ok || week < 0 || week > 10000 ||
        parseDouble(f[is], sow) != FieldStatus::Ok || !(sow >= 0.0 && sow < 604800.0) ||
        parseDouble(f[ix], x) != FieldStatus::Ok || parseDouble(f[iy], y) != FieldStatus::Ok ||
        parseDouble(f[iz], z) != FieldStatus::Ok) {
      report.addProblem(source.lineNumber(), "malformed truth row (week, seconds of week or position)");
      continue;
    }
    const Eigen::Vector3d p(x, y, z);
    // A position must be finite and within 100 km of the Earth's surface (radius 6357-6378 km) or
    // below orbit heights: a loose sanity range that rejects garbage, not a model.
    if (!p.allFinite() || p.norm() < 6.2e6 || p.norm() > 7.0e6) {
      report.addProblem(source.lineNumber(), "truth position not near the Earth's surface");
      continue;
    }
    const GnssTime t = GnssTime::fromGpsWeek(static_cast<int>(week), sow);
    if (!truth.time.empty() && !(t > truth.time.back())) {
      report.addProblem(source.lineNumber(), "truth row not after the previous one in time");
      continue;
    }
    truth.time.push_back(t);
    truth.position_ecef_m.push_back(p);
  }
  if (source.streamError()) report.addProblem(source.lineNumber(), "compressed stream truncated or corrupt");
  return truth;
}

TruthTrajectory readTruthCsv(const std::string& path, ParseReport& report) {
  auto source = openLineSource(path);
  return readTruthCsv(*source, report);
}

AssembledSolution assembleReplaySolution(const std::vector<ReplayStatusSample>& status,
                                         std::vector<ReplayPositionSample> positions, double tolerance_s) {
  // Positions in time order; of samples at the same time the last one received wins.
  std::stable_sort(positions.begin(), positions.end(),
                   [](const ReplayPositionSample& a, const ReplayPositionSample& b) { return a.time < b.time; });
  std::vector<ReplayPositionSample> unique;
  for (auto& p : positions) {
    if (!unique.empty() && std::abs(p.time - unique.back().time) <= tolerance_s) unique.back() = std::move(p);
    else unique.push_back(std::move(p));
  }
  std::vector<bool> used(unique.size(), false);
  auto find = [&](const GnssTime& t) -> std::optional<std::size_t> {
    const auto it = std::lower_bound(unique.begin(), unique.end(), t,
                                     [](const ReplayPositionSample& p, const GnssTime& v) { return p.time < v; });
    const std::size_t k = static_cast<std::size_t>(it - unique.begin());
    if (k < unique.size() && std::abs(unique[k].time - t) <= tolerance_s) return k;
    if (k > 0 && std::abs(t - unique[k - 1].time) <= tolerance_s) return k - 1;
    return std::nullopt;
  };

  AssembledSolution out;
  for (const auto& s : status) {
    SolutionEpoch e;
    e.time = s.time;
    e.satellites_used = s.satellites_used;
    e.satellites_rejected = s.satellites_rejected;
    if (!s.solved) {
      e.status = SolutionStatus::NoSolution;
      out.epochs.push_back(e);
      continue;
    }
    const auto k = find(s.time);
    if (!k) {
      ++out.solved_without_position;
      continue;
    }
    used[*k] = true;
    e.status = s.ambiguities_fixed ? SolutionStatus::PppFixed : SolutionStatus::PppFloat;
    e.position_ecef_m = unique[*k].position_ecef_m;
    e.covariance_ecef_m2 = unique[*k].covariance_ecef_m2;
    e.zwd_m = s.zwd_m;
    e.receiver_clock_m = s.receiver_clock_m;
    out.epochs.push_back(e);
  }
  for (std::size_t k = 0; k < unique.size(); ++k) {
    if (used[k]) continue;
    if (!status.empty()) ++out.positions_without_status;
    SolutionEpoch e;
    e.time = unique[k].time;
    e.position_ecef_m = unique[k].position_ecef_m;
    e.covariance_ecef_m2 = unique[k].covariance_ecef_m2;
    out.epochs.push_back(e);
  }
  std::stable_sort(out.epochs.begin(), out.epochs.end(),
                   [](const SolutionEpoch& a, const SolutionEpoch& b) { return a.time < b.time; });
  return out;
}

NodeFigures replayNodeFigures(const std::string& name, const std::vector<ReplayStatusSample>& status,
                              std::optional<std::size_t> input_epochs) {
  NodeFigures n;
  n.name = name;
  n.status_messages = status.size();
  n.input_epochs = input_epochs;
  std::vector<double> times;
  for (const auto& s : status) {
    if (s.update_time_s && std::isfinite(*s.update_time_s)) times.push_back(*s.update_time_s);
    // Counters only grow (since the node started): the largest is the final one.
    n.epochs_processed = std::max(n.epochs_processed, s.epochs_processed);
    n.epochs_duplicate = std::max(n.epochs_duplicate, s.epochs_duplicate);
    n.epochs_out_of_order = std::max(n.epochs_out_of_order, s.epochs_out_of_order);
    n.estimator_resets = std::max(n.estimator_resets, s.estimator_resets);
  }
  n.update_time = summarizeTimes(times);
  return n;
}

std::size_t NodeFigures::dropped() const {
  if (input_epochs) return *input_epochs > epochs_processed ? *input_epochs - epochs_processed : 0;
  return epochs_duplicate + epochs_out_of_order;
}

double ReplayFixFigures::fixedShare() const {
  return solved_epochs > 0 ? static_cast<double>(fixed_epochs) / static_cast<double>(solved_epochs) : 0.0;
}

ReplayFixFigures replayFixFigures(const std::vector<SolutionEpoch>& solution) {
  ReplayFixFigures f;
  std::optional<GnssTime> first_solved;
  for (const auto& e : solution) {
    if (!e.position_ecef_m) continue;
    ++f.solved_epochs;
    if (!first_solved) first_solved = e.time;
    if (e.status != SolutionStatus::PppFixed) continue;
    ++f.fixed_epochs;
    if (!f.time_to_first_fix_s) f.time_to_first_fix_s = e.time - *first_solved;
  }
  return f;
}

ReplayReportRow buildReplayReportRow(const std::string& label, const std::string& key,
                                     std::vector<SolutionEpoch> solution, const TruthTrajectory& truth,
                                     const StatisticsOptions& statistics, const TruthMatchOptions& match) {
  ReplayReportRow row;
  row.label = label;
  row.key = key;
  std::stable_sort(solution.begin(), solution.end(),
                   [](const SolutionEpoch& a, const SolutionEpoch& b) { return a.time < b.time; });
  for (auto& e : solution) {
    const std::optional<Eigen::Vector3d> t = truth.at(e.time, match);
    if (!t) {
      ++row.unmatched_epochs;
      continue;
    }
    row.solution.push_back(std::move(e));
    row.truth_ecef_m.push_back(*t);
  }
  row.statistics = computePositionErrorStatistics(row.solution, row.truth_ecef_m, statistics);
  row.fix = replayFixFigures(row.solution);
  if (row.statistics.epochs == 0)
    row.missing = row.solution.empty() ? "no epoch matched the truth in time (" + std::to_string(row.unmatched_epochs) +
                                             " epochs outside it)"
                                       : "no epoch with a position";
  return row;
}

ReplayReportRow missingReplayReportRow(const std::string& label, const std::string& key, const std::string& why) {
  ReplayReportRow row;
  row.label = label;
  row.key = key;
  row.missing = why;
  return row;
}

std::string formatReplayReport(const std::vector<ReplayReportRow>& rows) {
  std::ostringstream os;
  const double window_min =
      rows.empty() ? 15.0 : rows.front().statistics.options.convergence_window_s / 60.0;
  std::vector<double> thresholds = rows.empty() ? std::vector<double>{} : rows.front().statistics.options.convergence_thresholds_m;
  const std::string w = format("%g", window_min);
  const int conv_width = std::max(0, static_cast<int>(7 * thresholds.size()) - 1);
  os << format("%-26s | %-31s | %-31s |%s%-*s | %-14s | %-16s | %s\n", "", "3D error, all epochs [cm]",
               ("3D error, first " + w + " min [cm]").c_str(), thresholds.empty() ? "" : " ", conv_width,
               thresholds.empty() ? "" : "conv. [min]", "PPP-AR", "node update [ms]", "node epochs");
  os << format("%-18s %7s | %7s %7s %7s %7s | %7s %7s %7s %7s |", "estimator", "epochs", "median", "mean", "sigma",
               "max", "median", "mean", "sigma", "max");
  for (double thr : thresholds) os << format(" %6s", ("<" + format("%g", thr * 100.0) + "cm").c_str());
  os << " | " << format("%6s", "fixed%") << format(" %7s", "1st fix") << " | " << format("%7s", "median") << format(" %8s", "p99")
     << " | processed dropped\n";
  for (const auto& r : rows) {
    if (!r.missing.empty()) continue;
    const auto& s = r.statistics;
    os << format("%-18s %7zu | %7s %7s %7s %7s | %7s %7s %7s %7s |", r.label.substr(0, 18).c_str(), s.epochs,
                 cm(s.all.median_m).c_str(), cm(s.all.mean_m).c_str(), cm(s.all.std_m).c_str(), cm(s.all.max_m).c_str(),
                 cm(s.first_window.median_m).c_str(), cm(s.first_window.mean_m).c_str(),
                 cm(s.first_window.std_m).c_str(), cm(s.first_window.max_m).c_str());
    for (std::size_t k = 0; k < thresholds.size(); ++k) {
      const auto& c = k < s.convergence.size() ? s.convergence[k].time_s : std::nullopt;
      os << format(" %6s", c ? format("%.1f", *c / 60.0).c_str() : "never");
    }
    os << " | " << format("%6.1f", 100.0 * r.fix.fixedShare())
       << format(" %7s", r.fix.time_to_first_fix_s ? format("%.1f", *r.fix.time_to_first_fix_s / 60.0).c_str() : "never");
    if (r.node && r.node->update_time.count > 0) {
      os << " | " << format("%7.2f", r.node->update_time.median_s * 1e3) << format(" %8.2f", r.node->update_time.p99_s * 1e3);
      os << " | " << format("%9.0f", static_cast<double>(r.node->epochs_processed))
         << format(" %7.0f", static_cast<double>(r.node->dropped()));
    } else {
      os << " | " << format("%7s", "-") << format(" %8s", "-") << " | " << format("%9s", "-") << format(" %7s", "-");
    }
    os << "\n";
  }
  for (const auto& r : rows)
    if (!r.missing.empty()) os << r.label << ": no statistics: " << r.missing << "\n";
  for (const auto& r : rows)
    if (r.missing.empty() && r.unmatched_epochs > 0)
      os << r.label << ": " << r.unmatched_epochs << " epochs without a truth at their time left out\n";
  return os.str();
}

std::string replayReportJson(const std::vector<ReplayReportRow>& rows) {
  std::ostringstream os;
  os << "{\"rows\": [";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    os << (i ? ",\n  " : "\n  ") << "{\"label\": " << jsonString(r.label) << ", \"key\": " << jsonString(r.key)
       << ", \"missing\": " << (r.missing.empty() ? "null" : jsonString(r.missing))
       << ", \"unmatched_epochs\": " << r.unmatched_epochs << ", \"solved_epochs\": " << r.fix.solved_epochs
       << ", \"fixed_epochs\": " << r.fix.fixed_epochs << ", \"fixed_share\": " << jsonNumber(r.fix.fixedShare())
       << ", \"time_to_first_fix_s\": " << (r.fix.time_to_first_fix_s ? jsonNumber(*r.fix.time_to_first_fix_s) : "null")
       << ", \"statistics\": "
       << (r.missing.empty() ? statisticsToJson(r.statistics, r.label) : "null") << ", \"node\": ";
    if (!r.node) {
      os << "null}";
      continue;
    }
    const NodeFigures& n = *r.node;
    os << "{\"name\": " << jsonString(n.name) << ", \"status_messages\": " << n.status_messages
       << ", \"update_time_count\": " << n.update_time.count
       << ", \"update_time_median_s\": " << jsonNumber(n.update_time.count ? n.update_time.median_s : NAN)
       << ", \"update_time_p99_s\": " << jsonNumber(n.update_time.count ? n.update_time.p99_s : NAN)
       << ", \"update_time_max_s\": " << jsonNumber(n.update_time.count ? n.update_time.max_s : NAN)
       << ", \"epochs_processed\": " << n.epochs_processed << ", \"epochs_duplicate\": " << n.epochs_duplicate
       << ", \"epochs_out_of_order\": " << n.epochs_out_of_order << ", \"estimator_resets\": " << n.estimator_resets
       << ", \"input_epochs\": " << (n.input_epochs ? std::to_string(*n.input_epochs) : std::string("null"))
       << ", \"epochs_dropped\": " << n.dropped() << "}}";
  }
  os << "\n]}\n";
  return os.str();
}

std::string replayReportCsv(const ReplayReportRow& row) {
  std::string out = SolutionCsvWriter::headerRow(true) + "\n";
  for (std::size_t i = 0; i < row.solution.size(); ++i)
    out += SolutionCsvWriter::row(row.solution[i], row.truth_ecef_m[i]) + "\n";
  return out;
}

Eigen::Vector3d mapDatumFromPair(const Eigen::Vector3d& position_ecef_m, const Eigen::Vector3d& enu_m) {
  Eigen::Vector3d datum = position_ecef_m;
  for (int k = 0; k < 5; ++k) {
    const Geodetic g = ecefToGeodetic(datum);
    datum = position_ecef_m - rotationEnuFromEcef(g.latitude_rad, g.longitude_rad).transpose() * enu_m;
  }
  return datum;
}

}  // namespace ppp
