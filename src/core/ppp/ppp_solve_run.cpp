#include "ppp_bayes_tree/ppp/ppp_solve_run.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "ppp_bayes_tree/evaluation/rtklib_pos.h"
#include "ppp_bayes_tree/evaluation/solution_csv_writer.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

std::string jsonText(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      o += '\\';
      o += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      o += buf;
    } else {
      o += c;
    }
  }
  return o + "\"";
}

std::string jsonNum(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::ofstream openOut(const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + path);
  return out;
}

std::string fixed(double v, int decimals) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

}  // namespace

PppSolveOutcome solvePpp(const PppSolveRequest& req) {
  std::string why;
  auto estimator = makeEstimator(req.estimator, req.config, &why);
  if (!estimator) throw std::invalid_argument(why);
  std::error_code ec;
  std::filesystem::create_directories(req.out_dir, ec);
  if (!std::filesystem::is_directory(req.out_dir)) throw std::runtime_error("cannot create directory " + req.out_dir);

  PppPipeline pipeline(req.files, req.config);
  PppSolveOutcome out;
  out.name = req.name;
  if (out.name.empty()) {
    out.name = pipeline.stationName();
    for (auto& c : out.name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  const std::string stem = req.out_dir + "/" + out.name + "_" + estimator->name();
  out.csv_path = stem + ".csv";
  out.pos_path = stem + ".pos";
  out.epochs_path = stem + "_epochs.csv";
  out.residuals_path = stem + "_residuals.csv";
  out.json_path = stem + "_summary.json";

  std::ofstream csv = openOut(out.csv_path), pos = openOut(out.pos_path), epochs = openOut(out.epochs_path),
                residuals = openOut(out.residuals_path);
  SolutionCsvWriter csv_writer(csv, req.truth_ecef_m);
  PosWriterOptions pos_options;
  pos_options.comment_lines = {"ppp_solve estimator " + estimator->name() + ", obs " + req.files.obs,
                               "kinematic PPP, ionosphere-free float, forward filter"};
  RtklibPosWriter pos_writer(pos, pos_options);
  epochs << "time_gpst,status,reason,observed,selected,used,rejected,new_arcs,slips,gap_s,events\n";
  residuals << "time_gpst,sat,arc,new_arc,elevation_deg,azimuth_deg,code_prefit_m,phase_prefit_m,"
               "code_postfit_m,phase_postfit_m,code_sigma_m,phase_sigma_m\n";

  out.run = pipeline.run(*estimator, [&](const PppEpochRecord& rec) {
    const std::string t = isoTimeText(rec.solution.time, 1);
    if (!rec.refused) {
      out.solution.push_back(rec.solution);
      csv_writer.write(rec.solution);
      pos_writer.write(rec.solution);
    }
    std::string rej;
    for (const auto& r : rec.rejected) {
      if (!rej.empty()) rej += "; ";
      rej += r.satellite.toString() + " " + r.stage + ": " + r.reason;
    }
    for (const auto& e : rec.arc_events) rej += (rej.empty() ? "" : "; ") + e;
    for (auto& c : rej)
      if (c == '"') c = '\'';
    const std::string status = rec.refused ? "refused" : toString(rec.status);
    std::string reason = rec.reason;
    for (auto& c : reason)
      if (c == '"') c = '\'';
    epochs << t << ',' << status << ",\"" << reason << "\"," << rec.satellites_observed << ','
           << rec.satellites_selected << ',' << rec.used.size() << ',' << rec.rejected.size() << ',' << rec.new_arcs
           << ',' << rec.slips << ',' << (rec.gap_s ? fixed(*rec.gap_s, 1) : "") << ",\"" << rej << "\"\n";
    for (const auto& r : rec.residuals) {
      residuals << t << ',' << r.satellite.toString() << ',' << r.arc << ',' << (r.new_arc ? 1 : 0) << ','
                << fixed(r.elevation_rad * kRadToDeg, 2) << ',' << fixed(r.azimuth_rad * kRadToDeg, 2) << ','
                << fixed(r.code_prefit_m, 4) << ',' << fixed(r.phase_prefit_m, 4) << ','
                << fixed(r.code_postfit_m, 4) << ',' << fixed(r.phase_postfit_m, 4) << ','
                << fixed(r.code_sigma_m, 4) << ',' << fixed(r.phase_sigma_m, 4) << '\n';
    }
    if (req.on_epoch) req.on_epoch(pipeline.progress(), rec);
  });
  for (auto* f : {&csv, &pos, &epochs, &residuals}) {
    f->flush();
    if (!*f) throw std::runtime_error("write error in " + req.out_dir);
  }
  if (req.truth_ecef_m) out.statistics = computePositionErrorStatistics(out.solution, *req.truth_ecef_m);
  std::ofstream json = openOut(out.json_path);
  json << runSummaryToJson(out);
  if (!json) throw std::runtime_error("cannot write " + out.json_path);
  return out;
}

std::string runSummaryToJson(const PppSolveOutcome& o) {
  const PppRunSummary& r = o.run;
  std::ostringstream os;
  os << "{\n  \"name\": " << jsonText(o.name) << ",\n  \"estimator\": " << jsonText(r.estimator) << ",\n";
  os << "  \"statistics\": ";
  if (o.statistics) {
    std::string s = statisticsToJson(*o.statistics, r.estimator);
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    os << s;
  } else {
    os << "null";
  }
  os << ",\n  \"epochs\": {\"read\": " << r.epochs_read << ", \"solved\": " << r.epochs_solved
     << ", \"no_solution\": " << r.epochs_no_solution << ", \"failed\": " << r.epochs_failed
     << ", \"refused\": " << r.epochs_refused << ", \"data_gaps\": " << r.data_gaps << "},\n";
  os << "  \"arcs\": " << r.arcs << ",\n  \"slips\": " << r.slips << ",\n";
  os << "  \"processing_time_s\": " << jsonNum(r.processing_time_s) << ",\n";
  os << "  \"rejections\": {";
  bool first = true;
  for (const auto& [k, n] : r.rejection_counts) {
    os << (first ? "" : ", ") << jsonText(k) << ": " << n;
    first = false;
  }
  os << "},\n  \"satellite_residuals\": [";
  for (std::size_t i = 0; i < r.residual_statistics.size(); ++i) {
    const auto& s = r.residual_statistics[i];
    os << (i ? "," : "") << "\n    {\"sat\": " << jsonText(s.satellite.toString()) << ", \"count\": " << s.count
       << ", \"rejections\": " << s.rejections << ", \"code_mean_m\": " << jsonNum(s.code_mean_m)
       << ", \"code_rms_m\": " << jsonNum(s.code_rms_m) << ", \"phase_mean_m\": " << jsonNum(s.phase_mean_m)
       << ", \"phase_rms_m\": " << jsonNum(s.phase_rms_m) << ", \"phase_max_abs_m\": " << jsonNum(s.phase_max_abs_m)
       << ", \"elevation_deg\": [" << jsonNum(s.min_elevation_deg) << ", " << jsonNum(s.max_elevation_deg) << "]}";
  }
  os << "\n  ],\n  \"notes\": [";
  for (std::size_t i = 0; i < r.notes.size(); ++i) os << (i ? "," : "") << "\n    " << jsonText(r.notes[i]);
  os << "\n  ],\n  \"problems\": [";
  for (std::size_t i = 0; i < r.problems.size(); ++i) os << (i ? "," : "") << "\n    " << jsonText(r.problems[i]);
  os << "\n  ]\n}\n";
  return os.str();
}

std::string formatRunReport(const PppRunSummary& r) {
  std::ostringstream os;
  os << "epochs: " << r.epochs_read << " read, " << r.epochs_solved << " solved, " << r.epochs_no_solution
     << " no solution, " << r.epochs_failed << " failed, " << r.epochs_refused << " refused; " << r.data_gaps
     << " data gaps; " << r.arcs << " arcs, " << r.slips << " slips; " << fixed(r.processing_time_s, 2) << " s\n";
  if (!r.rejection_counts.empty()) {
    os << "rejections (satellite-epochs):\n";
    for (const auto& [k, n] : r.rejection_counts) os << "  " << n << "  " << k << "\n";
  }
  os << "postfit residuals per satellite [mm]:  n  code mean/rms  phase mean/rms/max  elevation [deg]  rejected\n";
  for (const auto& s : r.residual_statistics) {
    if (s.count == 0 && s.rejections == 0) continue;
    char buf[200];
    std::snprintf(buf, sizeof buf, "  %s %4zu  %6.0f %6.0f   %5.1f %5.1f %5.1f   %4.1f-%4.1f  %zu\n",
                  s.satellite.toString().c_str(), s.count, s.code_mean_m * 1e3, s.code_rms_m * 1e3,
                  s.phase_mean_m * 1e3, s.phase_rms_m * 1e3, s.phase_max_abs_m * 1e3, s.min_elevation_deg,
                  s.max_elevation_deg, s.rejections);
    os << buf;
  }
  os << "notes:\n";
  for (const auto& n : r.notes) os << "  " << n << "\n";
  if (!r.problems.empty()) {
    os << "problems (" << r.problems.size() << "):\n";
    for (std::size_t i = 0; i < r.problems.size() && i < 20; ++i) os << "  " << r.problems[i] << "\n";
  }
  return os.str();
}

}  // namespace ppp
