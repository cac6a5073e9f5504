// Tests of the RINEX clock reader on the IGS and WUM clock files, on synthetic
// 3.04 (9-character names) and 2.00 files and on malformed files. Known values
// are quoted from the files with their line.
#include <gtest/gtest.h>

#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "test_support.h"

namespace ppp {
namespace {

const char* kIgsClk = "zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK";
const char* kWumClk = "ccj2-2021-210/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz";

using ppp::test::gpst;

const ClockStation* station(const RinexClockFile& f, const std::string& name) {
  for (const auto& s : f.header.stations) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

TEST(RinexClockReader, IgsFinalHeaderAndRecords) {
  PPP_REQUIRE_SHARED_DATA();
  const RinexClockFile f = readRinexClock(test::dataPath(kIgsClk));
  const RinexClockHeader& h = f.header;
  EXPECT_EQ(h.version_text, "3.00");  // line 1
  EXPECT_EQ(h.leap_seconds, 18);      // line 11
  EXPECT_EQ(h.data_types, (std::vector<std::string>{"AR", "AS"}));  // line 12
  EXPECT_EQ(h.analysis_center_id, "IGS");                          // line 13
  EXPECT_EQ(h.analysis_center_name, "IGSACC @ GA MIT");
  EXPECT_EQ(h.station_count, 239);  // line 14 "   239    IGc20 : IGS REALIZATION ..."
  EXPECT_EQ(h.reference_frame, "IGc20 : IGS REALIZATION of THE ITRF2020-u2024");
  EXPECT_EQ(h.stations.size(), 239u);
  EXPECT_EQ(h.time_system, TimeSystem::GPS);  // no TIME SYSTEM ID line: GPS
  // Line 15: "ABMF 97103M001            2919785836 -5383744889  1774604947"
  const ClockStation* abmf = station(f, "ABMF");
  ASSERT_NE(abmf, nullptr);
  EXPECT_EQ(abmf->domes, "97103M001");
  EXPECT_DOUBLE_EQ(abmf->position_ecef_m.x(), 2919785.836);
  EXPECT_DOUBLE_EQ(abmf->position_ecef_m.y(), -5383744.889);
  EXPECT_DOUBLE_EQ(abmf->position_ecef_m.z(), 1774604.947);
  EXPECT_EQ(h.satellite_count, 32);  // line 254
  ASSERT_EQ(h.prn_list.size(), 32u);  // lines 255-257
  EXPECT_EQ(h.prn_list.back().toString(), "G32");
  EXPECT_EQ(h.header_lines, 259u);

  EXPECT_TRUE(f.report.clean()) << f.report.summary();
  EXPECT_TRUE(f.receiver_clocks.empty());  // the file holds no AR record
  ASSERT_EQ(f.satellite_clocks.size(), 32u);
  const auto& g01 = f.satellite_clocks.at(*SatelliteId::parse("G01"));
  ASSERT_EQ(g01.size(), 181u);  // 00:00 .. 01:30 every 30 s
  // Line 260: "AS G01  2026 05 13 00 00  0.000000  2    2.761547232975e-04  4.197517456140e-11"
  EXPECT_EQ(g01.front().time, gpst(2026, 5, 13, 0, 0, 0.0));
  EXPECT_EQ(g01.front().clock_bias_s, 2.761547232975e-04);
  ASSERT_TRUE(g01.front().clock_bias_sigma_s.has_value());
  EXPECT_EQ(*g01.front().clock_bias_sigma_s, 4.197517456140e-11);
  EXPECT_FALSE(g01.front().clock_rate_s_per_s.has_value());
  // Line 6020: "AS G01  2026 05 13 01 30  0.000000  2    2.761037475957e-04 ..."
  EXPECT_EQ(g01.back().time, gpst(2026, 5, 13, 1, 30, 0.0));
  EXPECT_EQ(g01.back().clock_bias_s, 2.761037475957e-04);
}

TEST(RinexClockReader, WumHeaderHasCcj2Coordinates) {
  PPP_REQUIRE_SHARED_DATA();
  const RinexClockFile f = readRinexClock(test::dataPath(kWumClk));
  const RinexClockHeader& h = f.header;
  EXPECT_EQ(h.version_text, "3.00");
  EXPECT_EQ(h.satellite_system, 'M');                    // line 1
  EXPECT_EQ(h.program, "PANDA");                          // line 2
  EXPECT_EQ(h.run_by, "WHU");
  EXPECT_EQ(h.time_system, TimeSystem::GPS);              // line 10 "   GPS ... TIME SYSTEM ID"
  EXPECT_EQ(h.analysis_center_id, "WHU");                 // line 21
  EXPECT_EQ(h.station_count, 181);                        // line 24 "   181    IGS14"
  EXPECT_EQ(h.reference_frame, "IGS14");
  EXPECT_EQ(h.satellite_count, 107);                      // line 206
  EXPECT_EQ(h.prn_list.size(), 107u);
  // Line 53: "CCJ2 21732M002           -4490605094  3483895065  2884928334" (mm);
  // the dataset README gives the same truth X -4490605.094, Y 3483895.065, Z 2884928.334 m.
  const ClockStation* ccj2 = station(f, "CCJ2");
  ASSERT_NE(ccj2, nullptr);
  EXPECT_EQ(ccj2->domes, "21732M002");
  EXPECT_DOUBLE_EQ(ccj2->position_ecef_m.x(), -4490605.094);
  EXPECT_DOUBLE_EQ(ccj2->position_ecef_m.y(), 3483895.065);
  EXPECT_DOUBLE_EQ(ccj2->position_ecef_m.z(), 2884928.334);
  EXPECT_TRUE(f.report.clean()) << f.report.summary();
  // Line 216: "AS G01  2021  7 29  0  0  0.000000  1    0.614187685254E-03"
  const auto& g01 = f.satellite_clocks.at(*SatelliteId::parse("G01"));
  EXPECT_EQ(g01.front().clock_bias_s, 0.614187685254E-03);
  EXPECT_FALSE(g01.front().clock_bias_sigma_s.has_value());
  // Line 323: "AS G01  2021  7 29  0  0 30.000000  1    0.614187740953E-03"
  EXPECT_EQ(g01[1].time, gpst(2021, 7, 29, 0, 0, 30.0));
  EXPECT_EQ(g01[1].clock_bias_s, 0.614187740953E-03);
  EXPECT_EQ(g01.size(), 2880u);
}

TEST(RinexClockReader, SummaryOfWumFile) {
  PPP_REQUIRE_SHARED_DATA();
  const FileSummary s = summarizeClockFile(test::dataPath(kWumClk));
  EXPECT_EQ(s.type, "RINEX clock");
  EXPECT_EQ(s.version, "3.00");
  EXPECT_EQ(s.epoch_count, 2880u);
  ASSERT_TRUE(s.interval_s.has_value());
  EXPECT_DOUBLE_EQ(*s.interval_s, 30.0);
  EXPECT_EQ(*s.first_epoch, gpst(2021, 7, 29, 0, 0, 0.0));
  EXPECT_EQ(*s.last_epoch, gpst(2021, 7, 29, 23, 59, 30.0));
  for (GnssSystem sys : {GnssSystem::GPS, GnssSystem::GLONASS, GnssSystem::Galileo, GnssSystem::BeiDou}) {
    EXPECT_TRUE(s.satellites.count(sys)) << systemName(sys);
  }
  EXPECT_NE(std::find(s.facts.begin(), s.facts.end(), "stations with coordinates 181 (IGS14)"), s.facts.end());
}

TEST(RinexClockReader, Version304LongNamesReceiverClocksAndContinuationLines) {
  const RinexClockFile f = readRinexClock(test::fixturePath("rinex_clock/clock_304_long_names.txt"));
  EXPECT_TRUE(f.report.clean()) << f.report.summary();
  EXPECT_DOUBLE_EQ(f.header.version, 3.04);
  ASSERT_EQ(f.header.stations.size(), 2u);  // labels in columns 66-85
  EXPECT_EQ(f.header.stations[1].name, "CCJ200JPN");
  EXPECT_DOUBLE_EQ(f.header.stations[1].position_ecef_m.x(), -4490605.094);
  EXPECT_EQ(f.header.prn_list.size(), 3u);
  // AR with four values (one continuation line)
  const auto& zim = f.receiver_clocks.at("ZIM200CHE");
  ASSERT_EQ(zim.size(), 2u);
  EXPECT_EQ(zim[0].clock_bias_s, -1.234567890123e-06);
  EXPECT_EQ(zim[0].clock_rate_s_per_s, 2.0e-12);
  EXPECT_EQ(zim[0].clock_rate_sigma_s_per_s, 3.0e-13);
  EXPECT_FALSE(zim[0].clock_acceleration_per_s.has_value());
  // AS with six values
  const auto& e11 = f.satellite_clocks.at(*SatelliteId::parse("E11"));
  ASSERT_EQ(e11.size(), 2u);
  EXPECT_EQ(e11[0].clock_acceleration_per_s, 5.0e-14);
  EXPECT_EQ(e11[0].clock_acceleration_sigma_per_s, 6.0e-15);
  EXPECT_EQ(e11[1].clock_bias_s, 1.5e-04);
  EXPECT_EQ(f.satellite_clocks.at(*SatelliteId::parse("G01")).size(), 2u);
  EXPECT_EQ(f.report.counters().at("CR records skipped"), 1u);

  // Receiver clocks can be dropped at read time.
  auto src = memoryLineSource(test::readFileBytes(test::fixturePath("rinex_clock/clock_304_long_names.txt")));
  const RinexClockFile g = readRinexClock(*src, RinexClockReadOptions{false});
  EXPECT_TRUE(g.receiver_clocks.empty());
  EXPECT_EQ(g.report.counters().at("AR records skipped"), 2u);
}

TEST(RinexClockReader, Version200) {
  const RinexClockFile f = readRinexClock(test::fixturePath("rinex_clock/clock_200.txt"));
  EXPECT_TRUE(f.report.clean()) << f.report.summary();
  EXPECT_EQ(f.header.version_text, "2.00");
  EXPECT_EQ(f.header.time_system, TimeSystem::GPS);
  ASSERT_EQ(f.header.stations.size(), 1u);
  EXPECT_DOUBLE_EQ(f.header.stations[0].position_ecef_m.z(), 3676976.434);
  const auto& g16 = f.satellite_clocks.at(*SatelliteId::parse("G16"));
  ASSERT_EQ(g16.size(), 2u);
  EXPECT_EQ(g16[0].time, gpst(1994, 7, 14, 20, 59, 0.0));
  EXPECT_EQ(g16[0].clock_bias_s, -0.123456789012);
}

// --------------------------------------------------------------- malformed
void expectHeaderError(const std::string& name, std::size_t line, const std::string& reason_part) {
  try {
    readRinexClock(test::fixturePath("malformed/rinex_clock/" + name));
    FAIL() << name << ": no ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), line) << name << ": " << e.what();
    EXPECT_NE(e.reason().find(reason_part), std::string::npos) << name << ": " << e.what();
  }
}

TEST(RinexClockReaderMalformed, HeaderErrors) {
  expectHeaderError("not_clock_type.txt", 1, "not 'C'");
  expectHeaderError("unsupported_version.txt", 1, "unsupported RINEX clock version");
  expectHeaderError("no_end_of_header.txt", 8, "before 'END OF HEADER'");
  expectHeaderError("unknown_time_system.txt", 2, "unknown time system 'XYZ'");
  expectHeaderError("bad_station_coordinate.txt", 6, "malformed coordinate");
  expectHeaderError("label_missing.txt", 4, "without a label");
  auto empty = memoryLineSource("", "empty");
  EXPECT_THROW(readRinexClock(*empty), ParseError);
}

TEST(RinexClockReaderMalformed, BadRecordsAreSkippedAndReported) {
  const RinexClockFile f = readRinexClock(test::fixturePath("malformed/rinex_clock/bad_records.txt"));
  // 11 malformed value, 12 value count 9, 13 satellite G0X, 14 30 February,
  // 15 continuation line missing, 16 unknown record, 17 fewer values than announced.
  std::vector<std::size_t> lines;
  for (const auto& p : f.report.problems()) lines.push_back(p.line);
  EXPECT_EQ(lines, (std::vector<std::size_t>{11, 12, 13, 14, 15, 16, 17}));
  const auto& g01 = f.satellite_clocks.at(*SatelliteId::parse("G01"));
  ASSERT_EQ(g01.size(), 2u);
  EXPECT_EQ(g01[0].clock_bias_s, 2.761547232975e-04);  // line 10 kept, line 19 repeated epoch dropped
  EXPECT_EQ(f.report.counters().at("repeated clock epochs dropped"), 1u);
  const auto& g02 = f.satellite_clocks.at(*SatelliteId::parse("G02"));
  ASSERT_EQ(g02.size(), 1u);
  EXPECT_EQ(g02[0].time, gpst(2026, 5, 13, 0, 0, 30.0));
}

TEST(RinexClockReaderMalformed, TruncatedGzipKeepsRecords) {
  PPP_REQUIRE_SHARED_DATA();
  std::string bytes = test::readFileBytes(test::dataPath(kWumClk));
  bytes.resize(100000);
  auto src = memoryLineSource(bytes, "cut.clk.gz");
  const RinexClockFile f = readRinexClock(*src);
  EXPECT_FALSE(f.satellite_clocks.empty());
  EXPECT_FALSE(f.report.clean());
}

}  // namespace
}  // namespace ppp
