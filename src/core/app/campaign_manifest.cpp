#include "ppp_bayes_tree/app/campaign_manifest.h"

#include <glob.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>

#include "ppp_bayes_tree/app/campaign_job.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"
#include "ppp_bayes_tree/ppp/config/yaml_document.h"
#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/simulation/flight_trajectory.h"

namespace ppp {
namespace fs = std::filesystem;

const char* toString(CampaignJobKind kind) {
  switch (kind) {
    case CampaignJobKind::Ppp: return "ppp";
    case CampaignJobKind::Bag: return "bag";
    case CampaignJobKind::MonteCarloShard: return "monte_carlo";
  }
  return "unknown";
}

namespace {

const std::set<std::string> kTopKeys = {"campaign", "slurm", "ppp", "bags", "monte_carlo"};

/// The value of `key` in a mapping, a null node when absent (never yaml-cpp's invalid node).
YAML::Node childOrNull(const YAML::Node& map, const std::string& key) {
  for (const auto& kv : map)
    if (kv.first.as<std::string>() == key) return kv.second;
  return YAML::Node();
}

std::string lineText(const YAML::Node& node) { return "line " + std::to_string(node.Mark().line + 1); }

/// A day of a date range, with the placeholder values of its paths.
struct CampaignDay {
  GnssTime midnight;  // 00:00 GPST
  std::string date;   // YYYY-MM-DD
};

std::optional<GnssTime> parseDate(const std::string& text) {
  int y = 0, m = 0, d = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%4d-%2d-%2d%c", &y, &m, &d, &tail) != 3) return std::nullopt;
  char slashed[32];
  std::snprintf(slashed, sizeof slashed, "%04d/%02d/%02d", y, m, d);
  return parseReferenceDate(slashed);
}

std::string dateText(const GnssTime& t) {
  const CalendarTime c = t.toCalendar();
  char b[16];
  std::snprintf(b, sizeof b, "%04d-%02d-%02d", c.year, c.month, c.day);
  return b;
}

/// {yyyy} {yy} {doy} {mm} {dd} {gpsweek} {dow} of `day` in `pattern`.
std::string substituteDay(std::string pattern, const std::optional<CampaignDay>& day) {
  if (!day) return pattern;
  const CalendarTime c = day->midnight.toCalendar();
  const GpsWeekTime w = day->midnight.gpsWeek();
  char b[16];
  const std::pair<const char*, std::string> values[] = {
      {"{yyyy}", (std::snprintf(b, sizeof b, "%04d", c.year), b)},
      {"{yy}", (std::snprintf(b, sizeof b, "%02d", c.year % 100), b)},
      {"{doy}", (std::snprintf(b, sizeof b, "%03d", day->midnight.dayOfYear()), b)},
      {"{mm}", (std::snprintf(b, sizeof b, "%02d", c.month), b)},
      {"{dd}", (std::snprintf(b, sizeof b, "%02d", c.day), b)},
      {"{gpsweek}", (std::snprintf(b, sizeof b, "%04d", w.week), b)},
      {"{dow}", (std::snprintf(b, sizeof b, "%d", static_cast<int>(w.seconds_of_week / 86400.0)), b)}};
  for (const auto& [key, value] : values)
    for (std::size_t at = pattern.find(key); at != std::string::npos; at = pattern.find(key, at + value.size()))
      pattern.replace(at, std::string(key).size(), value);
  return pattern;
}

std::string resolve(const std::string& root, const std::string& path) {
  if (path.empty() || fs::path(path).is_absolute()) return path;
  return (fs::path(root) / path).lexically_normal().string();
}

bool isGlob(const std::string& p) { return p.find_first_of("*?[") != std::string::npos; }

/// The files a pattern names (sorted); the pattern itself when it is no glob or
/// matches nothing (the input check then names it).
std::vector<std::string> expandGlob(const std::string& pattern) {
  if (!isGlob(pattern)) return {pattern};
  glob_t g{};
  std::vector<std::string> out;
  if (::glob(pattern.c_str(), 0, nullptr, &g) == 0)
    for (std::size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
  ::globfree(&g);
  std::sort(out.begin(), out.end());
  if (out.empty()) out.push_back(pattern);
  return out;
}

bool validId(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
           return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
         }) && s[0] != '.';
}

std::string fileStem(const std::string& path) {
  std::string stem = fs::path(path).filename().string();
  for (const char* ext : {".gz", ".Z", ".crx", ".rnx", ".CRX", ".RNX", ".bag"})
    if (stem.size() > std::string(ext).size() && stem.compare(stem.size() - std::string(ext).size(), std::string::npos, ext) == 0)
      stem.resize(stem.size() - std::string(ext).size());
  for (char& c : stem)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
  return stem;
}

/// A time window of a day a ppp entry is split into (`hours` or `restarts`).
struct CampaignWindow {
  std::string id_suffix;  // "_h03", "_r0030"
  int hour = -1;          // hourly windows: the hour
  double start_s = 0.0;   // since the day's 00:00 GPST
  std::optional<double> end_s;  // none: to the end of the observations
};

/// A ppp entry of the manifest before expansion.
struct PppEntry {
  std::string station, obs, format = "rinex", estimator = "ekf";
  std::vector<std::string> sp3, clk, nav, atx, config;
  std::string bia, blq;
  std::optional<Eigen::Vector3d> truth;
  std::vector<CampaignDay> days;  // empty: no dates
  int first_hour = -1, last_hour = -1;
  std::vector<CampaignWindow> restarts;  // empty: no restarts
};

/// A date of the manifest: YYYY-MM-DD within kFirstCampaignDate .. kLastCampaignDate.
GnssTime readDate(YamlSection& dates, const char* key, const std::string& text, const YAML::Node& node) {
  const auto t = parseDate(text);
  if (!t) dates.fail(key, "needs a date YYYY-MM-DD (" + lineText(node) + "), not '" + text + "'");
  if (*t < *parseDate(kFirstCampaignDate) || *t > *parseDate(kLastCampaignDate))
    dates.fail(key, "'" + text + "' is outside " + kFirstCampaignDate + " (the start of GPS time) .. " +
                        kLastCampaignDate + " (" + lineText(node) + ")");
  return *t;
}

std::vector<CampaignDay> readDates(YamlSection dates, const YAML::Node& node) {
  const std::string first_text = dates.text("first", ""), last_text = dates.text("last", first_text);
  dates.finish();
  const std::optional<GnssTime> first = readDate(dates, "first", first_text, node),
                                last = readDate(dates, "last", last_text, node);
  if (*last < *first) dates.fail("last", "is before first (" + lineText(node) + ")");
  if (*last - *first > 3660.0 * 86400.0) dates.fail("last", "more than ten years after first (" + lineText(node) + ")");
  std::vector<CampaignDay> days;
  for (GnssTime t = *first; t <= *last; t += 86400.0) days.push_back({t, dateText(t)});
  return days;
}

/// "HH:MM" of a day in minutes 0..1439; nullopt when the text is not that.
std::optional<int> minuteOfDay(const std::string& text) {
  int h = 0, m = 0;
  char tail = 0;
  if (text.size() != 5 || std::sscanf(text.c_str(), "%2d:%2d%c", &h, &m, &tail) != 2) return std::nullopt;
  if (h < 0 || h > 23 || m < 0 || m > 59) return std::nullopt;
  return h * 60 + m;
}

/// The restart windows of `restarts: {first: "HH:MM", last: "HH:MM", every_min: N, length_min: M}`.
std::vector<CampaignWindow> readRestarts(YamlSection r, const YAML::Node& node) {
  const std::string first_text = r.text("first", "00:00"), last_text = r.text("last", first_text);
  const int every_min = r.integer("every_min", 60, 1);
  const int length_min = r.integer("length_min", 0, 0);
  r.finish();
  const auto first = minuteOfDay(first_text), last = minuteOfDay(last_text);
  if (!first) r.fail("first", "needs a time of day \"HH:MM\" (" + lineText(node) + "), not '" + first_text + "'");
  if (!last) r.fail("last", "needs a time of day \"HH:MM\" (" + lineText(node) + "), not '" + last_text + "'");
  if (*last < *first) r.fail("last", "is before first (" + lineText(node) + ")");
  std::vector<CampaignWindow> windows;
  for (int m = *first; m <= *last; m += every_min) {
    CampaignWindow w;
    char b[16];
    std::snprintf(b, sizeof b, "_r%02d%02d", m / 60, m % 60);
    w.id_suffix = b;
    w.start_s = 60.0 * m;
    if (length_min > 0) w.end_s = 60.0 * (m + length_min);
    windows.push_back(w);
  }
  return windows;
}

PppEntry readPppEntry(const YAML::Node& node, const std::string& file, const std::string& path) {
  YamlSection s(node, file, path);
  PppEntry e;
  e.station = s.text("station", "");
  if (!validId(e.station)) s.fail("station", "needs a name of letters, digits, '-', '_' or '.' (" + lineText(node) + ")");
  e.obs = s.text("obs", "");
  if (e.obs.empty()) s.fail("obs", "an observation file (or glob) is required (" + lineText(node) + ")");
  e.format = s.choice("format", "rinex", {"rinex", "rtcm", "ubx"});
  e.estimator = s.choice("estimator", std::string(kDefaultEstimator), estimatorChoices());
  e.sp3 = s.textList("sp3", {}, true);
  e.clk = s.textList("clk", {}, true);
  e.nav = s.textList("nav", {}, true);
  e.atx = s.textList("atx", {});
  e.config = s.textList("config", {}, true);
  e.bia = s.text("bia", "");
  e.blq = s.text("blq", "");
  if (s.has("truth")) {
    const auto t = s.numberList("truth", {}, 3);
    e.truth = Eigen::Vector3d(t[0], t[1], t[2]);
  }
  if (e.nav.empty() && (e.sp3.empty() || e.clk.empty()))
    s.fail("sp3", "sp3 and clk (or nav) are required (" + lineText(node) + ")");
  if (!e.nav.empty() && (!e.sp3.empty() || !e.clk.empty()))
    s.fail("nav", "give either sp3/clk or nav, not both (" + lineText(node) + ")");
  if (s.has("dates")) e.days = readDates(s.section("dates"), node["dates"]);
  if (s.has("hours")) {
    const auto h = s.numberList("hours", {}, 2);
    if (h[0] != static_cast<int>(h[0]) || h[1] != static_cast<int>(h[1]) || h[0] < 0 || h[1] > 23 || h[1] < h[0])
      s.fail("hours", "needs [first, last] whole hours 0..23, first <= last (" + lineText(node) + ")");
    if (e.days.empty()) s.fail("hours", "hourly jobs need dates: {first, last} (the day of each hour; " + lineText(node) + ")");
    e.first_hour = static_cast<int>(h[0]);
    e.last_hour = static_cast<int>(h[1]);
  }
  if (s.has("restarts")) {
    if (e.first_hour >= 0) s.fail("restarts", "give hours or restarts, not both (" + lineText(node) + ")");
    e.restarts = readRestarts(s.section("restarts"), node["restarts"]);
    if (e.days.empty()) s.fail("restarts", "restart windows need dates: {first, last} (the day of each; " + lineText(node) + ")");
  }
  s.finish();
  return e;
}

std::vector<std::string> expandAll(const std::vector<std::string>& patterns, const std::string& root,
                                   const std::optional<CampaignDay>& day) {
  std::vector<std::string> out;
  for (const auto& p : patterns)
    for (auto& f : expandGlob(resolve(root, substituteDay(p, day)))) out.push_back(std::move(f));
  return out;
}

/// Refuses a manifest that would expand to more than kMaxCampaignJobs jobs, before they are made.
void checkJobCount(std::size_t jobs_so_far, std::uint64_t more, const std::string& file, const std::string& key) {
  if (jobs_so_far + more <= kMaxCampaignJobs) return;
  throw ConfigError(file, key,
                    "the campaign would have more than " + std::to_string(kMaxCampaignJobs) + " jobs (" +
                        std::to_string(jobs_so_far) + " before this entry, " + std::to_string(more) +
                        " from it): split it into several campaigns");
}

/// Refuses jobs of one entry that would read the same observations for different
/// dates (a dated range whose obs path has no date placeholder): every day's job
/// would solve the same file and be labelled with its own date.
void checkDistinctInputs(const std::vector<CampaignJob>& jobs, std::size_t from, const std::string& file,
                         const std::string& key) {
  std::map<std::string, const CampaignJob*> seen;
  for (std::size_t k = from; k < jobs.size(); ++k) {
    const PppInputFiles& f = jobs[k].ppp.files;
    std::string input = f.obs + "|";
    if (f.window.start) input += std::to_string(f.window.start->wholeSeconds());
    const auto [it, fresh] = seen.emplace(input, &jobs[k]);
    if (fresh) continue;
    throw ConfigError(file, key + ".obs",
                      "jobs " + it->second->id + " and " + jobs[k].id + " (dates " + it->second->date + " and " +
                          jobs[k].date + ") read the same file " + f.obs +
                          ": give the path the day's placeholders ({yyyy} {yy} {doy} {mm} {dd} {gpsweek} {dow})");
  }
}

/// The time windows an entry splits each day into: its hours or its restarts; none: the whole file.
std::vector<CampaignWindow> entryWindows(const PppEntry& e) {
  if (!e.restarts.empty()) return e.restarts;
  std::vector<CampaignWindow> windows;
  for (int h = e.first_hour; h >= 0 && h <= e.last_hour; ++h) {
    CampaignWindow w;
    char b[16];
    std::snprintf(b, sizeof b, "_h%02d", h);
    w.id_suffix = b;
    w.hour = h;
    w.start_s = 3600.0 * h;
    w.end_s = 3600.0 * (h + 1);
    windows.push_back(w);
  }
  return windows;
}

void expandPppEntry(const PppEntry& e, const std::string& data_root, const std::string& manifest_dir,
                    std::vector<CampaignJob>& jobs, const std::string& file, const std::string& key) {
  const std::size_t first_job = jobs.size();
  std::vector<std::optional<CampaignDay>> days;
  if (e.days.empty()) days.push_back(std::nullopt);
  for (const auto& d : e.days) days.push_back(d);
  for (const auto& day : days) {
    const std::vector<std::string> obs_files = expandGlob(resolve(data_root, substituteDay(e.obs, day)));
    const std::vector<CampaignWindow> windows = entryWindows(e);
    checkJobCount(jobs.size(), obs_files.size() * static_cast<std::uint64_t>(std::max<std::size_t>(1, windows.size())),
                  file, key);
    for (const auto& obs : obs_files) {
      CampaignJob job;
      job.kind = CampaignJobKind::Ppp;
      job.group = e.station;
      job.date = day ? day->date : "";
      std::string id = e.station;
      if (day) {
        char b[16];
        std::snprintf(b, sizeof b, "_%s-%03d", day->date.substr(0, 4).c_str(), day->midnight.dayOfYear());
        id += b;
      }
      if (obs_files.size() > 1) id += "_" + fileStem(obs);
      PppInputFiles& f = job.ppp.files;
      f.obs = obs;
      f.obs_format = e.format == "rtcm" ? ObservationFormat::Rtcm3 : e.format == "ubx" ? ObservationFormat::Ubx
                                                                                        : ObservationFormat::Rinex;
      if (day && f.obs_format == ObservationFormat::Rtcm3) f.rtcm_reference_time = day->midnight;
      f.sp3 = expandAll(e.sp3, data_root, day);
      f.clk = expandAll(e.clk, data_root, day);
      f.nav = expandAll(e.nav, data_root, day);
      f.atx = expandAll(e.atx, data_root, day);
      if (!e.bia.empty()) f.bias = expandAll({e.bia}, data_root, day).front();
      if (!e.blq.empty()) f.blq = expandAll({e.blq}, data_root, day).front();
      for (const auto& c : e.config) job.ppp.config.push_back(resolve(manifest_dir, c));
      job.ppp.estimator = e.estimator;
      job.ppp.truth_ecef_m = e.truth;
      if (windows.empty()) {
        job.id = id;
        jobs.push_back(job);
        continue;
      }
      for (const auto& w : windows) {
        CampaignJob windowed = job;
        windowed.id = id + w.id_suffix;
        windowed.hour = w.hour;
        windowed.ppp.files.window.start = day->midnight + w.start_s;
        if (w.end_s) windowed.ppp.files.window.end = day->midnight + *w.end_s;
        jobs.push_back(windowed);
      }
    }
  }
  if (!e.days.empty()) checkDistinctInputs(jobs, first_job, file, key);
}

/// A bags entry: one job per bag the pattern matches.
void expandBagEntry(const YAML::Node& node, const std::string& file, const std::string& path,
                    const std::string& data_root, const std::string& manifest_dir, std::vector<CampaignJob>& jobs) {
  YamlSection s(node, file, path);
  const std::string name = s.text("name", "");
  if (!validId(name)) s.fail("name", "needs a name of letters, digits, '-', '_' or '.' (" + lineText(node) + ")");
  const std::string pattern = s.text("bag", "");
  if (pattern.empty()) s.fail("bag", "a bag (or glob) is required (" + lineText(node) + ")");
  CampaignJob job;
  job.kind = CampaignJobKind::Bag;
  job.group = name;
  PppInputFiles& f = job.ppp.files;
  f.atx = expandAll(s.textList("atx", {}), data_root, std::nullopt);
  if (const std::string b = s.text("bia", ""); !b.empty()) f.bias = expandAll({b}, data_root, std::nullopt).front();
  if (const std::string b = s.text("blq", ""); !b.empty()) f.blq = expandAll({b}, data_root, std::nullopt).front();
  for (const auto& c : s.textList("config", {}, true)) job.ppp.config.push_back(resolve(manifest_dir, c));
  job.ppp.estimator = s.choice("estimator", std::string(kDefaultEstimator), estimatorChoices());
  if (s.has("truth")) {
    const auto t = s.numberList("truth", {}, 3);
    job.ppp.truth_ecef_m = Eigen::Vector3d(t[0], t[1], t[2]);
  }
  if (const std::string t = s.text("truth_csv", ""); !t.empty()) {
    if (job.ppp.truth_ecef_m) s.fail("truth_csv", "give truth or truth_csv, not both (" + lineText(node) + ")");
    job.ppp.truth_csv = expandAll({t}, data_root, std::nullopt).front();
  }
  s.finish();
  const std::vector<std::string> bags = expandGlob(resolve(data_root, pattern));
  checkJobCount(jobs.size(), bags.size(), file, path);
  for (const auto& bag : bags) {
    CampaignJob b = job;
    b.id = bags.size() > 1 ? name + "_" + fileStem(bag) : name;
    b.ppp.files.obs = bag;
    jobs.push_back(std::move(b));
  }
}

void readMonteCarloEntry(const YAML::Node& node, const std::string& file, const std::string& path,
                         const std::string& manifest_dir, std::vector<CampaignJob>& jobs) {
  YamlSection s(node, file, path);
  const std::string study = s.text("study", "");
  if (!validId(study)) s.fail("study", "needs a name of letters, digits, '-', '_' or '.' (" + lineText(node) + ")");
  CampaignMonteCarloShard m;
  const double seed = s.number("seed", -1.0, Bound::NonNegative);
  if (seed < 0 || seed != static_cast<double>(static_cast<std::uint64_t>(seed)) || seed > 9.0e15)
    s.fail("seed", "needs an explicit whole seed 0..9e15 (" + lineText(node) + ")");
  m.seed = static_cast<std::uint64_t>(seed);
  m.study_flights = s.integer("flights", 0, 1);
  const int per_job = s.integer("flights_per_job", m.study_flights, 1);
  m.duration_min = s.number("duration_min", 30.0, Bound::Positive);
  if (m.duration_min > kMaxFlightDuration_min)
    s.fail("duration_min", "at most " + std::to_string(static_cast<int>(kMaxFlightDuration_min)) +
                               " (one day: the longest simulated flight; " + lineText(node) + ")");
  m.rate_hz = s.number("rate_hz", 1.0, Bound::Positive);
  if (m.rate_hz != 1.0 && m.rate_hz != 10.0) s.fail("rate_hz", "must be 1 or 10 (" + lineText(node) + ")");
  m.systems = s.has("systems") ? s.choice("systems", "G", {"G", "GE"}) : "";
  m.ambiguity_resolution = s.boolean("ambiguity_resolution", false);
  m.smoother_lag_s = s.number("smoother_lag_s", 60.0, Bound::NonNegative);
  m.profiles = s.textList("profiles", {}, true);
  for (const auto& p : m.profiles) {
    try {
      parseFlightProfile(p);
    } catch (const std::exception& ex) {
      s.fail("profiles", ex.what());
    }
  }
  m.config = resolve(manifest_dir, s.text("config", ""));
  m.sim_config = resolve(manifest_dir, s.text("sim_config", ""));
  s.finish();
  checkJobCount(jobs.size(), (static_cast<std::uint64_t>(m.study_flights) + per_job - 1) / per_job, file, path);
  for (int first = 0; first < m.study_flights; first += per_job) {
    CampaignJob job;
    job.kind = CampaignJobKind::MonteCarloShard;
    job.group = study;
    job.monte_carlo = m;
    job.monte_carlo.first_flight = first;
    job.monte_carlo.flights = std::min(per_job, m.study_flights - first);
    job.id = study + "_f" + std::to_string(first) + "-" + std::to_string(first + job.monte_carlo.flights - 1);
    jobs.push_back(job);
  }
}

CampaignResources readResources(YamlSection s) {
  CampaignResources r;
  r.partition = s.text("partition", r.partition);
  r.time_limit = s.text("time_limit", r.time_limit);
  if (!slurmTimeLimit_s(r.time_limit))
    s.fail("time_limit", "'" + r.time_limit + "' is no Slurm time limit (minutes, HH:MM:SS, D-HH:MM:SS or UNLIMITED)");
  r.mem = s.text("mem", r.mem);
  r.cpus_per_task = s.integer("cpus_per_task", r.cpus_per_task, 1);
  r.jobs_per_task = s.integer("jobs_per_task", r.jobs_per_task, 1);
  r.max_resubmits = s.integer("max_resubmits", r.max_resubmits, 0);
  s.finish();
  return r;
}

YAML::Node loadYamlFile(const std::string& path) {
  std::ifstream probe(path);
  if (!probe) throw FileOpenError("cannot open campaign manifest " + path);
  return loadYamlDocument(path);  // syntax errors and keys written twice: ConfigError naming the line
}

void problemIfMissing(const CampaignJob& job, const char* what, const std::string& path,
                      std::vector<std::string>& problems) {
  std::error_code ec;
  if (isGlob(path) && !fs::exists(path, ec)) {
    problems.push_back("job " + job.id + ": " + what + " " + path + ": the pattern matches no file");
    return;
  }
  if (!fs::is_regular_file(path, ec)) {
    problems.push_back("job " + job.id + ": " + what + " " + path + ": no such file");
    return;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) problems.push_back("job " + job.id + ": " + what + " " + path + ": cannot be read");
}

}  // namespace

CampaignManifest loadCampaignManifest(const std::string& path) {
  const YAML::Node doc = loadYamlFile(path);
  if (!doc.IsMap())
    throw ConfigError(path, "", "a campaign manifest is a mapping (campaign, slurm, ppp, bags, monte_carlo)");
  for (const auto& kv : doc) {
    const std::string key = kv.first.as<std::string>();
    if (!kTopKeys.count(key))
      throw ConfigError(path, key,
                        "unknown key (" + lineText(kv.first) + "; expected campaign, slurm, ppp, bags, monte_carlo)");
  }
  CampaignManifest m;
  m.path = path;
  const std::string manifest_dir = fs::absolute(path).parent_path().lexically_normal().string();
  YamlSection campaign(childOrNull(doc, "campaign"), path, "campaign");
  m.name = campaign.text("name", fs::path(path).stem().string());
  m.data_root = resolve(manifest_dir, campaign.text("data_root", manifest_dir));
  campaign.finish();
  m.resources = readResources(YamlSection(childOrNull(doc, "slurm"), path, "slurm"));
  for (const char* list : {"ppp", "bags", "monte_carlo"}) {
    const YAML::Node entries = childOrNull(doc, list);
    if (!entries.IsDefined() || entries.IsNull()) continue;
    if (!entries.IsSequence()) throw ConfigError(path, list, "must be a list of entries (" + lineText(entries) + ")");
    for (std::size_t i = 0; i < entries.size(); ++i) {
      const std::string key_path = std::string(list) + "[" + std::to_string(i) + "]";
      if (std::string(list) == "ppp")
        expandPppEntry(readPppEntry(entries[i], path, key_path), m.data_root, manifest_dir, m.jobs, path, key_path);
      else if (std::string(list) == "bags")
        expandBagEntry(entries[i], path, key_path, m.data_root, manifest_dir, m.jobs);
      else
        readMonteCarloEntry(entries[i], path, key_path, manifest_dir, m.jobs);
    }
  }
  if (m.jobs.empty()) throw ConfigError(path, "", "no jobs: give a ppp, bags or monte_carlo list");
  std::set<std::string> ids;
  for (const auto& j : m.jobs)
    if (!ids.insert(j.id).second)
      throw ConfigError(path, "", "two jobs have the id " + j.id + " (give the entries different station/study names)");
  return m;
}

std::optional<double> slurmTimeLimit_s(const std::string& text) {
  if (text == "UNLIMITED" || text == "INFINITE" || text == "unlimited" || text == "infinite")
    return std::numeric_limits<double>::infinity();
  // "D-" prefix, then up to three ':'-separated unsigned fields
  std::string rest = text;
  long days = 0;
  const auto dash = rest.find('-');
  if (dash != std::string::npos) {
    const std::string d = rest.substr(0, dash);
    if (d.empty() || d.find_first_not_of("0123456789") != std::string::npos || d.size() > 6) return std::nullopt;
    days = std::stol(d);
    rest = rest.substr(dash + 1);
  }
  std::vector<long> fields;
  std::size_t from = 0;
  for (;;) {
    const auto colon = rest.find(':', from);
    const std::string f = rest.substr(from, colon == std::string::npos ? std::string::npos : colon - from);
    if (f.empty() || f.find_first_not_of("0123456789") != std::string::npos || f.size() > 9) return std::nullopt;
    fields.push_back(std::stol(f));
    if (colon == std::string::npos) break;
    from = colon + 1;
  }
  if (fields.size() > 3) return std::nullopt;
  long seconds = 0;
  if (dash != std::string::npos) {  // days-hours[:minutes[:seconds]]
    const long unit[] = {3600, 60, 1};
    for (std::size_t k = 0; k < fields.size(); ++k) seconds += fields[k] * unit[k];
    seconds += days * 86400;
  } else if (fields.size() == 3) {  // hours:minutes:seconds
    seconds = fields[0] * 3600 + fields[1] * 60 + fields[2];
  } else {  // minutes[:seconds]
    seconds = fields[0] * 60 + (fields.size() == 2 ? fields[1] : 0);
  }
  if (seconds == 0) return std::numeric_limits<double>::infinity();  // sbatch: no limit imposed
  return static_cast<double>(seconds);
}

std::vector<std::string> campaignInputProblems(const CampaignManifest& manifest) {
  std::vector<std::string> problems;
  std::set<std::string> configs_checked;
  bool bag_solver_checked = false;
  auto checkConfig = [&](const CampaignJob& job, const std::vector<std::string>& paths, bool simulation) {
    for (const auto& c : paths) problemIfMissing(job, simulation ? "sim_config" : "config", c, problems);
    const std::string key = (simulation ? "sim:" : "ppp:") + [&] {
      std::string k;
      for (const auto& c : paths) k += c + "\n";
      return k;
    }();
    if (paths.empty() || !configs_checked.insert(key).second) return;
    try {
      if (simulation) loadSimulationConfig(paths.front());
      else loadPppConfig(paths);
    } catch (const std::exception& e) {
      problems.push_back("job " + job.id + ": configuration: " + e.what());
    }
  };
  for (const auto& job : manifest.jobs) {
    if (job.kind == CampaignJobKind::Ppp) {
      const PppInputFiles& f = job.ppp.files;
      problemIfMissing(job, "obs", f.obs, problems);
      for (const auto& [what, list] : {std::make_pair("sp3", &f.sp3), std::make_pair("clk", &f.clk),
                                       std::make_pair("nav", &f.nav), std::make_pair("atx", &f.atx)})
        for (const auto& p : *list) problemIfMissing(job, what, p, problems);
      if (f.bias) problemIfMissing(job, "bia", *f.bias, problems);
      if (f.blq) problemIfMissing(job, "blq", *f.blq, problems);
      checkConfig(job, job.ppp.config, false);
    } else if (job.kind == CampaignJobKind::Bag) {
      const PppInputFiles& f = job.ppp.files;
      problemIfMissing(job, "bag", f.obs, problems);
      for (const auto& p : f.atx) problemIfMissing(job, "atx", p, problems);
      if (f.bias) problemIfMissing(job, "bia", *f.bias, problems);
      if (f.blq) problemIfMissing(job, "blq", *f.blq, problems);
      if (!job.ppp.truth_csv.empty()) problemIfMissing(job, "truth_csv", job.ppp.truth_csv, problems);
      checkConfig(job, job.ppp.config, false);
      if (!bag_solver_checked) {
        bag_solver_checked = true;
        const std::string solver = campaignBagSolverPath();
        if (::access(solver.c_str(), X_OK) != 0)
          problems.push_back("job " + job.id + ": bag jobs run " + solver +
                             ", which is not there: the ROS tools are built by the catkin build only");
      }
    } else {
      if (!job.monte_carlo.config.empty()) checkConfig(job, {job.monte_carlo.config}, false);
      if (!job.monte_carlo.sim_config.empty()) checkConfig(job, {job.monte_carlo.sim_config}, true);
    }
  }
  return problems;
}

namespace {

/// A problem without its job id and with every run of digits as '#': problems of
/// the same kind on other days or hours have the same shape.
std::string problemShape(const std::string& problem) {
  std::string text = problem;
  if (text.rfind("job ", 0) == 0)
    if (const auto colon = text.find(": "); colon != std::string::npos) text = text.substr(colon + 2);
  std::string shape;
  for (std::size_t k = 0; k < text.size(); ++k) {
    const bool digit = std::isdigit(static_cast<unsigned char>(text[k])) != 0;
    if (!digit) shape += text[k];
    else if (shape.empty() || shape.back() != '#') shape += '#';
  }
  return shape;
}

}  // namespace

std::vector<std::string> foldCampaignProblems(const std::vector<std::string>& problems) {
  std::vector<std::string> first;
  std::vector<std::size_t> more;
  std::map<std::string, std::size_t> index;
  for (const auto& p : problems) {
    const auto [it, fresh] = index.emplace(problemShape(p), first.size());
    if (fresh) {
      first.push_back(p);
      more.push_back(0);
    } else {
      ++more[it->second];
    }
  }
  for (std::size_t k = 0; k < first.size(); ++k)
    if (more[k] > 0) first[k] += " (and " + std::to_string(more[k]) + " more like it)";
  return first;
}

MonteCarloOptions monteCarloStudyOptions(const CampaignMonteCarloShard& m) {
  MonteCarloOptions o;
  o.flights = m.study_flights;
  o.first_flight = 0;
  o.seed = m.seed;
  o.duration_s = m.duration_min * 60.0;
  o.rate_hz = m.rate_hz;
  o.smoother_filtered_lag_s = m.smoother_lag_s;
  o.threads = 1;
  if (!m.profiles.empty()) {
    o.profiles.clear();
    for (const auto& p : m.profiles) o.profiles.push_back(parseFlightProfile(p));
  }
  if (!m.config.empty()) o.ppp = loadPppConfig(m.config);
  if (!m.sim_config.empty()) o.simulation = loadSimulationConfig(m.sim_config);
  if (m.systems == "G") o.simulation.systems = {GnssSystem::GPS};
  if (m.systems == "GE") o.simulation.systems = {GnssSystem::GPS, GnssSystem::Galileo};
  if (m.ambiguity_resolution) {
    o.ppp.ambiguity_resolution.enabled = true;
    o.simulation.errors.ambiguity.satellite_phase_biases = true;
  }
  return o;
}

MonteCarloOptions monteCarloShardOptions(const CampaignMonteCarloShard& m) {
  MonteCarloOptions o = monteCarloStudyOptions(m);
  o.first_flight = m.first_flight;
  o.flights = m.flights;
  return o;
}

}  // namespace ppp
