#include "ppp_bayes_tree/app/campaign_summary.h"

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <tuple>

#include <yaml-cpp/yaml.h>

#include "ppp_bayes_tree/evaluation/json_text.h"
#include "ppp_bayes_tree/evaluation/monte_carlo_records.h"
#include "ppp_bayes_tree/types/number_text.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace fs = std::filesystem;
namespace {

std::string fmt(const char* f, double v) {
  if (!std::isfinite(v)) return std::isinf(v) ? "never" : "";
  return format(f, v);
}

std::string csvField(std::string s) {
  for (auto& c : s)
    if (c == '"') c = '\'';
  return "\"" + s + "\"";
}

/// Per-flight wall times of a shard (timing.json), by flight index.
/// A flight's wall times: the simulation's, then each studied estimator's.
struct FlightTimes {
  double simulate_s = 0.0;
  std::array<double, kMonteCarloStudy.size()> estimator_s{};
};

void readFlightTimes(const std::string& job_dir, std::map<int, FlightTimes>& times) {
  try {
    const YAML::Node t = YAML::LoadFile((fs::path(job_dir) / "timing.json").string());
    for (const auto& f : t["flights"]) {
      FlightTimes ft;
      ft.simulate_s = f[1].as<double>();
      for (std::size_t i = 0; i < ft.estimator_s.size(); ++i) ft.estimator_s[i] = f[2 + i].as<double>();
      times[f[0].as<int>()] = ft;
    }
  } catch (const std::exception&) {
    // no timing: the merged study shows zero times
  }
}

/// The stale jobs (their old results are not shown) and the done jobs with problems.
void appendAttentionSections(const CampaignSummary& s, std::ostringstream& md) {
  if (s.stale > 0) {
    md << "## Stale (run the campaign again)\n\n";
    for (const auto& row : s.jobs)
      if (row.status.state == CampaignJobState::Stale) md << "- " << row.job.id << ": " << row.status.reason << "\n";
    md << "\n";
  }
  if (s.done_with_problems > 0) {
    md << "## Done with problems\n\n";
    for (const auto& row : s.jobs) {
      if (row.status.state != CampaignJobState::Done || !row.status.result || row.status.result->problems == 0) continue;
      const CampaignJobResult& r = *row.status.result;
      md << "- " << row.job.id << ": " << r.problems << " problem(s)"
         << (r.first_problem.empty() ? "" : ", the first: " + r.first_problem) << " (jobs/" << row.job.id
         << "/log.txt)\n";
    }
    md << "\n";
  }
}

std::string spreadText(const CampaignArSpread& s, double scale, const char* f) {
  if (s.count == 0) return "";
  std::string t = fmt(f, s.median * scale) + " / " + fmt(f, s.p90 * scale) + " / " + fmt(f, s.max * scale);
  if (s.never > 0) t += " (" + std::to_string(s.never) + " never)";
  return t;
}

std::string spreadJson(const CampaignArSpread& s) {
  auto number = [](double v) { return campaignFigureJson(v, 10); };
  return "{\"count\": " + std::to_string(s.count) + ", \"never\": " + std::to_string(s.never) +
         ", \"median\": " + number(s.median) + ", \"p90\": " + number(s.p90) + ", \"max\": " + number(s.max) + "}";
}

/// "HH:MM" GPST of the job's start, "" for a whole file.
std::string startText(const CampaignJob& job) {
  if (!job.ppp.files.window.start) return "";
  const CalendarTime c = job.ppp.files.window.start->toCalendar();
  return format("%02d:%02d", c.hour, c.minute);
}

/// The PPP-AR distributions: per station, runs and solution; then over all stations.
void appendArSection(const CampaignSummary& s, std::ostringstream& md) {
  const std::vector<CampaignArDistribution> dist = campaignArDistributions(s);
  if (dist.empty()) return;
  md << "## PPP-AR\n\nPer station and over all stations (runs: restarts = jobs from a start time, whole = whole "
        "files). Median / p90 / max over the runs; a run that never fixed (never stayed below 10 cm) counts as "
        "never. A wrong fixed epoch is a fixed epoch more than 10 cm 3D from the job's truth.\n\n"
        "| station | runs | solution | runs | fixed epochs | wrong fixed epochs (runs) | first fix [min] | "
        "below 10 cm for good [min] | mean 3D [cm] |\n|---|---|---|---:|---:|---:|---|---|---|\n";
  for (const auto& d : dist)
    md << "| " << d.station << " | " << d.runs << " | " << d.solution << " | " << d.run_count << " | " << d.fixed_epochs
       << "/" << d.solved_epochs << " | " << d.wrong_fixed_epochs << " (" << d.runs_with_wrong_fix << ") | "
       << spreadText(d.first_fix_s, 1.0 / 60.0, "%.1f") << " | " << spreadText(d.below_10cm_s, 1.0 / 60.0, "%.1f")
       << " | " << spreadText(d.mean_3d_m, 100.0, "%.2f") << " |\n";
  md << "\nPer job and solution: summary_ar.csv.\n\n";
  bool any_wrong = false;
  for (const auto& row : s.jobs)
    if (row.status.result)
      for (const auto& f : row.status.result->solutions)
        if (f.wrong_fixed_epochs > 0) {
          if (!any_wrong) md << "Runs with wrong fixed epochs:\n\n";
          any_wrong = true;
          md << "- " << row.job.id << " " << f.solution << ": " << f.wrong_fixed_epochs << " of " << f.fixed_epochs
             << " fixed epochs, the worst " << fmt("%.1f", f.worst_wrong_fix_m * 100.0) << " cm\n";
        }
  if (any_wrong) md << "\n";
}

}  // namespace

std::string campaignJobDir(const std::string& campaign_dir, const std::string& job_id) {
  return (fs::path(campaign_dir) / "jobs" / job_id).string();
}

const char* campaignRunsKind(const CampaignJob& job) { return job.ppp.files.window.start ? "restarts" : "whole"; }

std::vector<CampaignArDistribution> campaignArDistributions(const CampaignSummary& s) {
  struct Values {
    CampaignArDistribution d;
    std::vector<double> first_fix_s, below_s, mean_m;
  };
  std::vector<Values> groups;
  std::map<std::tuple<std::string, std::string, std::string>, std::size_t> index;
  auto add = [&](const std::string& station, const char* runs, const CampaignArFigures& f) {
    const auto key = std::make_tuple(station, std::string(runs), f.solution);
    auto it = index.find(key);
    if (it == index.end()) {
      it = index.emplace(key, groups.size()).first;
      groups.push_back({});
      groups.back().d.station = station;
      groups.back().d.runs = runs;
      groups.back().d.solution = f.solution;
    }
    Values& v = groups[it->second];
    addCampaignArRun(f, v.first_fix_s, v.below_s, v.mean_m, v.d);
  };
  for (const std::string pass : {"station", "all"})
    for (const auto& row : s.jobs) {
      if (row.status.state != CampaignJobState::Done || !row.status.result) continue;
      for (const auto& f : row.status.result->solutions)
        add(pass == "all" ? "all" : row.job.group, campaignRunsKind(row.job), f);
    }
  std::vector<CampaignArDistribution> out;
  for (auto& v : groups) {
    v.d.first_fix_s = campaignArSpread(v.first_fix_s);
    v.d.below_10cm_s = campaignArSpread(v.below_s);
    v.d.mean_3d_m = campaignArSpread(v.mean_m);
    out.push_back(v.d);
  }
  return out;
}

std::string campaignArSummaryCsv(const CampaignSummary& s) {
  std::ostringstream os;
  os << "id,group,date,start,runs,solution,solved_epochs,fixed_epochs,wrong_fixed_epochs,first_fix_min,"
        "below_10cm_min,mean_3d_cm,worst_wrong_fix_cm\n";
  for (const auto& row : s.jobs) {
    if (row.status.state != CampaignJobState::Done || !row.status.result) continue;
    for (const auto& f : row.status.result->solutions)
      os << row.job.id << ',' << row.job.group << ',' << row.job.date << ',' << startText(row.job) << ','
         << campaignRunsKind(row.job) << ',' << f.solution << ',' << f.solved_epochs << ',' << f.fixed_epochs << ','
         << f.wrong_fixed_epochs << ',' << fmt("%.2f", f.first_fix_s / 60.0) << ',' << fmt("%.2f", f.below_10cm_s / 60.0)
         << ',' << fmt("%.2f", f.mean_3d_m * 100.0) << ',' << fmt("%.2f", f.worst_wrong_fix_m * 100.0) << '\n';
  }
  return os.str();
}

CampaignSummary summarizeCampaign(const CampaignManifest& manifest, const std::string& campaign_dir) {
  CampaignSummary s;
  s.name = manifest.name;
  std::vector<std::string> study_order;
  for (const auto& job : manifest.jobs) {
    CampaignJobRow row{job, campaignJobStatus(campaignJobDir(campaign_dir, job.id), job)};
    switch (row.status.state) {
      case CampaignJobState::Done:
        ++s.done;
        s.done_with_problems += row.status.result && row.status.result->problems > 0;
        break;
      case CampaignJobState::Stale: ++s.stale; break;
      case CampaignJobState::Failed: ++s.failed; break;
      case CampaignJobState::Interrupted: ++s.interrupted; break;
      case CampaignJobState::Pending: ++s.pending; break;
    }
    s.jobs.push_back(std::move(row));
  }
  std::map<std::string, std::vector<const CampaignJobRow*>> shards;
  for (const auto& row : s.jobs) {
    if (row.job.kind != CampaignJobKind::MonteCarloShard) continue;
    if (!shards.count(row.job.group)) study_order.push_back(row.job.group);
    shards[row.job.group].push_back(&row);
  }
  for (const auto& study : study_order) {
    const auto& list = shards[study];
    CampaignStudyRow row;
    row.study = study;
    row.shards = static_cast<int>(list.size());
    for (const auto* r : list) row.shards_done += r->status.state == CampaignJobState::Done;
    if (row.shards_done == row.shards) {
      try {
        const MonteCarloOptions options = monteCarloStudyOptions(list.front()->job.monte_carlo);
        std::vector<std::vector<MonteCarloFlightRun>> records;
        std::map<int, FlightTimes> times;
        for (const auto* r : list) {
          const std::string dir = campaignJobDir(campaign_dir, r->job.id);
          records.push_back(readMonteCarloFlightRecords((fs::path(dir) / "output" / "flights.mcr").string(), options));
          readFlightTimes(dir, times);
        }
        MonteCarloResult merged = mergeMonteCarloShards(options, std::move(records));
        for (auto& f : merged.flights) {
          auto it = times.find(f.setup.index);
          if (it == times.end()) continue;
          f.simulate_s = it->second.simulate_s;
          f.estimator_s = it->second.estimator_s;
          merged.summary.simulate_s += f.simulate_s;
          for (std::size_t i = 0; i < f.estimator_s.size(); ++i) merged.summary.estimator_s[i] += f.estimator_s[i];
        }
        merged.threads_used = 1;
        row.merged = std::move(merged);
      } catch (const std::exception& e) {
        row.problem = e.what();
      }
    }
    s.studies.push_back(std::move(row));
  }
  return s;
}

std::string campaignSummaryCsv(const CampaignSummary& s) {
  std::ostringstream os;
  os << "id,kind,group,date,hour,state,epochs_read,epochs_solved,mean_3d_cm,first15_mean_3d_cm,time_to_10cm_min,"
        "fixed_share,flights,flights_failed,reason\n";
  for (const auto& row : s.jobs) {
    const CampaignJob& j = row.job;
    os << j.id << ',' << toString(j.kind) << ',' << j.group << ',' << j.date << ','
       << (j.hour >= 0 ? std::to_string(j.hour) : "") << ',' << toString(row.status.state) << ',';
    if (row.status.result) {
      const CampaignJobResult& r = *row.status.result;
      if (j.kind != CampaignJobKind::MonteCarloShard) {
        os << r.epochs_read << ',' << r.epochs_solved << ',' << fmt("%.2f", r.mean_3d_m * 100.0) << ','
           << fmt("%.2f", r.first_window_mean_3d_m * 100.0) << ',' << fmt("%.2f", r.time_to_10cm_s / 60.0) << ','
           << fmt("%.4f", r.fixed_share) << ",,";
      } else {
        os << ",,,,,," << r.flights << ',' << r.flights_failed;
      }
    } else {
      os << ",,,,,,,";
    }
    os << ',' << (row.status.reason.empty() ? "" : csvField(row.status.reason)) << '\n';
  }
  return os.str();
}

std::string campaignSummaryJson(const CampaignSummary& s) {
  std::ostringstream j;
  j << "{\n  \"campaign\": " << jsonString(s.name) << ",\n  \"jobs_total\": " << s.jobs.size()
    << ", \"done\": " << s.done << ", \"failed\": " << s.failed << ", \"interrupted\": " << s.interrupted
    << ", \"pending\": " << s.pending;
  if (s.stale > 0) j << ", \"stale\": " << s.stale;
  if (s.done_with_problems > 0) j << ", \"done_with_problems\": " << s.done_with_problems;
  j << ",\n  \"jobs\": [";
  for (std::size_t i = 0; i < s.jobs.size(); ++i) {
    const auto& row = s.jobs[i];
    const CampaignJob& job = row.job;
    j << (i ? "," : "") << "\n    {\"id\": " << jsonString(job.id) << ", \"kind\": " << jsonString(toString(job.kind))
      << ", \"group\": " << jsonString(job.group) << ", \"date\": " << jsonString(job.date)
      << ", \"hour\": " << (job.hour >= 0 ? std::to_string(job.hour) : "null")
      << ", \"state\": " << jsonString(toString(row.status.state));
    if (row.status.result) {
      const CampaignJobResult& r = *row.status.result;
      if (job.kind != CampaignJobKind::MonteCarloShard)
        j << ", \"epochs_read\": " << r.epochs_read << ", \"epochs_solved\": " << r.epochs_solved
          << ", \"problems\": " << r.problems << ", \"mean_3d_m\": " << jsonNumber(r.mean_3d_m, 10)
          << ", \"first_window_mean_3d_m\": " << jsonNumber(r.first_window_mean_3d_m, 10) << ", \"time_to_10cm_s\": "
          << (std::isinf(r.time_to_10cm_s) ? "\"never\"" : jsonNumber(r.time_to_10cm_s, 10))
          << ", \"fixed_share\": " << jsonNumber(r.fixed_share, 10)
          << (r.first_problem.empty() ? "" : ", \"first_problem\": " + jsonString(r.first_problem));
      if (job.kind != CampaignJobKind::MonteCarloShard && !r.solutions.empty()) j << ", \"solutions\": " << campaignArFiguresJson(r.solutions, 10);
      else
        j << ", \"flights\": " << r.flights << ", \"flights_failed\": " << r.flights_failed;
    }
    if (!row.status.reason.empty()) j << ", \"reason\": " << jsonString(row.status.reason);
    j << "}";
  }
  j << "\n  ],\n  \"ar_distributions\": [";
  const std::vector<CampaignArDistribution> dist = campaignArDistributions(s);
  for (std::size_t i = 0; i < dist.size(); ++i) {
    const CampaignArDistribution& d = dist[i];
    j << (i ? "," : "") << "\n    {\"station\": " << jsonString(d.station) << ", \"runs\": " << jsonString(d.runs)
      << ", \"solution\": " << jsonString(d.solution) << ", \"run_count\": " << d.run_count
      << ", \"solved_epochs\": " << d.solved_epochs << ", \"fixed_epochs\": " << d.fixed_epochs
      << ", \"wrong_fixed_epochs\": " << d.wrong_fixed_epochs << ", \"runs_with_wrong_fix\": " << d.runs_with_wrong_fix
      << ", \"first_fix_s\": " << spreadJson(d.first_fix_s) << ", \"below_10cm_s\": " << spreadJson(d.below_10cm_s)
      << ", \"mean_3d_m\": " << spreadJson(d.mean_3d_m) << "}";
  }
  j << "\n  ],\n  \"monte_carlo\": [";
  for (std::size_t i = 0; i < s.studies.size(); ++i) {
    const auto& st = s.studies[i];
    j << (i ? "," : "") << "\n    {\"study\": " << jsonString(st.study) << ", \"shards\": " << st.shards
      << ", \"shards_done\": " << st.shards_done;
    if (!st.problem.empty()) j << ", \"problem\": " << jsonString(st.problem);
    if (st.merged) {
      const MonteCarloSummary& m = st.merged->summary;
      j << ", \"flights\": " << m.flights << ", \"failed\": " << m.failed << ", \"estimators\": {";
      for (int e = 0; e < kMonteCarloEstimators; ++e) {
        const auto k = static_cast<std::size_t>(e);
        j << (e ? ", " : "") << jsonString(monteCarloEstimatorKey(e)) << ": {\"mean_3d_m\": "
          << jsonNumber(m.all[k].mean_m, 10) << ", \"first_window_median_3d_m\": " << jsonNumber(m.first_window[k].median_m, 10)
          << ", \"first_window_mean_3d_m\": " << jsonNumber(m.first_window[k].mean_m, 10) << "}";
      }
      j << "}, \"outputs\": " << jsonString("monte_carlo/" + st.study);
    }
    j << "}";
  }
  j << "\n  ]\n}\n";
  return j.str();
}

std::string campaignSummaryMarkdown(const CampaignSummary& s) {
  std::ostringstream md;
  md << "# Campaign " << s.name << "\n\n" << s.jobs.size() << " jobs: " << s.done << " done";
  if (s.done_with_problems > 0) md << " (" << s.done_with_problems << " with problems)";
  md << ", " << s.failed << " failed, " << s.interrupted << " interrupted, ";
  if (s.stale > 0) md << s.stale << " stale, ";
  md << s.pending << " not run.\n\n";
  bool any_ppp = false;
  for (const auto& row : s.jobs) any_ppp |= row.job.kind != CampaignJobKind::MonteCarloShard;
  if (any_ppp) {
    md << "| job | station | date | start | state | epochs solved | mean 3D [cm] | first 15 min mean [cm] | < 10 cm from "
          "[min] | fixed share |\n|---|---|---|---:|---|---:|---:|---:|---:|---:|\n";
    for (const auto& row : s.jobs) {
      if (row.job.kind == CampaignJobKind::MonteCarloShard) continue;
      md << "| " << row.job.id << " | " << row.job.group << " | " << row.job.date << " | "
         << startText(row.job) << " | " << toString(row.status.state) << " | ";
      if (row.status.result) {
        const CampaignJobResult& r = *row.status.result;
        md << r.epochs_solved << "/" << r.epochs_read << " | " << fmt("%.2f", r.mean_3d_m * 100.0) << " | "
           << fmt("%.2f", r.first_window_mean_3d_m * 100.0) << " | " << fmt("%.1f", r.time_to_10cm_s / 60.0) << " | "
           << fmt("%.3f", r.fixed_share) << " |\n";
      } else {
        md << " | | | | |\n";
      }
    }
    md << "\nErrors need a truth: the manifest's, or a bag's truth/path (empty otherwise).\n\n";
  }
  for (const auto& st : s.studies) {
    md << "## Monte Carlo study " << st.study << ": " << st.shards_done << " of " << st.shards << " shards done\n\n";
    if (!st.problem.empty()) md << "Not merged: " << st.problem << "\n\n";
    if (!st.merged) continue;
    const MonteCarloSummary& m = st.merged->summary;
    md << m.flights << " flights (" << m.failed << " failed); tables in monte_carlo/" << st.study << "/summary.md\n\n"
       << "| estimator | mean 3D [cm] | first 15 min median [cm] | first 15 min mean [cm] |\n|---|---:|---:|---:|\n";
    for (int e = 0; e < kMonteCarloEstimators; ++e) {
      const auto k = static_cast<std::size_t>(e);
      md << "| " << monteCarloEstimatorLabel(e) << " | " << fmt("%.2f", m.all[k].mean_m * 100.0) << " | "
         << fmt("%.2f", m.first_window[k].median_m * 100.0) << " | " << fmt("%.2f", m.first_window[k].mean_m * 100.0)
         << " |\n";
    }
    md << "\n";
  }
  appendArSection(s, md);
  if (s.failed + s.interrupted > 0) {
    md << "## Failures\n\n";
    for (const auto& row : s.jobs)
      if (row.status.state == CampaignJobState::Failed || row.status.state == CampaignJobState::Interrupted)
        md << "- " << row.job.id << " (" << toString(row.status.state) << "): " << row.status.reason << "\n";
    md << "\n";
  }
  appendAttentionSections(s, md);
  return md.str();
}

void writeCampaignSummary(const CampaignSummary& s, const std::string& dir) {
  fs::create_directories(dir);
  writeFileAtomically((fs::path(dir) / "summary.csv").string(), campaignSummaryCsv(s));
  writeFileAtomically((fs::path(dir) / "summary.json").string(), campaignSummaryJson(s));
  writeFileAtomically((fs::path(dir) / "summary.md").string(), campaignSummaryMarkdown(s));
  writeFileAtomically((fs::path(dir) / "summary_ar.csv").string(), campaignArSummaryCsv(s));
  for (const auto& st : s.studies)
    if (st.merged) writeMonteCarloOutputs(*st.merged, (fs::path(dir) / "monte_carlo" / st.study).string());
}

std::string formatCampaignProgress(const CampaignProgress& p) {
  const int finished = p.done + p.failed;
  const int waiting = std::max(0, p.total - finished - p.running);
  std::string left = "?";
  if (finished > 0) left = minutesSecondsText(p.elapsed_s / finished * (p.total - finished));
  if (finished == p.total) left = "0:00";
  const std::string problems =
      p.done_with_problems > 0 ? std::to_string(p.done_with_problems) + " with problems, " : std::string();
  return std::to_string(p.done) + "/" + std::to_string(p.total) + " done, " + problems + std::to_string(p.failed) + " failed, " +
         std::to_string(p.running) + " running, " + std::to_string(waiting) + " waiting; " + minutesSecondsText(p.elapsed_s) +
         " elapsed, ~" + left + " left";
}

}  // namespace ppp
