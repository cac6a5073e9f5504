// ppp_solve --estimator smoother|both end to end on the real ZIM2 hour, through
// solvePppEstimators (what the tool calls): every written file exists and the
// .pos files read back through our reader with the written positions; the
// smoothed solution's last epoch equals the filtered one (consistency:
// the smoothed and the filtered estimate of the newest state are the same
// estimate); the smoothed mean 3D error is below the EKF's (a loose regression
// guard; the accuracy targets are measured and reported by ppp_solve itself);
// the smoother's diagnostics and bias files hold what they announce; unknown
// estimators are refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "ppp_bayes_tree/evaluation/rtklib_pos.h"
#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_dataset.h"
#include "test_support.h"

namespace ppp {
namespace {

PppSolveRequest zim2Request(const std::string& out_dir, const std::string& estimator) {
  return test::solveRequest(test::zim2Dataset(), out_dir, estimator);
}

std::vector<std::string> readLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

std::vector<std::string> splitCsv(const std::string& line) {  // no quoted commas in the checked columns
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(item);
  return out;
}

TEST(PppSolveSmoother, Zim2BothEndToEnd) {
  PPP_REQUIRE_SHARED_DATA();
  const std::string dir = test::tempDir("ppp_solve_smoother_zim2").string();
  const std::vector<PppSolveOutcome> runs = solvePppEstimators(zim2Request(dir, "both"));
  ASSERT_EQ(runs.size(), 2u);
  const PppSolveOutcome& ekf = runs[0];
  const PppSolveOutcome& sm = runs[1];
  EXPECT_EQ(ekf.run.estimator, "ekf");
  EXPECT_EQ(sm.run.estimator, "smoother");
  ASSERT_EQ(ekf.outputs.size(), 1u);
  ASSERT_EQ(sm.outputs.size(), 2u);
  EXPECT_EQ(sm.outputs[0].pos_path, dir + "/zim2_smoother_filtered.pos");
  EXPECT_EQ(sm.outputs[1].pos_path, dir + "/zim2_smoother_smoothed.pos");
  EXPECT_EQ(sm.epochs_path, dir + "/zim2_smoother_epochs.csv");
  EXPECT_EQ(sm.biases_path, dir + "/zim2_smoother_biases.csv");
  EXPECT_EQ(sm.run.epochs_solved, 120u);  // all 120 epochs of the file (../shared/data/README.md)

  // Every file exists; every .pos reads back with the written positions.
  for (const auto* run : {&ekf, &sm}) {
    for (const auto& o : run->outputs) {
      for (const auto& p : {o.csv_path, o.pos_path, o.json_path}) EXPECT_TRUE(std::filesystem::exists(p)) << p;
      const PosFile pos = readRtklibPos(o.pos_path);
      EXPECT_TRUE(pos.report.clean()) << o.pos_path << ": " << pos.report.summary();
      ASSERT_EQ(pos.records.size(), 120u) << o.pos_path;
      ASSERT_EQ(o.solution.size(), 120u);
      for (std::size_t i = 0; i < pos.records.size(); ++i) {
        EXPECT_EQ(pos.records[i].time, o.solution[i].time);
        ASSERT_TRUE(o.solution[i].position_ecef_m.has_value());
        EXPECT_LT((pos.records[i].position_ecef_m - *o.solution[i].position_ecef_m).norm(), 1e-3);  // %14.4f
      }
      ASSERT_TRUE(o.statistics.has_value());
      const auto reread = computePositionErrorStatistics(toSolutionEpochs(pos), *zim2Request("", "").truth_ecef_m);
      EXPECT_NEAR(reread.all.mean_m, o.statistics->all.mean_m, 1e-3) << o.label;
      const std::string json = test::readFileBytes(o.json_path);
      EXPECT_NE(json.find("\"solution\": \"" + o.label + "\""), std::string::npos) << o.json_path;
    }
    EXPECT_TRUE(std::filesystem::exists(run->epochs_path));
    EXPECT_TRUE(std::filesystem::exists(run->residuals_path));
  }

  // The smoothed solution's last epoch is the filtered one (same estimate of the newest state).
  const auto& filtered = sm.outputs[0].solution;
  const auto& smoothed = sm.outputs[1].solution;
  EXPECT_EQ(smoothed.back().time, filtered.back().time);
  EXPECT_LT((*smoothed.back().position_ecef_m - *filtered.back().position_ecef_m).norm(), 1e-6);
  EXPECT_NEAR(*smoothed.back().zwd_m, *filtered.back().zwd_m, 1e-6);
  // ... while earlier epochs differ (smoothing used the later data): the first by more than 1 cm.
  EXPECT_GT((*smoothed.front().position_ecef_m - *filtered.front().position_ecef_m).norm(), 0.01);
  ASSERT_TRUE(smoothed.front().covariance_ecef_m2.has_value());
  EXPECT_LT(smoothed.front().covariance_ecef_m2->trace(), filtered.front().covariance_ecef_m2->trace());

  // Loose regression guard: smoothed mean 3D below the EKF's, and below 10 cm.
  const auto& ekf_stats = *ekf.outputs[0].statistics;
  const auto& smoothed_stats = *sm.outputs[1].statistics;
  EXPECT_LT(smoothed_stats.all.mean_m, ekf_stats.all.mean_m);
  EXPECT_LT(smoothed_stats.all.mean_m, 0.10);

  // Update times: one per solved epoch, the median positive and not above p99.
  ASSERT_TRUE(sm.update_time.has_value());
  EXPECT_EQ(sm.update_time->count, 120u);
  EXPECT_GT(sm.update_time->median_s, 0.0);
  EXPECT_LE(sm.update_time->median_s, sm.update_time->p99_s);
  EXPECT_FALSE(ekf.update_time.has_value());
  EXPECT_NE(test::readFileBytes(sm.outputs[1].json_path).find("\"update_time_ms\""), std::string::npos);

  // Smoother diagnostics: one row per epoch, with the smoother's columns filled.
  const auto epochs = readLines(sm.epochs_path);
  ASSERT_EQ(epochs.size(), 121u);
  const auto header = splitCsv(epochs[0]);
  auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t c_used = column("used"), c_sats = column("used_sats"), c_active = column("active_biases"),
                    c_reelim = column("reeliminated"), c_update = column("update_ms");
  column("relinearized");
  for (std::size_t i = 1; i < epochs.size(); ++i) {
    const auto f = splitCsv(epochs[i]);
    ASSERT_GT(f.size(), c_update) << epochs[i];
    const int used = std::stoi(f[c_used]);
    EXPECT_EQ(static_cast<int>((f[c_sats].size() + 1) / 4), used) << epochs[i];  // "G10 G12 ..."
    EXPECT_GE(std::stoi(f[c_active]), used);  // every used satellite has an active bias
    EXPECT_GT(std::stoi(f[c_reelim]), 0);     // each update re-eliminates at least the new state
    EXPECT_GT(std::stod(f[c_update]), 0.0);
  }

  // Biases: the filtered value per epoch and observed arc, with the arc's final smoothed value.
  const auto biases = readLines(sm.biases_path);
  ASSERT_GT(biases.size(), 120u);
  EXPECT_EQ(biases[0], "time_gpst,arc,sat,bias_m,sigma_m,smoothed_final_m");
  std::set<std::string> arcs;
  std::string last_bias_of_g10_arc, final_of_g10_arc;
  for (std::size_t i = 1; i < biases.size(); ++i) {
    const auto f = splitCsv(biases[i]);
    ASSERT_EQ(f.size(), 6u) << biases[i];
    arcs.insert(f[2] + "/" + f[1]);
    EXPECT_GT(std::stod(f[4]), 0.0);  // sigma
    ASSERT_FALSE(f[5].empty()) << biases[i];  // full smoother: every arc's final value is known
    if (f[2] == "G10") {
      last_bias_of_g10_arc = f[3];
      final_of_g10_arc = f[5];
    }
  }
  EXPECT_GE(arcs.size(), 12u);  // 12 satellites used at the first epoch
  // G10 is tracked to the last epoch (ZIM2 file): its filtered value at the last
  // epoch is the final smoothed one (same estimate, 0.1 mm text resolution).
  ASSERT_FALSE(last_bias_of_g10_arc.empty());
  EXPECT_NEAR(std::stod(last_bias_of_g10_arc), std::stod(final_of_g10_arc), 2e-4);
  std::filesystem::remove_all(dir);
}

TEST(PppSolveSmoother, UnknownEstimatorsAreRefused) {
  PppSolveRequest r;
  r.out_dir = test::tempDir("ppp_solve_smoother_args").string();
  r.estimator = "kalman";
  EXPECT_THROW(solvePpp(r), std::invalid_argument);
  EXPECT_THROW(solvePppEstimators(r), std::invalid_argument);
  r.estimator = "";
  EXPECT_THROW(solvePppEstimators(r), std::invalid_argument);
  r.estimator = "both";  // only through solvePppEstimators
  try {
    solvePpp(r);
    ADD_FAILURE() << "solvePpp accepted 'both'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'both'"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(r.out_dir);
}

TEST(PppSolveSmoother, TimingSummaryNearestRank) {
  // 1..100 ms: median 50.5 ms (mean of the two middle values), p90 = 90th value, p99 = 99th
  // value, max 100 ms.
  std::vector<double> t;
  for (int k = 100; k >= 1; --k) t.push_back(k * 1e-3);
  const TimingSummary s = summarizeTimes(t);
  EXPECT_EQ(s.count, 100u);
  EXPECT_NEAR(s.median_s, 0.0505, 1e-12);
  EXPECT_NEAR(s.p90_s, 0.090, 1e-12);
  EXPECT_NEAR(s.p99_s, 0.099, 1e-12);
  EXPECT_NEAR(s.max_s, 0.100, 1e-12);
  EXPECT_EQ(summarizeTimes({}).count, 0u);
  EXPECT_NEAR(summarizeTimes({0.003}).p99_s, 0.003, 1e-15);
  EXPECT_NEAR(summarizeTimes({0.003}).p90_s, 0.003, 1e-15);
}

}  // namespace
}  // namespace ppp
