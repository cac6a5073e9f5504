// Campaigns without a backend: manifest expansion (globs, date ranges, hours),
// the up-front input check, job directories with their finished marker,
// resume, the summary, the time window of ppp_solve, and the exact merge of
// Monte Carlo shards (app/campaign_*.h, io/rinex/time_window_source.h,
// evaluation/monte_carlo_records.h). The backends (local pool, Slurm) are
// exercised by scripts/test_campaign_slurm.sh.
#include <gtest/gtest.h>

#include <cmath>

#include <filesystem>
#include <fstream>

#include "ppp_bayes_tree/app/campaign_summary.h"
#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/evaluation/monte_carlo_records.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "test_support.h"

using namespace ppp;
namespace fs = std::filesystem;

namespace {

void touch(const fs::path& p) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << "x\n";
}

fs::path writeManifest(const fs::path& dir, const std::string& text) {
  const fs::path p = dir / "manifest.yaml";
  std::ofstream(p) << text;
  return p;
}

// ZIM2, one hour at 30 s (shared data README): the real inputs of a PPP job.
const char* kZim2Entry = R"(
  - station: zim2
    obs: zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx
    sp3: [zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3]
    clk: [zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK]
    atx: [antex/igs20_zim2_gps_trim.atx]
    truth: [4331299.5841, 567537.7070, 4633133.9645]
)";

std::string zim2Manifest(const std::string& extra_ppp = "") {
  return "campaign: {name: t, data_root: " + test::sharedDataDir() + "}\nppp:" + kZim2Entry + extra_ppp;
}

}  // namespace

TEST(CampaignManifest, DatesHoursAndGlobsExpandToJobs) {
  const fs::path dir = test::tempDir("campaign_expand");
  for (const char* f : {"obs/abcd1770.20o", "obs/abcd1780.20o", "prod/ORB_2020177.sp3", "prod/ORB_2020178.sp3",
                        "prod/CLK_2020177_a.clk", "prod/CLK_2020177_b.clk", "prod/CLK_2020178_a.clk",
                        "ant.atx", "multi/x_one.rnx", "multi/x_two.rnx"})
    touch(dir / f);
  const fs::path m = writeManifest(dir, R"(
campaign: {name: expand, data_root: .}
ppp:
  - station: abcd
    obs: "obs/abcd{doy}0.{yy}o"
    dates: {first: 2020-06-25, last: 2020-06-26}
    hours: [22, 23]
    sp3: ["prod/ORB_{yyyy}{doy}.sp3"]
    clk: ["prod/CLK_{yyyy}{doy}_*.clk"]
    atx: [ant.atx]
  - station: multi
    obs: multi/x_*.rnx
    sp3: [prod/ORB_2020177.sp3]
    clk: [prod/CLK_2020177_a.clk]
    atx: [ant.atx]
monte_carlo:
  - {study: mc, seed: 7, flights: 10, flights_per_job: 4}
)");
  const CampaignManifest manifest = loadCampaignManifest(m.string());
  std::vector<std::string> ids;
  for (const auto& j : manifest.jobs) ids.push_back(j.id);
  EXPECT_EQ(ids, (std::vector<std::string>{"abcd_2020-177_h22", "abcd_2020-177_h23", "abcd_2020-178_h22",
                                           "abcd_2020-178_h23", "multi_x_one", "multi_x_two", "mc_f0-3", "mc_f4-7",
                                           "mc_f8-9"}));
  const CampaignJob& j = manifest.jobs[1];  // day 177, hour 23
  EXPECT_EQ(j.ppp.files.obs, (dir / "obs/abcd1770.20o").string());
  EXPECT_EQ(j.ppp.files.sp3, std::vector<std::string>{(dir / "prod/ORB_2020177.sp3").string()});
  // the clk glob: both files of the day, sorted, not the other day's
  EXPECT_EQ(j.ppp.files.clk, (std::vector<std::string>{(dir / "prod/CLK_2020177_a.clk").string(),
                                                        (dir / "prod/CLK_2020177_b.clk").string()}));
  EXPECT_EQ(j.date, "2020-06-25");
  EXPECT_EQ(j.hour, 23);
  ASSERT_TRUE(j.ppp.files.window.start && j.ppp.files.window.end);
  EXPECT_EQ(*j.ppp.files.window.start, test::gpst(2020, 6, 25, 23));
  EXPECT_EQ(*j.ppp.files.window.end, test::gpst(2020, 6, 26, 0));
  EXPECT_EQ(manifest.jobs[2].ppp.files.obs, (dir / "obs/abcd1780.20o").string());
  EXPECT_EQ(manifest.jobs[8].monte_carlo.first_flight, 8);
  EXPECT_EQ(manifest.jobs[8].monte_carlo.flights, 2);
  EXPECT_EQ(manifest.jobs[8].monte_carlo.study_flights, 10);
  EXPECT_TRUE(campaignInputProblems(manifest).empty());

  // job.yaml carries every concrete input: it reads back to the same job
  for (const auto& job : manifest.jobs) {
    const std::string yaml = campaignJobYaml(job);
    EXPECT_EQ(campaignJobYaml(parseCampaignJob(yaml, "job.yaml")), yaml) << job.id;
  }
}

TEST(CampaignManifest, MissingInputsAreNamedBeforeAnythingRuns) {
  const fs::path dir = test::tempDir("campaign_missing");
  touch(dir / "a.rnx");
  touch(dir / "a.clk");
  touch(dir / "ant.atx");
  const CampaignManifest manifest = loadCampaignManifest(writeManifest(dir, R"(
campaign: {data_root: .}
ppp:
  - station: a
    obs: a.rnx
    sp3: [gone.sp3]
    clk: [a.clk, "nothing_*.clk"]
    atx: [ant.atx]
)").string());
  const auto problems = campaignInputProblems(manifest);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_NE(problems[0].find((dir / "gone.sp3").string()), std::string::npos) << problems[0];
  EXPECT_NE(problems[0].find("no such file"), std::string::npos) << problems[0];
  EXPECT_NE(problems[1].find("nothing_*.clk"), std::string::npos) << problems[1];
  EXPECT_NE(problems[1].find("matches no file"), std::string::npos) << problems[1];
}

TEST(CampaignManifest, BagEntriesExpandToOneJobPerBagAndAreChecked) {
  const fs::path dir = test::tempDir("campaign_bags");
  touch(dir / "flights" / "f1.bag");
  touch(dir / "flights" / "f2.bag");
  touch(dir / "truth.csv");
  const CampaignManifest manifest = loadCampaignManifest(writeManifest(dir, R"(
campaign: {data_root: .}
bags:
  - {name: uav, bag: "flights/*.bag", estimator: both, truth_csv: truth.csv}
  - {name: lost, bag: flights/f3.bag, truth: [1, 2, 3]}
)").string());
  ASSERT_EQ(manifest.jobs.size(), 3u);
  EXPECT_EQ(manifest.jobs[0].id, "uav_f1");
  EXPECT_EQ(manifest.jobs[1].id, "uav_f2");
  EXPECT_EQ(manifest.jobs[2].id, "lost");
  for (const auto& job : manifest.jobs) {
    EXPECT_EQ(job.kind, CampaignJobKind::Bag);
    const std::string yaml = campaignJobYaml(job);
    EXPECT_EQ(campaignJobYaml(parseCampaignJob(yaml, "job.yaml")), yaml) << job.id;
  }
  EXPECT_EQ(manifest.jobs[1].ppp.files.obs, (dir / "flights" / "f2.bag").string());
  EXPECT_EQ(manifest.jobs[1].ppp.truth_csv, (dir / "truth.csv").string());
  EXPECT_EQ(manifest.jobs[1].ppp.estimator, "both");
  // The missing bag is named; this test binary has no ppp_bag_solve beside it
  // only in the core (plain CMake) build, which is then named as well.
  const auto problems = campaignInputProblems(manifest);
  ASSERT_GE(problems.size(), 1u);
  EXPECT_NE(problems[0].find("job lost: bag " + (dir / "flights" / "f3.bag").string() + ": no such file"),
            std::string::npos)
      << problems[0];
  const bool solver_built = fs::exists(campaignBagSolverPath());
  EXPECT_EQ(problems.size(), solver_built ? 1u : 2u);
  if (!solver_built) EXPECT_NE(problems[1].find("ppp_bag_solve"), std::string::npos) << problems[1];
}

TEST(CampaignManifest, BadManifestsNameTheKey) {
  const fs::path dir = test::tempDir("campaign_bad");
  auto error = [&](const std::string& text) {
    try {
      loadCampaignManifest(writeManifest(dir, text).string());
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("campaign: {}\nstations: []\n").find("stations: unknown key (line 2"), std::string::npos);
  EXPECT_NE(error("ppp:\n  - {station: a, obs: x, sp3: [s], clk: [c], atx: [a], hours: [0, 1]}\n").find("ppp[0].hours"),
            std::string::npos);
  EXPECT_NE(error("ppp:\n  - {station: a, obs: x, sp3: [s], clk: [c], atx: [a], dates: {first: 2020-13-01}}\n")
                .find("ppp[0].dates.first"),
            std::string::npos);
  EXPECT_NE(error("ppp:\n  - {station: a, obs: x, sp3: [s], clk: [c], atx: [a]}\n  - {station: a, obs: y, sp3: [s], "
                  "clk: [c], atx: [a]}\n")
                .find("two jobs have the id a"),
            std::string::npos);
  EXPECT_NE(error("campaign: {}\n").find("no jobs"), std::string::npos);
  EXPECT_NE(error("slurm: {time_limit: \"1:xx\"}\nppp:\n  - {station: a, obs: x, sp3: [s], clk: [c], atx: [a]}\n")
                .find("slurm.time_limit"),
            std::string::npos);
}

// The formats of sbatch --time (sbatch(1), "-t, --time"): "minutes", "minutes:seconds",
// "hours:minutes:seconds", "days-hours", "days-hours:minutes", "days-hours:minutes:seconds";
// a limit of zero imposes none.
TEST(CampaignManifest, SlurmTimeLimitsInEveryFormOfSbatch) {
  EXPECT_EQ(slurmTimeLimit_s("30"), 1800.0);
  EXPECT_EQ(slurmTimeLimit_s("30:15"), 1815.0);
  EXPECT_EQ(slurmTimeLimit_s("01:00:00"), 3600.0);
  EXPECT_EQ(slurmTimeLimit_s("2-12"), 2 * 86400.0 + 12 * 3600.0);
  EXPECT_EQ(slurmTimeLimit_s("1-00:30"), 86400.0 + 1800.0);
  EXPECT_EQ(slurmTimeLimit_s("1-02:03:04"), 86400.0 + 2 * 3600.0 + 3 * 60.0 + 4.0);
  EXPECT_TRUE(std::isinf(*slurmTimeLimit_s("UNLIMITED")));
  EXPECT_TRUE(std::isinf(*slurmTimeLimit_s("0")));
  for (const char* bad : {"", "1:2:3:4", "1h", "-5", "1-", "1--2", "a-01:00", "01::00", " 30"})
    EXPECT_FALSE(slurmTimeLimit_s(bad)) << "'" << bad << "'";
}

TEST(CampaignJob, FinishedMarkerResumeAndSummary) {
  PPP_REQUIRE_SHARED_DATA();
  const fs::path out = test::tempDir("campaign_jobs");
  const CampaignManifest manifest =
      loadCampaignManifest(writeManifest(out, zim2Manifest(R"(
  - station: broken
    obs: zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK
    sp3: [zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3]
    clk: [zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK]
    atx: [antex/igs20_zim2_gps_trim.atx]
)")).string());
  ASSERT_EQ(manifest.jobs.size(), 2u);
  const std::string zim2 = campaignJobDir(out.string(), "zim2"), broken = campaignJobDir(out.string(), "broken");
  ASSERT_TRUE(prepareCampaignJob(zim2, manifest.jobs[0]));
  ASSERT_TRUE(prepareCampaignJob(broken, manifest.jobs[1]));
  EXPECT_EQ(campaignJobStatus(zim2).state, CampaignJobState::Pending);

  // A job writes into work/, renames it to output/ and only then writes the marker.
  const CampaignJobStatus done = runCampaignJob(zim2);
  ASSERT_EQ(done.state, CampaignJobState::Done) << done.reason;
  EXPECT_FALSE(fs::exists(fs::path(zim2) / "work"));
  EXPECT_TRUE(fs::exists(fs::path(zim2) / "output" / "zim2_ekf.csv"));
  EXPECT_TRUE(fs::exists(fs::path(zim2) / "done.json"));
  // no wall-clock figure in the outputs: runs of the same inputs write the same bytes
  EXPECT_EQ(test::readFileBytes(zim2 + "/output/zim2_ekf_summary.json").find("processing_time_s"), std::string::npos);

  // The figures are those of ppp_solve on the same inputs.
  PppSolveRequest req;
  req.files = manifest.jobs[0].ppp.files;
  req.truth_ecef_m = manifest.jobs[0].ppp.truth_ecef_m;
  req.out_dir = (out / "direct").string();
  const PppSolveOutcome direct = solvePpp(req);
  ASSERT_TRUE(done.result && direct.statistics);
  EXPECT_EQ(done.result->mean_3d_m, direct.statistics->all.mean_m);
  EXPECT_EQ(done.result->first_window_mean_3d_m, direct.statistics->first_window.mean_m);
  EXPECT_EQ(done.result->epochs_solved, direct.run.epochs_solved);
  EXPECT_EQ(test::readFileBytes(zim2 + "/output/zim2_ekf.csv"), test::readFileBytes(direct.csv_path));

  // A failing job leaves failed.json with the reason, no marker, no output.
  const CampaignJobStatus failed = runCampaignJob(broken);
  EXPECT_EQ(failed.state, CampaignJobState::Failed);
  EXPECT_NE(failed.reason.find("IGS0OPSFIN_20261330000_90M_30S_CLK.CLK"), std::string::npos) << failed.reason;
  EXPECT_FALSE(fs::exists(fs::path(broken) / "done.json"));
  EXPECT_FALSE(fs::exists(fs::path(broken) / "output"));
  // The status carries when the failed marker was written (a watcher tells a new attempt's
  // marker from an earlier one by it); other states have none.
  EXPECT_EQ(campaignJobStatus(broken).failed_marker_time, fs::last_write_time(fs::path(broken) / "failed.json"));
  EXPECT_FALSE(campaignJobStatus(zim2).failed_marker_time);

  // Resume: the finished job is not prepared again (its outputs stay as they are) ...
  const auto written = fs::last_write_time(fs::path(zim2) / "done.json");
  EXPECT_FALSE(prepareCampaignJob(zim2, manifest.jobs[0]));
  EXPECT_TRUE(prepareCampaignJob(broken, manifest.jobs[1]));
  EXPECT_EQ(fs::last_write_time(fs::path(zim2) / "done.json"), written);
  // ... an attempt killed mid-run (work/ left, no marker) is interrupted and runs again ...
  fs::remove(fs::path(broken) / "failed.json");
  fs::create_directories(fs::path(broken) / "work");
  EXPECT_EQ(campaignJobStatus(broken).state, CampaignJobState::Interrupted);
  EXPECT_TRUE(prepareCampaignJob(broken, manifest.jobs[1]));
  // ... an output/ without its marker is not finished either (renamed, marker not yet written) ...
  fs::remove(fs::path(zim2) / "done.json");
  EXPECT_EQ(campaignJobStatus(zim2).state, CampaignJobState::Interrupted);
  ASSERT_EQ(runCampaignJob(zim2).state, CampaignJobState::Done);
  // ... and a job whose specification changed runs again.
  CampaignJob changed = manifest.jobs[0];
  changed.ppp.estimator = "smoother";
  EXPECT_TRUE(prepareCampaignJob(zim2, changed));
  EXPECT_EQ(campaignJobStatus(zim2).state, CampaignJobState::Interrupted);  // old output, no valid marker
  ASSERT_TRUE(prepareCampaignJob(zim2, manifest.jobs[0]));
  ASSERT_EQ(runCampaignJob(zim2).state, CampaignJobState::Done);

  // The summary: one row per job, from the job directories alone.
  const CampaignSummary summary = summarizeCampaign(manifest, out.string());
  EXPECT_EQ(summary.done, 1);
  EXPECT_EQ(summary.failed + summary.interrupted, 1);
  const std::string csv = campaignSummaryCsv(summary);
  char mean_cm[32];
  std::snprintf(mean_cm, sizeof mean_cm, ",%.2f,", direct.statistics->all.mean_m * 100.0);
  EXPECT_NE(csv.find("zim2,ppp,zim2,,,done,120,120"), std::string::npos) << csv;
  EXPECT_NE(csv.find(mean_cm), std::string::npos) << csv;
  EXPECT_NE(campaignSummaryJson(summary).find("\"done\": 1"), std::string::npos);
  EXPECT_NE(campaignSummaryMarkdown(summary).find("## Failures"), std::string::npos);
}

TEST(CampaignTimeWindow, OnlyTheEpochsInsideTheWindowAreProcessed) {
  PPP_REQUIRE_SHARED_DATA();
  const CampaignManifest manifest =
      loadCampaignManifest(writeManifest(test::tempDir("campaign_window"), zim2Manifest()).string());
  PppSolveRequest req;
  req.files = manifest.jobs[0].ppp.files;
  req.files.window.start = test::gpst(2026, 5, 13, 0, 15);
  req.files.window.end = test::gpst(2026, 5, 13, 0, 30);
  req.out_dir = test::tempDir("campaign_window_out").string();
  const PppSolveOutcome o = solvePpp(req);
  EXPECT_EQ(o.run.epochs_read, 30u);  // 00:15:00 .. 00:29:30 at 30 s
  ASSERT_FALSE(o.solution.empty());
  EXPECT_EQ(o.solution.front().time, test::gpst(2026, 5, 13, 0, 15));
  EXPECT_EQ(o.solution.back().time, test::gpst(2026, 5, 13, 0, 29, 30));
}

TEST(CampaignMonteCarlo, ShardsMergeIntoTheOneRunStudyExactly) {
  MonteCarloOptions study;
  study.flights = 4;
  study.seed = 11;
  study.duration_s = 120.0;
  study.first_window_s = 60.0;
  study.threads = 2;
  const MonteCarloResult one = runMonteCarlo(study);

  const fs::path dir = test::tempDir("campaign_mc");
  std::vector<std::vector<MonteCarloFlightRun>> shards;
  for (int first : {2, 0}) {  // shards in any order
    MonteCarloOptions shard = study;
    shard.first_flight = first;
    shard.flights = 2;
    shard.threads = 1;
    const std::string path = (dir / ("shard" + std::to_string(first) + ".mcr")).string();
    writeMonteCarloFlightRecords(runMonteCarlo(shard).flights, path);
    shards.push_back(readMonteCarloFlightRecords(path, study));
  }
  const MonteCarloResult merged = mergeMonteCarloShards(study, shards);
  const MonteCarloSummary &a = one.summary, &b = merged.summary;
  for (std::size_t e = 0; e < kMonteCarloEstimators; ++e) {
    EXPECT_EQ(a.cdf_all_m[e], b.cdf_all_m[e]);
    EXPECT_EQ(a.cdf_first_window_m[e], b.cdf_first_window_m[e]);
    EXPECT_EQ(a.first_window[e].mean_m, b.first_window[e].mean_m);
    EXPECT_EQ(a.first_window[e].median_m, b.first_window[e].median_m);
    EXPECT_EQ(a.convergence_median_s[e], b.convergence_median_s[e]);
    EXPECT_EQ(a.convergence_never[e], b.convergence_never[e]);
  }
  EXPECT_EQ(a.representative, b.representative);
  const fs::path w1 = dir / "one", w2 = dir / "merged";
  writeMonteCarloOutputs(one, w1.string());
  writeMonteCarloOutputs(merged, w2.string());
  for (const char* f : {"error_cdf.csv", "error_vs_time.csv", "bias_convergence.csv", "representative_flight.csv"})
    EXPECT_EQ(test::readFileBytes((w1 / f).string()), test::readFileBytes((w2 / f).string())) << f;

  // a missing shard, a repeated one, records of another study, a truncated file
  EXPECT_THROW(mergeMonteCarloShards(study, {shards[0]}), std::invalid_argument);
  EXPECT_THROW(mergeMonteCarloShards(study, {shards[0], shards[0], shards[1]}), std::invalid_argument);
  MonteCarloOptions other = study;
  other.seed = 12;
  const std::string path = (dir / "shard0.mcr").string();
  EXPECT_THROW(readMonteCarloFlightRecords(path, other), ParseError);
  std::string bytes = test::readFileBytes(path);
  bytes.resize(bytes.size() / 2);
  std::ofstream((dir / "cut.mcr").string(), std::ios::binary) << bytes;
  try {
    readMonteCarloFlightRecords((dir / "cut.mcr").string(), study);
    ADD_FAILURE() << "a truncated file was read";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("cut.mcr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
}

TEST(CampaignProgress, CountsAndTimeLeft) {
  CampaignProgress p;
  p.total = 10;
  p.done = 3;
  p.failed = 1;
  p.running = 2;
  p.elapsed_s = 40.0;
  // 4 finished in 40 s: 6 more take about 60 s
  EXPECT_EQ(formatCampaignProgress(p), "3/10 done, 1 failed, 2 running, 4 waiting; 0:40 elapsed, ~1:00 left");
  p.done = p.failed = p.running = 0;
  EXPECT_NE(formatCampaignProgress(p).find("~? left"), std::string::npos);
}
