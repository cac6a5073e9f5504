#pragma once
// A campaign: many independent jobs (PPP of RINEX/CRX files with precise or
// broadcast products; PPP of ROS replay bags; Monte Carlo shards of a
// simulated-flight study), listed in a YAML manifest and expanded here into
// concrete jobs: per day (`dates`, with the {yyyy} {doy} ... placeholders), per
// matching file (`obs` and `bag` are globs), per hour or restart window, per
// Monte Carlo shard (the shards merge into the one-run study exactly,
// evaluation/monte_carlo_records.h). Out-of-range dates, too many jobs, too long
// flights and dated entries that would read the same file are refused with the
// key named. Nothing here runs anything or knows about Slurm: the tool
// ppp_campaign does.
// The manifest's keys, the expansion rules, the job ids and the bounds:
// doc/campaigns.md and the commented example config/campaign_example.yaml.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"

namespace ppp {

/// The dates a manifest may name: the start of GPS time .. the end of 2100.
inline constexpr const char* kFirstCampaignDate = "1980-01-06";
inline constexpr const char* kLastCampaignDate = "2100-12-31";
/// The most jobs a campaign expands to (a job directory and about 1.4 kB of memory each).
inline constexpr std::size_t kMaxCampaignJobs = 100000;
/// The longest simulated flight of a Monte Carlo study (one day, simulation/flight_trajectory.h).
inline constexpr double kMaxFlightDuration_min = 1440.0;

enum class CampaignJobKind { Ppp, Bag, MonteCarloShard };
const char* toString(CampaignJobKind kind);  // "ppp", "bag", "monte_carlo"

/// One PPP run (ppp_solve's inputs; the window splits a day file into hours).
/// A bag job uses files.obs (the bag), atx, bias, blq and the rest; the orbits
/// and clocks are the bag's corrections.
struct CampaignPppJob {
  PppInputFiles files;
  std::vector<std::string> config;  // PPP configuration files, laid one on another
  std::string estimator = std::string(kDefaultEstimator);  // a registered name or "both" (estimator_registry.h)
  std::optional<Eigen::Vector3d> truth_ecef_m;
  std::string truth_csv;  // bag jobs: a truth trajectory (ppp_bag_solve --truth-csv); empty: none
};

/// One shard of a Monte Carlo study: flights first_flight .. first_flight + flights - 1
/// of a study of study_flights flights (ppp_monte_carlo's options).
struct CampaignMonteCarloShard {
  std::uint64_t seed = 1;
  int study_flights = 0;
  int first_flight = 0;
  int flights = 0;
  double duration_min = 30.0;
  double rate_hz = 1.0;
  std::string systems;  // G | GE; empty: the simulation configuration's (GPS by default)
  bool ambiguity_resolution = false;
  double smoother_lag_s = 60.0;
  std::vector<std::string> profiles;  // empty: the study's default round robin
  std::string config, sim_config;     // empty: the defaults
};

struct CampaignJob {
  std::string id;  // unique in the campaign; a file name
  CampaignJobKind kind = CampaignJobKind::Ppp;
  std::string group;  // the station (ppp), the name (bag) or the study (monte_carlo)
  std::string date;   // "2020-06-25" when the entry has dates, else ""
  int hour = -1;      // the hour of an hourly job, else -1
  CampaignPppJob ppp;  // ppp and bag jobs
  CampaignMonteCarloShard monte_carlo;
};

/// Slurm resources of every array task (ppp_campaign --slurm; flags override).
struct CampaignResources {
  std::string partition;           // empty: the cluster's default partition
  std::string time_limit = "01:00:00";  // sbatch --time of each array task (slurmTimeLimit_s)
  std::string mem = "2G";
  int cpus_per_task = 1;
  /// Jobs one array task runs one after another: more than 1 bundles short jobs,
  /// so that the scheduler's per-task start-up (about a second) is paid once per bundle.
  /// The array has ceil(jobs / jobs_per_task) tasks; each takes the next job not yet
  /// taken whenever it is free, and takes more than jobs_per_task only while its time
  /// limit leaves room (so tasks that start late or run slow jobs take fewer).
  int jobs_per_task = 1;
  int max_resubmits = 1;  // a task that ended without finishing is resubmitted this many times
};

struct CampaignManifest {
  std::string path;  // the manifest file
  std::string name;
  std::string data_root;
  CampaignResources resources;
  std::vector<CampaignJob> jobs;  // in manifest order
};

/// Reads and expands a manifest. Throws ConfigError (file, key path, line: an
/// unknown key, a wrong type, a bad date, a duplicate job id...) or
/// FileOpenError. A glob that matches nothing is not an error here: the job
/// keeps the pattern and campaignInputProblems names it.
CampaignManifest loadCampaignManifest(const std::string& path);

/// A Slurm time limit as sbatch --time takes it ("minutes", "minutes:seconds",
/// "hours:minutes:seconds", "days-hours", "days-hours:minutes",
/// "days-hours:minutes:seconds") in seconds; "UNLIMITED", "INFINITE" and a zero
/// limit (sbatch: none imposed) give infinity. nullopt when the text is none of these.
std::optional<double> slurmTimeLimit_s(const std::string& text);

/// Every input of every job that is missing or unreadable ("job zim2: sp3
/// /data/x.SP3: no such file"), configuration files that do not load, and
/// bag jobs without the ROS tool ppp_bag_solve (campaignBagSolverPath()).
/// Empty: the campaign may run.
std::vector<std::string> campaignInputProblems(const CampaignManifest& manifest);

/// Problems that differ only in their job id and numbers (the same missing file of
/// every day or hour) folded into their first line with a count: "job
/// esbc_2020-177_h00: sp3 /data/GRG0..._2020177...: no such file (and 263 more like
/// it)". The order is that of the first of each kind.
std::vector<std::string> foldCampaignProblems(const std::vector<std::string>& problems);

/// ppp_monte_carlo's options for a shard (threads 1: one core per job).
/// Throws ConfigError when its config or sim_config does not load.
MonteCarloOptions monteCarloShardOptions(const CampaignMonteCarloShard& shard);
/// The options of the whole study a shard belongs to (first_flight 0, all flights).
MonteCarloOptions monteCarloStudyOptions(const CampaignMonteCarloShard& shard);

}  // namespace ppp
