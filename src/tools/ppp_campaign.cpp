// ppp_campaign: many independent jobs (PPP of station days, day files split into
// hours, ROS replay bags through the ROS tool ppp_bag_solve beside this
// executable, Monte Carlo shards) from one YAML manifest, on this machine's cores or
// on a Slurm cluster, resumable, with one summary at the end
// (app/campaign_manifest.h: the manifest; app/campaign_job.h: the job
// directories and markers; app/campaign_summary.h: the summary).
//
// usage: ppp_campaign check MANIFEST [--out DIR]
//        ppp_campaign run MANIFEST --out DIR [--local | --slurm] [--jobs N]
//                     [--partition P] [--time HH:MM:SS] [--mem M] [--max-resubmits N]
//                     [--jobs-per-task K] [--poll-s S] [--lease-s S] [--no-plot]
//        ppp_campaign summary MANIFEST --out DIR [--no-plot]
//        ppp_campaign run-job JOB_DIR
// check: expands the manifest, checks every input (missing files are named) and
//   lists the jobs (with --out, their states). Exit 0 when the campaign may run.
// run: refuses the whole campaign when an input is missing (nothing is created or
//   submitted); then runs every job that is not done, writes the summary and
//   prints it. --local (default): a pool of --jobs processes (default: the cores),
//   each job a subprocess `ppp_campaign run-job DIR` (a crash ends that job only;
//   its output goes to DIR/log.txt). --slurm: one `sbatch --array` over the jobs to
//   run (resources from the manifest's slurm section, overridden by the flags;
//   task logs in OUT/slurm/), progress from squeue, exit states from sacct (or
//   scontrol when accounting is off); tasks that ended without finishing are
//   resubmitted up to --max-resubmits times. --jobs-per-task K makes an array of
//   ceil(jobs / K) tasks, for jobs of a few seconds: each task takes the next job
//   not yet taken whenever it is free (OUT/slurm/roundR.claims/LINE names the task
//   that took list line LINE), K of them or more while its time limit leaves room.
//   Both backends run the same run-job, so the outputs are the same bytes whichever
//   ran them. One run at a time per OUT (a
//   lock); an array an earlier, stopped run left in the queue must end first.
//   A stop signal (SIGTERM, SIGINT, SIGHUP) reaches the jobs: the local pool passes
//   it to each job's process group, Slurm's array is cancelled; the summary is
//   written and the exit status is 128 + the signal. A campaign that cannot stop
//   its array (killed with -9, its host down) stops watching it: the campaign
//   touches OUT/slurm/watcher at every look at the queue, and each array task
//   cancels the array when that heartbeat is older than --lease-s (default 120 s;
//   checked before each job and every lease/4 s, at most 10 s, while one runs).
//   OUT must be this campaign's (OUT/campaign.json), new or empty.
// summary: the summary of the jobs as they are (nothing runs).
// run-job: runs one prepared job directory (what both backends start).
// The plot: scripts/plot_campaign.py OUT (python3 with matplotlib), unless --no-plot.
// Exit status: 0 every job done; 1 jobs failed, were interrupted or are stale (listed
// in the summary; run again to re-run them); 2 usage, a bad manifest, missing inputs
// or an OUT of another campaign; 128 + N stopped by signal N. run-job: 3 when
// another process runs that job.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/statvfs.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

#include <cerrno>
#include <charconv>
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "ppp_bayes_tree/app/allocator_tuning.h"
#include "ppp_bayes_tree/app/campaign_summary.h"
#include "ppp_bayes_tree/app/child_process.h"
#include "ppp_bayes_tree/evaluation/json_text.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/ppp/config/yaml_section.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// Default watcher lease of a Slurm campaign (s): see SlurmSettings::lease_s.
constexpr int kDefaultLease_s = 120;

namespace {

/// The status looks while jobs run (the pool's ended jobs, the Slurm watcher's
/// polls) take done.json as it is: a job's outputs are checked once, when the run
/// or the summary starts (prepareCampaignJob, summarizeCampaign).
constexpr ppp::CampaignOutputCheck kWatcherLook = ppp::CampaignOutputCheck::Trust;

int usage(const std::string& why) {
  std::cerr << "ppp_campaign: " << why << "\n"
            << "usage: ppp_campaign check MANIFEST [--out DIR]\n"
            << "       ppp_campaign run MANIFEST --out DIR [--local | --slurm] [--jobs N]\n"
            << "                    [--partition P] [--time HH:MM:SS] [--mem M] [--max-resubmits N]\n"
            << "                    [--jobs-per-task K] [--poll-s S] [--lease-s S] [--no-plot]\n"
            << "       ppp_campaign summary MANIFEST --out DIR [--no-plot]\n"
            << "       ppp_campaign run-job JOB_DIR\n";
  return 2;
}

struct Options {
  std::string command, manifest, out;
  bool slurm = false, plot = true;
  unsigned jobs = 0;
  double poll_s = 1.0;
  int lease_s = kDefaultLease_s;
  std::optional<std::string> partition, time_limit, mem;
  std::optional<int> max_resubmits, jobs_per_task;
};

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string selfExecutable() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("ppp_campaign") : p.string();
}

/// Where a command's standard error goes: dropped, or with its output.
enum class CommandErrors { Drop, WithOutput };

/// A command's standard output (looked up on PATH) and its exit status (-1 when
/// a signal killed it or it could not start; then, with its errors, the output
/// is the reason it could not start).
std::string capture(const std::vector<std::string>& argv, CommandErrors errors, int* status = nullptr) {
  ppp::ChildProcessSpec spec;
  spec.argv = argv;
  spec.search_path = true;
  spec.stderr_to = errors == CommandErrors::Drop ? ppp::ChildStream::null() : ppp::ChildStream::withStdout();
  try {
    ppp::CapturedOutput run = ppp::runCapturingOutput(spec);
    if (status) *status = run.end.exited() ? run.end.exit_status : -1;
    return run.output;
  } catch (const ppp::ProcessStartError& e) {
    if (status) *status = -1;
    return errors == CommandErrors::WithOutput ? e.what() : "";
  }
}

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Progress on stderr: redrawn in place on a terminal, else a line when it changes.
class ProgressLine {
 public:
  explicit ProgressLine(int total) : tty_(isatty(STDERR_FILENO) != 0), t0_(Clock::now()) { p_.total = total; }
  void show(const ppp::CampaignProgress& counts, int running) {
    show(counts.done, counts.failed, running, counts.done_with_problems);
  }
  void show(int done, int failed, int running, int done_with_problems = 0) {
    p_.done = done;
    p_.failed = failed;
    p_.running = running;
    p_.done_with_problems = done_with_problems;
    p_.elapsed_s = secondsSince(t0_);
    const std::string line = ppp::formatCampaignProgress(p_);
    if (tty_) {
      std::fprintf(stderr, "\r%s   ", line.c_str());
    } else if (done != last_done_ || failed != last_failed_ || running != last_running_) {
      std::fprintf(stderr, "%s\n", line.c_str());
    }
    last_done_ = done;
    last_failed_ = failed;
    last_running_ = running;
    std::fflush(stderr);
  }
  void finish() {
    if (tty_) std::fprintf(stderr, "\n");
  }

 private:
  bool tty_;
  Clock::time_point t0_;
  ppp::CampaignProgress p_;
  int last_done_ = -1, last_failed_ = -1, last_running_ = -1;
};

struct PendingJob {
  std::string id, dir;
};

/// Set in the environment of the local pool's run-job processes: the pool's process
/// id. Such a job leads its own process group (the pool forwards the stop signals
/// to it, reaching the tools it starts), and ends when the pool dies.
constexpr const char* kPoolParentVariable = "PPP_CAMPAIGN_POOL_PID";

/// The signals that stop a campaign: those not ignored when it started (under nohup
/// SIGHUP stays ignored, in a background job of a script SIGINT).
std::vector<int> stopSignals() {
  std::vector<int> signals;
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) {
    struct sigaction now {};
    if (::sigaction(sig, nullptr, &now) == 0 && now.sa_handler == SIG_IGN) continue;
    signals.push_back(sig);
  }
  return signals;
}

/// Whether the campaign's signal set includes SIGCHLD (the local pool waits for its children by it).
enum class ChildEnds { Watched, Ignored };

/// The stop signals (and for the local pool SIGCHLD), blocked while the object
/// lives and taken by wait(): a stop is never lost between two looks, and no
/// handler runs. The jobs of the pool inherit the mask and unblock these signals
/// first thing (prepareJobProcess).
class CampaignSignals {
 public:
  explicit CampaignSignals(ChildEnds children) {
    sigemptyset(&set_);
    if (children == ChildEnds::Watched) sigaddset(&set_, SIGCHLD);
    for (int sig : stopSignals()) sigaddset(&set_, sig);
    ::sigprocmask(SIG_BLOCK, &set_, &previous_);
  }
  ~CampaignSignals() { ::sigprocmask(SIG_SETMASK, &previous_, nullptr); }
  CampaignSignals(const CampaignSignals&) = delete;
  CampaignSignals& operator=(const CampaignSignals&) = delete;
  /// Blocks until a child changes state (0) or a stop signal arrives (its number).
  int wait() const {
    for (;;) {
      const int sig = ::sigwaitinfo(&set_, nullptr);
      if (sig < 0 && errno == EINTR) continue;
      return sig == SIGCHLD || sig < 0 ? 0 : sig;
    }
  }
  /// Waits up to `seconds` for a stop signal: its number, or 0.
  int waitFor(double seconds) const {
    const long ns = static_cast<long>(seconds * 1e9);
    const struct timespec timeout {ns / 1000000000L, ns % 1000000000L};
    const int sig = ::sigtimedwait(&set_, nullptr, &timeout);
    return sig == SIGCHLD || sig < 0 ? 0 : sig;
  }

 private:
  sigset_t set_, previous_;
};

extern "C" void stopJobProcessGroup(int sig) {
  ::signal(sig, SIG_DFL);
  ::kill(0, sig);  // this process and the tools it started (its own group): ends them all
}

/// First thing a run-job process does. Started by the local pool: it leads its own
/// process group (the pool's stop reaches the tools it starts), a stop signal ends
/// the whole group, and it gets SIGTERM when the pool dies (even by SIGKILL;
/// Linux). Returns false when the pool is already gone. Then it unblocks the
/// signals the pool blocks.
bool prepareJobProcess() {
  bool pool_alive = true;
  if (const char* pool = std::getenv(kPoolParentVariable)) {
    ::setpgid(0, 0);
#ifdef __linux__
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
#endif
    pool_alive = std::to_string(::getppid()) == pool;
    for (int sig : stopSignals()) {
      struct sigaction action {};
      action.sa_handler = stopJobProcessGroup;
      sigemptyset(&action.sa_mask);
      ::sigaction(sig, &action, nullptr);
    }
  }
  sigset_t pool_blocked;
  sigemptyset(&pool_blocked);
  for (int sig : {SIGCHLD, SIGTERM, SIGINT, SIGHUP}) sigaddset(&pool_blocked, sig);
  ::sigprocmask(SIG_UNBLOCK, &pool_blocked, nullptr);
  return pool_alive;
}

/// Sends `sig` to a job's process group (the job and the tools it started), or to
/// the job alone before it has made its group.
void signalJob(ppp::ChildProcess& child, int sig) {
  if (child.end()) return;
  if (::kill(-child.pid(), sig) != 0) child.kill(sig);
}

/// Records a failure in a job's marker; when even that cannot be written (a full
/// disk), says so on the campaign's standard error instead.
void recordJobFailure(const PendingJob& job, const std::string& reason) {
  try {
    ppp::markCampaignJobFailed(job.dir, reason);
  } catch (const std::exception& e) {
    std::cerr << "\nppp_campaign: job " << job.id << " failed (" << reason << ") and its failure cannot be recorded: "
              << e.what() << "\n";
  }
}

/// When a job that did not finish left an empty log, says so, with the free space
/// of its file system when none is left (its own messages could not be written).
void noteEmptyLog(const PendingJob& job) {
  const fs::path log = fs::path(job.dir) / "log.txt";
  std::error_code ec;
  if (fs::file_size(log, ec) != 0 || ec) return;
  struct statvfs fsinfo {};
  const bool full = ::statvfs(job.dir.c_str(), &fsinfo) == 0 && fsinfo.f_bavail == 0;
  std::cerr << "\nppp_campaign: job " << job.id << " did not finish and its log " << log.string() << " is empty"
            << (full ? ": no space is left on the file system of " + job.dir : std::string()) << "\n";
}

// ---------------------------------------------------------------------------
// Local backend: a pool of subprocesses `ppp_campaign run-job DIR`.
// ---------------------------------------------------------------------------
/// Starts `ppp_campaign run-job DIR` with its console output in DIR/log.txt.
ppp::ChildProcess spawnJob(const std::string& exe, const std::string& dir) {
  ppp::ChildProcessSpec spec;
  spec.argv = {exe, "run-job", dir};
  spec.environment = {{kPoolParentVariable, std::to_string(::getpid())}};
  spec.stdout_to = ppp::ChildStream::file((fs::path(dir) / "log.txt").string());
  spec.stderr_to = ppp::ChildStream::withStdout();
  return ppp::ChildProcess::spawn(spec);
}

/// Records how a job's process ended when the job did not record it itself.
void noteJobProcessEnd(const PendingJob& job, const ppp::ProcessEnd& end, int stop_signal) {
  const ppp::CampaignJobState st = ppp::campaignJobStatus(job.dir, kWatcherLook).state;
  if (st == ppp::CampaignJobState::Done || st == ppp::CampaignJobState::Failed) return;
  noteEmptyLog(job);
  const std::string stopped =
      stop_signal ? std::string("; the campaign was stopped by signal ") + std::to_string(stop_signal) + " (" +
                        strsignal(stop_signal) + ")"
                  : std::string();
  recordJobFailure(job, "run-job " + end.text() + " without finishing (see " + job.dir + "/log.txt" + stopped + ")");
}

/// The local pool's jobs in progress, by process id.
using RunningJobs = std::map<pid_t, std::pair<ppp::ChildProcess, const PendingJob*>>;

/// A stop signal: forwarded to every running job (a second one kills them).
void stopRunningJobs(RunningJobs& running, int sig, int& stop_signal) {
  const int forward = stop_signal ? SIGKILL : sig;
  if (!stop_signal) {
    stop_signal = sig;
    std::cerr << "\nppp_campaign: stopped by signal " << sig << " (" << strsignal(sig) << "): stopping "
              << running.size() << " running job(s), starting no more (a second signal kills them)\n";
  }
  for (auto& [pid, entry] : running) signalJob(entry.first, forward);
}

/// Collects the jobs that ended; counts them done (with or without problems) or failed.
void collectEndedJobs(RunningJobs& running, int stop_signal, ppp::CampaignProgress& counts) {
  for (auto it = running.begin(); it != running.end();) {
    const auto end = it->second.first.poll();
    if (!end) {
      ++it;
      continue;
    }
    const PendingJob& job = *it->second.second;
    noteJobProcessEnd(job, *end, stop_signal);
    it = running.erase(it);
    const ppp::CampaignJobStatus st = ppp::campaignJobStatus(job.dir, kWatcherLook);
    if (st.state != ppp::CampaignJobState::Done) {
      ++counts.failed;
      continue;
    }
    ++counts.done;
    counts.done_with_problems += st.result && st.result->problems > 0;
  }
}

/// Runs the jobs in a pool of `slots` processes. Returns the stop signal that ended
/// it early (its jobs stopped and marked failed), or 0 when every job ran.
int runLocal(const std::vector<PendingJob>& jobs, int already_done, int total, unsigned slots) {
  const std::string exe = selfExecutable();
  if (slots == 0) slots = std::max(1u, std::thread::hardware_concurrency());
  const CampaignSignals signals(ChildEnds::Watched);
  RunningJobs running;
  std::size_t next = 0;
  int stop_signal = 0;
  ppp::CampaignProgress counts;
  counts.done = already_done;
  ProgressLine progress(total);
  progress.show(counts, 0);
  while ((next < jobs.size() && !stop_signal) || !running.empty()) {
    while (!stop_signal && next < jobs.size() && running.size() < slots) {
      try {
        ppp::ChildProcess child = spawnJob(exe, jobs[next].dir);
        const pid_t pid = child.pid();
        running.emplace(pid, std::make_pair(std::move(child), &jobs[next]));
      } catch (const ppp::ProcessStartError& e) {
        recordJobFailure(jobs[next], std::string("could not start a process: ") + e.what());
        ++counts.failed;
      }
      ++next;
    }
    progress.show(counts, static_cast<int>(running.size()));
    if (running.empty()) continue;
    if (const int sig = signals.wait()) stopRunningJobs(running, sig, stop_signal);
    collectEndedJobs(running, stop_signal, counts);
  }
  progress.show(counts, 0);
  progress.finish();
  if (stop_signal)
    std::cerr << "ppp_campaign: stopped; " << jobs.size() - next << " job(s) not started; run again to resume\n";
  return stop_signal;
}

// ---------------------------------------------------------------------------
// Slurm backend: one array job per round, squeue for progress, sacct/scontrol
// for the exit states, resubmission of what did not finish.
// ---------------------------------------------------------------------------
struct SlurmTaskEnd {
  std::string state, exit_code;
};

/// Task index -> end state of an array job: sacct, or scontrol when accounting is off.
std::map<int, SlurmTaskEnd> slurmTaskEnds(const std::string& array_id) {
  std::map<int, SlurmTaskEnd> ends;
  int status = 0;
  const std::string sacct =
      capture({"sacct", "-n", "-P", "-X", "-j", array_id, "-o", "JobID,State,ExitCode"}, CommandErrors::Drop, &status);
  if (status == 0) {
    std::istringstream lines(sacct);
    std::string line;
    while (std::getline(lines, line)) {  // 123_4|CANCELLED by 0|0:15
      const auto us = line.find('_'), bar1 = line.find('|'), bar2 = line.rfind('|');
      if (us == std::string::npos || bar1 == std::string::npos || bar1 == bar2 || us > bar1) continue;
      ends[std::atoi(line.c_str() + us + 1)] = {line.substr(bar1 + 1, bar2 - bar1 - 1), line.substr(bar2 + 1)};
    }
    if (!ends.empty()) return ends;
  }
  const std::string show = capture({"scontrol", "-o", "show", "job", array_id}, CommandErrors::Drop);
  std::istringstream lines(show);
  std::string line;
  auto field = [](const std::string& l, const std::string& key) {
    const auto at = l.find(" " + key + "=");
    if (at == std::string::npos) return std::string();
    const auto from = at + key.size() + 2;
    return l.substr(from, l.find(' ', from) - from);
  };
  while (std::getline(lines, line)) {
    const std::string task = field(line, "ArrayTaskId");
    // a task index, not a range ("3-7") nor Slurm's NO_VAL (4294967294) of cancelled pending tasks
    if (task.empty() || task.size() > 9 || task.find_first_not_of("0123456789") != std::string::npos) continue;
    ends[std::stoi(task)] = {field(line, "JobState"), field(line, "ExitCode")};
  }
  return ends;
}

struct SlurmSettings {
  ppp::CampaignResources resources;
  std::string name, out;
  double poll_s = 1.0;
  /// The watcher's lease: an array task that finds the campaign's heartbeat older
  /// than this cancels the array (the campaign is gone: killed with -9, its host down).
  int lease_s = kDefaultLease_s;
};

/// OUT/slurm/watcher: touched by the campaign at every look at its array (the
/// heartbeat the array's tasks check against the lease).
std::string watcherHeartbeat(const std::string& out) { return (fs::path(out) / "slurm" / "watcher").string(); }

/// Touches the heartbeat (creating it, with the campaign's pid, the first time).
void touchHeartbeat(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    fs::create_directories(fs::path(path).parent_path());
    ppp::writeFileAtomically(path, "ppp_campaign pid " + std::to_string(getpid()) + "\n");
    return;
  }
  fs::last_write_time(path, fs::file_time_type::clock::now(), ec);
}

/// The task script's part that ends the array when no campaign watches it: a
/// check before each job (`campaign_watched`) and a watchdog beside the running
/// job (so a long job stops too), both comparing the heartbeat's age with the lease.
std::string watcherCheckScript(const SlurmSettings& s) {
  const int check_s = std::max(1, std::min(10, s.lease_s / 4));
  return "heartbeat=" + shellQuote(watcherHeartbeat(s.out)) + "\nlease_s=" + std::to_string(s.lease_s) +
         "\ncampaign_watched() {\n"
         "  local age=$(( $(date +%s) - $(stat -c %Y \"$heartbeat\" 2> /dev/null || echo 0) ))\n"
         "  [ $age -le $lease_s ] && return 0\n"
         "  echo \"ppp_campaign: no campaign watches array $SLURM_ARRAY_JOB_ID any more ($heartbeat last touched $age s "
         "ago, lease $lease_s s): cancelling the array\" >&2\n"
         "  scancel \"$SLURM_ARRAY_JOB_ID\"; return 1\n}\n"
         "( while sleep " + std::to_string(check_s) + "; do campaign_watched || exit 0; done ) &\n"
         "watchdog=$!\ntrap 'kill $watchdog 2> /dev/null' EXIT\n";
}

/// The cluster's MaxArraySize (array indices 0 .. MaxArraySize - 1; Slurm's default 1001).
std::size_t maxArraySize() {
  std::istringstream lines(capture({"scontrol", "show", "config"}, CommandErrors::Drop));
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("MaxArraySize", 0) != 0) continue;
    const auto eq = line.find('=');
    if (eq != std::string::npos) return static_cast<std::size_t>(std::max(2, std::atoi(line.c_str() + eq + 1)));
  }
  return 1001;
}

/// Jobs per array task: the manifest's (or --jobs-per-task), raised when the array
/// would have more tasks than the cluster allows (said on stderr).
std::size_t jobsPerTask(const SlurmSettings& s, std::size_t jobs) {
  std::size_t per_task = static_cast<std::size_t>(std::max(1, s.resources.jobs_per_task));
  const std::size_t max_tasks = maxArraySize() - 1;  // indices 1 .. MaxArraySize - 1
  if ((jobs + per_task - 1) / per_task > max_tasks) {
    per_task = (jobs + max_tasks - 1) / max_tasks;
    std::cerr << "ppp_campaign: " << jobs << " jobs exceed the cluster's MaxArraySize: " << per_task
              << " jobs per array task\n";
  }
  return per_task;
}

/// The files of one submission round under OUT/slurm: the job list (one job
/// directory a line), the task script, and the claims: `next` (the last line taken),
/// `lock`, and one file per taken line holding the array task id that took it.
struct RoundFiles {
  std::string list, script, claims;
  RoundFiles(const std::string& out, int round) {
    const fs::path dir = fs::path(out) / "slurm";
    const std::string stem = "round" + std::to_string(round);
    list = (dir / (stem + ".list")).string();
    script = (dir / (stem + ".sh")).string();
    claims = (dir / (stem + ".claims")).string();
  }
  /// Lines taken so far (the counter the tasks advance under the lock; 0 before the
  /// first, and while a task rewrites it).
  std::size_t taken() const {
    std::ifstream in(fs::path(claims) / "next");
    std::size_t n = 0;
    return in >> n ? n : 0;
  }
  /// The array task that took list line `line` (1-based), or nullopt when none did.
  std::optional<int> claimant(std::size_t line) const {
    std::ifstream in(fs::path(claims) / std::to_string(line));
    int task = 0;
    if (in >> task) return task;
    return std::nullopt;
  }
};

/// The array task script: jobs are taken one at a time, the next line of the list
/// not yet taken (a counter under flock, so two tasks never take the same line),
/// and the taking task is written beside the claim. A task takes more than
/// `per_task` jobs only while its elapsed time plus twice its longest job stays
/// within its time limit. So the array ends when its last job does: tasks that
/// start late or draw slow jobs take fewer (a static split of the list would end
/// with the slowest bundle).
std::string arrayTaskScript(const SlurmSettings& s, const RoundFiles& f, std::size_t jobs, std::size_t per_task,
                            int round) {
  const double limit_s = ppp::slurmTimeLimit_s(s.resources.time_limit).value_or(0.0);
  const std::string room =
      std::isfinite(limit_s)
          ? "  if [ $taken -ge $per_task ] && [ $(( SECONDS - start + 2 * longest )) -ge " +
                std::to_string(static_cast<long>(limit_s)) + " ]; then break; fi\n"
          : "";
  return "#!/bin/bash\n# ppp_campaign " + s.name + ", round " + std::to_string(round) + ": each array task takes the " +
         "next job of " + f.list + " not yet taken\n# (" + f.claims + "/LINE names the task that took it), " +
         std::to_string(per_task) + " or more while the time limit (" + s.resources.time_limit +
         ") leaves room\nclaims=" + shellQuote(f.claims) + "\nlist=" + shellQuote(f.list) +
         "\njobs=" + std::to_string(jobs) + "\nper_task=" + std::to_string(per_task) +
         "\n" + watcherCheckScript(s) + "status=0 taken=0 longest=0 start=$SECONDS\nwhile :; do\n" + room +
         "  campaign_watched || break\n" +
         "  line=$( { flock 9 || exit 1; n=$(( $(cat \"$claims/next\" 2> /dev/null || echo 0) + 1 ))\n"
         "    if [ $n -le $jobs ]; then echo $n > \"$claims/next\"; echo \"$SLURM_ARRAY_TASK_ID\" > \"$claims/$n\"; fi\n"
         "    echo $n; } 9> \"$claims/lock\" )\n"
         "  [ -n \"$line\" ] && [ \"$line\" -le $jobs ] || break\n"
         "  t0=$SECONDS\n  " + shellQuote(selfExecutable()) + " run-job \"$(sed -n \"${line}p\" \"$list\")\" || status=1\n"
         "  taken=$(( taken + 1 )); [ $(( SECONDS - t0 )) -gt $longest ] && longest=$(( SECONDS - t0 ))\n"
         "done\nexit $status\n";
}

/// Submits one array over `jobs`; returns the array job id ("" when sbatch failed: `why`).
std::string submitArray(const SlurmSettings& s, const RoundFiles& f, const std::vector<PendingJob>& jobs,
                        std::size_t per_task, int round, std::string& why) {
  std::error_code ec;
  fs::remove_all(f.claims, ec);  // a round number of an earlier invocation
  fs::create_directories(f.claims);
  std::string listing;
  for (const auto& j : jobs) listing += j.dir + "\n";
  ppp::writeFileAtomically(f.list, listing);
  const std::size_t tasks = (jobs.size() + per_task - 1) / per_task;
  ppp::writeFileAtomically(f.script, arrayTaskScript(s, f, jobs.size(), per_task, round));
  const fs::path dir = fs::path(s.out) / "slurm";
  std::vector<std::string> cmd = {"sbatch", "--parsable", "--job-name=ppp_campaign_" + s.name,
                                  "--array=1-" + std::to_string(tasks), "--time=" + s.resources.time_limit,
                                  "--mem=" + s.resources.mem,
                                  "--cpus-per-task=" + std::to_string(s.resources.cpus_per_task),
                                  "--chdir=" + s.out, "--output=" + (dir / "%A_%a.log").string()};
  if (!s.resources.partition.empty()) cmd.push_back("--partition=" + s.resources.partition);
  cmd.push_back(f.script);
  int status = 0;
  std::string out = capture(cmd, CommandErrors::WithOutput, &status);
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  const std::string id = out.substr(0, out.find(';'));
  if (status != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
    why = "sbatch failed (exit " + std::to_string(status) + "): " + out;
    return "";
  }
  return id;
}

/// Task index -> squeue state of a running array (empty when it has ended).
std::map<int, std::string> slurmQueue(const std::string& array_id, bool& ended) {
  int status = 0;
  const std::string out = capture({"squeue", "-h", "-r", "-j", array_id, "-o", "%K %T"}, CommandErrors::Drop, &status);
  std::map<int, std::string> q;
  std::istringstream lines(out);
  int task = 0;
  std::string state;
  while (lines >> task >> state) q[task] = state;
  ended = q.empty();  // an ended (or purged) array has no line (squeue may even fail on it)
  return q;
}

/// The array a previous invocation left in the queue (the campaign process was
/// stopped while it ran): its id when squeue still lists it, else "".
std::string arrayStillQueued(const std::string& marker) {
  std::ifstream in(marker);
  std::string id;
  if (!(in >> id) || id.find_first_not_of("0123456789") != std::string::npos) return "";
  bool ended = true;
  slurmQueue(id, ended);
  return ended ? "" : id;
}

/// Why a job of `array_id` did not finish, for its failed marker: the end state of
/// the task that took it, or that no task took it.
std::string whyUnfinished(const SlurmSettings& s, const std::string& array_id, std::optional<int> task,
                          const std::map<int, SlurmTaskEnd>& ends) {
  if (!task) return "no task of Slurm array " + array_id + " took it (the tasks ended or were stopped before)";
  const auto it = ends.find(*task);
  const std::string how = it == ends.end() ? "ended without finishing (state unknown: no accounting record)"
                                           : "ended " + it->second.state + ", exit code " + it->second.exit_code;
  const std::string name = array_id + "_" + std::to_string(*task);
  return "Slurm task " + name + " " + how + " (log " + s.out + "/slurm/" + name + ".log)";
}

void cancelArray(const std::string& array_id, int sig, int& stop_signal);

/// Progress of a submitted round until every job of it has its finished marker or
/// a failed marker of this round (not the one an earlier attempt left, which the
/// job clears when it starts), or the array has left the queue. The markers are
/// looked at every 0.1 s (only the jobs still open), squeue every poll_s: the
/// round ends with its last job, not with the scheduler's clean-up of the tasks.
/// Only jobs a task has taken can have finished, so only those are looked at: the
/// cost per look follows the running tasks, not the size of the campaign.
/// Once every job is taken, the array's tasks still pending are cancelled: they
/// would find nothing to take, and would hold the cluster's CPUs while they start.
/// A stop signal to the campaign cancels the array (scancel: Slurm signals its
/// running tasks); the round then ends when the array has left the queue.
void waitForRound(const SlurmSettings& s, const std::string& array_id, const RoundFiles& files,
                  const std::vector<PendingJob>& jobs, int already_done, ProgressLine& progress,
                  const CampaignSignals& signals, int& stop_signal) {
  bool pending_cancelled = false;
  std::vector<std::size_t> open(jobs.size());  // list order: line k + 1
  std::vector<std::optional<fs::file_time_type>> earlier_failure(jobs.size());
  for (std::size_t k = 0; k < open.size(); ++k) {
    open[k] = k;
    earlier_failure[k] = ppp::campaignJobStatus(jobs[k].dir, kWatcherLook).failed_marker_time;
  }
  int done = already_done, failed = 0, running = 0, done_with_problems = 0;
  auto next_queue_look = Clock::now();
  for (;;) {
    const std::size_t taken = files.taken();
    std::vector<std::size_t> still;
    for (const std::size_t k : open) {
      if (k >= taken) {  // not taken yet
        still.push_back(k);
        continue;
      }
      const auto st = ppp::campaignJobStatus(jobs[k].dir, kWatcherLook);
      const bool failed_now =
          st.state == ppp::CampaignJobState::Failed && st.failed_marker_time != earlier_failure[k];
      done += st.state == ppp::CampaignJobState::Done;
      done_with_problems += st.state == ppp::CampaignJobState::Done && st.result && st.result->problems > 0;
      failed += failed_now;
      if (st.state != ppp::CampaignJobState::Done && !failed_now) still.push_back(k);
    }
    open = std::move(still);
    if (!pending_cancelled && taken >= jobs.size()) {
      capture({"scancel", "--state=PENDING", array_id}, CommandErrors::Drop);
      pending_cancelled = true;
    }
    bool ended = open.empty();
    if (!ended && Clock::now() >= next_queue_look) {
      touchHeartbeat(watcherHeartbeat(s.out));
      running = 0;
      for (const auto& [task, state] : slurmQueue(array_id, ended))
        running += state == "RUNNING" || state == "COMPLETING";
      next_queue_look = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s.poll_s));
    }
    progress.show(done, failed, ended ? 0 : running, done_with_problems);
    if (ended) return;
    if (const int sig = signals.waitFor(0.1)) cancelArray(array_id, sig, stop_signal);
  }
}

/// A stop signal while an array runs: the array is cancelled (a second signal cancels it again).
void cancelArray(const std::string& array_id, int sig, int& stop_signal) {
  if (!stop_signal)
    std::cerr << "\nppp_campaign: stopped by signal " << sig << " (" << strsignal(sig) << "): cancelling array job "
              << array_id << "\n";
  stop_signal = stop_signal ? stop_signal : sig;
  capture({"scancel", array_id}, CommandErrors::Drop);
}

/// How a Slurm campaign ended: it could not submit (or an earlier array still runs),
/// or it ran its rounds, or a stop signal ended it early (the signal).
struct SlurmOutcome {
  bool submitted = false;
  int stop_signal = 0;
};

SlurmOutcome runSlurm(const SlurmSettings& s, std::vector<PendingJob> jobs, int already_done, int total) {
  const CampaignSignals signals(ChildEnds::Ignored);
  SlurmOutcome outcome;
  ProgressLine progress(total);
  const std::string marker = (fs::path(s.out) / "slurm" / "active_array").string();
  if (const std::string id = arrayStillQueued(marker); !id.empty()) {
    std::cerr << "ppp_campaign: array job " << id << " of this campaign is still queued or running (an earlier "
              << "invocation was stopped; its tasks cancel it within " << s.lease_s << " s of the last watch): wait "
              << "for it or scancel " << id << ", then run again\n";
    return outcome;
  }
  touchHeartbeat(watcherHeartbeat(s.out));
  outcome.submitted = true;
  for (int round = 0;; ++round) {
    std::string why;
    const std::size_t per_task = jobsPerTask(s, jobs.size());
    const RoundFiles files(s.out, round);
    const std::string array_id = submitArray(s, files, jobs, per_task, round, why);
    if (array_id.empty()) {
      std::cerr << "ppp_campaign: " << why << "\n";
      outcome.submitted = false;
      return outcome;
    }
    ppp::writeFileAtomically(marker, array_id + "\n");
    std::cerr << "ppp_campaign: submitted array job " << array_id << " (" << jobs.size() << " jobs in "
              << (jobs.size() + per_task - 1) / per_task << " tasks, round " << round << ")\n";
    waitForRound(s, array_id, files, jobs, already_done, progress, signals, outcome.stop_signal);
    std::error_code ec;
    fs::remove(marker, ec);
    std::optional<std::map<int, SlurmTaskEnd>> ends;  // read only when a job did not finish
    std::vector<PendingJob> again;
    for (std::size_t k = 0; k < jobs.size(); ++k) {
      const auto st = ppp::campaignJobStatus(jobs[k].dir, kWatcherLook);
      if (st.state == ppp::CampaignJobState::Done) {
        ++already_done;
        continue;
      }
      if (st.state != ppp::CampaignJobState::Failed) {
        if (!ends) ends = slurmTaskEnds(array_id);
        const std::string stopped = outcome.stop_signal ? "; the campaign was stopped by signal " +
                                                              std::to_string(outcome.stop_signal) + " (" +
                                                              strsignal(outcome.stop_signal) + ")"
                                                        : std::string();
        recordJobFailure(jobs[k], whyUnfinished(s, array_id, files.claimant(k + 1), *ends) + stopped);
      }
      again.push_back(jobs[k]);
    }
    progress.finish();
    if (again.empty()) return outcome;
    if (round >= s.resources.max_resubmits || outcome.stop_signal) {
      std::cerr << "ppp_campaign: " << again.size() << " job(s) did not finish after " << round + 1
                << " submission(s); run the campaign again to re-run them\n";
      return outcome;
    }
    std::cerr << "ppp_campaign: resubmitting " << again.size() << " job(s) that did not finish\n";
    jobs = std::move(again);
  }
}

// ---------------------------------------------------------------------------

void plotSummary(const std::string& out) {
#ifdef PPP_SCRIPTS_DIR
  const std::string script = std::string(PPP_SCRIPTS_DIR) + "/plot_campaign.py";
  if (!fs::exists(script) || !fs::exists("/usr/bin/python3")) return;
  int status = 0;
  const std::string text = capture({"/usr/bin/python3", script, out}, CommandErrors::WithOutput, &status);
  if (status != 0) std::cerr << "ppp_campaign: the plot failed (the summary files are written):\n" << text;
  else std::cout << text;
#else
  (void)out;
#endif
}

/// OUT/campaign.json: the campaign a directory belongs to (its name and manifest).
constexpr const char* kCampaignIdentityFile = "campaign.json";

/// The campaign name a YAML file gives under `keys` ("" when it gives none or does not load).
std::string campaignNameIn(const fs::path& file, std::initializer_list<const char*> keys) {
  try {
    YAML::Node node = YAML::LoadFile(file.string());
    for (const char* key : keys) {
      if (!node.IsMap() || !node[key]) return "";
      node = node[key];
    }
    return node.IsScalar() ? node.as<std::string>() : "";
  } catch (const YAML::Exception&) {
    return "";
  }
}

/// Why `out` must not take this campaign's summary and jobs: it holds another
/// campaign (by its campaign.json, or the manifest.yaml a campaign of an earlier
/// version left), or it is a directory with other files. "" when it is this
/// campaign's, empty, or not there.
std::string foreignCampaignFolder(const std::string& out, const ppp::CampaignManifest& manifest) {
  const fs::path dir(out);
  std::error_code ec;
  if (!fs::exists(dir, ec)) return "";
  if (!fs::is_directory(dir, ec)) return "--out " + out + " is not a directory";
  if (fs::exists(dir / kCampaignIdentityFile, ec)) {
    const std::string name = campaignNameIn(dir / kCampaignIdentityFile, {"campaign"});
    if (name == manifest.name) return "";
    const std::string other = campaignNameIn(dir / kCampaignIdentityFile, {"manifest"});
    return "--out " + out + " holds the campaign '" + name + "' (manifest " + other + "), not '" + manifest.name +
           "' of " + manifest.path + ": give another --out (or the same campaign name to resume)";
  }
  if (fs::exists(dir / "manifest.yaml", ec) && fs::is_directory(dir / "jobs", ec)) {
    const std::string name = campaignNameIn(dir / "manifest.yaml", {"campaign", "name"});
    if (name.empty() || name == manifest.name) return "";
    return "--out " + out + " holds the campaign '" + name + "' (" + (dir / "manifest.yaml").string() + "), not '" +
           manifest.name + "' of " + manifest.path + ": give another --out";
  }
  if (fs::is_empty(dir, ec)) return "";
  return "--out " + out + " is a directory with other files and no campaign (no " + kCampaignIdentityFile +
         "): give a new or empty directory";
}

int writeSummary(const ppp::CampaignManifest& manifest, const Options& o) {
  if (const std::string why = foreignCampaignFolder(o.out, manifest); !why.empty()) {
    std::cerr << "ppp_campaign: refused: " << why << "\n";
    return 2;
  }
  const ppp::CampaignSummary summary = ppp::summarizeCampaign(manifest, o.out);
  ppp::writeCampaignSummary(summary, o.out);
  std::cout << ppp::campaignSummaryMarkdown(summary);
  for (const auto& st : summary.studies)
    if (st.merged) std::cout << "Monte Carlo study " << st.study << " merged: " << o.out << "/monte_carlo/" << st.study << "/\n";
  std::cout << "summary: " << o.out << "/summary.csv, summary.json, summary.md, summary_ar.csv\n";
  if (o.plot) plotSummary(o.out);
  return summary.done == static_cast<int>(summary.jobs.size()) ? 0 : 1;
}

int commandCheck(const ppp::CampaignManifest& manifest, const Options& o, const std::vector<std::string>& problems) {
  for (const auto& job : manifest.jobs) {
    std::cout << job.id << "  " << ppp::toString(job.kind) << "  " << job.group;
    if (!o.out.empty()) std::cout << "  " << ppp::toString(ppp::campaignJobStatus(ppp::campaignJobDir(o.out, job.id), job).state);
    std::cout << "\n";
  }
  std::cout << manifest.jobs.size() << " jobs; " << problems.size() << " input problem(s)\n";
  return problems.empty() ? 0 : 2;
}

int commandRun(const ppp::CampaignManifest& manifest, const Options& o) {
  if (const std::string why = foreignCampaignFolder(o.out, manifest); !why.empty()) {
    std::cerr << "ppp_campaign: refused: " << why << "; nothing was run\n";
    return 2;
  }
  fs::create_directories(fs::path(o.out) / "jobs");
  // One invocation at a time per campaign directory (held until exit).
  const std::string lock_path = (fs::path(o.out) / ".lock").string();
  const int lock = ::open(lock_path.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (lock < 0 || ::flock(lock, LOCK_EX | LOCK_NB) != 0) {
    std::cerr << "ppp_campaign: another ppp_campaign run is working in " << o.out << " (" << lock_path << ")\n";
    return 1;
  }
  std::ifstream src(manifest.path, std::ios::binary);
  std::ostringstream text;
  text << src.rdbuf();
  ppp::writeFileAtomically((fs::path(o.out) / kCampaignIdentityFile).string(),
                           "{\"campaign\": " + ppp::jsonString(manifest.name) + ", \"manifest\": " +
                               ppp::jsonString(fs::absolute(manifest.path).lexically_normal().string()) + "}\n");
  ppp::writeFileAtomically((fs::path(o.out) / "manifest.yaml").string(), text.str());
  std::vector<PendingJob> pending;
  for (const auto& job : manifest.jobs) {
    const std::string dir = fs::absolute(ppp::campaignJobDir(o.out, job.id)).string();
    if (ppp::prepareCampaignJob(dir, job)) pending.push_back({job.id, dir});
  }
  const int total = static_cast<int>(manifest.jobs.size());
  const int already = total - static_cast<int>(pending.size());
  std::cerr << "ppp_campaign: " << total << " jobs: " << already << " already done, " << pending.size() << " to run ("
            << (o.slurm ? "slurm" : "local") << ")\n";
  int stop_signal = 0;
  if (!pending.empty()) {
    if (o.slurm) {
      SlurmSettings s;
      s.resources = manifest.resources;
      if (o.partition) s.resources.partition = *o.partition;
      if (o.time_limit) s.resources.time_limit = *o.time_limit;
      if (o.mem) s.resources.mem = *o.mem;
      if (o.max_resubmits) s.resources.max_resubmits = *o.max_resubmits;
      if (o.jobs_per_task) s.resources.jobs_per_task = *o.jobs_per_task;
      s.name = manifest.name;
      s.out = fs::absolute(o.out).string();
      s.poll_s = o.poll_s;
      s.lease_s = o.lease_s;
      const SlurmOutcome outcome = runSlurm(s, pending, already, total);
      if (!outcome.submitted) return 1;
      stop_signal = outcome.stop_signal;
    } else {
      stop_signal = runLocal(pending, already, total, o.jobs);
    }
  }
  if (!stop_signal) return writeSummary(manifest, o);
  Options stopped = o;
  stopped.plot = false;
  writeSummary(manifest, stopped);
  return 128 + stop_signal;
}

/// A whole number of at least `minimum`, all of `text` (no sign, no trailing characters).
std::optional<int> wholeNumber(const std::string& text, int minimum) {
  int value = 0;
  const char* end = text.data() + text.size();
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end || value < minimum) return std::nullopt;
  return value;
}

/// A finite number of seconds > 0, all of `text`.
std::optional<double> positiveSeconds(const std::string& text) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  if (errno != 0 || end != text.c_str() + text.size() || !std::isfinite(value) || !(value > 0.0)) return std::nullopt;
  return value;
}

bool parseOptions(int argc, char** argv, Options& o, std::string& why) {
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](std::string& dst) {
      if (i + 1 >= argc) return false;
      dst = argv[++i];
      return true;
    };
    std::string v;
    if (a == "--local") o.slurm = false;
    else if (a == "--slurm") o.slurm = true;
    else if (a == "--no-plot") o.plot = false;
    else if (a == "--out") {
      if (!value(o.out)) return (why = "--out needs a directory", false);
    } else if (a == "--jobs") {
      const auto n = value(v) ? wholeNumber(v, 1) : std::nullopt;
      if (!n) return (why = "--jobs needs a whole count >= 1, not '" + v + "'", false);
      o.jobs = static_cast<unsigned>(*n);
    } else if (a == "--poll-s") {
      const auto t = value(v) ? positiveSeconds(v) : std::nullopt;
      if (!t) return (why = "--poll-s needs seconds > 0, not '" + v + "'", false);
      o.poll_s = *t;
    } else if (a == "--lease-s") {
      const auto n = value(v) ? wholeNumber(v, 2) : std::nullopt;
      if (!n) return (why = "--lease-s needs whole seconds >= 2, not '" + v + "'", false);
      o.lease_s = *n;
    } else if (a == "--partition" || a == "--time" || a == "--mem") {
      if (!value(v)) return (why = a + " needs a value", false);
      if (a == "--time" && !ppp::slurmTimeLimit_s(v))
        return (why = "--time needs a Slurm time limit (minutes, HH:MM:SS, D-HH:MM:SS or UNLIMITED), not " + v, false);
      (a == "--partition" ? o.partition : a == "--time" ? o.time_limit : o.mem) = v;
    } else if (a == "--jobs-per-task") {
      o.jobs_per_task = value(v) ? wholeNumber(v, 1) : std::nullopt;
      if (!o.jobs_per_task) return (why = "--jobs-per-task needs a whole count >= 1, not '" + v + "'", false);
    } else if (a == "--max-resubmits") {
      o.max_resubmits = value(v) ? wholeNumber(v, 0) : std::nullopt;
      if (!o.max_resubmits) return (why = "--max-resubmits needs a whole count >= 0, not '" + v + "'", false);
    } else if (!a.empty() && a[0] != '-' && o.manifest.empty()) {
      o.manifest = a;
    } else {
      return (why = "unexpected argument " + a, false);
    }
  }
  if (o.lease_s < 3.0 * o.poll_s)
    return (why = "--lease-s (" + std::to_string(o.lease_s) + " s) must be at least 3 looks of --poll-s", false);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  ppp::useAllocatorWithoutFastBins();  // app/allocator_tuning.h
  if (argc < 2) return usage("a command is required");
  Options o;
  o.command = argv[1];
  if (o.command == "-h" || o.command == "--help") {
    usage("help");
    return 0;
  }
  if (o.command == "run-job") {
    if (argc != 3) return usage("run-job needs one job directory");
    if (!prepareJobProcess()) {
      std::cerr << "ppp_campaign: run-job " << argv[2] << ": the campaign that started it has ended; not started\n";
      return 1;
    }
    bool locked = false;
    const ppp::CampaignJobStatus st = ppp::runCampaignJob(argv[2], &locked);
    if (locked) std::cerr << "ppp_campaign: run-job " << argv[2] << ": " << st.reason << "\n";
    return locked ? 3 : st.state == ppp::CampaignJobState::Done ? 0 : 1;
  }
  if (o.command != "check" && o.command != "run" && o.command != "summary")
    return usage("unknown command '" + o.command + "'");
  std::string why;
  if (!parseOptions(argc, argv, o, why)) return usage(why);
  if (o.manifest.empty()) return usage(o.command + " needs a manifest");
  if (o.command != "check" && o.out.empty()) return usage(o.command + " needs --out DIR");
  try {
    const ppp::CampaignManifest manifest = ppp::loadCampaignManifest(o.manifest);
    const std::vector<std::string> problems = ppp::campaignInputProblems(manifest);
    for (const auto& p : ppp::foldCampaignProblems(problems)) std::cerr << "ppp_campaign: " << p << "\n";
    if (o.command == "check") return commandCheck(manifest, o, problems);
    if (o.command == "summary") return writeSummary(manifest, o);
    if (!problems.empty()) {
      std::cerr << "ppp_campaign: refused: " << problems.size() << " input problem(s) in " << o.manifest
                << "; nothing was run\n";
      return 2;
    }
    return commandRun(manifest, o);
  } catch (const ppp::ConfigError& e) {
    std::cerr << "ppp_campaign: manifest: " << e.what() << "\n";
  } catch (const ppp::FileOpenError& e) {
    std::cerr << "ppp_campaign: " << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "ppp_campaign: " << e.what() << "\n";
    return 1;
  }
  return 2;
}
