// ppp_solve --estimator ekf_ins end to end on the real ZIM2 hour (a static station)
// through solvePppEstimators, with noise-free readings of an IMU at rest (level,
// x north, z down; gravity and the Earth rate in its axes; 20 Hz) and the heading
// given: every epoch is solved, the attitude file holds one row per epoch with the
// levelled attitude, and the GNSS estimators write no attitude file; the GNSS/INS
// smoother (smoother_ins) on the same input solves every epoch, ends where the
// GNSS/INS EKF ends and writes its attitude file too.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "attitude_file.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_dataset.h"
#include "test_support.h"

namespace ppp {
namespace {

/// Readings of a level IMU (x north, y east, z down) at rest at `position_ecef_m`,
/// every 0.05 s from `from` over `duration_s`.
std::vector<ImuSample> atRest(const Eigen::Vector3d& position_ecef_m, const GnssTime& from, double duration_s) {
  const Eigen::Matrix3d ecef_body = rotationEcefNed(position_ecef_m);
  ImuSample r;
  r.specific_force_mps2 = -ecef_body.transpose() * ecefNavigationFrame(position_ecef_m).gravity_world_mps2;
  r.angular_rate_radps = ecef_body.transpose() * Eigen::Vector3d(0.0, 0.0, kEarthRotationRate_radps);
  std::vector<ImuSample> out;
  for (int k = 0; k * 0.05 <= duration_s; ++k) {
    r.time = from + k * 0.05;
    out.push_back(r);
  }
  return out;
}

/// The request of `estimator` on the ZIM2 hour with the readings of an IMU at rest from
/// 10 s before its first epoch (2026-05-13 00:00 GPST, ../shared/data/README.md; for the
/// levelling) and the heading given (north).
PppSolveRequest staticImuRequest(const std::string& dir, const std::string& estimator) {
  const test::PppDataset data = test::zim2Dataset();
  PppSolveRequest request = test::solveRequest(data, dir, estimator);
  const GnssTime start = GnssTime::fromGpsWeek(2418, 259200.0);
  request.imu = atRest(data.truth_ecef_m, start - 10.0, 3610.0);
  request.config.ins.initial_heading_rad = 0.0;
  return request;
}

/// The runs of `request`: one, of its estimator, every one of the hour's 120 epochs solved.
std::vector<PppSolveOutcome> solveEveryEpoch(const PppSolveRequest& request) {
  std::vector<PppSolveOutcome> runs = solvePppEstimators(request);
  EXPECT_EQ(runs.size(), 1u);
  for (const PppSolveOutcome& r : runs) {
    EXPECT_EQ(r.run.estimator, request.estimator);
    EXPECT_EQ(r.run.epochs_solved, 120u);
  }
  return runs;
}

/// The largest roll, pitch or heading of the rows [deg].
double largestAngle_deg(const test::AttitudeFileRows& file) {
  double worst_deg = 0.0;
  for (const test::AttitudeRow& row : file.rows)
    for (int i = 2; i <= 4 && i < static_cast<int>(row.cells.size()); ++i)
      worst_deg = std::max(worst_deg, std::abs(std::stod(row.cells[i])));
  return worst_deg;
}

TEST(PppSolveIns, Zim2StaticImuEveryEpochSolvedWithItsAttitude) {
  PPP_REQUIRE_SHARED_DATA();
  const std::string dir = test::tempDir("ppp_solve_ins_zim2").string();
  const PppSolveRequest request = staticImuRequest(dir, "ekf_ins");
  const std::vector<PppSolveOutcome> runs = solveEveryEpoch(request);
  ASSERT_EQ(runs.size(), 1u);
  const std::optional<test::AttitudeFileRows> file = test::readAttitudeFile(dir + "/zim2_ekf_ins_attitude.csv");
  ASSERT_TRUE(file) << "no attitude file";
  EXPECT_EQ(file->header,
            "time_gpst,status,roll_deg,pitch_deg,heading_deg,velocity_north_mps,velocity_east_mps,velocity_down_mps,"
            "alignment,tilt_sigma_deg,heading_sigma_deg,attitude_publishable,antenna_x_m,antenna_y_m,antenna_z_m,"
            "doppler_update,doppler_satellites,doppler_rejected,doppler_velocity_north_mps,doppler_velocity_east_mps,"
            "doppler_velocity_down_mps");
  int doppler_applied = 0;
  double worst_doppler_mps = 0.0;
  Eigen::Vector3d doppler_sum_mps = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < file->rows.size(); ++i) {
    const test::AttitudeRow& row = file->rows[i];
    const std::vector<std::string>& cells = row.cells;
    ASSERT_EQ(cells.size(), 21u) << row.line;
    // The heading was given: aligned from the start, publishable while the sigmas
    // are within 2 deg (tilt) and 5 deg (heading). At rest the heading is not
    // observable: its sigma grows with the gyro noise (7.2 deg after the hour).
    EXPECT_EQ(cells[8], "aligned") << row.line;
    const bool small = std::stod(cells[9]) <= 2.0 && std::stod(cells[10]) <= 5.0;
    EXPECT_EQ(cells[11], small ? "1" : "0") << row.line;
    if (i == 0) EXPECT_EQ(cells[11], "1") << row.line;
    // The RINEX file's D1C reaches the filter: the station's Doppler velocity is
    // zero within its noise (a few cm/s at 0.05 m/s per range rate) and without a
    // bias (a sign or a missing term of the model would leave one).
    if (cells[15] == "applied") {
      ++doppler_applied;
      const Eigen::Vector3d v(std::stod(cells[18]), std::stod(cells[19]), std::stod(cells[20]));
      worst_doppler_mps = std::max(worst_doppler_mps, v.norm());
      doppler_sum_mps += v;
    }
  }
  EXPECT_EQ(file->rows.size(), 120u);
  const double worst_deg = largestAngle_deg(*file);
  std::printf("ZIM2 with a static IMU: %zu of 120 epochs solved, attitude within %.4f deg of level and north; "
              "%d Doppler updates, Doppler speed at most %.4f m/s, mean %.4f m/s\n",
              runs[0].run.epochs_solved, worst_deg, doppler_applied, worst_doppler_mps,
              doppler_sum_mps.norm() / std::max(doppler_applied, 1));
  EXPECT_LT(worst_deg, 0.05);
  EXPECT_EQ(doppler_applied, 120);
  EXPECT_LT(worst_doppler_mps, 0.1);  // 0.063 m/s measured
  EXPECT_LT(doppler_sum_mps.norm() / std::max(doppler_applied, 1), 0.005);  // 0.0014 m/s measured

  // The GNSS estimators ignore the readings and write no attitude file.
  PppSolveRequest ekf = request;
  ekf.estimator = "ekf";
  solvePppEstimators(ekf);
  EXPECT_FALSE(std::filesystem::exists(dir + "/zim2_ekf_attitude.csv"));
}

TEST(PppSolveIns, Zim2StaticImuSmootherInsSolvesEveryEpochLikeTheEkfIns) {
  PPP_REQUIRE_SHARED_DATA();
  const std::string dir = test::tempDir("ppp_solve_smoother_ins_zim2").string();
  const PppSolveRequest request = staticImuRequest(dir, "smoother_ins");
  const std::vector<PppSolveOutcome> runs = solveEveryEpoch(request);
  ASSERT_EQ(runs.size(), 1u);
  ASSERT_EQ(runs[0].outputs.size(), 2u);  // filtered and smoothed
  EXPECT_TRUE(std::filesystem::exists(runs[0].outputs[1].csv_path)) << runs[0].outputs[1].csv_path;
  PppSolveRequest ekf_ins = request;
  ekf_ins.estimator = "ekf_ins";
  const std::vector<PppSolveOutcome> ekf = solvePppEstimators(ekf_ins);
  ASSERT_EQ(ekf.size(), 1u);
  ASSERT_TRUE(runs[0].outputs[0].statistics && runs[0].outputs[1].statistics && ekf[0].outputs[0].statistics);
  const double filtered_m = runs[0].outputs[0].statistics->final_error_m;
  const double smoothed_m = runs[0].outputs[1].statistics->final_error_m;
  const double ekf_m = ekf[0].outputs[0].statistics->final_error_m;
  std::printf("ZIM2 with a static IMU, final 3D error: smoother_ins filtered %.3f m, smoothed %.3f m, ekf_ins %.3f m\n",
              filtered_m, smoothed_m, ekf_m);
  EXPECT_LT(std::abs(filtered_m - ekf_m), 0.05);
  // Its attitude file: one row per epoch, level and north.
  const std::optional<test::AttitudeFileRows> file = test::readAttitudeFile(dir + "/zim2_smoother_ins_attitude.csv");
  ASSERT_TRUE(file) << "no attitude file";
  for (const test::AttitudeRow& row : file->rows)
    ASSERT_EQ(row.cells.size(), 21u) << row.line;  // the columns of the attitude file's header (the Doppler ones empty)
  EXPECT_EQ(file->rows.size(), 120u);
  const double worst_deg = largestAngle_deg(*file);
  std::printf("smoother_ins attitude within %.4f deg of level and north\n", worst_deg);
  EXPECT_LT(worst_deg, 0.05);
}

}  // namespace
}  // namespace ppp
