// The ROS-free part of ppp_bag_report (app/replay_report.h): truth
// matching by time, assembling a node's solution from its status and position
// samples, the rows with the core statistics, the table/JSON/CSV, the datum.
// Known values are built into the in-memory data (errors of 1..N cm, etc.).
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "ppp_bayes_tree/app/replay_report.h"
#include "ppp_bayes_tree/types/frames.h"

namespace {

using ppp::GnssTime;

const GnssTime kT0 = GnssTime::fromGpsWeek(2418, 259200.0);  // 2026-05-13 00:00 GPST
const Eigen::Vector3d kZim2(4331299.5841, 567537.7070, 4633133.9645);  // ../shared/data/README.md

// A truth trajectory at 1 Hz moving 2 m/s east from ZIM2.
ppp::TruthTrajectory eastwardTruth(int n) {
  ppp::TruthTrajectory t;
  for (int k = 0; k < n; ++k) {
    t.time.push_back(kT0 + k);
    t.position_ecef_m.push_back(ppp::enuToEcef(Eigen::Vector3d(2.0 * k, 0, 0), kZim2));
  }
  return t;
}

TEST(TruthTrajectory, MatchesSamplesWithinToleranceAndInterpolatesShortGaps) {
  const ppp::TruthTrajectory t = eastwardTruth(10);
  ASSERT_TRUE(t.at(kT0 + 3.004).has_value());
  EXPECT_EQ(*t.at(kT0 + 3.004), t.position_ecef_m[3]);  // within 10 ms: the sample itself
  EXPECT_EQ(*t.at(kT0 + 2.996), t.position_ecef_m[3]);
  // Half-way between samples 3 and 4: the mean of the two (1 m further east than sample 3).
  const auto mid = t.at(kT0 + 3.5);
  ASSERT_TRUE(mid.has_value());
  EXPECT_NEAR((*mid - 0.5 * (t.position_ecef_m[3] + t.position_ecef_m[4])).norm(), 0.0, 1e-6);
  EXPECT_NEAR((*mid - t.position_ecef_m[3]).norm(), 1.0, 1e-6);
  // No extrapolation before the first or after the last sample.
  EXPECT_FALSE(t.at(kT0 - 0.5).has_value());
  EXPECT_FALSE(t.at(kT0 + 9.5).has_value());
  // A gap longer than max_gap_s is not bridged.
  ppp::TruthMatchOptions strict;
  strict.max_gap_s = 0.5;
  EXPECT_FALSE(t.at(kT0 + 3.5, strict).has_value());
  // A fixed point is the truth of every instant.
  const auto fixed = ppp::TruthTrajectory::fixedPoint(kZim2);
  EXPECT_EQ(*fixed.at(kT0 + 12345.6), kZim2);
}

TEST(TruthCsv, ReadsSimulatorTruthColumnsAndReportsBadRows) {
  // The columns of writeTruthEpochsCsv (simulation_writers.h), plus bad rows.
  const std::string text =
      "time_gpst,gps_week,seconds_of_week,x_m,y_m,z_m,latitude_deg\n"
      "2026-05-13 00:00:00.000,2418,259200.000,4331299.5841,567537.7070,4633133.9645,46.8\n"
      "2026-05-13 00:00:01.000,2418,259201.000,4331300.5841,567537.7070,4633133.9645,46.8\n"
      "bad,2418,abc,1,2,3,4\n"                                                            // malformed
      "2026-05-13 00:00:01.000,2418,259201.000,4331300.5841,567537.7070,4633133.9645,46.8\n"  // not after
      "2026-05-13 00:00:02.000,2418,259202.000,1.0,2.0,3.0,46.8\n"                         // not on Earth
      "2026-05-13 00:00:03.000,2418,259203.000,,,,46.8\n"                                  // no position
      "2026-05-13 00:00:04.000,2418\n"                                                     // short
      "2026-05-13 00:00:05.000,2418,259205.500,4331301.0,567537.7070,4633133.9645,46.8\n";
  auto src = ppp::memoryLineSource(text, "truth.csv");
  ppp::ParseReport report;
  const ppp::TruthTrajectory t = ppp::readTruthCsv(*src, report);
  ASSERT_EQ(t.time.size(), 3u);
  EXPECT_EQ(t.time[0], kT0);
  EXPECT_DOUBLE_EQ(t.time[2] - kT0, 5.5);
  EXPECT_DOUBLE_EQ(t.position_ecef_m[1].x(), 4331300.5841);
  EXPECT_EQ(report.problemCount(), 4u);  // malformed, not after, not on Earth, short
  EXPECT_EQ(report.counters().at("rows without position"), 1u);
}

TEST(TruthCsv, AcceptsPppSolveColumnsAndRejectsHeaderWithoutPosition) {
  auto ok = ppp::memoryLineSource("gps_week,tow_s,time_gpst,x_m,y_m,z_m\n2418,259200,t,4331299.5,567537.7,4633133.9\n");
  ppp::ParseReport report;
  EXPECT_EQ(ppp::readTruthCsv(*ok, report).time.size(), 1u);
  auto bad = ppp::memoryLineSource("gps_week,seconds_of_week,x_m,y_m\n2418,1,2,3\n", "nz.csv");
  try {
    ppp::readTruthCsv(*bad, report);
    FAIL() << "expected ParseError";
  } catch (const ppp::ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("z_m"), std::string::npos) << e.what();
  }
  auto empty = ppp::memoryLineSource("", "empty.csv");
  EXPECT_THROW(ppp::readTruthCsv(*empty, report), ppp::ParseError);
}

// Solution k (k = 0..n-1) is the truth plus (k + 1) cm up, except the listed epochs.
std::vector<ppp::SolutionEpoch> offsetSolution(const ppp::TruthTrajectory& truth, int n) {
  std::vector<ppp::SolutionEpoch> s;
  for (int k = 0; k < n; ++k) {
    ppp::SolutionEpoch e;
    e.time = truth.time[k];
    e.position_ecef_m = ppp::enuToEcef(Eigen::Vector3d(2.0 * k, 0, 0.01 * (k + 1)), kZim2);
    s.push_back(e);
  }
  return s;
}

TEST(ReplayReportRow, MatchesEpochsToMovingTruthAndUsesTheCoreStatistics) {
  const ppp::TruthTrajectory truth = eastwardTruth(40);
  std::vector<ppp::SolutionEpoch> sol = offsetSolution(truth, 40);
  std::reverse(sol.begin(), sol.end());  // order does not matter
  ppp::SolutionEpoch outside;            // 100 s after the truth ends: unmatched
  outside.time = kT0 + 139.0;
  outside.position_ecef_m = kZim2;
  sol.push_back(outside);
  ppp::SolutionEpoch none;  // an epoch without a solution, inside the truth
  none.time = kT0 + 20.5;
  none.status = ppp::SolutionStatus::NoSolution;
  sol.push_back(none);

  ppp::StatisticsOptions opt;
  opt.convergence_window_s = 10.0;  // "first 10 s": epochs 0..9, errors 1..10 cm
  opt.convergence_thresholds_m = {0.10};
  const ppp::ReplayReportRow row = ppp::buildReplayReportRow("EKF", "ekf", sol, truth, opt);
  EXPECT_TRUE(row.missing.empty());
  EXPECT_EQ(row.unmatched_epochs, 1u);
  ASSERT_EQ(row.solution.size(), 41u);  // 40 + the no-solution epoch
  EXPECT_EQ(row.solution.front().time, kT0);  // sorted
  const auto& st = row.statistics;
  EXPECT_EQ(st.epochs, 40u);
  EXPECT_EQ(st.epochs_without_solution, 1u);
  // Errors 1..40 cm: median 20.5 cm, mean 20.5 cm, population sigma sqrt((40^2-1)/12) cm, max 40 cm.
  EXPECT_NEAR(st.all.median_m, 0.205, 1e-9);
  EXPECT_NEAR(st.all.mean_m, 0.205, 1e-9);
  EXPECT_NEAR(st.all.std_m, std::sqrt((40.0 * 40.0 - 1.0) / 12.0) / 100.0, 1e-9);
  EXPECT_NEAR(st.all.max_m, 0.40, 1e-9);
  EXPECT_NEAR(st.first_window.median_m, 0.055, 1e-9);  // 1..10 cm
  EXPECT_NEAR(st.first_window.max_m, 0.10, 1e-9);
  // Error >= 10 cm from epoch 9 on: never stays below 10 cm.
  ASSERT_EQ(st.convergence.size(), 1u);
  EXPECT_FALSE(st.convergence[0].time_s.has_value());

  // Against the same solution the moving-truth statistics equal the fixed-point ones when the truth is fixed.
  const auto fixed = ppp::buildReplayReportRow("x", "x", sol, ppp::TruthTrajectory::fixedPoint(kZim2), opt);
  const auto direct = ppp::computePositionErrorStatistics(fixed.solution, kZim2, opt);
  EXPECT_EQ(fixed.unmatched_epochs, 0u);
  EXPECT_DOUBLE_EQ(fixed.statistics.all.median_m, direct.all.median_m);
  EXPECT_DOUBLE_EQ(fixed.statistics.all.max_m, direct.all.max_m);
}

TEST(ReplayReportRow, ConvergenceTimeAgainstTheTruth) {
  // Errors 50 cm for the first 30 epochs, then 2 cm: stays below 10 cm from t = 30 s.
  const ppp::TruthTrajectory truth = eastwardTruth(60);
  std::vector<ppp::SolutionEpoch> sol;
  for (int k = 0; k < 60; ++k) {
    ppp::SolutionEpoch e;
    e.time = truth.time[k];
    e.position_ecef_m = truth.position_ecef_m[k] + Eigen::Vector3d(k < 30 ? 0.5 : 0.02, 0, 0);
    sol.push_back(e);
  }
  const auto row = ppp::buildReplayReportRow("s", "s", sol, truth);
  ASSERT_EQ(row.statistics.convergence.size(), 2u);  // default thresholds 10 and 5 cm
  EXPECT_DOUBLE_EQ(*row.statistics.convergence[0].time_s, 30.0);
}

TEST(ReplayReportRow, NoMatchingEpochIsAMissingRowWithItsReason) {
  const ppp::TruthTrajectory truth = eastwardTruth(5);
  ppp::SolutionEpoch e;
  e.time = kT0 + 1000.0;
  e.position_ecef_m = kZim2;
  const auto row = ppp::buildReplayReportRow("smoother smoothed", "smoother_smoothed", {e}, truth);
  EXPECT_NE(row.missing.find("no epoch matched the truth"), std::string::npos) << row.missing;
  const auto gone = ppp::missingReplayReportRow("smoother filtered", "smoother_filtered", "topic /smoother/ppp/fix not in the bag");
  const std::string table = ppp::formatReplayReport({row, gone});
  EXPECT_NE(table.find("smoother filtered: no statistics: topic /smoother/ppp/fix not in the bag"), std::string::npos)
      << table;
  const std::string json = ppp::replayReportJson({row, gone});
  EXPECT_NE(json.find("\"statistics\": null"), std::string::npos) << json;
}

TEST(AssembleReplaySolution, OneEpochPerStatusPositionsMatchedByTime) {
  std::vector<ppp::ReplayStatusSample> status(4);
  for (int k = 0; k < 4; ++k) {
    status[k].time = kT0 + k;
    status[k].solved = k != 1;
    status[k].satellites_used = 8;
    status[k].zwd_m = 0.1;
    status[k].update_time_s = 0.001 * (k + 1);
    status[k].epochs_processed = k + 1;
  }
  std::vector<ppp::ReplayPositionSample> pos;
  for (int k : {3, 0, 0, 5}) {  // epoch 0 twice (the later sample wins), epoch 2 missing, epoch 5 without status
    ppp::ReplayPositionSample p;
    p.time = kT0 + k + 0.0004;  // stamps rounded: within the tolerance
    p.position_ecef_m = kZim2 + Eigen::Vector3d(k, pos.size(), 0);
    pos.push_back(p);
  }
  const ppp::AssembledSolution a = ppp::assembleReplaySolution(status, pos);
  ASSERT_EQ(a.epochs.size(), 4u);  // 0, 1 (no solution), 3, 5
  EXPECT_EQ(a.solved_without_position, 1u);   // epoch 2
  EXPECT_EQ(a.positions_without_status, 1u);  // epoch 5
  EXPECT_EQ(a.epochs[0].time, kT0);
  EXPECT_EQ(*a.epochs[0].position_ecef_m, kZim2 + Eigen::Vector3d(0, 2, 0));  // the later of the two
  EXPECT_EQ(a.epochs[0].satellites_used, 8);
  EXPECT_EQ(*a.epochs[0].zwd_m, 0.1);
  EXPECT_EQ(a.epochs[1].status, ppp::SolutionStatus::NoSolution);
  EXPECT_FALSE(a.epochs[1].position_ecef_m.has_value());
  EXPECT_EQ(a.epochs[3].time - kT0, 5.0004);

  const ppp::NodeFigures n = ppp::replayNodeFigures("ekf", status, std::size_t{6});
  EXPECT_EQ(n.epochs_processed, 4u);
  EXPECT_EQ(n.dropped(), 2u);  // 6 input epochs, 4 processed
  EXPECT_EQ(n.update_time.count, 4u);
  EXPECT_DOUBLE_EQ(n.update_time.median_s, 0.0025);  // mean of 2 and 3 ms
  EXPECT_DOUBLE_EQ(n.update_time.p99_s, 0.004);
}

TEST(ReplayReport, TableJsonAndCsvCarryTheRows) {
  const ppp::TruthTrajectory truth = eastwardTruth(40);
  ppp::ReplayReportRow row = ppp::buildReplayReportRow("EKF", "ekf", offsetSolution(truth, 40), truth);
  ppp::ReplayStatusSample s;
  s.update_time_s = 0.002;
  s.epochs_processed = 40;
  row.node = ppp::replayNodeFigures("ekf", {s});
  const std::string table = ppp::formatReplayReport({row});
  // median 20.50 cm, mean 20.50, max 40.00; first 15 min = all 40 epochs; update 2.00 ms; 40 processed, 0 dropped.
  EXPECT_NE(table.find("EKF                     40 |   20.50   20.50"), std::string::npos) << table;
  EXPECT_NE(table.find("   40.00 |   20.50"), std::string::npos) << table;
  EXPECT_NE(table.find("|    2.00     2.00 |        40       0"), std::string::npos) << table;
  const std::string json = ppp::replayReportJson({row});
  EXPECT_NE(json.find("\"epochs_processed\": 40"), std::string::npos) << json;
  EXPECT_NE(json.find("\"median_m\": 0.205"), std::string::npos) << json;
  const std::string csv = ppp::replayReportCsv(row);
  std::istringstream in(csv);
  std::string header, line;
  std::getline(in, header);
  EXPECT_NE(header.find("err3d_m"), std::string::npos);
  int n = 0;
  while (std::getline(in, line)) ++n;
  EXPECT_EQ(n, 40);
}

TEST(ReplayReport, FixedEpochsGiveTheFixedShareAndTheTimeToFirstFix) {
  // 40 solved epochs, 1 s apart; the node says fixed from epoch 10 on, except epoch 20.
  const ppp::TruthTrajectory truth = eastwardTruth(40);
  std::vector<ppp::ReplayStatusSample> status(40);
  std::vector<ppp::ReplayPositionSample> pos(40);
  for (int k = 0; k < 40; ++k) {
    status[k].time = pos[k].time = truth.time[k];
    status[k].solved = true;
    status[k].ambiguities_fixed = k >= 10 && k != 20;
    pos[k].position_ecef_m = truth.position_ecef_m[k];
  }
  const ppp::AssembledSolution a = ppp::assembleReplaySolution(status, pos);
  ASSERT_EQ(a.epochs.size(), 40u);
  EXPECT_EQ(a.epochs[9].status, ppp::SolutionStatus::PppFloat);
  EXPECT_EQ(a.epochs[10].status, ppp::SolutionStatus::PppFixed);
  const ppp::ReplayReportRow row = ppp::buildReplayReportRow("EKF", "ekf", a.epochs, truth);
  EXPECT_EQ(row.fix.solved_epochs, 40u);
  EXPECT_EQ(row.fix.fixed_epochs, 29u);
  ASSERT_TRUE(row.fix.time_to_first_fix_s.has_value());
  EXPECT_DOUBLE_EQ(*row.fix.time_to_first_fix_s, 10.0);
  const std::string table = ppp::formatReplayReport({row});
  EXPECT_NE(table.find("fixed% 1st fix"), std::string::npos) << table;
  EXPECT_NE(table.find("|   72.5     0.2 |"), std::string::npos) << table;  // 29/40, 10 s = 0.17 min
  const std::string json = ppp::replayReportJson({row});
  EXPECT_NE(json.find("\"fixed_epochs\": 29"), std::string::npos) << json;
  EXPECT_NE(json.find("\"time_to_first_fix_s\": 10"), std::string::npos) << json;
  // A float run: no fixed epoch, "never".
  const ppp::ReplayReportRow float_row = ppp::buildReplayReportRow("EKF", "ekf", offsetSolution(truth, 40), truth);
  EXPECT_FALSE(float_row.fix.time_to_first_fix_s.has_value());
  EXPECT_NE(ppp::formatReplayReport({float_row}).find("|    0.0   never |"), std::string::npos);
}

TEST(MapDatum, RecoveredFromOnePositionKnownInBothFrames) {
  // A map datum at ZIM2 and a point 5 km east, 3 km south, 120 m up of it.
  const Eigen::Vector3d enu(5000.0, -3000.0, 120.0);
  const Eigen::Vector3d p = ppp::enuToEcef(enu, kZim2);
  EXPECT_LT((ppp::mapDatumFromPair(p, enu) - kZim2).norm(), 1e-4);
  EXPECT_LT((ppp::mapDatumFromPair(kZim2, Eigen::Vector3d::Zero()) - kZim2).norm(), 1e-9);
}

}  // namespace
