// IMU text readers: the u-blox walk's logged IMU (g, deg/s, ms tick, RTKLIB time
// tags) and the plain SI CSV; bad lines are counted with their line, never fatal.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "ppp_bayes_tree/io/imu/imu_csv_reader.h"
#include "ppp_bayes_tree/io/imu/logged_imu_reader.h"
#include "ppp_bayes_tree/io/imu/rtklib_time_tag.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/types/constants.h"
#include "test_support.h"

namespace ppp {
namespace {

namespace fs = std::filesystem;

std::string walkCsv() { return test::dataPath("streams/ubx/imu_1730.csv"); }
bool walkAvailable() { return fs::exists(walkCsv()) && fs::exists(walkCsv() + ".tag"); }
#define REQUIRE_WALK() \
  if (!walkAvailable()) GTEST_SKIP() << "no ../shared/data/streams/ubx/imu_1730.csv (set PPP_SHARED_DATA)"

std::string writeText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

/// A time-tag file: RTKLIB header, start 2025-08-28 17:30:40.961 GPST, the given records.
std::string writeTag(const fs::path& path, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& records,
                     const char* magic = "TIMETAG RTKLIB EX 2.4.3") {
  std::string bytes(60, '\0');
  std::memcpy(&bytes[0], magic, std::strlen(magic));
  auto put = [&bytes](const void* p, std::size_t n) { bytes.append(static_cast<const char*>(p), n); };
  const std::uint32_t tick = 705026197, whole = 1756402240;
  const double fraction = 0.961;
  put(&tick, 4);
  put(&whole, 4);
  put(&fraction, 8);
  for (const auto& [ms, offset] : records) {
    put(&ms, 4);
    put(&offset, 4);
  }
  return writeText(path, bytes);
}

bool hasProblemAt(const ParseReport& report, std::size_t line, const std::string& text) {
  for (const auto& p : report.problems())
    if (p.line == line && p.reason.find(text) != std::string::npos) return true;
  return false;
}

TEST(LoggedImuReader, ReadsTheWalkInSiUnitsAndGpsTime) {
  REQUIRE_WALK();
  const LoggedImuRead read = readLoggedImu(walkCsv(), walkCsv() + ".tag");
  // 20,457 lines; the first and the last are cut mid-line (data README: 20,455 samples).
  EXPECT_EQ(read.lines, 20457u);
  EXPECT_EQ(read.samples.size(), 20455u);
  EXPECT_EQ(read.report.counters().at("short line"), 2u);
  EXPECT_TRUE(hasProblemAt(read.report, 1, "short line"));
  EXPECT_TRUE(hasProblemAt(read.report, 20457, "short line"));
  EXPECT_EQ(read.report.problemCount(), 2u) << read.report.summary();
  // Start: the tag's 2025-08-28 17:30:40.961 GPST; span ~134 s (the last tag record: 134.271 s).
  EXPECT_NEAR(read.samples.front().time - test::gpst(2025, 8, 28, 17, 30, 40.961), 0.0, 1e-6);
  const double span_s = read.samples.back().time - read.samples.front().time;
  EXPECT_NEAR(span_s, 134.271, 1e-6);
  EXPECT_NEAR(read.seconds_per_tick, 1e-3, 1e-6);  // the tick is a millisecond within 1000 ppm
  // At rest for the first 1.5 s: |f| is gravity. WGS 84 normal gravity at the walk
  // (40.0967 N, 1601 m, from the RTK reference gnss_1730_sf.pos) is 9.797 m/s^2
  // (NIMA TR8350.2 eqs. 4-1, 4-3); the consumer sensor reads ~1.2 % high (scale and
  // offset tolerances of a few percent and tens of mg are usual for MEMS).
  const double g_site = normalGravity_mps2(40.0966916 * kDegToRad, 1601.4);
  EXPECT_NEAR(g_site, 9.797, 0.001);
  double sum_f = 0.0, sum_w = 0.0;
  std::size_t n = 0;
  for (const auto& s : read.samples) {
    if (s.time - read.samples.front().time > 1.5) break;
    sum_f += s.specific_force_mps2.norm();
    sum_w += s.angular_rate_radps.norm();
    ++n;
  }
  ASSERT_GT(n, 150u);
  EXPECT_NEAR(sum_f / n, g_site, 0.25);
  EXPECT_LT(sum_w / n, 0.02);  // rad/s at rest (0.02 rad/s = 1.1 deg/s): rates were converted from deg/s
  // The first kept reading, converted: az 1.011 g, gz 0.160 deg/s.
  EXPECT_NEAR(read.samples.front().specific_force_mps2.z(), 1.011 * 9.80665, 1e-9);
  EXPECT_NEAR(read.samples.front().angular_rate_radps.z(), 0.160 * kDegToRad, 1e-12);
  std::printf("walk IMU: %zu readings over %.3f s, mean |f| at rest %.4f m/s^2 (normal gravity %.4f)\n",
              read.samples.size(), span_s, sum_f / n, g_site);
}

TEST(LoggedImuReader, CountsBadLinesWithTheirLineAndKeepsGoing) {
  const fs::path dir = test::tempDir("logged_imu");
  const std::string csv = writeText(dir / "imu.csv",
                                    "0.007,1.011,0.038,-0.160,0.160,1000\n"   // 1 cut: 6 fields
                                    "0,0,1,0,0,0,1000\n"                      // 2 kept
                                    "0,0,1,0,0,0,1008\n"                      // 3 kept
                                    "0,0,nan,0,0,0,1016\n"                    // 4 NaN
                                    "0,0,1,abc,0,0,1024\n"                    // 5 not numeric
                                    "0,0,1,0,0,0,1004\n"                      // 6 backwards
                                    "0,0,1,0,0,0,1008\n"                      // 7 duplicate
                                    "0,0,1,0,0,0,1200\n"                      // 8 gap, kept
                                    "\n"                                      // 9 empty: short
                                    "0,0,1,0,0,0,1208\n"                      // 10 kept
                                    "0,0,1,0,0,");                            // 11 cut
  const std::string tag = writeTag(dir / "imu.csv.tag", {{100, 0}, {208, 100}});
  const LoggedImuRead read = readLoggedImu(csv, tag);
  EXPECT_EQ(read.lines, 11u);
  ASSERT_EQ(read.samples.size(), 4u);
  const auto& c = read.report.counters();
  EXPECT_EQ(c.at("short line"), 3u);
  EXPECT_EQ(c.at("not a number"), 2u);
  EXPECT_EQ(c.at("time going backwards"), 1u);
  EXPECT_EQ(c.at("duplicate time"), 1u);
  EXPECT_EQ(c.at("gap"), 1u);
  EXPECT_TRUE(hasProblemAt(read.report, 4, "not a number: field 3 'nan'"));
  EXPECT_TRUE(hasProblemAt(read.report, 5, "field 4 'abc'"));
  EXPECT_TRUE(hasProblemAt(read.report, 6, "backwards"));
  EXPECT_TRUE(hasProblemAt(read.report, 7, "duplicate"));
  EXPECT_TRUE(hasProblemAt(read.report, 8, "gap"));
  // Ticks 1000..1208 map onto the tag's 0..0.208 s.
  EXPECT_NEAR(read.samples.back().time - read.samples.front().time, 0.208, 1e-9);
}

TEST(LoggedImuReader, ReportsTicksThatDisagreeWithTheTimeTags) {
  const fs::path dir = test::tempDir("logged_imu_clock");
  const std::string csv = writeText(dir / "imu.csv", "0,0,1,0,0,0,0\n0,0,1,0,0,0,10\n0,0,1,0,0,0,20\n");
  const std::string tag = writeTag(dir / "imu.csv.tag", {{40, 10}});  // 40 ms of tags for 20 ms of ticks
  const LoggedImuRead read = readLoggedImu(csv, tag);
  EXPECT_EQ(read.report.counters().at("clock mismatch"), 1u);
}

TEST(RtklibTimeTag, ReadsHeaderAndRecordsAndRefusesOtherFiles) {
  const fs::path dir = test::tempDir("time_tag");
  const RtklibTimeTag tag = readRtklibTimeTag(writeTag(dir / "a.tag", {{113, 835}, {134271, 1001983}}));
  EXPECT_EQ(tag.start_tick_ms, 705026197u);
  EXPECT_NEAR(tag.start - test::gpst(2025, 8, 28, 17, 30, 40.961), 0.0, 1e-9);
  ASSERT_EQ(tag.records.size(), 2u);
  EXPECT_EQ(tag.records[1].file_offset, 1001983u);
  EXPECT_NEAR(tag.lastRecordTime() - tag.start, 134.271, 1e-9);
  EXPECT_THROW(readRtklibTimeTag(writeTag(dir / "b.tag", {}, "NOT A TAG")), ParseError);
  EXPECT_THROW(readRtklibTimeTag(writeText(dir / "c.tag", "TIMETAG RTKLIB")), ParseError);
  EXPECT_THROW(readRtklibTimeTag((dir / "missing.tag").string()), FileOpenError);
  // A record cut short is counted, not fatal.
  const std::string cut = writeTag(dir / "d.tag", {{1, 2}});
  std::ofstream(cut, std::ios::app | std::ios::binary) << "abc";
  EXPECT_EQ(readRtklibTimeTag(cut).report.counters().at("cut record"), 1u);
}

TEST(RtklibTimeTag, TheWalksTagStartsAtItsDocumentedTime) {
  REQUIRE_WALK();
  const RtklibTimeTag tag = readRtklibTimeTag(walkCsv() + ".tag");
  EXPECT_EQ(tag.start.toString(TimeSystem::GPS, 3), "2025-08-28 17:30:40.961 GPS");
  EXPECT_EQ(tag.records.size(), 9560u);  // (76556 - 76) / 8
  EXPECT_TRUE(tag.report.clean());
}

TEST(ImuCsvReader, ReadsThePlainFormatAndCountsBadLines) {
  const fs::path dir = test::tempDir("imu_csv");
  const std::string csv = writeText(dir / "imu.csv",
                                    "# plain IMU CSV\n"                                           // 1
                                    "gps_week,seconds_of_week,fx,fy,fz,wx,wy,wz\n"                // 2 header
                                    "2381,415840.000,0.1,-0.2,9.8,0.001,0.002,0.003\n"            // 3
                                    "2381,415840.010,0.1,-0.2,9.8,0.001,0.002,0.003\n"            // 4
                                    "2381,415840.020,0.1,-0.2,inf,0.001,0.002,0.003\n"            // 5 not finite
                                    "2381,415840.005,0.1,-0.2,9.8,0.001,0.002,0.003\n"            // 6 backwards
                                    "2381,415840.020,0.1,-0.2\n"                                  // 7 short
                                    "2381,604800.5,0.1,-0.2,9.8,0.001,0.002,0.003\n"              // 8 out of range
                                    "2381,415841.000,0.1,-0.2,9.8,0.001,0.002,0.003\r\n");        // 9 gap, kept
  const ImuCsvRead read = readImuCsv(csv);
  ASSERT_EQ(read.samples.size(), 3u);
  EXPECT_FALSE(read.units_look_like_g);
  EXPECT_EQ(read.report.counters().at("header line"), 1u);
  EXPECT_TRUE(hasProblemAt(read.report, 5, "not a number"));
  EXPECT_TRUE(hasProblemAt(read.report, 6, "backwards"));
  EXPECT_TRUE(hasProblemAt(read.report, 7, "short line"));
  EXPECT_TRUE(hasProblemAt(read.report, 8, "time out of range"));
  EXPECT_TRUE(hasProblemAt(read.report, 9, "gap"));
  EXPECT_NEAR(read.samples[1].time - read.samples[0].time, 0.01, 1e-9);
  EXPECT_NEAR(read.samples[0].time - GnssTime::fromGpsWeek(2381, 415840.0), 0.0, 1e-9);
  EXPECT_EQ(read.samples[0].angular_rate_radps.z(), 0.003);
}

TEST(ImuCsvReader, FlagsAccelerationsGivenInG) {
  const fs::path dir = test::tempDir("imu_csv_g");
  const std::string csv = writeText(dir / "imu.csv",
                                    "2381,1.00,0.01,0.02,1.01,0,0,0\n"
                                    "2381,1.01,0.01,0.02,1.00,0,0,0\n");
  const ImuCsvRead read = readImuCsv(csv);
  EXPECT_TRUE(read.units_look_like_g);
  EXPECT_EQ(read.report.counters().at("accelerations look like g"), 1u);
  EXPECT_THROW(readImuCsv((dir / "missing.csv").string()), FileOpenError);
}

}  // namespace
}  // namespace ppp
