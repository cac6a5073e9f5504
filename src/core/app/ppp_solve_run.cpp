#include "ppp_bayes_tree/app/ppp_solve_run.h"

#include "ppp_bayes_tree/evaluation/json_text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "ppp_bayes_tree/evaluation/rtklib_pos.h"
#include "ppp_bayes_tree/evaluation/solution_csv_writer.h"
#include "ppp_bayes_tree/io/data_file_name.h"
#include "ppp_bayes_tree/io/untrusted_text.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/number_text.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

std::ofstream openOut(const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + path);
  return out;
}

/// Writes one solution as CSV and .pos.
void writeSolutionFiles(const PppSolutionOutput& o, const std::optional<Eigen::Vector3d>& truth,
                        const std::vector<std::string>& comments) {
  std::ofstream csv = openOut(o.csv_path), pos = openOut(o.pos_path);
  SolutionCsvWriter csv_writer(csv, truth);
  PosWriterOptions pos_options;
  pos_options.comment_lines = comments;
  RtklibPosWriter pos_writer(pos, pos_options);
  for (const auto& e : o.solution) {
    csv_writer.write(e);
    pos_writer.write(e);
  }
  csv.flush();
  pos.flush();
  if (!csv || !pos) throw std::runtime_error("write error in " + o.csv_path + " or " + o.pos_path);
}

/// The smoothed solution: the filtered epochs with the states re-read from the final estimate.
std::vector<SolutionEpoch> smoothedSolution(const std::vector<SolutionEpoch>& filtered,
                                             const SmoothedTrajectoryProvider& smoother) {
  std::map<GnssTime, SmoothedEpoch> by_time;
  for (auto& e : smoother.smoothedTrajectory(true)) by_time.emplace(e.time, e);
  std::vector<SolutionEpoch> out = filtered;
  for (auto& e : out) {
    if (!e.position_ecef_m) continue;
    auto it = by_time.find(e.time);
    if (it == by_time.end()) continue;  // cannot happen: every solved epoch has a state
    const SmoothedEpoch& s = it->second;
    e.position_ecef_m = s.state.position_ecef_m;
    e.zwd_m = s.state.zwd_m;
    e.receiver_clock_m = s.state.referenceClock_m();
    if (s.covariance) {
      const int p = s.state.layout.position();
      e.covariance_ecef_m2 = s.covariance->block<3, 3>(p, p);
    } else {
      e.covariance_ecef_m2.reset();  // fixed lag: marginalized states have no covariance
    }
  }
  return out;
}

std::string csvText(std::string s) {
  for (auto& c : s)
    if (c == '"') c = '\'';
  return "\"" + s + "\"";
}

struct BiasRow {
  GnssTime time;
  ArcBiasEstimate estimate;
};

/// Statistics against a moving truth: the solution epochs it has a truth for.
PositionErrorStatistics statisticsAlong(const std::vector<SolutionEpoch>& solution,
                                        const std::function<std::optional<Eigen::Vector3d>(const GnssTime&)>& truth_at) {
  std::vector<SolutionEpoch> matched;
  std::vector<Eigen::Vector3d> truth_ecef_m;
  for (const auto& e : solution) {
    if (const auto t = truth_at(e.time)) {
      matched.push_back(e);
      truth_ecef_m.push_back(*t);
    }
  }
  return computePositionErrorStatistics(matched, truth_ecef_m);
}

}  // namespace

TimingSummary summarizeTimes(std::vector<double> t) {
  TimingSummary s;
  s.count = t.size();
  if (t.empty()) return s;
  std::sort(t.begin(), t.end());
  auto rank = [&](double p) {  // nearest rank
    const auto k = static_cast<std::size_t>(std::ceil(p * static_cast<double>(t.size())));
    return t[std::min(t.size() - 1, k == 0 ? 0 : k - 1)];
  };
  s.median_s = t.size() % 2 ? t[t.size() / 2] : 0.5 * (t[t.size() / 2 - 1] + t[t.size() / 2]);
  s.p90_s = rank(0.90);
  s.p99_s = rank(0.99);
  s.max_s = t.back();
  return s;
}

namespace {

/// The output file prefix: the given name, else the station name in lower case,
/// as a file name that stays in the output folder (io/data_file_name.h).
std::string outputName(const std::string& given, const PppPipeline& pipeline) {
  std::string name = given;
  if (name.empty()) {
    name = pipeline.stationName();
    for (auto& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return dataFileName(name);
}

}  // namespace

namespace {

/// The outcome with its output paths: one solution file set per solution the
/// registry lists for the estimator, the epochs, residuals and (smoother) biases.
PppSolveOutcome plannedOutputs(const PppSolveRequest& req, const EstimatorEntry& entry, const PppPipeline& pipeline,
                               const PppEstimator& estimator) {
  PppSolveOutcome out;
  out.name = outputName(req.name, pipeline);
  const std::string prefix = req.out_dir + "/" + out.name + "_";
  const std::string stem = prefix + estimator.name();
  for (const EstimatorSolution& solution : solutionOutputs(entry)) {
    PppSolutionOutput o;
    o.label = solution.label;
    o.tag = solution.tag;
    o.csv_path = prefix + solution.tag + ".csv";
    o.pos_path = prefix + solution.tag + ".pos";
    o.json_path = prefix + solution.tag + "_summary.json";
    out.outputs.push_back(std::move(o));
  }
  if (estimator.smoothing()) out.biases_path = stem + "_biases.csv";
  out.epochs_path = stem + "_epochs.csv";
  out.residuals_path = stem + "_residuals.csv";
  return out;
}

/// The GNSS/INS estimator's attitude and velocity after each epoch, also through
/// epochs without a GNSS solution (<stem>_attitude.csv): the ZYX Euler angles of
/// R_ned_body (ins_alignment.h) and the velocity in the local level frame; the
/// Doppler velocity update's outcome, satellites, outliers and velocity (ekf_ins).
class AttitudeFile {
 public:
  AttitudeFile(std::string path, const PppEstimator& estimator)
      : path_(std::move(path)), out_(openOut(path_)), estimator_(estimator) {
    out_ << "time_gpst,status,roll_deg,pitch_deg,heading_deg,velocity_north_mps,velocity_east_mps,velocity_down_mps,"
            "alignment,tilt_sigma_deg,heading_sigma_deg,attitude_publishable,antenna_x_m,antenna_y_m,antenna_z_m,"
            "doppler_update,doppler_satellites,doppler_rejected,doppler_velocity_north_mps,doppler_velocity_east_mps,"
            "doppler_velocity_down_mps\n";
  }
  void write(const PppEpochRecord& rec) {
    if (rec.refused) return;
    const std::optional<InertialState> row = estimator_.inertialState();
    if (!row || !(row->time == rec.solution.time)) return;
    const NavState& s = row->nav;
    const Eigen::Matrix3d ecef_ned = rotationEcefNed(s.position_world_m);
    const EulerAngles e = eulerAngles(ecef_ned.transpose() * s.rotation_world_body);
    const Eigen::Vector3d v = ecef_ned.transpose() * s.velocity_world_mps;
    out_ << isoTimeText(rec.solution.time, 1) << ',' << solutionStatusName(rec.solution.status) << ','
         << fixedDecimals(e.roll_rad * kRadToDeg, 4) << ',' << fixedDecimals(e.pitch_rad * kRadToDeg, 4) << ','
         << fixedDecimals(e.yaw_rad * kRadToDeg, 4) << ',' << fixedDecimals(v.x(), 4) << ','
         << fixedDecimals(v.y(), 4) << ',' << fixedDecimals(v.z(), 4) << ',';
    writeQuality(row->attitude_quality);
    const Eigen::Vector3d& antenna = row->antenna_ecef_m;
    out_ << fixedDecimals(antenna.x(), 4) << ',' << fixedDecimals(antenna.y(), 4) << ','
         << fixedDecimals(antenna.z(), 4) << ',';
    writeDoppler(row->doppler, ecef_ned);
  }
  void finish() {
    out_.flush();
    if (!out_) throw std::runtime_error("cannot write " + path_);
  }

 private:
  /// alignment (aligned | level_only | not_aligned), tilt and heading sigma [deg], publishable (0/1);
  /// four empty fields for an estimator that does not report them.
  void writeQuality(const std::optional<InsAttitudeQuality>& quality) {
    if (!quality) {
      out_ << ",,,,";
      return;
    }
    const InsAttitudeQuality& q = *quality;
    const char* state = q.state == AlignmentState::Aligned     ? "aligned"
                        : q.state == AlignmentState::LevelOnly ? "level_only"
                                                               : "not_aligned";
    out_ << state << ',' << fixedDecimals(q.tilt_sigma_rad * kRadToDeg, 3) << ','
         << fixedDecimals(q.heading_sigma_rad * kRadToDeg, 3) << ',' << (q.publishable ? 1 : 0) << ',';
  }

  /// outcome (dopplerOutcomeText), satellites used, outliers rejected, and the Doppler's
  /// antenna velocity in the local level frame; empty fields without.
  void writeDoppler(const std::optional<DopplerUpdate>& doppler, const Eigen::Matrix3d& ecef_ned) {
    if (!doppler) {
      out_ << ",,,,,\n";
      return;
    }
    out_ << dopplerOutcomeText(doppler->outcome) << ',' << doppler->satellites << ',' << doppler->rejected;
    if (doppler->velocity_ecef_mps) {
      const Eigen::Vector3d v = ecef_ned.transpose() * *doppler->velocity_ecef_mps;
      out_ << ',' << fixedDecimals(v.x(), 4) << ',' << fixedDecimals(v.y(), 4) << ',' << fixedDecimals(v.z(), 4) << '\n';
    } else {
      out_ << ",,,\n";
    }
  }

  std::string path_;
  std::ofstream out_;
  const PppEstimator& estimator_;
};

/// The attitude file of an estimator with inertial states; none for the others.
std::optional<AttitudeFile> attitudeFile(const PppSolveOutcome& out, const PppEstimator& estimator) {
  const EstimatorEntry* entry = findEstimator(estimator.name());
  if (!entry || entry->state != EstimatedState::GnssInertial) return std::nullopt;
  const std::string epochs_suffix = "_epochs.csv";
  return std::optional<AttitudeFile>(std::in_place,
      out.epochs_path.substr(0, out.epochs_path.size() - epochs_suffix.size()) + "_attitude.csv", estimator);
}

/// The per-epoch files (epochs, residuals) written as the run goes, and what the
/// run's end needs: the filtered solution, the smoother's timings and bias rows.
class EpochFiles {
 public:
  EpochFiles(const PppSolveOutcome& out, bool smoother, bool write_timings)
      : epochs_(openOut(out.epochs_path)), residuals_(openOut(out.residuals_path)), smoother_(smoother),
        write_timings_(write_timings) {
    epochs_ << "time_gpst,status,integrity,consistency,reason,observed,selected,used,rejected,new_arcs,slips,gap_s,"
               "used_sats";
    if (smoother_)
      epochs_ << ",active_biases,new_biases,relinearized,reeliminated,factors_relinearized,cliques_touched,"
                 "update_ms,epoch_ms";
    epochs_ << ",events\n";
    residuals_ << "time_gpst,sat,arc,new_arc,elevation_deg,azimuth_deg,code_prefit_m,phase_prefit_m,"
                  "code_postfit_m,phase_postfit_m,code_sigma_m,phase_sigma_m\n";
  }

  void write(const PppEpochRecord& rec) {
    const std::string t = isoTimeText(rec.solution.time, 1);
    if (!rec.refused) causal.push_back(rec.solution);
    writeEpochRow(t, rec);
    for (const auto& r : rec.residuals) writeResidualRow(t, r);
  }

  /// Flushes both files; a write error names the output folder.
  void finish(const std::string& out_dir) {
    for (auto* f : {&epochs_, &residuals_}) {
      f->flush();
      if (!*f) throw std::runtime_error("write error in " + out_dir);
    }
  }

  std::vector<SolutionEpoch> causal;
  std::vector<double> update_times, epoch_times;
  std::vector<BiasRow> bias_rows;

 private:
  void writeEpochRow(const std::string& t, const PppEpochRecord& rec) {
    std::string events;
    for (const auto& r : rec.rejected) {
      if (!events.empty()) events += "; ";
      events += r.satellite.toString() + " " + r.text();
    }
    for (const auto& e : rec.arc_events) events += (events.empty() ? "" : "; ") + e;
    std::string used;
    for (const auto& s : rec.used) used += (used.empty() ? "" : " ") + s.toString();
    const std::string status = rec.refused ? "refused" : toString(rec.status);
    epochs_ << t << ',' << status << ',' << toString(rec.solution.integrity) << ',' << csvText(rec.consistency)
            << ',' << csvText(rec.reason) << ',' << rec.satellites_observed << ',' << rec.satellites_selected << ','
            << rec.used.size() << ',' << rec.rejected.size() << ',' << rec.new_arcs << ',' << rec.slips << ','
            << (rec.gap_s ? fixedDecimals(*rec.gap_s, 1) : "") << ',' << used;
    if (smoother_) writeSmootherColumns(rec);
    epochs_ << ',' << csvText(events) << '\n';
  }

  void writeSmootherColumns(const PppEpochRecord& rec) {
    if (rec.refused || !rec.smoother) {
      epochs_ << ",,,,,,,,";
      return;
    }
    const SmootherEpochDiagnostics& r = *rec.smoother;
    epochs_ << ',' << rec.active_biases << ',' << r.new_biases << ',' << r.variables_relinearized << ','
            << r.variables_reeliminated << ',' << r.factors_relinearized << ',' << r.cliques_touched << ',';
    if (write_timings_)
      epochs_ << fixedDecimals(r.update_time_s * 1e3, 3) << ',' << fixedDecimals(rec.estimator_time_s * 1e3, 3);
    else
      epochs_ << ',';
    if (rec.status != EpochStatus::Ok) return;
    update_times.push_back(r.update_time_s);
    epoch_times.push_back(rec.estimator_time_s);
    for (const auto& b : r.biases) bias_rows.push_back({rec.solution.time, b});
  }

  void writeResidualRow(const std::string& t, const MeasurementResidual& r) {
    residuals_ << t << ',' << r.satellite.toString() << ',' << r.arc << ',' << (r.new_arc ? 1 : 0) << ','
               << fixedDecimals(r.elevation_rad * kRadToDeg, 2) << ',' << fixedDecimals(r.azimuth_rad * kRadToDeg, 2)
               << ',' << fixedDecimals(r.code_prefit_m, 4) << ',' << fixedDecimals(r.phase_prefit_m, 4) << ','
               << fixedDecimals(r.code_postfit_m, 4) << ',' << fixedDecimals(r.phase_postfit_m, 4) << ','
               << fixedDecimals(r.code_sigma_m, 4) << ',' << fixedDecimals(r.phase_sigma_m, 4) << '\n';
  }

  std::ofstream epochs_, residuals_;
  bool smoother_;
  bool write_timings_;
};

/// The smoother's biases: filtered per epoch, with each arc's final smoothed value.
void writeBiasFile(const std::string& path, const std::vector<BiasRow>& bias_rows,
                   const SmoothedTrajectoryProvider& smoother) {
  std::ofstream biases = openOut(path);
  biases << "time_gpst,arc,sat,bias_m,sigma_m,smoothed_final_m\n";
  std::map<ArcId, std::optional<double>> final_m;
  for (const auto& row : bias_rows) {
    auto it = final_m.find(row.estimate.arc);
    if (it == final_m.end())
      it = final_m.emplace(row.estimate.arc, smoother.smoothedBias_m(row.estimate.satellite, row.estimate.arc)).first;
    biases << isoTimeText(row.time, 1) << ',' << row.estimate.arc << ',' << row.estimate.satellite.toString() << ','
           << fixedDecimals(row.estimate.bias_m, 4) << ',' << fixedDecimals(row.estimate.sigma_m, 4) << ','
           << (it->second ? fixedDecimals(*it->second, 4) : "") << '\n';
  }
  biases.flush();
  if (!biases) throw std::runtime_error("cannot write " + path);
}

/// The solution files (csv, pos) of the filtered and, with a smoother, the
/// smoothed solution, and the smoother's bias file and timings.
void writeSolutions(const PppSolveRequest& req, const PppEstimator& estimator, EpochFiles& files,
                    PppSolveOutcome& out) {
  const SmoothedTrajectoryProvider* smoother = estimator.smoothing();
  const std::string source = "ppp_solve estimator " + estimator.name() + ", obs " + req.files.obs;
  out.outputs[0].solution = std::move(files.causal);
  writeSolutionFiles(out.outputs[0], req.truth_ecef_m,
                     {source, "kinematic PPP, ionosphere-free float, " +
                                  std::string(smoother ? "smoother FILTERED (newest state after each update)"
                                                       : "forward filter")});
  if (!smoother) return;
  out.outputs[1].solution = smoothedSolution(out.outputs[0].solution, *smoother);
  writeSolutionFiles(out.outputs[1], req.truth_ecef_m,
                     {source, "kinematic PPP, ionosphere-free float, smoother SMOOTHED (final estimate, all data)"});
  out.update_time = summarizeTimes(files.update_times);
  out.epoch_time = summarizeTimes(files.epoch_times);
  writeBiasFile(out.biases_path, files.bias_rows, *smoother);
}

/// Each solution's statistics against the truth (when given) and its summary json;
/// the first solution is the outcome's headline.
void writeSummaries(const PppSolveRequest& req, PppSolveOutcome& out) {
  for (auto& o : out.outputs) {
    if (req.truth_ecef_m) o.statistics = computePositionErrorStatistics(o.solution, *req.truth_ecef_m);
    else if (req.truth_at) o.statistics = statisticsAlong(o.solution, req.truth_at);
    std::ofstream json = openOut(o.json_path);
    json << runSummaryToJson(out, o, req.write_timings);
    if (!json) throw std::runtime_error("cannot write " + o.json_path);
  }
  out.solution = out.outputs[0].solution;
  out.statistics = out.outputs[0].statistics;
  out.csv_path = out.outputs[0].csv_path;
  out.pos_path = out.outputs[0].pos_path;
  out.json_path = out.outputs[0].json_path;
}

}  // namespace

// One ppp_solve run, as steps:
//   1. the estimator's name (and an inertial one's IMU readings) is checked before
//      any file is read; the output folder made;
//   2. the pipeline reads the products (they decide the systems and PPP-AR,
//      product_assembly.h); the registry makes the estimator;
//   3. the epochs go through the estimator, the per-epoch files written as they come;
//   4. the solution files, the smoother's biases, the summaries.
PppSolveOutcome solvePpp(const PppSolveRequest& req) {
  std::string why;
  if (!makeEstimator(req.estimator, req.config, &why)) throw std::invalid_argument(why);  // 1
  const EstimatorEntry& entry = *findEstimator(req.estimator);
  const bool inertial = entry.state == EstimatedState::GnssInertial;
  if (inertial && req.imu.empty())
    throw std::invalid_argument("estimator '" + req.estimator + "' needs IMU readings (ppp_solve --imu FILE); none given");
  std::error_code ec;
  std::filesystem::create_directories(req.out_dir, ec);
  if (!std::filesystem::is_directory(req.out_dir)) throw std::runtime_error("cannot create directory " + req.out_dir);

  std::unique_ptr<PppPipeline> owned_pipeline =  // 2
      req.make_pipeline ? req.make_pipeline(req.config) : std::make_unique<PppPipeline>(req.files, req.config);
  PppPipeline& pipeline = *owned_pipeline;
  if (inertial) pipeline.setImu(req.imu);
  auto estimator = makeEstimator(req.estimator, pipeline.config(), &why);
  if (!estimator) throw std::invalid_argument(why);
  PppSolveOutcome out = plannedOutputs(req, entry, pipeline, *estimator);

  EpochFiles files(out, estimator->smoothing() != nullptr, req.write_timings);  // 3
  std::optional<AttitudeFile> attitude = attitudeFile(out, *estimator);
  out.run = pipeline.run(*estimator, [&](const PppEpochRecord& rec) {
    files.write(rec);
    if (attitude) attitude->write(rec);
    if (req.on_epoch) req.on_epoch(pipeline.progress(), rec);
  });
  files.finish(req.out_dir);
  if (attitude) attitude->finish();

  writeSolutions(req, *estimator, files, out);  // 4
  writeSummaries(req, out);
  return out;
}

std::vector<PppSolveOutcome> solvePppEstimators(const PppSolveRequest& req) {
  std::string why;
  const auto selected = selectEstimators(req.estimator, &why);
  if (!selected) throw std::invalid_argument(why);
  if (req.estimator != kAllEstimators) return {solvePpp(req)};
  std::vector<PppSolveOutcome> out;
  for (const EstimatorEntry* e : *selected) {
    PppSolveRequest r = req;
    r.estimator = std::string(e->name);
    out.push_back(solvePpp(r));
  }
  return out;
}

std::string runSummaryToJson(const PppSolveOutcome& o) {
  if (o.outputs.empty()) {
    PppSolutionOutput only;
    only.label = o.run.estimator;
    only.statistics = o.statistics;
    return runSummaryToJson(o, only);
  }
  return runSummaryToJson(o, o.outputs.front());
}

std::string runSummaryToJson(const PppSolveOutcome& o, const PppSolutionOutput& output, bool timings) {
  const PppRunSummary& r = o.run;
  std::ostringstream os;
  os << "{\n  \"name\": " << jsonString(o.name) << ",\n  \"estimator\": " << jsonString(r.estimator)
     << ",\n  \"solution\": " << jsonString(output.label) << ",\n";
  os << "  \"statistics\": ";
  if (output.statistics) {
    std::string s = statisticsToJson(*output.statistics, output.label);
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    os << s;
  } else {
    os << "null";
  }
  os << ",\n  \"epochs\": {\"read\": " << r.epochs_read << ", \"solved\": " << r.epochs_solved
     << ", \"no_solution\": " << r.epochs_no_solution << ", \"failed\": " << r.epochs_failed
     << ", \"refused\": " << r.epochs_refused << ", \"data_gaps\": " << r.data_gaps
     << ", \"inconsistent\": " << r.epochs_inconsistent << "},\n";
  os << "  \"arcs\": " << r.arcs << ",\n  \"slips\": " << r.slips << ",\n";
  if (timings) os << "  \"processing_time_s\": " << jsonNumber(r.processing_time_s, 6) << ",\n";
  if (r.epochs_fixed > 0)  // PPP-AR ran and fixed (absent otherwise, so float runs keep their keys)
    os << "  \"epochs_fixed\": " << r.epochs_fixed << ",\n  \"time_to_first_fix_s\": "
       << jsonNumber(r.time_to_first_fix_s.value_or(0.0), 6) << ",\n";
  for (const auto& [key, t] : {std::make_pair("update_time", o.update_time), std::make_pair("epoch_time", o.epoch_time)}) {
    if (!t || !timings) continue;
    os << "  \"" << key << "_ms\": {\"epochs\": " << t->count << ", \"median\": " << jsonNumber(t->median_s * 1e3, 6)
       << ", \"p99\": " << jsonNumber(t->p99_s * 1e3, 6) << ", \"max\": " << jsonNumber(t->max_s * 1e3, 6) << "},\n";
  }
  os << "  \"rejections\": {";
  bool first = true;
  for (const auto& [k, n] : r.rejection_counts) {
    os << (first ? "" : ", ") << jsonString(toString(k)) << ": " << n;
    first = false;
  }
  os << "},\n  \"no_solution\": {";
  first = true;
  for (const auto& [k, n] : r.no_solution_counts) {
    os << (first ? "" : ", ") << jsonString(toString(k)) << ": " << n;
    first = false;
  }
  os << "},\n  \"estimator_resets\": " << r.estimator_resets << ",\n  \"satellite_residuals\": [";
  for (std::size_t i = 0; i < r.residual_statistics.size(); ++i) {
    const auto& s = r.residual_statistics[i];
    os << (i ? "," : "") << "\n    {\"sat\": " << jsonString(s.satellite.toString()) << ", \"count\": " << s.count
       << ", \"rejections\": " << s.rejections << ", \"code_mean_m\": " << jsonNumber(s.code_mean_m, 6)
       << ", \"code_rms_m\": " << jsonNumber(s.code_rms_m, 6) << ", \"phase_mean_m\": " << jsonNumber(s.phase_mean_m, 6)
       << ", \"phase_rms_m\": " << jsonNumber(s.phase_rms_m, 6) << ", \"phase_max_abs_m\": " << jsonNumber(s.phase_max_abs_m, 6)
       << ", \"elevation_deg\": [" << jsonNumber(s.min_elevation_deg, 6) << ", " << jsonNumber(s.max_elevation_deg, 6) << "]}";
  }
  os << "\n  ],\n  \"notes\": [";
  for (std::size_t i = 0; i < r.notes.size(); ++i) os << (i ? "," : "") << "\n    " << jsonString(r.notes[i]);
  os << "\n  ],\n  \"problems\": [";
  for (std::size_t i = 0; i < r.problems.size(); ++i) os << (i ? "," : "") << "\n    " << jsonString(r.problems[i]);
  os << "\n  ]\n}\n";
  return os.str();
}

std::string formatRunReport(const PppRunSummary& r) {
  std::ostringstream os;
  os << "epochs: " << r.epochs_read << " read, " << r.epochs_solved << " solved, " << r.epochs_no_solution
     << " no solution, " << r.epochs_failed << " failed, " << r.epochs_refused << " refused; " << r.data_gaps
     << " data gaps; " << r.arcs << " arcs, " << r.slips << " slips; " << fixedDecimals(r.processing_time_s, 2) << " s\n";
  if (!r.rejection_counts.empty()) {
    os << "rejections (satellite-epochs):\n";
    for (const auto& [k, n] : r.rejection_counts) os << "  " << n << "  " << toString(k) << "\n";
  }
  if (!r.no_solution_counts.empty()) {
    os << "epochs without a solution:\n";
    for (const auto& [k, n] : r.no_solution_counts) os << "  " << n << "  " << toString(k) << "\n";
  }
  if (r.epochs_inconsistent > 0)
    os << "epochs whose residuals contradict their covariance (consistency test): " << r.epochs_inconsistent
       << " (flagged \"inconsistent\": covariance inflated, or withheld)\n";
  if (r.estimator_resets > 0)
    os << "estimator restarts after a failed update: " << r.estimator_resets << "\n";
  os << "postfit residuals per satellite [mm]:  n  code mean/rms  phase mean/rms/max  elevation [deg]  rejected\n";
  for (const auto& s : r.residual_statistics) {
    if (s.count == 0 && s.rejections == 0) continue;
    os << format("  %s %4zu  %6.0f %6.0f   %5.1f %5.1f %5.1f   %4.1f-%4.1f  %zu\n", s.satellite.toString().c_str(),
                 s.count, s.code_mean_m * 1e3, s.code_rms_m * 1e3, s.phase_mean_m * 1e3, s.phase_rms_m * 1e3,
                 s.phase_max_abs_m * 1e3, s.min_elevation_deg, s.max_elevation_deg, s.rejections);
  }
  if (r.epochs_fixed > 0) {
    os << format("ambiguities fixed: %zu of %zu solved epochs (%.1f %%), first fix after %.1f min\n", r.epochs_fixed,
                 r.epochs_solved, 100.0 * r.epochs_fixed / std::max<std::size_t>(1, r.epochs_solved),
                 r.time_to_first_fix_s.value_or(0.0) / 60.0);
  }
  os << "notes:\n";
  // Notes and problems quote header text of the input files (printable, io/untrusted_text.h).
  const std::size_t whole = std::numeric_limits<std::size_t>::max();
  for (const auto& n : r.notes) os << "  " << printableText(n, whole) << "\n";
  if (!r.problems.empty()) {
    os << "problems (" << r.problems.size() << "):\n";
    for (std::size_t i = 0; i < r.problems.size() && i < 20; ++i) os << "  " << printableText(r.problems[i], whole) << "\n";
  }
  return os.str();
}

}  // namespace ppp
