// Evaluation: position error statistics (hand-computed values, and the numbers
// ../shared/peers/poserr.py prints for the same files), RTKLIB .pos writer and
// reader, per-epoch CSV writer, quantiles (evaluation/quantile.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "ppp_bayes_tree/evaluation/position_error_statistics.h"
#include "ppp_bayes_tree/evaluation/quantile.h"
#include "ppp_bayes_tree/evaluation/rtklib_pos.h"
#include "ppp_bayes_tree/evaluation/solution_csv_writer.h"
#include "fuzz/rtklib_pos_fuzz_entry.h"
#include "ppp_bayes_tree/types/frames.h"
#include "test_support.h"

namespace ppp {
namespace {

const Eigen::Vector3d kEquatorTruth(6378137.0, 0.0, 0.0);  // lat 0, lon 0: E = dy, N = dz, U = dx

/// The synthetic solution of test/fixtures/rtklib_pos/synthetic_convergence.pos:
/// 10 epochs 300 s apart with 3D errors 80 50 20 9 11 6 4 3 2 3 cm.
std::vector<SolutionEpoch> syntheticSolution() {
  const double d[10][3] = {{0.8, 0, 0},  {0, 0.3, 0.4},  {0.2, 0, 0},  {0, 0, 0.09},  {0, 0, 0.11},
                           {0, 0.06, 0}, {0.04, 0, 0},   {0, 0.03, 0}, {0, 0, -0.02}, {-0.03, 0, 0}};
  std::vector<SolutionEpoch> out;
  for (int i = 0; i < 10; ++i) {
    SolutionEpoch e;
    e.time = GnssTime::fromGpsWeek(2418, 259200.0 + 300.0 * i);
    e.position_ecef_m = kEquatorTruth + Eigen::Vector3d(d[i][0], d[i][1], d[i][2]);
    e.covariance_ecef_m2 = Eigen::Matrix3d::Identity() * 0.01;
    e.satellites_used = 8;
    out.push_back(e);
  }
  return out;
}

TEST(Quantile, ValueAtIndexFloorPnOfTheSortedValues) {
  // Sorted: 1 2 3 4 5 6 7 8 9 10 -> index floor(p 10).
  const std::vector<double> v = {7.0, 3.0, 10.0, 1.0, 9.0, 2.0, 8.0, 5.0, 4.0, 6.0};
  EXPECT_EQ(quantile(v, 0.0), 1.0);
  EXPECT_EQ(quantile(v, 0.5), 6.0);   // index 5: the upper of the two middle values
  EXPECT_EQ(quantile(v, 0.99), 10.0);  // index 9
  EXPECT_EQ(quantile(v, 0.95), 10.0);
  EXPECT_EQ(quantile(v, 0.85), 9.0);   // index 8
  EXPECT_EQ(quantile(v, 1.0), 10.0);   // clamped to the last
  std::vector<double> sorted = v;
  std::sort(sorted.begin(), sorted.end());
  for (const double p : {0.0, 0.25, 0.5, 0.99, 1.0}) EXPECT_EQ(quantileOfSorted(sorted, p), quantile(v, p)) << p;
  EXPECT_TRUE(std::isnan(quantile({}, 0.5)));
  EXPECT_EQ(quantile({4.2}, 0.99), 4.2);
}

TEST(PositionErrorStatistics, HandComputedValues) {
  const auto st = computePositionErrorStatistics(syntheticSolution(), kEquatorTruth);
  EXPECT_EQ(st.epochs, 10u);
  EXPECT_DOUBLE_EQ(st.span_s, 2700.0);
  // Sorted errors 2 3 3 4 6 9 11 20 50 80 cm: median (6 + 9) / 2, mean 188 / 10,
  // population std sqrt(0.9576 / 10 - 0.188^2) = sqrt(0.060416).
  EXPECT_NEAR(st.all.median_m, 0.075, 1e-9);
  EXPECT_NEAR(st.all.mean_m, 0.188, 1e-9);
  EXPECT_NEAR(st.all.std_m, std::sqrt(0.060416), 1e-9);
  EXPECT_NEAR(st.all.max_m, 0.80, 1e-9);
  // First 15 min = t < 900 s: 80, 50, 20 cm; std sqrt((0.09 + 0 + 0.09) / 3).
  EXPECT_EQ(st.first_window.count, 3u);
  EXPECT_NEAR(st.first_window.median_m, 0.50, 1e-9);
  EXPECT_NEAR(st.first_window.mean_m, 0.50, 1e-9);
  EXPECT_NEAR(st.first_window.std_m, std::sqrt(0.06), 1e-9);
  // < 10 cm: the last epoch >= 10 cm is 11 cm at 1200 s, so from 1500 s on;
  // < 5 cm: the last >= 5 cm is 6 cm at 1500 s, so from 1800 s on.
  ASSERT_EQ(st.convergence.size(), 2u);
  EXPECT_DOUBLE_EQ(*st.convergence[0].time_s, 1500.0);
  EXPECT_DOUBLE_EQ(*st.convergence[1].time_s, 1800.0);
  EXPECT_NEAR(st.final_error_m, 0.03, 1e-9);
  // Last 30 min = t >= 900 s (7 epochs): E = dy {6, 3}, N = dz {9, 11, -2}, U = dx {4, -3} cm.
  EXPECT_EQ(st.tail_epochs, 7u);
  EXPECT_NEAR(st.tail_enu_rms_m(0), std::sqrt(0.0045 / 7), 1e-9);
  EXPECT_NEAR(st.tail_enu_rms_m(1), std::sqrt(0.0206 / 7), 1e-9);
  EXPECT_NEAR(st.tail_enu_rms_m(2), std::sqrt(0.0025 / 7), 1e-9);
  // Empirical CDF: k / n at the sorted errors; nearest-rank percentiles.
  ASSERT_EQ(st.cdf.size(), 10u);
  EXPECT_NEAR(st.cdf[0].first, 0.02, 1e-9);
  EXPECT_DOUBLE_EQ(st.cdf[0].second, 0.1);
  EXPECT_DOUBLE_EQ(st.cdf[9].second, 1.0);
  EXPECT_NEAR(st.percentile_m(0.5), 0.06, 1e-9);
  EXPECT_NEAR(st.percentile_m(0.95), 0.80, 1e-9);
}

TEST(PositionErrorStatistics, NeverConvergedNoSolutionAndEmpty) {
  auto sol = syntheticSolution();
  sol.back().position_ecef_m = kEquatorTruth + Eigen::Vector3d(0.2, 0, 0);  // last epoch 20 cm
  SolutionEpoch gap;
  gap.time = sol.back().time + 300.0;
  gap.status = SolutionStatus::NoSolution;  // no position: counted, left out
  sol.push_back(gap);
  StatisticsOptions o;
  o.convergence_thresholds_m = {0.10, 0.5, 1.0};
  const auto st = computePositionErrorStatistics(sol, kEquatorTruth, o);
  EXPECT_EQ(st.epochs, 10u);
  EXPECT_EQ(st.epochs_without_solution, 1u);
  EXPECT_FALSE(st.convergence[0].time_s.has_value());  // never: the last epoch is above
  EXPECT_DOUBLE_EQ(*st.convergence[1].time_s, 600.0);  // 50 cm at 300 s counts as ">= 50 cm"
  EXPECT_DOUBLE_EQ(*st.convergence[2].time_s, 0.0);    // never at or above 1 m
  EXPECT_NE(formatStatisticsTable(st, "x").find("never"), std::string::npos);

  const auto empty = computePositionErrorStatistics({gap}, kEquatorTruth);
  EXPECT_EQ(empty.epochs, 0u);
  EXPECT_TRUE(std::isnan(empty.all.mean_m));
  EXPECT_TRUE(std::isnan(empty.final_error_m));
  EXPECT_NE(statisticsToJson(empty).find("\"final_error_m\": null"), std::string::npos);
}

TEST(PositionErrorStatistics, JsonHoldsTheFigures) {
  const auto st = computePositionErrorStatistics(syntheticSolution(), kEquatorTruth);
  const std::string j = statisticsToJson(st, "synthetic \"A\"");
  EXPECT_NE(j.find("\"label\": \"synthetic \\\"A\\\"\""), std::string::npos) << j;
  EXPECT_NE(j.find("\"mean_m\": 0.188"), std::string::npos) << j;
  EXPECT_NE(j.find("{\"threshold_m\": 0.1, \"time_s\": 1500}"), std::string::npos) << j;
  EXPECT_NE(j.find("\"final_error_m\": 0.03"), std::string::npos) << j;
  EXPECT_EQ(j.front(), '{');
  EXPECT_EQ(j.substr(j.size() - 2), "}\n");
}

TEST(RtklibPos, WriterReproducesTheSyntheticFixtureAndPoserrFigures) {
  // The fixture was written once by the same layout rules and cross-checked with
  // `python3 ../shared/peers/poserr.py synthetic_convergence.pos 6378137 0 0`, which printed:
  //   all epochs   median 7.50  mean 18.80  std 24.58  max 80.00 cm
  //   first 15 min  median 50.00  mean 50.00  std 24.49  max 80.00 cm
  //   converged <10cm at 25.0 min, <5cm at 30.0 min; final 3D 3.00 cm
  //   last 30 min ENU RMS  E 2.54  N 5.42  U 1.89 cm
  const std::string fixture = test::readFileBytes(test::fixturePath("rtklib_pos/synthetic_convergence.pos"));
  PosWriterOptions o;
  o.comment_lines = {"synthetic: truth 6378137,0,0 (lat 0, lon 0: E=dy N=dz U=dx); 3D errors 80 50 20 9 11 6 4 3 2 3 cm"};
  std::ostringstream out;
  RtklibPosWriter writer(out, o);
  for (const auto& e : syntheticSolution()) writer.write(e);
  EXPECT_EQ(out.str(), fixture);

  const auto file = readRtklibPos(test::fixturePath("rtklib_pos/synthetic_convergence.pos"));
  EXPECT_TRUE(file.report.clean()) << file.report.summary();
  const auto st = computePositionErrorStatistics(toSolutionEpochs(file), kEquatorTruth);
  EXPECT_NEAR(st.all.median_m * 100, 7.50, 0.005);
  EXPECT_NEAR(st.all.mean_m * 100, 18.80, 0.005);
  EXPECT_NEAR(st.all.std_m * 100, 24.58, 0.005);
  EXPECT_NEAR(st.first_window.std_m * 100, 24.49, 0.005);
  EXPECT_NEAR(*st.convergence[0].time_s / 60, 25.0, 0.05);
  EXPECT_NEAR(*st.convergence[1].time_s / 60, 30.0, 0.05);
  EXPECT_NEAR(st.tail_enu_rms_m(0) * 100, 2.54, 0.005);
  EXPECT_NEAR(st.tail_enu_rms_m(1) * 100, 5.42, 0.005);
  EXPECT_NEAR(st.tail_enu_rms_m(2) * 100, 1.89, 0.005);
}

TEST(RtklibPos, RecordLayoutMatchesRtklib) {
  // First epoch of rnx2rtkp 2.4.3 on ZIM2 without antenna files (out-timeform=tow):
  // "2418 259200.000   4331299.8984    567537.3331   4633134.3006   6  12   1.9239 ..."
  SolutionEpoch e;
  e.time = GnssTime::fromGpsWeek(2418, 259200.0);
  e.position_ecef_m = Eigen::Vector3d(4331299.8984, 567537.3331, 4633134.3006);
  Eigen::Matrix3d q;
  q << 1.9239 * 1.9239, 0.7939 * 0.7939, 1.4588 * 1.4588,  //
      0.7939 * 0.7939, 1.0740 * 1.0740, 0.7647 * 0.7647,    //
      1.4588 * 1.4588, 0.7647 * 0.7647, 2.3671 * 2.3671;
  e.covariance_ecef_m2 = q;
  e.satellites_used = 12;
  EXPECT_EQ(formatPosRecord(e, {}),
            "2418 259200.000   4331299.8984    567537.3331   4633134.3006   6  12   1.9239   1.0740   2.3671   "
            "0.7939   0.7647   1.4588   0.00    0.0\n");
  PosWriterOptions cal;
  cal.time_form = PosTimeForm::Calendar;
  EXPECT_EQ(formatPosRecord(e, cal).substr(0, 38), "2026/05/13 00:00:00.000   4331299.8984");
  // Header column line as RTKLIB writes it (tow and calendar forms).
  EXPECT_NE(formatPosHeader({}).find("\n%  GPST              x-ecef(m)      y-ecef(m)      z-ecef(m)   Q  ns   sdx(m)"),
            std::string::npos);
  EXPECT_NE(formatPosHeader(cal).find("\n%  GPST                      x-ecef(m)"), std::string::npos);
  // A negative covariance becomes a negative signed root; no position -> no line.
  q(0, 1) = q(1, 0) = -0.25;
  e.covariance_ecef_m2 = q;
  EXPECT_NE(formatPosRecord(e, {}).find("  -0.5000"), std::string::npos);
  e.position_ecef_m.reset();
  EXPECT_EQ(formatPosRecord(e, {}), "");
}

TEST(RtklibPos, FixedEpochsHaveQ1AndTheirRatio) {
  // RTKLIB 2.4.3 writes Q 1 (SOLQ_FIX) and the ratio factor of the ambiguity
  // validation in the last column (%6.1f, capped at 999.9); float PPP is Q 6, ratio 0.
  SolutionEpoch e;
  e.time = GnssTime::fromGpsWeek(2418, 259200.0);
  e.position_ecef_m = Eigen::Vector3d(4331299.8984, 567537.3331, 4633134.3006);
  e.satellites_used = 12;
  e.status = SolutionStatus::PppFixed;
  e.ambiguity_ratio = 5.34;
  const std::string line = "2418 259200.000   4331299.8984    567537.3331   4633134.3006   %d  12   0.0000   0.0000   "
                           "0.0000   0.0000   0.0000   0.0000   0.00 %6.1f\n";
  const auto expected = [&](int q, double ratio) {
    char buf[256];
    std::snprintf(buf, sizeof buf, line.c_str(), q, ratio);
    return std::string(buf);
  };
  EXPECT_EQ(formatPosRecord(e, {}), expected(1, 5.3));
  e.ambiguity_ratio = 12345.0;
  EXPECT_EQ(formatPosRecord(e, {}), expected(1, 999.9));
  e.status = SolutionStatus::PppFloat;  // a ratio without a fix is not written
  EXPECT_EQ(formatPosRecord(e, {}), expected(6, 0.0));
  // Written and read back.
  e.status = SolutionStatus::PppFixed;
  e.ambiguity_ratio = 5.34;
  auto src = memoryLineSource(formatPosHeader({}) + formatPosRecord(e, {}), "fixed.pos");
  const PosFile file = readRtklibPos(*src);
  ASSERT_EQ(file.records.size(), 1u);
  EXPECT_EQ(file.records[0].quality, 1);
  EXPECT_DOUBLE_EQ(*file.records[0].ratio, 5.3);
  const auto epochs = toSolutionEpochs(file);
  EXPECT_EQ(epochs[0].status, SolutionStatus::PppFixed);
  EXPECT_DOUBLE_EQ(*epochs[0].ambiguity_ratio, 5.3);
}

TEST(RtklibPos, ReadsRtklibXyzTowAndLlhCalendarFiles) {
  // Both fixtures are the first records of rnx2rtkp 2.4.3 runs on ZIM2 (the
  // calendar/llh one with -t and CRLF line ends as RTKLIB writes them).
  const auto xyz = readRtklibPos(test::fixturePath("rtklib_pos/zim2_rtklib_xyz_tow.pos"));
  EXPECT_TRUE(xyz.report.clean()) << xyz.report.summary();
  EXPECT_EQ(xyz.coordinates, PosCoordinates::Xyz);
  EXPECT_EQ(xyz.time_form, PosTimeForm::WeekTow);
  ASSERT_EQ(xyz.records.size(), 3u);
  EXPECT_EQ(xyz.records[0].time, GnssTime::fromGpsWeek(2418, 259200.0));
  EXPECT_DOUBLE_EQ(xyz.records[0].position_ecef_m.x(), 4331300.2764);
  EXPECT_EQ(xyz.records[0].quality, 6);
  EXPECT_EQ(xyz.records[0].satellites, 13);
  ASSERT_TRUE(xyz.records[0].sd_m);
  EXPECT_DOUBLE_EQ((*xyz.records[0].sd_m)[5], 1.4089);

  const auto llh = readRtklibPos(test::fixturePath("rtklib_pos/zim2_rtklib_llh_calendar.pos"));
  EXPECT_TRUE(llh.report.clean()) << llh.report.summary();
  EXPECT_EQ(llh.coordinates, PosCoordinates::Llh);
  EXPECT_EQ(llh.time_form, PosTimeForm::Calendar);
  ASSERT_EQ(llh.records.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(llh.records[i].time, xyz.records[i].time);
    // lat/lon to 1e-9 deg (0.1 mm) and height to 0.1 mm: the same point within 1 mm.
    EXPECT_LT((llh.records[i].position_ecef_m - xyz.records[i].position_ecef_m).norm(), 1e-3);
  }
}

TEST(RtklibPos, MalformedRecordsAreSkippedWithReasons) {
  const std::pair<const char*, const char*> cases[] = {
      {"bad_week.pos", "malformed GPS week / time of week"},
      {"missing_coordinates.pos", "malformed or missing coordinates"},
      {"bad_calendar.pos", "malformed calendar time"},
      {"latitude_out_of_range.pos", "latitude/longitude/height out of range"},
      {"bad_quality.pos", "malformed Q / ns"},
  };
  for (const auto& [name, reason] : cases) {
    const auto f = readRtklibPos(test::fixturePath(std::string("malformed/rtklib_pos/") + name));
    EXPECT_EQ(f.records.size(), 1u) << name;
    ASSERT_EQ(f.report.problemCount(), 1u) << name;
    EXPECT_EQ(f.report.problems()[0].reason, reason) << name;
    EXPECT_EQ(f.report.problems()[0].line, 3u) << name;
  }
  // Binary garbage: no crash, nothing read.
  auto src = memoryLineSource(std::string("\x00\xff\x12%\n\n 1 2\n", 10), "garbage");
  const auto g = readRtklibPos(*src);
  EXPECT_TRUE(g.records.empty());
}

TEST(SolutionCsv, HeaderAndRows) {
  EXPECT_EQ(SolutionCsvWriter::headerRow(true),
            "gps_week,tow_s,time_gpst,x_m,y_m,z_m,lat_deg,lon_deg,height_m,e_err_m,n_err_m,u_err_m,err3d_m,"
            "sigma_e_m,sigma_n_m,sigma_u_m,sats_used,sats_rejected,zwd_m,clock_m,status,integrity");
  auto e = syntheticSolution()[1];  // error (0, 0.3, 0.4) at lat 0 lon 0: E 0.3, N 0.4, U 0
  e.covariance_ecef_m2 = Eigen::Vector3d(0.09, 0.01, 0.04).asDiagonal();  // sigma U 0.3, E 0.1, N 0.2
  e.satellites_rejected = 2;
  e.zwd_m = 0.1234;
  e.receiver_clock_m = -12.5;
  const std::string row = SolutionCsvWriter::row(e, kEquatorTruth);
  EXPECT_EQ(row,
            "2418,259500.000,2026-05-13T00:05:00.000,6378137.0000,0.3000,0.4000,0.000003617,0.000002695,0.0000,"
            "0.3000,0.4000,0.0000,0.5000,0.1000,0.2000,0.3000,8,2,0.1234,-12.5000,ppp-float,unchecked")
      << row;
  SolutionEpoch none;
  none.time = e.time;
  none.status = SolutionStatus::NoSolution;
  EXPECT_EQ(SolutionCsvWriter::row(none, std::nullopt),
            "2418,259500.000,2026-05-13T00:05:00.000,,,,,,,,,,0,0,,,no-solution,unchecked");
  EXPECT_EQ(isoTimeText(GnssTime::fromGpsWeek(2418, 259199.9996)), "2026-05-13T00:00:00.000");
}

TEST(RtklibPos, FuzzEntryRunsOverItsSeedCorpus) {
  std::size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::string(PPP_FUZZ_DIR) + "/corpus/rtklib_pos")) {
    const std::string bytes = test::readFileBytes(e.path().string());
    EXPECT_NO_THROW(fuzz::fuzzRtklibPos(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
    ++n;
  }
  EXPECT_GE(n, 5u);
}

}  // namespace
}  // namespace ppp
