#pragma once
// The summary of a campaign (app/campaign_manifest.h, app/campaign_job.h), made
// from the job directories alone, so that it is the same whichever backend ran
// the jobs and however often the campaign was resumed:
//   <campaign>/summary.csv   one row per job: id, kind, station/study, date, hour,
//                            state, epochs, mean 3D, first-15-min mean 3D, time to
//                            10 cm, fixed share (PPP; errors need a truth), flights
//                            (Monte Carlo shards), the failure reason
//   <campaign>/summary.json  the same rows, the Monte Carlo studies, the counts
//   <campaign>/summary.md    the readable tables: stations x days, studies, failures,
//                            the PPP-AR distributions per station and overall
//   <campaign>/summary_ar.csv one row per done PPP job and solution: its PPP-AR
//                            figures (app/campaign_ar_figures.h); the CDF plot reads it
//   <campaign>/monte_carlo/<study>/  a study whose shards are all done, merged
//                            (evaluation/monte_carlo_records.h) and written as
//                            ppp_monte_carlo writes one run (writeMonteCarloOutputs)
// No wall-clock figure is in summary.*; the merged studies' per-flight times come
// from the shards' timing.json (informative, they differ from run to run).
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/app/campaign_job.h"
#include "ppp_bayes_tree/evaluation/monte_carlo.h"

namespace ppp {

/// <campaign>/jobs/<id>.
std::string campaignJobDir(const std::string& campaign_dir, const std::string& job_id);

struct CampaignJobRow {
  CampaignJob job;
  CampaignJobStatus status;
};

struct CampaignStudyRow {
  std::string study;
  int shards = 0, shards_done = 0;
  std::optional<MonteCarloResult> merged;  // when every shard is done
  std::string problem;                     // the merge failed: why
};

struct CampaignSummary {
  std::string name;
  std::vector<CampaignJobRow> jobs;  // manifest order
  std::vector<CampaignStudyRow> studies;
  int done = 0, failed = 0, interrupted = 0, pending = 0, stale = 0;
  int done_with_problems = 0;  // done jobs whose run reported problems (CampaignJobResult::problems)
};

/// Reads every job's state (against the manifest's job: a job the manifest changed
/// is stale, its old result neither shown nor merged) and merges the Monte Carlo studies whose shards are
/// all done (throws nothing for a bad shard: the study's `problem` says why).
CampaignSummary summarizeCampaign(const CampaignManifest& manifest, const std::string& campaign_dir);

/// "restarts" for a job with a start time (hours, restarts), "whole" for a whole file.
const char* campaignRunsKind(const CampaignJob& job);
/// The distributions of the PPP-AR figures of the done PPP and bag jobs: per
/// station, kind of runs and solution (in the order they first appear), then the
/// same over all stations ("all").
std::vector<CampaignArDistribution> campaignArDistributions(const CampaignSummary& summary);
std::string campaignArSummaryCsv(const CampaignSummary& summary);

std::string campaignSummaryCsv(const CampaignSummary& summary);
std::string campaignSummaryJson(const CampaignSummary& summary);
std::string campaignSummaryMarkdown(const CampaignSummary& summary);

/// Writes summary.csv, .json, .md and the merged studies into `campaign_dir`.
/// Throws std::runtime_error when a file cannot be written.
void writeCampaignSummary(const CampaignSummary& summary, const std::string& campaign_dir);

/// Counts for the progress line of a running campaign.
struct CampaignProgress {
  int total = 0, done = 0, failed = 0, running = 0;
  int done_with_problems = 0;  // of `done`
  double elapsed_s = 0.0;
};
/// "12/24 done, 1 failed, 2 running, 9 waiting; 1:05 elapsed, ~0:58 left" (the
/// estimate from the mean time per finished job so far; "?" before the first);
/// "12/24 done, 1 with problems, 1 failed, ..." when done jobs reported problems.
std::string formatCampaignProgress(const CampaignProgress& progress);

}  // namespace ppp
