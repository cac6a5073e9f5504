#pragma once
// One job of a campaign (app/campaign_manifest.h) in its own directory
// <campaign>/jobs/<id>/, run by whatever backend (a local process pool, a Slurm
// array task: the tool ppp_campaign), with the same bytes written whichever ran
// it. The finished marker done.json is written only after the outputs are
// complete; job.lock (flock) keeps a second process from running the same job.
// A job is DONE, STALE, FAILED, INTERRUPTED or PENDING; re-running a campaign
// runs every job that is not DONE, and only those. PPP jobs write ppp_solve's
// outputs (app/ppp_solve_run.h), bag jobs those of the ROS tool ppp_bag_solve run
// as a subprocess, Monte Carlo shards their flights' records.
// The directory layout and the states: doc/campaigns.md, "Job directories and
// states".
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/app/campaign_ar_figures.h"
#include "ppp_bayes_tree/app/campaign_manifest.h"
#include "ppp_bayes_tree/app/ppp_solve_run.h"

namespace ppp {

/// The job's specification as YAML (job.yaml), and back. parseCampaignJob throws
/// ConfigError naming the file and key.
std::string campaignJobYaml(const CampaignJob& job);
CampaignJob parseCampaignJob(const std::string& yaml_text, const std::string& file);
/// 64-bit FNV-1a of a text, 16 hex digits (the digest of job.yaml).
std::string fnv1aHex(const std::string& text);

enum class CampaignJobState { Pending, Done, Failed, Interrupted, Stale };
const char* toString(CampaignJobState state);  // "pending", "done", "failed", "interrupted", "stale"

/// The figures of a finished job (done.json "result"); NaN / -1 when not known
/// (no truth: no errors; a float run: no fixed share).
struct CampaignJobResult {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  // PPP
  std::size_t epochs_read = 0, epochs_solved = 0, problems = 0;
  std::string first_problem;  // the text of the first problem, when there are any
  double mean_3d_m = kNaN, first_window_mean_3d_m = kNaN;  // with a truth
  double time_to_10cm_s = kNaN;  // with a truth; +inf when never below 10 cm to the end
  double fixed_share = kNaN;     // fixed epochs / solved epochs (PPP-AR), NaN when float
  /// PPP-AR figures of every solution the job wrote (EKF; smoother filtered and
  /// smoothed), in the order of the outputs (app/campaign_ar_figures.h)
  std::vector<CampaignArFigures> solutions;
  // Monte Carlo shard
  int flights = 0, flights_failed = 0;
};

struct CampaignJobStatus {
  CampaignJobState state = CampaignJobState::Pending;
  std::string reason;  // failed / interrupted: why
  std::optional<CampaignJobResult> result;  // done
  /// failed: when failed.json was written, so that a watcher tells the marker of a
  /// new attempt from the one an earlier attempt left (which the job clears when it
  /// starts)
  std::optional<std::filesystem::file_time_type> failed_marker_time;
};

/// The figures of a PPP run from its first outcome (the causal solution), with the
/// PPP-AR figures of each of its solutions, and as done.json's "result" object
/// (ppp_bag_solve --result writes it for a bag job).
CampaignJobResult campaignPppResult(const PppSolveOutcome& first);
/// The same for a run of several estimators ("both"): the figures of the first, the
/// PPP-AR figures of every solution of each.
CampaignJobResult campaignPppResult(const std::vector<PppSolveOutcome>& runs);
std::string campaignPppResultJson(const PppSolveOutcome& first);

/// The ROS tool bag jobs run: ppp_bag_solve in the directory of the running
/// executable (ppp_campaign's, devel/lib/ppp_bayes_tree in the catkin build).
std::string campaignBagSolverPath();

/// Whether a done job's status looks at the outputs its done.json lists (a
/// deleted or resized output makes the job stale).
enum class CampaignOutputCheck {
  Stat,   // stat each listed output: when a run, a summary or a status starts
  Trust,  // take done.json as it is: the repeated looks of a watcher while jobs run
};

/// The state of the job in `job_dir` from its files (see above).
CampaignJobStatus campaignJobStatus(const std::string& job_dir,
                                    CampaignOutputCheck outputs = CampaignOutputCheck::Stat);
/// The same, compared with the job as the manifest gives it now: a job whose
/// job.yaml differs from it is STALE (its reason names the keys that changed),
/// so that a result of other parameters is never shown or merged as this job's.
CampaignJobStatus campaignJobStatus(const std::string& job_dir, const CampaignJob& job);

/// Creates the job directory and writes job.yaml (atomically) unless the job is
/// DONE with this very specification. Returns true when the job must run.
/// A job whose specification changed loses its old marker and outputs.
bool prepareCampaignJob(const std::string& job_dir, const CampaignJob& job);

/// Runs the job of `job_dir` (its job.yaml) under its lock (job.lock): clears a
/// previous attempt, writes into work/, renames work/ to output/, then writes
/// done.json. On failure writes failed.json with the reason (the exception's
/// text, naming the file and line). Never throws; returns the job's status
/// afterwards. When another process holds the job's lock, nothing is touched and
/// the status says so (CampaignJobStatus::reason; `locked` set when given).
CampaignJobStatus runCampaignJob(const std::string& job_dir, bool* locked = nullptr);

/// Records a failure seen by the backend (the process was killed, a Slurm task
/// ended without finishing): failed.json with `reason`, unless the job is DONE or
/// another process holds its lock (it runs the job now). Throws std::runtime_error
/// when the marker cannot be written.
void markCampaignJobFailed(const std::string& job_dir, const std::string& reason);

/// True when a process holds the lock of the job in `job_dir` (it runs the job).
bool campaignJobLocked(const std::string& job_dir);

/// Writes `text` to `path` atomically (a temporary file in the same directory,
/// flushed, then renamed). Throws std::runtime_error naming the file and the
/// system's reason ("No space left on device") when it cannot; the temporary
/// file is then removed.
void writeFileAtomically(const std::string& path, const std::string& text);

}  // namespace ppp
