#include "ppp_bayes_tree/app/campaign_job.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include <yaml-cpp/yaml.h>

#include "ppp_bayes_tree/app/child_process.h"
#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/evaluation/json_text.h"
#include "ppp_bayes_tree/evaluation/monte_carlo_records.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"
#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"

namespace ppp {
namespace fs = std::filesystem;
namespace {

constexpr const char* kSpecFile = "job.yaml";
constexpr const char* kDoneFile = "done.json";
constexpr const char* kFailedFile = "failed.json";
constexpr const char* kTimingFile = "timing.json";
constexpr const char* kRecordsFile = "flights.mcr";
constexpr const char* kBagResultFile = "bag_result.json";
constexpr const char* kBagLogFile = "ppp_bag_solve.log";
constexpr const char* kLockFile = "job.lock";
constexpr const char* kOutputDir = "output";

std::string path(const std::string& dir, const char* name) { return (fs::path(dir) / name).string(); }

std::string readText(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return {};
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

/// "YYYY/MM/DD HH:MM:SS" GPST (whole seconds: windows start on the hour).
std::string windowTimeText(const GnssTime& t) {
  const CalendarTime c = t.toCalendar();
  char b[40];
  std::snprintf(b, sizeof b, "%04d/%02d/%02d %02d:%02d:%02d", c.year, c.month, c.day, c.hour, c.minute,
                static_cast<int>(std::floor(c.second + 1e-6)));
  return b;
}

const char* formatName(ObservationFormat f) {
  switch (f) {
    case ObservationFormat::Rtcm3: return "rtcm";
    case ObservationFormat::Ubx: return "ubx";
    case ObservationFormat::Rinex: break;
  }
  return "rinex";
}

void emitList(YAML::Emitter& y, const char* key, const std::vector<std::string>& values) {
  y << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const auto& v : values) y << v;
  y << YAML::EndSeq;
}

/// The keys ppp and bag jobs share: atx, bia, blq, config, estimator, truth.
void emitRunSettings(YAML::Emitter& y, const CampaignPppJob& job) {
  const PppInputFiles& f = job.files;
  emitList(y, "atx", f.atx);
  y << YAML::Key << "bia" << YAML::Value << f.bias.value_or("");
  y << YAML::Key << "blq" << YAML::Value << f.blq.value_or("");
  emitList(y, "config", job.config);
  y << YAML::Key << "estimator" << YAML::Value << job.estimator;
  if (!job.truth_ecef_m) return;
  y << YAML::Key << "truth" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int k = 0; k < 3; ++k) y << (*job.truth_ecef_m)(k);
  y << YAML::EndSeq;
}

std::string resultJson(const CampaignJob& job, const CampaignJobResult& r) {
  std::ostringstream os;
  os << "{";
  if (job.kind != CampaignJobKind::MonteCarloShard) {
    const std::string ttc = std::isinf(r.time_to_10cm_s) ? "\"never\"" : jsonNumber(r.time_to_10cm_s, 17);
    os << "\"epochs_read\": " << r.epochs_read << ", \"epochs_solved\": " << r.epochs_solved
       << ", \"problems\": " << r.problems << ", \"mean_3d_m\": " << jsonNumber(r.mean_3d_m, 17)
       << ", \"first_window_mean_3d_m\": " << jsonNumber(r.first_window_mean_3d_m, 17)
       << ", \"time_to_10cm_s\": " << ttc << ", \"fixed_share\": " << jsonNumber(r.fixed_share, 17);
    if (!r.first_problem.empty()) os << ", \"first_problem\": " << jsonString(r.first_problem);
    if (!r.solutions.empty()) os << ", \"solutions\": " << campaignArFiguresJson(r.solutions, 17);
  } else {
    os << "\"flights\": " << r.flights << ", \"flights_failed\": " << r.flights_failed;
  }
  os << "}";
  return os.str();
}

double numberOrNaN(const YAML::Node& n) {
  if (!n.IsDefined() || n.IsNull()) return CampaignJobResult::kNaN;
  const std::string s = n.as<std::string>();
  if (s == "never") return std::numeric_limits<double>::infinity();
  return n.as<double>();
}

CampaignJobResult parseResult(const YAML::Node& r) {
  CampaignJobResult out;
  if (!r.IsMap()) return out;
  if (r["epochs_read"]) out.epochs_read = r["epochs_read"].as<std::size_t>();
  if (r["epochs_solved"]) out.epochs_solved = r["epochs_solved"].as<std::size_t>();
  if (r["problems"]) out.problems = r["problems"].as<std::size_t>();
  if (r["first_problem"]) out.first_problem = r["first_problem"].as<std::string>();
  out.mean_3d_m = numberOrNaN(r["mean_3d_m"]);
  out.first_window_mean_3d_m = numberOrNaN(r["first_window_mean_3d_m"]);
  out.time_to_10cm_s = numberOrNaN(r["time_to_10cm_s"]);
  out.fixed_share = numberOrNaN(r["fixed_share"]);
  for (const auto& a : r["solutions"]) {
    CampaignArFigures f;
    f.solution = a["solution"].as<std::string>();
    f.solved_epochs = a["solved_epochs"].as<std::size_t>();
    f.fixed_epochs = a["fixed_epochs"].as<std::size_t>();
    f.wrong_fixed_epochs = a["wrong_fixed_epochs"].as<std::size_t>();
    f.first_fix_s = numberOrNaN(a["first_fix_s"]);
    f.below_10cm_s = numberOrNaN(a["below_10cm_s"]);
    f.mean_3d_m = numberOrNaN(a["mean_3d_m"]);
    f.worst_wrong_fix_m = numberOrNaN(a["worst_wrong_fix_m"]);
    out.solutions.push_back(f);
  }
  if (r["flights"]) out.flights = r["flights"].as<int>();
  if (r["flights_failed"]) out.flights_failed = r["flights_failed"].as<int>();
  return out;
}

CampaignJobResult runPppJob(const CampaignJob& job, const std::string& work_dir) {
  PppSolveRequest req;
  req.files = job.ppp.files;
  if (!job.ppp.config.empty()) req.config = loadPppConfig(job.ppp.config);
  req.estimator = job.ppp.estimator;
  req.truth_ecef_m = job.ppp.truth_ecef_m;
  req.out_dir = work_dir;
  req.name = job.group;
  req.write_timings = false;
  const std::vector<PppSolveOutcome> runs = solvePppEstimators(req);
  for (const auto& out : runs) std::cout << "=== estimator " << out.run.estimator << " ===\n" << formatRunReport(out.run);
  const PppSolveOutcome& first = runs.front();
  if (first.run.epochs_solved == 0)
    throw std::runtime_error("no epoch solved (" + std::to_string(first.run.epochs_read) + " read) from " +
                             job.ppp.files.obs);
  return campaignPppResult(runs);
}

/// The arguments of ppp_bag_solve for a bag job writing into `work_dir`.
std::vector<std::string> bagSolverArguments(const CampaignJob& job, const std::string& work_dir) {
  const PppInputFiles& f = job.ppp.files;
  std::vector<std::string> a = {campaignBagSolverPath(), f.obs, "--out", work_dir, "--name", job.group,
                                "--estimator", job.ppp.estimator, "--no-timings",
                                "--result", path(work_dir, kBagResultFile)};
  if (!job.ppp.config.empty()) {
    a.push_back("--config");
    a.insert(a.end(), job.ppp.config.begin(), job.ppp.config.end());
  }
  if (!f.atx.empty()) {
    a.push_back("--atx");
    a.insert(a.end(), f.atx.begin(), f.atx.end());
  }
  if (f.bias) a.insert(a.end(), {"--bia", *f.bias});
  if (f.blq) a.insert(a.end(), {"--blq", *f.blq});
  if (job.ppp.truth_ecef_m) {
    a.push_back("--truth");
    for (int k = 0; k < 3; ++k) a.push_back(jsonNumber((*job.ppp.truth_ecef_m)(k), 17));
  }
  if (!job.ppp.truth_csv.empty()) a.insert(a.end(), {"--truth-csv", job.ppp.truth_csv});
  return a;
}

/// Runs ppp_bag_solve (a ROS tool: the core does not read bags) with its console
/// output to `log`; returns "" when it succeeded, else how it ended or why it
/// could not start.
std::string runProcess(const std::vector<std::string>& args, const std::string& log) {
  ChildProcessSpec spec;
  spec.argv = args;
  spec.stdout_to = ChildStream::file(log);
  spec.stderr_to = ChildStream::withStdout();
  try {
    const ProcessEnd end = runChildProcess(spec);
    return end.succeeded() ? "" : end.text();
  } catch (const ProcessStartError& e) {
    return e.what();
  }
}

/// The last lines of a log (the reason a tool gives on failure).
std::string logTail(const std::string& log, std::size_t lines) {
  const std::string text = readText(log);
  std::size_t pos = text.size(), n = 0;
  while (pos > 0 && n <= lines) {
    pos = text.rfind('\n', pos - 1);
    if (pos == std::string::npos) { pos = 0; break; }
    ++n;
  }
  std::string tail = text.substr(pos);
  while (!tail.empty() && (tail.front() == '\n')) tail.erase(tail.begin());
  while (!tail.empty() && (tail.back() == '\n')) tail.pop_back();
  return tail;
}

CampaignJobResult runBagJob(const CampaignJob& job, const std::string& work_dir) {
  const std::string solver = campaignBagSolverPath();
  if (::access(solver.c_str(), X_OK) != 0)
    throw std::runtime_error("bag jobs run " + solver + ", which is not there: the ROS tools are built by the "
                             "catkin build only");
  const std::string log = path(fs::path(work_dir).parent_path().string(), kBagLogFile);  // not an output
  const std::string ended = runProcess(bagSolverArguments(job, work_dir), log);
  if (!ended.empty()) throw std::runtime_error("ppp_bag_solve on " + job.ppp.files.obs + ": " + ended + ": " + logTail(log, 2));
  const std::string result = path(work_dir, kBagResultFile);
  try {
    return parseResult(YAML::LoadFile(result));
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("ppp_bag_solve wrote no readable " + result + ": " + e.msg);
  }
}

CampaignJobResult runMonteCarloJob(const CampaignJob& job, const std::string& work_dir, std::string& timing) {
  const MonteCarloOptions options = monteCarloShardOptions(job.monte_carlo);
  MonteCarloResult result = runMonteCarlo(options);
  writeMonteCarloFlightRecords(result.flights, path(work_dir, kRecordsFile));
  std::ostringstream t;
  t << ", \"flights\": [";
  for (std::size_t i = 0; i < result.flights.size(); ++i) {
    const auto& f = result.flights[i];
    t << (i ? ", " : "") << "[" << f.setup.index << ", " << jsonNumber(f.simulate_s, 6);
    for (double e : f.estimator_s) t << ", " << jsonNumber(e, 6);  // kMonteCarloStudy order
    t << "]";
  }
  t << "]";
  timing = t.str();
  std::cout << "Monte Carlo shard: flights " << options.first_flight << ".." << options.first_flight + options.flights - 1
            << " of " << job.monte_carlo.study_flights << ", " << result.summary.failed << " failed\n";
  for (const auto& f : result.summary.failures) std::cout << "  " << f << "\n";
  CampaignJobResult r;
  r.flights = result.summary.flights;
  r.flights_failed = result.summary.failed;
  if (r.flights_failed == r.flights) throw std::runtime_error("every flight of the shard failed");
  return r;
}

std::string hostName() {
  char b[256] = {0};
  if (gethostname(b, sizeof b - 1) != 0) return "unknown";
  return b;
}

std::string systemReason(int error) { return std::strerror(error); }

/// The lock of one job: flock(2) on job.lock, held while the object lives. The
/// descriptor is inherited by the tools the job starts (ppp_bag_solve), so the lock
/// lasts as long as any process of the attempt does.
class JobLock {
 public:
  /// Tries for `patience_s` (a process that only looks at the lock holds it for a
  /// moment); busy() afterwards when another process holds it.
  JobLock(const std::string& job_dir, double patience_s) {
    fd_ = ::open(path(job_dir, kLockFile).c_str(), O_CREAT | O_RDWR, 0644);
    if (fd_ < 0) return;  // no job directory: the attempt fails and says why
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(patience_s);
    while (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      if ((errno != EWOULDBLOCK && errno != EINTR) || std::chrono::steady_clock::now() >= until) {
        busy_ = errno == EWOULDBLOCK;
        ::close(fd_);
        fd_ = -1;
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  ~JobLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  JobLock(const JobLock&) = delete;
  JobLock& operator=(const JobLock&) = delete;
  bool busy() const { return busy_; }

 private:
  int fd_ = -1;
  bool busy_ = false;
};

constexpr double kLockPatience_s = 2.0;

/// The files of output/ (relative paths, sorted) with their sizes, as done.json lists them.
std::string outputListJson(const std::string& output_dir) {
  std::vector<std::pair<std::string, std::uintmax_t>> files;
  for (const auto& e : fs::recursive_directory_iterator(output_dir))
    if (e.is_regular_file()) files.emplace_back(fs::relative(e.path(), output_dir).generic_string(), e.file_size());
  std::sort(files.begin(), files.end());
  std::string json = "[";
  for (std::size_t i = 0; i < files.size(); ++i)
    json += (i ? ", [" : "[") + jsonString(files[i].first) + ", " + std::to_string(files[i].second) + "]";
  return json + "]";
}

/// What is missing of the outputs done.json lists ("" when all are there with
/// their sizes). A marker without the list needs output/ itself.
std::string missingOutput(const std::string& job_dir, const YAML::Node& outputs) {
  const fs::path output = path(job_dir, kOutputDir);
  std::error_code ec;
  if (!outputs || !outputs.IsSequence()) return fs::is_directory(output, ec) ? "" : "output/ is missing";
  for (const auto& f : outputs) {
    const std::string name = f[0].as<std::string>();
    const auto bytes = f[1].as<std::uintmax_t>();
    const auto size = fs::file_size(output / name, ec);
    if (ec) return "output/" + name + " is missing";
    if (size != bytes)
      return "output/" + name + " has " + std::to_string(size) + " bytes, not the " + std::to_string(bytes) +
             " it was written with";
  }
  return "";
}

/// The top-level keys whose values differ between two job specifications ("truth, estimator").
std::string changedKeys(const std::string& before, const std::string& now) {
  try {
    const YAML::Node a = YAML::Load(before), b = YAML::Load(now);
    std::string keys;
    for (const auto& kv : b) {
      const std::string key = kv.first.as<std::string>();
      if (!a[key] || YAML::Dump(a[key]) != YAML::Dump(kv.second)) keys += (keys.empty() ? "" : ", ") + key;
    }
    for (const auto& kv : a)
      if (!b[kv.first.as<std::string>()]) keys += (keys.empty() ? "" : ", ") + kv.first.as<std::string>();
    return keys.empty() ? "job.yaml" : keys;
  } catch (const YAML::Exception&) {
    return "job.yaml";
  }
}

}  // namespace

CampaignJobResult campaignPppResult(const PppSolveOutcome& first) {
  CampaignJobResult r;
  r.epochs_read = first.run.epochs_read;
  r.epochs_solved = first.run.epochs_solved;
  r.problems = first.run.problems.size();
  if (!first.run.problems.empty()) r.first_problem = first.run.problems.front();
  r.fixed_share = first.run.epochs_solved == 0 ? CampaignJobResult::kNaN
                                               : static_cast<double>(first.run.epochs_fixed) /
                                                     static_cast<double>(first.run.epochs_solved);
  if (first.statistics) {
    r.mean_3d_m = first.statistics->all.mean_m;
    r.first_window_mean_3d_m = first.statistics->first_window.mean_m;
    r.time_to_10cm_s = std::numeric_limits<double>::infinity();
    for (const auto& c : first.statistics->convergence)
      if (std::abs(c.threshold_m - 0.10) < 1e-9 && c.time_s) r.time_to_10cm_s = *c.time_s;
  }
  for (const auto& out : first.outputs) r.solutions.push_back(campaignArFigures(out.tag, out.solution, out.statistics));
  return r;
}

CampaignJobResult campaignPppResult(const std::vector<PppSolveOutcome>& runs) {
  if (runs.empty()) return {};
  CampaignJobResult r = campaignPppResult(runs.front());
  for (std::size_t k = 1; k < runs.size(); ++k)
    for (const auto& out : runs[k].outputs) r.solutions.push_back(campaignArFigures(out.tag, out.solution, out.statistics));
  return r;
}

std::string campaignPppResultJson(const PppSolveOutcome& first) {
  CampaignJob ppp_job;
  return resultJson(ppp_job, campaignPppResult(first));
}

std::string campaignBagSolverPath() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return (ec ? fs::path("ppp_bag_solve") : self.parent_path() / "ppp_bag_solve").string();
}

std::string fnv1aHex(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char b[20];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(h));
  return b;
}

const char* toString(CampaignJobState state) {
  switch (state) {
    case CampaignJobState::Pending: return "pending";
    case CampaignJobState::Done: return "done";
    case CampaignJobState::Failed: return "failed";
    case CampaignJobState::Interrupted: return "interrupted";
    case CampaignJobState::Stale: return "stale";
  }
  return "unknown";
}

void writeFileAtomically(const std::string& target, const std::string& text) {
  const std::string tmp = target + ".tmp." + std::to_string(::getpid());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot write " + tmp + ": " + systemReason(errno));
  int error = 0;
  for (std::size_t written = 0; written < text.size() && error == 0;) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n >= 0) written += static_cast<std::size_t>(n);
    else if (errno != EINTR) error = errno;
  }
  if (::close(fd) != 0 && error == 0) error = errno;
  std::error_code ec;
  if (error != 0) {
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot write " + tmp + ": " + systemReason(error));
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw std::runtime_error("cannot rename " + tmp + " to " + target + ": " + ec.message());
  }
}

std::string campaignJobYaml(const CampaignJob& job) {
  YAML::Emitter y;
  y.SetDoublePrecision(17);
  y << YAML::BeginMap;
  y << YAML::Key << "id" << YAML::Value << job.id;
  y << YAML::Key << "kind" << YAML::Value << toString(job.kind);
  y << YAML::Key << "group" << YAML::Value << job.group;
  y << YAML::Key << "date" << YAML::Value << job.date;
  y << YAML::Key << "hour" << YAML::Value << job.hour;
  if (job.kind == CampaignJobKind::Bag) {
    const PppInputFiles& f = job.ppp.files;
    y << YAML::Key << "bag" << YAML::Value << f.obs;
    emitRunSettings(y, job.ppp);
    y << YAML::Key << "truth_csv" << YAML::Value << job.ppp.truth_csv;
  } else if (job.kind == CampaignJobKind::Ppp) {
    const PppInputFiles& f = job.ppp.files;
    y << YAML::Key << "obs" << YAML::Value << f.obs;
    y << YAML::Key << "format" << YAML::Value << formatName(f.obs_format);
    if (f.rtcm_reference_time) y << YAML::Key << "reference_date" << YAML::Value << windowTimeText(*f.rtcm_reference_time);
    emitList(y, "sp3", f.sp3);
    emitList(y, "clk", f.clk);
    emitList(y, "nav", f.nav);
    emitRunSettings(y, job.ppp);
    if (f.window.start) y << YAML::Key << "start" << YAML::Value << windowTimeText(*f.window.start);
    if (f.window.end) y << YAML::Key << "end" << YAML::Value << windowTimeText(*f.window.end);
  } else {
    const CampaignMonteCarloShard& m = job.monte_carlo;
    y << YAML::Key << "seed" << YAML::Value << std::to_string(m.seed);
    y << YAML::Key << "study_flights" << YAML::Value << m.study_flights;
    y << YAML::Key << "first_flight" << YAML::Value << m.first_flight;
    y << YAML::Key << "flights" << YAML::Value << m.flights;
    y << YAML::Key << "duration_min" << YAML::Value << m.duration_min;
    y << YAML::Key << "rate_hz" << YAML::Value << m.rate_hz;
    y << YAML::Key << "systems" << YAML::Value << m.systems;
    y << YAML::Key << "ambiguity_resolution" << YAML::Value << m.ambiguity_resolution;
    y << YAML::Key << "smoother_lag_s" << YAML::Value << m.smoother_lag_s;
    emitList(y, "profiles", m.profiles);
    y << YAML::Key << "config" << YAML::Value << m.config;
    y << YAML::Key << "sim_config" << YAML::Value << m.sim_config;
  }
  y << YAML::EndMap;
  return std::string(y.c_str()) + "\n";
}

CampaignJob parseCampaignJob(const std::string& text, const std::string& file) {
  YAML::Node node;
  try {
    node = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(file, "", "line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  YamlSection s(node, file, "");
  CampaignJob job;
  job.id = s.text("id", "");
  const std::string kind = s.choice("kind", "ppp", {"ppp", "bag", "monte_carlo"});
  job.kind = kind == "ppp" ? CampaignJobKind::Ppp : kind == "bag" ? CampaignJobKind::Bag : CampaignJobKind::MonteCarloShard;
  job.group = s.text("group", "");
  job.date = s.text("date", "");
  job.hour = static_cast<int>(s.number("hour", -1));
  auto time = [&](const char* key) -> std::optional<GnssTime> {
    if (!s.has(key)) return std::nullopt;
    auto t = parseReferenceDate(s.text(key, ""));
    if (!t) s.fail(key, "needs YYYY/MM/DD HH:MM:SS");
    return t;
  };
  // The keys ppp and bag jobs share (emitRunSettings).
  auto readRunSettings = [&] {
    PppInputFiles& f = job.ppp.files;
    f.atx = s.textList("atx", {}, true);
    if (const std::string b = s.text("bia", ""); !b.empty()) f.bias = b;
    if (const std::string b = s.text("blq", ""); !b.empty()) f.blq = b;
    job.ppp.config = s.textList("config", {}, true);
    job.ppp.estimator = s.choice("estimator", std::string(kDefaultEstimator), estimatorChoices());
    if (!s.has("truth")) return;
    const auto t = s.numberList("truth", {}, 3);
    job.ppp.truth_ecef_m = Eigen::Vector3d(t[0], t[1], t[2]);
  };
  if (job.kind == CampaignJobKind::Bag) {
    job.ppp.files.obs = s.text("bag", "");
    readRunSettings();
    job.ppp.truth_csv = s.text("truth_csv", "");
  } else if (job.kind == CampaignJobKind::Ppp) {
    PppInputFiles& f = job.ppp.files;
    f.obs = s.text("obs", "");
    const std::string format = s.choice("format", "rinex", {"rinex", "rtcm", "ubx"});
    f.obs_format = format == "rtcm" ? ObservationFormat::Rtcm3 : format == "ubx" ? ObservationFormat::Ubx
                                                                                 : ObservationFormat::Rinex;
    f.rtcm_reference_time = time("reference_date");
    f.sp3 = s.textList("sp3", {}, true);
    f.clk = s.textList("clk", {}, true);
    f.nav = s.textList("nav", {}, true);
    readRunSettings();
    f.window.start = time("start");
    f.window.end = time("end");
  } else {
    CampaignMonteCarloShard& m = job.monte_carlo;
    const std::string seed = s.text("seed", "1");
    m.seed = std::stoull(seed);
    m.study_flights = s.integer("study_flights", 0, 1);
    m.first_flight = s.integer("first_flight", 0, 0);
    m.flights = s.integer("flights", 0, 1);
    m.duration_min = s.number("duration_min", 30.0, Bound::Positive);
    m.rate_hz = s.number("rate_hz", 1.0, Bound::Positive);
    m.systems = s.text("systems", "");
    m.ambiguity_resolution = s.boolean("ambiguity_resolution", false);
    m.smoother_lag_s = s.number("smoother_lag_s", 60.0, Bound::NonNegative);
    m.profiles = s.textList("profiles", {}, true);
    m.config = s.text("config", "");
    m.sim_config = s.text("sim_config", "");
  }
  s.finish();
  return job;
}

namespace {

/// The status from the job's files, its job.yaml text given (`spec`).
CampaignJobStatus jobStatusOfSpec(const std::string& job_dir, const std::string& spec, CampaignOutputCheck outputs) {
  CampaignJobStatus st;
  std::error_code ec;
  if (fs::exists(path(job_dir, kDoneFile), ec)) {
    try {
      const YAML::Node done = YAML::LoadFile(path(job_dir, kDoneFile));
      if (done["spec_digest"] && done["spec_digest"].as<std::string>() == fnv1aHex(spec)) {
        const std::string missing =
            outputs == CampaignOutputCheck::Stat ? missingOutput(job_dir, done["outputs"]) : std::string();
        if (!missing.empty()) {
          st.state = CampaignJobState::Stale;
          st.reason = "finished, but " + missing + " (changed after the job ended): it runs again";
          return st;
        }
        st.state = CampaignJobState::Done;
        st.result = parseResult(done["result"]);
        return st;
      }
    } catch (const YAML::Exception&) {
      // an unreadable marker is no marker: the job runs again
    }
  }
  if (const auto written = fs::last_write_time(path(job_dir, kFailedFile), ec); !ec) {
    st.state = CampaignJobState::Failed;
    st.failed_marker_time = written;
    try {
      const YAML::Node failed = YAML::LoadFile(path(job_dir, kFailedFile));
      st.reason = failed["reason"] ? failed["reason"].as<std::string>() : "";
    } catch (const YAML::Exception&) {
      st.reason = "unreadable " + path(job_dir, kFailedFile);
    }
    return st;
  }
  if (fs::exists(path(job_dir, "work"), ec) || fs::exists(path(job_dir, "output"), ec)) {
    st.state = CampaignJobState::Interrupted;
    st.reason = campaignJobLocked(job_dir)
                    ? "another process runs it now (" + path(job_dir, kLockFile) + " is locked)"
                    : "an attempt ended without finishing (killed, cancelled or its node lost)";
  }
  return st;
}

}  // namespace

CampaignJobStatus campaignJobStatus(const std::string& job_dir, CampaignOutputCheck outputs) {
  return jobStatusOfSpec(job_dir, readText(path(job_dir, kSpecFile)), outputs);
}

CampaignJobStatus campaignJobStatus(const std::string& job_dir, const CampaignJob& job) {
  const std::string on_disk = readText(path(job_dir, kSpecFile)), wanted = campaignJobYaml(job);
  CampaignJobStatus st = jobStatusOfSpec(job_dir, on_disk, CampaignOutputCheck::Stat);
  if (st.state == CampaignJobState::Pending || on_disk.empty() || on_disk == wanted) return st;
  CampaignJobStatus stale;
  stale.state = CampaignJobState::Stale;
  stale.reason = "the manifest changed " + changedKeys(on_disk, wanted) + " since its last attempt (" +
                 toString(st.state) + "): it runs again";
  return stale;
}

bool campaignJobLocked(const std::string& job_dir) {
  const int fd = ::open(path(job_dir, kLockFile).c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool locked = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);  // releases the shared lock when it was taken
  return locked;
}

bool prepareCampaignJob(const std::string& job_dir, const CampaignJob& job) {
  fs::create_directories(job_dir);
  const std::string spec = campaignJobYaml(job);
  if (readText(path(job_dir, kSpecFile)) == spec && campaignJobStatus(job_dir).state == CampaignJobState::Done)
    return false;
  std::error_code ec;
  fs::remove(path(job_dir, kDoneFile), ec);  // a marker of another specification
  writeFileAtomically(path(job_dir, kSpecFile), spec);
  return true;
}

void markCampaignJobFailed(const std::string& job_dir, const std::string& reason) {
  const JobLock lock(job_dir, kLockPatience_s);
  if (lock.busy() || campaignJobStatus(job_dir).state == CampaignJobState::Done) return;
  writeFileAtomically(path(job_dir, kFailedFile), "{\"reason\": " + jsonString(reason) + "}\n");
}

CampaignJobStatus runCampaignJob(const std::string& job_dir, bool* locked) {
  const JobLock lock(job_dir, kLockPatience_s);
  if (locked) *locked = lock.busy();
  if (lock.busy()) {
    CampaignJobStatus st = campaignJobStatus(job_dir);
    st.reason = "another process runs this job (" + path(job_dir, kLockFile) + " is locked): not started";
    return st;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const std::string work = path(job_dir, "work"), output = path(job_dir, "output");
  std::string timing_extra;
  try {
    const std::string spec = readText(path(job_dir, kSpecFile));
    if (spec.empty()) throw std::runtime_error("no job specification " + path(job_dir, kSpecFile));
    const CampaignJob job = parseCampaignJob(spec, path(job_dir, kSpecFile));
    std::error_code ec;
    for (const char* marker : {kDoneFile, kFailedFile}) fs::remove(path(job_dir, marker), ec);
    fs::remove_all(work, ec);
    fs::remove_all(output, ec);
    fs::create_directories(work);
    const CampaignJobResult result = job.kind == CampaignJobKind::Ppp   ? runPppJob(job, work)
                                     : job.kind == CampaignJobKind::Bag ? runBagJob(job, work)
                                                                        : runMonteCarloJob(job, work, timing_extra);
    fs::rename(work, output);  // the outputs are complete ...
    writeFileAtomically(path(job_dir, kDoneFile),  // ... and only then the marker
                        "{\"id\": " + jsonString(job.id) + ", \"spec_digest\": " + jsonString(fnv1aHex(spec)) +
                            ", \"result\": " + resultJson(job, result) + ", \"outputs\": " + outputListJson(output) +
                            "}\n");
  } catch (const std::exception& e) {
    try {
      writeFileAtomically(path(job_dir, kFailedFile), "{\"reason\": " + jsonString(e.what()) + "}\n");
    } catch (const std::exception& e2) {
      std::cerr << "ppp_campaign: " << e2.what() << "\n";
    }
    std::cerr << "ppp_campaign: job " << job_dir << " failed: " << e.what() << "\n";
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  try {
    writeFileAtomically(path(job_dir, kTimingFile), "{\"wall_s\": " + jsonNumber(wall_s, 6) + ", \"host\": " +
                                                        jsonString(hostName()) + timing_extra + "}\n");
  } catch (const std::exception&) {
    // timing is informative only
  }
  return campaignJobStatus(job_dir);
}

}  // namespace ppp
