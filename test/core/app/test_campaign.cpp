// Campaigns without a backend: manifest expansion (globs, date ranges, hours),
// the up-front input check, job directories with their finished marker,
// resume, the summary, the time window of ppp_solve, and the exact merge of
// Monte Carlo shards (app/campaign_*.h, io/rinex/time_window_source.h,
// evaluation/monte_carlo_records.h). The backends (local pool, Slurm) are
// exercised by scripts/test_campaign_slurm.sh.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>

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

// ---------------------------------------------------------------------------
// Bounds of a manifest, refused with the key named
// ---------------------------------------------------------------------------
namespace {

std::string manifestError(const fs::path& dir, const std::string& text) {
  try {
    loadCampaignManifest(writeManifest(dir, text).string());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

const char* kEntry = "  - {station: a, obs: x, sp3: [s], clk: [c], atx: [a], ";

}  // namespace

TEST(CampaignManifest, DatesOutsideGpsTimeAreRefusedNamingTheKey) {
  const fs::path dir = test::tempDir("campaign_dates_bounds");
  const std::string before = manifestError(dir, std::string("ppp:\n") + kEntry + "dates: {first: 0000-01-01, last: 2020-01-01}}\n");
  EXPECT_NE(before.find("ppp[0].dates.first"), std::string::npos) << before;
  EXPECT_NE(before.find("outside 1980-01-06"), std::string::npos) << before;
  const std::string after = manifestError(dir, std::string("ppp:\n") + kEntry + "dates: {first: 2020-01-01, last: 9999-12-31}}\n");
  EXPECT_NE(after.find("ppp[0].dates.last"), std::string::npos) << after;
  const std::string eve = manifestError(dir, std::string("ppp:\n") + kEntry + "dates: {first: 1980-01-05}}\n");
  EXPECT_NE(eve.find("ppp[0].dates.first"), std::string::npos) << eve;
  // the first day of GPS time and the last of 2100 are dates a manifest may name
  EXPECT_EQ(manifestError(dir, std::string("ppp:\n") + kEntry + "dates: {first: 1980-01-06}}\n"), "no error");
  EXPECT_EQ(manifestError(dir, std::string("ppp:\n") + kEntry + "dates: {first: 2100-12-31}}\n"), "no error");
}

TEST(CampaignManifest, MonteCarloDurationBeyondADayIsRefusedUpFront) {
  const fs::path dir = test::tempDir("campaign_duration");
  const std::string e = manifestError(dir, "monte_carlo:\n  - {study: s, seed: 1, flights: 2, duration_min: 1e9}\n");
  EXPECT_NE(e.find("monte_carlo[0].duration_min"), std::string::npos) << e;
  EXPECT_NE(e.find("at most 1440"), std::string::npos) << e;
  EXPECT_EQ(manifestError(dir, "monte_carlo:\n  - {study: s, seed: 1, flights: 2, duration_min: 1440}\n"), "no error");
}

TEST(CampaignManifest, TheJobCountIsBoundedBeforeTheJobsAreMade) {
  const fs::path dir = test::tempDir("campaign_job_limit");
  const auto t0 = std::chrono::steady_clock::now();
  const std::string e =
      manifestError(dir, "monte_carlo:\n  - {study: s, seed: 1, flights: 100000000, flights_per_job: 1}\n");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  EXPECT_NE(e.find("monte_carlo[0]"), std::string::npos) << e;
  EXPECT_NE(e.find("more than 100000 jobs"), std::string::npos) << e;
  // ten years of hourly jobs (3652 days x 24 = 87,648) and a study of 20,000 shards
  const std::string both = manifestError(dir, "ppp:\n  - {station: a, obs: \"x{yyyy}{doy}\", sp3: [s], clk: [c], atx: [a], "
                                              "dates: {first: 2010-01-01, last: 2019-12-31}, hours: [0, 23]}\n"
                                              "monte_carlo:\n  - {study: s, seed: 1, flights: 20000, flights_per_job: 1}\n");
  EXPECT_NE(both.find("monte_carlo[0]: the campaign would have more than 100000 jobs (87648 before"), std::string::npos)
      << both;
  EXPECT_EQ(manifestError(dir, "monte_carlo:\n  - {study: s, seed: 1, flights: 100000, flights_per_job: 1}\n"),
            "no error");
}

TEST(CampaignManifest, DatedJobsThatWouldReadTheSameFileAreRefused) {
  const fs::path dir = test::tempDir("campaign_same_file");
  touch(dir / "one.rnx");
  const std::string e = manifestError(dir, "ppp:\n  - {station: a, obs: one.rnx, sp3: [s], clk: [c], atx: [a], "
                                               "dates: {first: 2026-05-12, last: 2026-05-14}}\n");
  EXPECT_NE(e.find("ppp[0].obs"), std::string::npos) << e;
  EXPECT_NE(e.find("a_2026-132 and a_2026-133"), std::string::npos) << e;
  EXPECT_NE(e.find("read the same file"), std::string::npos) << e;
  // one day, or hours of a file that spans the days, read different data
  EXPECT_EQ(manifestError(dir, "ppp:\n  - {station: a, obs: one.rnx, sp3: [s], clk: [c], atx: [a], "
                               "dates: {first: 2026-05-13, last: 2026-05-13}}\n"),
            "no error");
  EXPECT_EQ(manifestError(dir, "ppp:\n  - {station: a, obs: one.rnx, sp3: [s], clk: [c], atx: [a], "
                               "dates: {first: 2026-05-12, last: 2026-05-14}, hours: [0, 23]}\n"),
            "no error");
}

TEST(CampaignManifest, ProblemsOfTheSameKindAreFoldedWithACount) {
  const fs::path dir = test::tempDir("campaign_fold");
  touch(dir / "ant.atx");
  const CampaignManifest manifest = loadCampaignManifest(writeManifest(dir, R"(
campaign: {data_root: .}
ppp:
  - station: esbc
    obs: "esbc-{yyyy}-{doy}/ESBC{doy}0.{yy}o"
    dates: {first: 2020-01-01, last: 2020-12-31}
    hours: [0, 23]
    sp3: ["GRG_{yyyy}{doy}.SP3"]
    clk: ["GRG_{yyyy}{doy}*.CLK"]
    atx: [ant.atx]
)").string());
  const auto problems = campaignInputProblems(manifest);
  ASSERT_EQ(problems.size(), 366u * 24u * 3u);
  const auto folded = foldCampaignProblems(problems);
  ASSERT_EQ(folded.size(), 3u);
  EXPECT_EQ(folded[0], problems[0] + " (and 8783 more like it)");
  EXPECT_NE(folded[1].find("sp3 "), std::string::npos) << folded[1];
  EXPECT_NE(folded[2].find("matches no file (and 8783 more like it)"), std::string::npos) << folded[2];
  // different problems stay apart, a single one has no count
  EXPECT_EQ(foldCampaignProblems({"job a: obs /x/a.rnx: no such file", "job b: obs /x/b.rnx: no such file"}).size(), 2u);
  EXPECT_EQ(foldCampaignProblems({"job a: obs /x/1.rnx: no such file"}).front(), "job a: obs /x/1.rnx: no such file");
}

// ---------------------------------------------------------------------------
// Job markers: outputs, stale results, one process per job, write errors
// ---------------------------------------------------------------------------
namespace {

std::string monteCarloManifest(const std::string& parameters) {
  return "campaign: {name: mc}\nmonte_carlo:\n  - {study: s, seed: 7, flights: 2, flights_per_job: 1, rate_hz: 1, " +
         parameters + "}\n";
}

/// Prepares and runs every job of a manifest in `out`.
void runAll(const CampaignManifest& manifest, const fs::path& out) {
  for (const auto& job : manifest.jobs) {
    const std::string dir = campaignJobDir(out.string(), job.id);
    if (!prepareCampaignJob(dir, job)) continue;
    const CampaignJobStatus st = runCampaignJob(dir);
    ASSERT_EQ(st.state, CampaignJobState::Done) << job.id << ": " << st.reason;
  }
}

/// flock(2) on a job's lock file, as another process running the job holds it.
struct HeldJobLock {
  explicit HeldJobLock(const std::string& job_dir) : fd(::open((job_dir + "/job.lock").c_str(), O_CREAT | O_RDWR, 0644)) {
    EXPECT_GE(fd, 0);
    EXPECT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  }
  ~HeldJobLock() { ::close(fd); }
  int fd;
};

}  // namespace

TEST(CampaignJob, AManifestChangeMakesTheJobsStaleNeverMerged) {
  const fs::path out = test::tempDir("campaign_stale");
  const fs::path mdir = out / "m";
  fs::create_directories(mdir);
  const CampaignManifest before = loadCampaignManifest(writeManifest(mdir, monteCarloManifest("duration_min: 1, systems: GE")).string());
  runAll(before, out);
  const CampaignSummary first = summarizeCampaign(before, out.string());
  ASSERT_EQ(first.done, 2);
  ASSERT_EQ(first.studies.size(), 1u);
  EXPECT_TRUE(first.studies[0].merged) << first.studies[0].problem;

  for (const std::string changed : {"duration_min: 2, systems: GE", "duration_min: 1, systems: G, ambiguity_resolution: true"}) {
    const CampaignManifest after = loadCampaignManifest(writeManifest(mdir, monteCarloManifest(changed)).string());
    const CampaignSummary s = summarizeCampaign(after, out.string());
    EXPECT_EQ(s.done, 0) << changed;
    EXPECT_EQ(s.stale, 2) << changed;
    ASSERT_EQ(s.studies.size(), 1u);
    EXPECT_FALSE(s.studies[0].merged) << changed << ": old flights merged under the new parameters";
    const std::string reason = s.jobs[0].status.reason;
    EXPECT_NE(reason.find(changed.rfind("duration_min: 2", 0) == 0 ? "duration_min" : "systems"), std::string::npos)
        << reason;
    EXPECT_FALSE(s.jobs[0].status.result);
    const std::string md = campaignSummaryMarkdown(s);
    EXPECT_NE(md.find("2 stale"), std::string::npos) << md;
    EXPECT_NE(md.find("## Stale"), std::string::npos) << md;
    EXPECT_NE(campaignSummaryCsv(s).find("s_f0-0,monte_carlo,s,,,stale,"), std::string::npos) << campaignSummaryCsv(s);
    // the next run runs them again
    EXPECT_TRUE(prepareCampaignJob(campaignJobDir(out.string(), after.jobs[0].id), after.jobs[0]));
    ASSERT_TRUE(prepareCampaignJob(campaignJobDir(out.string(), after.jobs[0].id), before.jobs[0]));
  }
  // unchanged, the results are the done ones (the directories were prepared back to the old specification)
  runAll(before, out);
  EXPECT_EQ(summarizeCampaign(before, out.string()).done, 2);
}

TEST(CampaignJob, ADoneJobWhoseOutputsAreGoneIsStaleAndRunsAgain) {
  const fs::path out = test::tempDir("campaign_outputs_gone");
  const CampaignManifest manifest =
      loadCampaignManifest(writeManifest(out, monteCarloManifest("duration_min: 1")).string());
  runAll(manifest, out);
  const std::string dir = campaignJobDir(out.string(), manifest.jobs[0].id);
  EXPECT_NE(test::readFileBytes(dir + "/done.json").find("\"outputs\": [[\"flights.mcr\", "), std::string::npos);
  ASSERT_EQ(campaignJobStatus(dir).state, CampaignJobState::Done);

  fs::remove_all(fs::path(dir) / "output");
  EXPECT_EQ(campaignJobStatus(dir, CampaignOutputCheck::Trust).state, CampaignJobState::Done)
      << "a watcher's look takes done.json as it is";
  const CampaignJobStatus gone = campaignJobStatus(dir, manifest.jobs[0]);
  EXPECT_EQ(gone.state, CampaignJobState::Stale);
  EXPECT_NE(gone.reason.find("output/flights.mcr is missing"), std::string::npos) << gone.reason;
  EXPECT_EQ(summarizeCampaign(manifest, out.string()).stale, 1);
  EXPECT_TRUE(prepareCampaignJob(dir, manifest.jobs[0]));
  ASSERT_EQ(runCampaignJob(dir).state, CampaignJobState::Done);

  std::ofstream(dir + "/output/flights.mcr", std::ios::app) << "x";  // changed after the job ended
  EXPECT_EQ(campaignJobStatus(dir).state, CampaignJobState::Stale);
  EXPECT_NE(campaignJobStatus(dir).reason.find("output/flights.mcr has "), std::string::npos);
}

TEST(CampaignJob, AJobIsRunByOneProcessAtATime) {
  const fs::path out = test::tempDir("campaign_job_lock");
  const CampaignManifest manifest =
      loadCampaignManifest(writeManifest(out, monteCarloManifest("duration_min: 1")).string());
  const std::string dir = campaignJobDir(out.string(), manifest.jobs[0].id);
  ASSERT_TRUE(prepareCampaignJob(dir, manifest.jobs[0]));
  {
    const HeldJobLock other(dir);
    EXPECT_TRUE(campaignJobLocked(dir));
    bool locked = false;
    const CampaignJobStatus st = runCampaignJob(dir, &locked);
    EXPECT_TRUE(locked);
    EXPECT_NE(st.reason.find("another process runs this job"), std::string::npos) << st.reason;
    EXPECT_FALSE(fs::exists(fs::path(dir) / "work"));
    EXPECT_FALSE(fs::exists(fs::path(dir) / "failed.json"));
    // the backend does not mark a job failed while another process runs it
    fs::create_directories(fs::path(dir) / "work");
    markCampaignJobFailed(dir, "killed");
    EXPECT_FALSE(fs::exists(fs::path(dir) / "failed.json"));
    EXPECT_NE(campaignJobStatus(dir).reason.find("another process runs it now"), std::string::npos);
  }
  EXPECT_FALSE(campaignJobLocked(dir));
  bool locked = true;
  ASSERT_EQ(runCampaignJob(dir, &locked).state, CampaignJobState::Done);
  EXPECT_FALSE(locked);
  // a finished job is never marked failed: never both markers
  markCampaignJobFailed(dir, "killed");
  EXPECT_FALSE(fs::exists(fs::path(dir) / "failed.json"));
}

TEST(CampaignJob, WriteErrorsSayTheSystemsReasonAndLeaveNoTemporaryFile) {
  const fs::path dir = test::tempDir("campaign_write_error");
  // A file size limit (setrlimit RLIMIT_FSIZE) makes write(2) fail with EFBIG.
  struct rlimit old {};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  struct rlimit small = old;
  small.rlim_cur = 1000;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  std::string error;
  try {
    writeFileAtomically((dir / "big.json").string(), std::string(5000, 'x'));
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_NE(error.find((dir / "big.json.tmp.").string()), std::string::npos) << error;
  EXPECT_NE(error.find(std::strerror(EFBIG)), std::string::npos) << error;
  EXPECT_TRUE(fs::is_empty(dir)) << "a temporary file was left behind";
}

// A full file system (a tmpfs of 64 kB, mounted when this process may): the job's
// failure names "No space left on device", and no temporary file is left.
TEST(CampaignJob, AFullDiskIsNamedAndLeavesNoTemporaryFile) {
  const fs::path mnt = test::tempDir("campaign_full_disk");
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=64k") != 0)
    GTEST_SKIP() << "cannot mount a small tmpfs here (" << std::strerror(errno) << "; needs root)";
  std::string error;
  try {
    writeFileAtomically((mnt / "big.json").string(), std::string(200000, 'x'));
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  EXPECT_NE(error.find(std::strerror(ENOSPC)), std::string::npos) << error;
  EXPECT_NE(error.find((mnt / "big.json.tmp.").string()), std::string::npos) << error;
  EXPECT_TRUE(fs::is_empty(mnt)) << "a temporary file was left behind";
  // a job directory on the full disk: its attempt fails, its marker names the reason
  const CampaignManifest manifest =
      loadCampaignManifest(writeManifest(test::tempDir("campaign_full_disk_m"), monteCarloManifest("duration_min: 1")).string());
  const std::string dir = campaignJobDir(mnt.string(), manifest.jobs[0].id);
  ASSERT_TRUE(prepareCampaignJob(dir, manifest.jobs[0]));
  {
    std::ofstream fill((mnt / "fill").string(), std::ios::binary);
    const std::string block(4096, 'f');
    for (int k = 0; k < 64 && fill; ++k) fill << block;
  }
  const CampaignJobStatus st = runCampaignJob(dir);
  EXPECT_NE(st.state, CampaignJobState::Done);
  for (const auto& e : fs::recursive_directory_iterator(mnt))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
  if (st.state == CampaignJobState::Failed) {
    EXPECT_NE(st.reason.find(std::strerror(ENOSPC)), std::string::npos) << st.reason;
  }
  ::umount(mnt.c_str());
}

TEST(CampaignSummary, DoneJobsWithProblemsAreCountedAndNamed) {
  CampaignSummary s;
  s.name = "p";
  CampaignJobRow row;
  row.job.id = "zim2";
  row.job.group = "zim2";
  row.status.state = CampaignJobState::Done;
  CampaignJobResult r;
  r.epochs_read = r.epochs_solved = 100;
  r.problems = 2;
  r.first_problem = "zim2.rnx line 9000: truncated epoch";
  row.status.result = r;
  s.jobs.push_back(row);
  row.job.id = "ccj2";
  row.status.result->problems = 0;
  row.status.result->first_problem.clear();
  s.jobs.push_back(row);
  s.done = 2;
  s.done_with_problems = 1;
  const std::string md = campaignSummaryMarkdown(s);
  EXPECT_NE(md.find("2 jobs: 2 done (1 with problems)"), std::string::npos) << md;
  EXPECT_NE(md.find("- zim2: 2 problem(s), the first: zim2.rnx line 9000: truncated epoch (jobs/zim2/log.txt)"),
            std::string::npos)
      << md;
  EXPECT_EQ(md.find("- ccj2"), std::string::npos) << md;
  EXPECT_NE(campaignSummaryJson(s).find("\"done_with_problems\": 1"), std::string::npos);

  CampaignProgress p;
  p.total = p.done = 23;
  p.done_with_problems = 1;
  EXPECT_EQ(formatCampaignProgress(p).rfind("23/23 done, 1 with problems, 0 failed, ", 0), 0u) << formatCampaignProgress(p);
}

// A RINEX file cut in the middle of an epoch: the job is done, with its problem
// counted and its first problem's text in the marker and the summary.
TEST(CampaignJob, ATruncatedObservationFileIsDoneWithItsProblemNamed) {
  PPP_REQUIRE_SHARED_DATA();
  const fs::path out = test::tempDir("campaign_truncated");
  std::string rinex = test::readFileBytes(test::dataPath("zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx"));
  rinex.resize(rinex.size() * 2 / 3);
  std::ofstream(out / "cut.rnx", std::ios::binary) << rinex;
  const std::string d = test::sharedDataDir();
  const CampaignManifest manifest = loadCampaignManifest(writeManifest(out, R"(
campaign: {name: cut}
ppp:
  - station: cut
    obs: )" + (out / "cut.rnx").string() + R"(
    sp3: [)" + d + R"(/zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3]
    clk: [)" + d + R"(/zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK]
    atx: [)" + d + R"(/antex/igs20_zim2_gps_trim.atx]
)").string());
  runAll(manifest, out);
  const CampaignSummary s = summarizeCampaign(manifest, out.string());
  ASSERT_EQ(s.done, 1);
  ASSERT_TRUE(s.jobs[0].status.result);
  EXPECT_GT(s.jobs[0].status.result->problems, 0u);
  EXPECT_FALSE(s.jobs[0].status.result->first_problem.empty());
  EXPECT_EQ(s.done_with_problems, 1);
  EXPECT_NE(campaignSummaryMarkdown(s).find("## Done with problems\n\n- cut: "), std::string::npos)
      << campaignSummaryMarkdown(s);
}

namespace {

/// One epoch of a synthetic solution: `error_m` east of the truth... along X, at t0 + k * 30 s.
SolutionEpoch syntheticEpoch(const Eigen::Vector3d& truth, int k, double error_m, bool fixed) {
  SolutionEpoch e;
  e.time = test::gpst(2020, 6, 25, 1) + 30.0 * k;
  e.position_ecef_m = truth + Eigen::Vector3d(error_m, 0.0, 0.0);
  e.status = fixed ? SolutionStatus::PppFixed : SolutionStatus::PppFloat;
  return e;
}

}  // namespace

// A synthetic solution of 21 epochs at 30 s: 5 float at 50 cm, one fixed at 30 cm
// (a wrong fix), 4 float at 20 cm, 10 fixed at 2 cm, and one epoch without a position.
TEST(CampaignArFigures, FirstFixWrongFixesAndConvergenceOfASyntheticSolution) {
  const Eigen::Vector3d truth(3582104.757, 532590.1752, 5232755.1289);
  std::vector<SolutionEpoch> sol;
  for (int k = 0; k < 5; ++k) sol.push_back(syntheticEpoch(truth, k, 0.50, false));
  sol.push_back(syntheticEpoch(truth, 5, 0.30, true));
  for (int k = 6; k < 10; ++k) sol.push_back(syntheticEpoch(truth, k, 0.20, false));
  SolutionEpoch none;
  none.time = test::gpst(2020, 6, 25, 1) + 30.0 * 10;
  none.status = SolutionStatus::NoSolution;
  sol.push_back(none);
  for (int k = 11; k < 21; ++k) sol.push_back(syntheticEpoch(truth, k, 0.02, true));

  const CampaignArFigures f = campaignArFigures("ekf", sol, truth);
  EXPECT_EQ(f.solution, "ekf");
  EXPECT_EQ(f.solved_epochs, 20u);
  EXPECT_EQ(f.fixed_epochs, 11u);
  EXPECT_EQ(f.wrong_fixed_epochs, 1u);
  EXPECT_NEAR(f.worst_wrong_fix_m, 0.30, 1e-6);
  EXPECT_DOUBLE_EQ(f.first_fix_s, 150.0);   // epoch 5
  EXPECT_DOUBLE_EQ(f.below_10cm_s, 330.0);  // epoch 11: below 10 cm from then on
  EXPECT_NEAR(f.mean_3d_m, (5 * 0.50 + 0.30 + 4 * 0.20 + 10 * 0.02) / 20.0, 1e-6);

  // never fixed, never below 10 cm; no truth: the fix figures only
  std::vector<SolutionEpoch> floating;
  for (int k = 0; k < 4; ++k) floating.push_back(syntheticEpoch(truth, k, 0.2, false));
  const CampaignArFigures g = campaignArFigures("smoother_filtered", floating, truth);
  EXPECT_TRUE(std::isinf(g.first_fix_s));
  EXPECT_TRUE(std::isinf(g.below_10cm_s));
  EXPECT_EQ(g.wrong_fixed_epochs, 0u);
  const CampaignArFigures h = campaignArFigures("ekf", sol, std::optional<PositionErrorStatistics>());
  EXPECT_EQ(h.fixed_epochs, 11u);
  EXPECT_DOUBLE_EQ(h.first_fix_s, 150.0);
  EXPECT_TRUE(std::isnan(h.mean_3d_m) && std::isnan(h.below_10cm_s));

  // the summary: per job (summary_ar.csv, summary.json) and the distributions
  CampaignSummary s;
  s.name = "ar";
  for (int k = 0; k < 3; ++k) {
    CampaignJobRow row;
    row.job.id = "esbc_2020-177_r0" + std::to_string(k) + "00";
    row.job.group = "esbc";
    row.job.date = "2020-06-25";
    row.job.ppp.files.window.start = test::gpst(2020, 6, 25, k);
    row.status.state = CampaignJobState::Done;
    CampaignJobResult r;
    r.solutions = {k < 2 ? f : g};
    row.status.result = r;
    s.jobs.push_back(row);
  }
  s.jobs[2].job.id = "esbc_2020-177";  // a whole-file run
  s.jobs[2].job.ppp.files.window.start.reset();
  s.done = 3;
  const std::vector<CampaignArDistribution> d = campaignArDistributions(s);
  ASSERT_EQ(d.size(), 4u);  // esbc restarts ekf, esbc whole smoother_filtered, then the same over "all"
  EXPECT_EQ(d[0].station, "esbc");
  EXPECT_EQ(d[0].runs, "restarts");
  EXPECT_EQ(d[0].run_count, 2u);
  EXPECT_EQ(d[0].fixed_epochs, 22u);
  EXPECT_EQ(d[0].wrong_fixed_epochs, 2u);
  EXPECT_EQ(d[0].runs_with_wrong_fix, 2u);
  EXPECT_DOUBLE_EQ(d[0].first_fix_s.median, 150.0);
  EXPECT_EQ(d[1].runs, "whole");
  EXPECT_EQ(d[1].first_fix_s.never, 1u);
  EXPECT_TRUE(std::isinf(d[1].first_fix_s.median));
  EXPECT_EQ(d[2].station, "all");
  const std::string csv = campaignArSummaryCsv(s);
  EXPECT_NE(csv.find("esbc_2020-177_r0000,esbc,2020-06-25,00:00,restarts,ekf,20,11,1,2.50,5.50,19.00,30.00\n"),
            std::string::npos)
      << csv;
  EXPECT_NE(csv.find("esbc_2020-177,esbc,2020-06-25,,whole,smoother_filtered,4,0,0,never,never,20.00,\n"),
            std::string::npos)
      << csv;
  const std::string md = campaignSummaryMarkdown(s);
  EXPECT_NE(md.find("| esbc | restarts | ekf | 2 | 22/40 | 2 (2) | 2.5 / 2.5 / 2.5 | 5.5 / 5.5 / 5.5 | 19.00 / 19.00 / "
                    "19.00 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("- esbc_2020-177_r0100 ekf: 1 of 11 fixed epochs, the worst 30.0 cm"), std::string::npos) << md;
  const std::string json = campaignSummaryJson(s);
  EXPECT_NE(json.find("\"wrong_fixed_epochs\": 2, \"runs_with_wrong_fix\": 2"), std::string::npos) << json;
  EXPECT_NE(json.find("\"first_fix_s\": {\"count\": 1, \"never\": 1, \"median\": \"never\""), std::string::npos) << json;
}

TEST(CampaignManifest, RestartsExpandToOneJobPerStartTime) {
  const fs::path dir = test::tempDir("campaign_restarts");
  for (const char* f : {"obs/abcd1770.20o", "prod/ORB.sp3", "prod/CLK.clk"}) touch(dir / f);
  const std::string entry = R"(
campaign: {name: r, data_root: .}
ppp:
  - station: abcd
    obs: "obs/abcd{doy}0.{yy}o"
    dates: {first: 2020-06-25, last: 2020-06-25}
    sp3: [prod/ORB.sp3]
    clk: [prod/CLK.clk]
)";
  const CampaignManifest m =
      loadCampaignManifest(writeManifest(dir, entry + "    restarts: {first: \"22:30\", last: \"23:30\", every_min: 30, "
                                                      "length_min: 60}\n").string());
  ASSERT_EQ(m.jobs.size(), 3u);
  EXPECT_EQ(m.jobs[0].id, "abcd_2020-177_r2230");
  EXPECT_EQ(m.jobs[2].id, "abcd_2020-177_r2330");
  EXPECT_EQ(*m.jobs[1].ppp.files.window.start, test::gpst(2020, 6, 25, 23));
  EXPECT_EQ(*m.jobs[2].ppp.files.window.end, test::gpst(2020, 6, 26, 0, 30));
  for (const auto& job : m.jobs)
    EXPECT_EQ(campaignJobYaml(parseCampaignJob(campaignJobYaml(job), "job.yaml")), campaignJobYaml(job));
  // without length_min: to the end of the observations
  const CampaignManifest open_end =
      loadCampaignManifest(writeManifest(dir, entry + "    restarts: {first: \"00:00\", last: \"00:45\", every_min: 5}\n").string());
  ASSERT_EQ(open_end.jobs.size(), 10u);
  EXPECT_EQ(*open_end.jobs[9].ppp.files.window.start, test::gpst(2020, 6, 25, 0, 45));
  EXPECT_FALSE(open_end.jobs[9].ppp.files.window.end);
  // a bad time of day, and hours with restarts, are refused naming the key
  try {
    loadCampaignManifest(writeManifest(dir, entry + "    restarts: {first: \"24:00\"}\n").string());
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("restarts.first"), std::string::npos) << e.what();
  }
  try {
    loadCampaignManifest(writeManifest(dir, entry + "    hours: [0, 1]\n    restarts: {first: \"00:00\"}\n").string());
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("give hours or restarts, not both"), std::string::npos) << e.what();
  }
}

// The PPP-AR restart benchmark of doc/campaigns.md: it expands to its 58 jobs and
// every input is there.
TEST(CampaignManifest, TheArRestartBenchmarkManifestValidates) {
  const CampaignManifest m = loadCampaignManifest(std::string(PPP_REPO_DIR) + "/config/ar_restart_benchmark.yaml");
  ASSERT_EQ(m.jobs.size(), 10u + 47u + 1u);
  EXPECT_EQ(m.jobs[0].id, "ccj2_2021-210_r0000");
  EXPECT_EQ(m.jobs[10].id, "esbc_2020-177_r0000");
  EXPECT_EQ(m.jobs[56].id, "esbc_2020-177_r2300");
  EXPECT_EQ(m.jobs[57].id, "esbc_2020-177");
  for (const auto& j : m.jobs) EXPECT_EQ(j.ppp.estimator, "both") << j.id;
  if (!test::sharedDataAvailable() || fs::path(m.data_root) != fs::path(test::sharedDataDir()).lexically_normal())
    GTEST_SKIP() << "the manifest's data_root " << m.data_root << " is not the shared data";
  EXPECT_EQ(campaignInputProblems(m), std::vector<std::string>{});
}
