// loadImuFile: either IMU file format read and screened in one step; bad lines
// named with the file and line, accelerations in g refused, saturated readings
// counted, the stamps checked once (by the reader).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ppp_bayes_tree/io/imu/imu_file_loader.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "test_support.h"

namespace ppp {
namespace {

namespace fs = std::filesystem;

std::string writeText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

/// `count` plain CSV lines 10 ms apart from 2381 / 415840 s, at rest in m/s^2 (or g).
std::string restLines(int count, double gravity = 9.8, double first_s = 415840.0) {
  std::ostringstream s;
  s.precision(10);
  for (int k = 0; k < count; ++k)
    s << "2381," << first_s + 0.01 * k << ",0.01,-0.02," << gravity << ",0.001,0.002,0.003\n";
  return s.str();
}

ImuFileOptions csvFile(const std::string& path) {
  ImuFileOptions o;
  o.path = path;
  return o;
}

bool linesMention(const std::vector<std::string>& lines, const std::string& a, const std::string& b) {
  for (const auto& l : lines)
    if (l.find(a) != std::string::npos && l.find(b) != std::string::npos) return true;
  return false;
}

TEST(ImuFileLoader, NamesBadLinesWithTheFileAndLine) {
  const fs::path dir = test::tempDir("imu_loader_lines");
  const std::string csv = writeText(dir / "imu.csv", restLines(60) + "2381,415840.60,0.1,-0.2\n" + restLines(5, 9.8, 415840.60));
  const ImuFileLoad load = loadImuFile(csvFile(csv));
  EXPECT_EQ(load.lines, 66u);
  EXPECT_EQ(load.readings_read, 65u);
  EXPECT_EQ(load.samples.size(), 65u);
  EXPECT_EQ(load.units, ImuAccelerationUnits::MetresPerSecondSquared);
  ASSERT_EQ(load.report.problems().size(), 1u);
  EXPECT_EQ(load.report.problems()[0].line, 61u);
  EXPECT_TRUE(linesMention(load.problemLines(), csv, "line 61: short line")) << load.problemLines().front();
}

TEST(ImuFileLoader, RefusesAccelerationsInG) {
  const fs::path dir = test::tempDir("imu_loader_g");
  const std::string csv = writeText(dir / "imu.csv", restLines(80, 1.0));
  const ImuFileLoad load = loadImuFile(csvFile(csv));
  EXPECT_EQ(load.units, ImuAccelerationUnits::Gravity);
  EXPECT_TRUE(load.samples.empty());
  EXPECT_EQ(load.refused, 80u);
  EXPECT_EQ(load.screen_problems.at(ImuInputProblem::InGravityUnits).count, 80u);
  EXPECT_TRUE(linesMention(load.problemLines(), csv, "accelerations in g"));
}

TEST(ImuFileLoader, CountsSaturatedReadings) {
  const fs::path dir = test::tempDir("imu_loader_saturated");
  // Readings 3 and 7 (0-based) at the gyro's full scale of 4.0 rad/s.
  std::string text;
  for (int k = 0; k < 60; ++k) {
    std::ostringstream s;
    s.precision(10);
    const double wz = k == 3 || k == 7 ? 4.0 : 0.003;
    s << "2381," << 415840.0 + 0.01 * k << ",0.01,-0.02,9.8,0.001,0.002," << wz << "\n";
    text += s.str();
  }
  ImuFileOptions options = csvFile(writeText(dir / "imu.csv", text));
  options.screen.gyro_full_scale_radps = 4.0;
  const ImuFileLoad load = loadImuFile(options);
  EXPECT_EQ(load.saturated, 2u);
  EXPECT_EQ(load.refused, 2u);
  EXPECT_EQ(load.samples.size(), 58u);
  EXPECT_TRUE(linesMention(load.problemLines(), "2 x reading at", "saturated"));
}

TEST(ImuFileLoader, ChecksTheStampsOnceInTheReader) {
  const fs::path dir = test::tempDir("imu_loader_time");
  // A 0.5 s gap after line 60 and a repeated stamp on line 62: the reader counts
  // both with their lines; the screen counts no time problem of its own.
  const std::string csv =
      writeText(dir / "imu.csv", restLines(60) + restLines(1, 9.8, 415841.0) + restLines(1, 9.8, 415841.0));
  const ImuFileLoad load = loadImuFile(csvFile(csv));
  EXPECT_EQ(load.samples.size(), 61u);
  EXPECT_EQ(load.report.counters().at("gap"), 1u);
  EXPECT_EQ(load.report.counters().at("duplicate time"), 1u);
  EXPECT_EQ(load.screen_problems.count(ImuInputProblem::Gap), 0u);
  EXPECT_EQ(load.screen_problems.count(ImuInputProblem::DuplicateTime), 0u);
}

TEST(ImuFileLoader, TurnsTheReadingsIntoTheBodyAxes) {
  const fs::path dir = test::tempDir("imu_loader_rotation");
  ImuFileOptions options = csvFile(writeText(dir / "imu.csv", restLines(60)));
  // The walk's mounting: IMU z up (roll 180), x to the body's left (yaw -90):
  // f_imu = (0.01, -0.02, 9.8) reads (0.02, -0.01, -9.8) in x forward, y right, z down
  // (ppp_solve --imu-rotation 180,0,-90: R_body_imu = Rz(-90) Rx(180)).
  Eigen::Matrix3d body_imu;
  body_imu << 0, -1, 0, -1, 0, 0, 0, 0, -1;
  EXPECT_LT((rotationNedBody(M_PI, 0.0, -M_PI / 2) - body_imu).norm(), 1e-15);
  options.rotation_body_imu = body_imu;
  const ImuFileLoad load = loadImuFile(options);
  ASSERT_EQ(load.samples.size(), 60u);
  EXPECT_NEAR((load.samples[0].specific_force_mps2 - Eigen::Vector3d(0.02, -0.01, -9.8)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((load.samples[0].angular_rate_radps - Eigen::Vector3d(-0.002, -0.001, -0.003)).norm(), 0.0, 1e-12);
}

TEST(ImuFileLoader, LoggedFormatNeedsItsTagAndMissingFilesThrow) {
  ImuFileOptions options;
  options.path = "imu.csv";
  options.format = ImuFileFormat::RtklibLogged;
  EXPECT_THROW(loadImuFile(options), std::invalid_argument);
  EXPECT_THROW(loadImuFile(csvFile((test::tempDir("imu_loader_missing") / "none.csv").string())), FileOpenError);
}

TEST(ImuFileLoader, LoadsTheLoggedWalk) {
  const std::string csv = test::dataPath("streams/ubx/imu_1730.csv");
  if (!fs::exists(csv) || !fs::exists(csv + ".tag")) GTEST_SKIP() << "no " << csv << " (set PPP_SHARED_DATA)";
  ImuFileOptions options;
  options.path = csv;
  options.tag_path = csv + ".tag";
  options.format = ImuFileFormat::RtklibLogged;
  const ImuFileLoad load = loadImuFile(options);
  // 20,455 readings (data README); the two lines cut short are the reader's problems.
  EXPECT_EQ(load.readings_read, 20455u);
  EXPECT_EQ(load.samples.size(), 20455u);
  EXPECT_EQ(load.units, ImuAccelerationUnits::MetresPerSecondSquared);
  EXPECT_EQ(load.report.problemCount(), 2u);
  EXPECT_TRUE(linesMention(load.problemLines(), csv, "line 1: short line"));
}

}  // namespace
}  // namespace ppp
