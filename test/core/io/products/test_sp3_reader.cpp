// Tests of the SP3 reader on the real IGS / WUM products and on synthetic and
// malformed files. Known values are quoted from the files with their line.
#include <gtest/gtest.h>

#include <cmath>

#include "ppp_bayes_tree/io/products/sp3_reader.h"
#include "synthetic_sp3.h"
#include "test_support.h"

namespace ppp {
namespace {

const char* kIgsSp3 = "zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3";
const char* kWumSp3 = "ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz";

using ppp::test::gpst;

const Sp3Record* recordAt(const Sp3File& f, const char* sat, const GnssTime& t) {
  const auto it = f.satellites.find(*SatelliteId::parse(sat));
  if (it == f.satellites.end()) return nullptr;
  for (const auto& r : it->second) {
    if (r.time == t) return &r;
  }
  return nullptr;
}

TEST(Sp3Reader, IgsFinalHeader) {
  PPP_REQUIRE_SHARED_DATA();
  const Sp3File f = readSp3(test::dataPath(kIgsSp3));
  const Sp3Header& h = f.header;
  // Line 1: "#cP2026  5 13  0  0  0.00000000      13 ORBIT IGc20 HLM  IGS"
  EXPECT_EQ(h.version, 'c');
  EXPECT_EQ(h.pv_flag, 'P');
  EXPECT_EQ(h.first_epoch, gpst(2026, 5, 13, 0, 0, 0.0));
  EXPECT_EQ(h.epoch_count, 13);
  EXPECT_EQ(h.data_used, "ORBIT");
  EXPECT_EQ(h.coordinate_system, "IGc20");
  EXPECT_EQ(h.orbit_type, "HLM");
  EXPECT_EQ(h.agency, "IGS");
  // Line 2: "## 2418 259200.00000000   900.00000000 61173 0.0000000000000"
  EXPECT_EQ(h.gps_week, 2418);
  EXPECT_DOUBLE_EQ(h.seconds_of_week, 259200.0);
  EXPECT_DOUBLE_EQ(h.interval_s, 900.0);
  EXPECT_EQ(h.mjd, 61173);
  // Line 3: "+   32   G01G02..." and line 8 "++         2  2  2  1 ..."
  ASSERT_EQ(h.satellites.size(), 32u);
  EXPECT_EQ(h.satellites.front().toString(), "G01");
  EXPECT_EQ(h.satellites.back().toString(), "G32");
  ASSERT_EQ(h.accuracy_exponents.size(), 32u);
  EXPECT_EQ(h.accuracy_exponents[0], 2);
  EXPECT_EQ(h.accuracy_exponents[3], 1);
  // Line 13: "%c G  cc GPS ccc ..."; line 15: "%f  1.2500000  1.025000000 ..."
  EXPECT_EQ(h.file_type, 'G');
  EXPECT_EQ(h.time_system, TimeSystem::GPS);
  EXPECT_DOUBLE_EQ(h.position_base, 1.25);
  EXPECT_DOUBLE_EQ(h.clock_base, 1.025);
  ASSERT_EQ(h.comments.size(), 4u);
  EXPECT_EQ(h.comments[1], "cod emr esa gfz grg jgx jpl mit ngs sio");
  EXPECT_EQ(h.header_lines, 22u);

  EXPECT_TRUE(f.complete);
  EXPECT_TRUE(f.report.clean()) << f.report.summary();
  ASSERT_EQ(f.epochs.size(), 13u);
  EXPECT_EQ(f.epochs.back(), gpst(2026, 5, 13, 3, 0, 0.0));
  EXPECT_EQ(f.satellites.size(), 32u);
}

TEST(Sp3Reader, IgsFinalRecordValuesAndUnits) {
  PPP_REQUIRE_SHARED_DATA();
  const Sp3File f = readSp3(test::dataPath(kIgsSp3));
  // Line 24: "PG01 -14847.471875  16720.664221  14257.386631    276.154723  8  9 10  69"
  const Sp3Record* r = recordAt(f, "G01", gpst(2026, 5, 13, 0, 0, 0.0));
  ASSERT_NE(r, nullptr);
  ASSERT_TRUE(r->position_ecef_m.has_value());
  EXPECT_DOUBLE_EQ(r->position_ecef_m->x(), -14847471.875);
  EXPECT_DOUBLE_EQ(r->position_ecef_m->y(), 16720664.221);
  EXPECT_DOUBLE_EQ(r->position_ecef_m->z(), 14257386.631);
  ASSERT_TRUE(r->clock_bias_s.has_value());
  EXPECT_NEAR(*r->clock_bias_s, 276.154723e-6, 1e-18);
  // Standard deviations: 1.25^8 mm and 1.025^69 ps (SP3-d, %f base and exponents).
  ASSERT_TRUE(r->position_sigma_m[0].has_value());
  EXPECT_NEAR(*r->position_sigma_m[0], std::pow(1.25, 8) * 1e-3, 1e-12);
  EXPECT_NEAR(*r->position_sigma_m[2], std::pow(1.25, 10) * 1e-3, 1e-12);
  ASSERT_TRUE(r->clock_sigma_s.has_value());
  EXPECT_NEAR(*r->clock_sigma_s, std::pow(1.025, 69) * 1e-12, 1e-22);
  EXPECT_FALSE(r->velocity_ecef_mps.has_value());
  EXPECT_FALSE(r->clock_event || r->clock_predicted || r->maneuver || r->orbit_predicted);
  // Last record of the file, "PG32   8852.275214 -14845.411510  20395.800954     51.023796"
  const Sp3Record* last = recordAt(f, "G32", gpst(2026, 5, 13, 3, 0, 0.0));
  ASSERT_NE(last, nullptr);
  EXPECT_DOUBLE_EQ(last->position_ecef_m->z(), 20395800.954);
}

TEST(Sp3Reader, WumSp3dWithMoreThan99Satellites) {
  PPP_REQUIRE_SHARED_DATA();
  const Sp3File f = readSp3(test::dataPath(kWumSp3));
  const Sp3Header& h = f.header;
  // Line 1: "#dP2021  7 29  0  0  0.00000000    1440   u+U IGS14 FIT  WHU"
  EXPECT_EQ(h.version, 'd');
  EXPECT_EQ(h.epoch_count, 1440);
  EXPECT_EQ(h.data_used, "u+U");
  EXPECT_EQ(h.coordinate_system, "IGS14");
  EXPECT_EQ(h.orbit_type, "FIT");
  EXPECT_EQ(h.agency, "WHU");
  EXPECT_EQ(h.first_epoch, gpst(2021, 7, 29, 0, 0, 0.0));
  // Line 2: "## 2168 345600.00000000    60.00000000 59424 0.0000000000000"
  EXPECT_EQ(h.gps_week, 2168);
  EXPECT_DOUBLE_EQ(h.interval_s, 60.0);
  EXPECT_EQ(h.mjd, 59424);
  // Line 3: "+  106   G01G02..." (three-digit count, seven "+" lines)
  ASSERT_EQ(h.satellites.size(), 106u);
  EXPECT_EQ(h.satellites.back().toString(), "C37");
  std::map<GnssSystem, int> per_system;
  for (const auto& s : h.satellites) ++per_system[s.system];
  EXPECT_EQ(per_system[GnssSystem::GPS], 30);
  EXPECT_EQ(per_system[GnssSystem::GLONASS], 20);
  EXPECT_EQ(per_system[GnssSystem::Galileo], 24);
  EXPECT_EQ(per_system[GnssSystem::BeiDou], 32);
  // Line 10 "++ 5 5 5 4 ..." : exponent of G04 is 4
  EXPECT_EQ(h.accuracy_exponents[3], 4);
  // Line 17: "%c M  cc GPS ..."
  EXPECT_EQ(h.file_type, 'M');
  EXPECT_EQ(h.time_system, TimeSystem::GPS);
  EXPECT_TRUE(f.complete);
  EXPECT_EQ(f.epochs.size(), 1440u);
  EXPECT_EQ(f.satellites.size(), 106u);
  EXPECT_TRUE(f.report.clean()) << f.report.summary();

  // Line 10908, epoch 01:41: "PC03 -14757.615656  39457.936361    330.229673 999999.999999"
  const Sp3Record* r = recordAt(f, "C03", gpst(2021, 7, 29, 1, 41, 0.0));
  ASSERT_NE(r, nullptr);
  EXPECT_FALSE(r->clock_bias_s.has_value());
  EXPECT_TRUE(r->clock_marked_bad);
  ASSERT_TRUE(r->position_ecef_m.has_value());
  EXPECT_DOUBLE_EQ(r->position_ecef_m->x(), -14757615.656);
  // 61 clock records carry the marker in the whole file (grep 999999).
  EXPECT_EQ(f.report.counters().at("clocks with the bad-value marker 999999.999999"), 61u);
}

TEST(Sp3Reader, SummaryOfWumFile) {
  PPP_REQUIRE_SHARED_DATA();
  const FileSummary s = summarizeSp3File(test::dataPath(kWumSp3));
  EXPECT_EQ(s.type, "SP3 orbit");
  EXPECT_EQ(s.version, "d");
  EXPECT_EQ(s.epoch_count, 1440u);
  ASSERT_TRUE(s.interval_s.has_value());
  EXPECT_DOUBLE_EQ(*s.interval_s, 60.0);
  ASSERT_TRUE(s.last_epoch.has_value());
  EXPECT_EQ(*s.last_epoch, gpst(2021, 7, 29, 23, 59, 0.0));
  EXPECT_EQ(s.satellites.at(GnssSystem::BeiDou).size(), 32u);
  EXPECT_NE(std::find(s.facts.begin(), s.facts.end(), "agency WHU"), s.facts.end());
  EXPECT_NE(std::find(s.facts.begin(), s.facts.end(), "coordinate system IGS14"), s.facts.end());
}

// Synthetic SP3-d: 120 satellites (8 "+" lines), velocities, flags, bad markers,
// EP/EV records, UTC time system, many comments.
TEST(Sp3Reader, SyntheticSp3dVelocitiesFlagsAndMarkers) {
  test::SyntheticSp3 gen;
  gen.satellites.clear();
  for (int i = 1; i <= 32; ++i) gen.satellites.push_back("G" + std::string(i < 10 ? "0" : "") + std::to_string(i));
  for (int i = 1; i <= 36; ++i) gen.satellites.push_back("E" + std::string(i < 10 ? "0" : "") + std::to_string(i));
  for (int i = 1; i <= 46; ++i) gen.satellites.push_back("C" + std::string(i < 10 ? "0" : "") + std::to_string(i));
  for (int i = 1; i <= 6; ++i) gen.satellites.push_back("R0" + std::to_string(i));
  ASSERT_EQ(gen.satellites.size(), 120u);
  gen.epochs = 3;
  gen.time_system = "UTC";
  gen.file_type = 'M';
  gen.with_velocity = true;
  gen.comments = {"c1", "c2", "c3", "c4", "c5", "c6 (SP3-d allows more than four)"};
  gen.record = [](int e, const std::string& sat) {
    test::SyntheticRecord r;
    r.position_km = Eigen::Vector3d(20000.0 + e, -10000.5, 5000.25);
    r.clock_us = 12.5;
    r.velocity_dm_s = Eigen::Vector3d(10000.0, -20000.0, 5.0);
    r.clock_rate = 2.0;
    if (sat == "E05" && e == 1) r.position_km.y() = 0.0;           // bad position marker
    if (sat == "C10" && e == 2) r.clock_us = 999999.999999;        // bad clock marker
    if (sat == "G07" && e == 0) r.flags = "EP  MP";                // all four flags
    if (sat == "R06" && e == 2) r.present = false;                 // absent
    return r;
  };
  std::string text = gen.text();
  // Insert an EP and an EV record after the first P/V pair.
  const auto pos = text.find("\nVG01");
  ASSERT_NE(pos, std::string::npos);
  const auto eol = text.find('\n', pos + 1);
  text.insert(eol + 1,
              "EP   55   55   55     222 1234567 -1234567 5999999      -30      -20      -10      -40\n"
              "EV   22   22   22     111 1234567 1234567 1234567 1234567 1234567 1234567 1234567\n");
  auto src = memoryLineSource(text, "synthetic.sp3");
  const Sp3File f = readSp3(*src);
  EXPECT_TRUE(f.report.clean()) << f.report.summary();
  EXPECT_EQ(f.header.satellites.size(), 120u);
  EXPECT_EQ(f.header.pv_flag, 'V');
  EXPECT_EQ(f.header.time_system, TimeSystem::UTC);
  EXPECT_EQ(f.header.comments.size(), 6u);
  EXPECT_EQ(f.report.counters().at("correlation records (EP/EV) skipped"), 2u);
  // UTC 2026-05-13 00:00 is GPST 00:00:18 (TAI-UTC 37 s, GPST = TAI - 19 s).
  EXPECT_EQ(f.epochs.front(), gpst(2026, 5, 13, 0, 0, 18.0));
  const Sp3Record* g1 = recordAt(f, "G01", f.epochs[0]);
  ASSERT_NE(g1, nullptr);
  ASSERT_TRUE(g1->velocity_ecef_mps.has_value());
  EXPECT_DOUBLE_EQ(g1->velocity_ecef_mps->x(), 1000.0);   // 10000 dm/s
  EXPECT_DOUBLE_EQ(g1->velocity_ecef_mps->y(), -2000.0);
  EXPECT_NEAR(*g1->clock_rate_s_per_s, 2.0e-10, 1e-24);   // 2 x 1e-4 us/s
  EXPECT_NEAR(*g1->clock_bias_s, 12.5e-6, 1e-18);
  EXPECT_DOUBLE_EQ(g1->position_ecef_m->z(), 5000250.0);
  const Sp3Record* g7 = recordAt(f, "G07", f.epochs[0]);
  ASSERT_NE(g7, nullptr);
  EXPECT_TRUE(g7->clock_event && g7->clock_predicted && g7->maneuver && g7->orbit_predicted);
  const Sp3Record* e5 = recordAt(f, "E05", f.epochs[1]);
  ASSERT_NE(e5, nullptr);
  EXPECT_FALSE(e5->position_ecef_m.has_value());
  EXPECT_TRUE(e5->position_marked_bad);
  EXPECT_TRUE(e5->clock_bias_s.has_value());
  const Sp3Record* c10 = recordAt(f, "C10", f.epochs[2]);
  ASSERT_NE(c10, nullptr);
  EXPECT_FALSE(c10->clock_bias_s.has_value());
  EXPECT_TRUE(c10->position_ecef_m.has_value());
  EXPECT_EQ(recordAt(f, "R06", f.epochs[2]), nullptr);
  EXPECT_EQ(f.satellites.at(*SatelliteId::parse("R06")).size(), 2u);
}

// --------------------------------------------------------------- malformed
Sp3File readFixture(const std::string& name) {
  return readSp3(test::fixturePath("malformed/sp3/" + name));
}

void expectHeaderError(const std::string& name, std::size_t line, const std::string& reason_part) {
  try {
    readFixture(name);
    FAIL() << name << ": no ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), line) << name << ": " << e.what();
    EXPECT_NE(e.reason().find(reason_part), std::string::npos) << name << ": " << e.what();
    EXPECT_NE(e.file().find(name), std::string::npos);
  }
}

TEST(Sp3ReaderMalformed, HeaderErrors) {
  expectHeaderError("bad_version.txt", 1, "not an SP3 file");
  expectHeaderError("satellite_count_mismatch.txt", 3, "announces 3 satellites but lists 2");
  expectHeaderError("huge_satellite_count.txt", 3, "announces 999 satellites but lists 2");
  expectHeaderError("bad_interval.txt", 2, "epoch interval");
  expectHeaderError("unknown_time_system.txt", 13, "unknown time system 'XYZ'");
  expectHeaderError("header_truncated.txt", 3, "header ends inside the satellite list");
}

TEST(Sp3ReaderMalformed, EmptyInputIsAHeaderError) {
  auto src = memoryLineSource("", "empty");
  EXPECT_THROW(readSp3(*src), ParseError);
}

TEST(Sp3ReaderMalformed, BadRecordsAreSkippedAndReported) {
  const Sp3File f = readFixture("bad_records.txt");
  // Lines 20 (P before any epoch), 24 (month 13), 25 (record of that epoch),
  // 27 (malformed Y), 28 (satellite X99), 30 (V not after its P), 31 (epoch
  // going back), 32 (record of that epoch), 36 (junk).
  std::vector<std::size_t> lines;
  for (const auto& p : f.report.problems()) lines.push_back(p.line);
  EXPECT_EQ(lines, (std::vector<std::size_t>{20, 24, 25, 27, 28, 30, 31, 32, 36}));
  EXPECT_TRUE(f.complete);
  ASSERT_EQ(f.epochs.size(), 3u);
  EXPECT_EQ(f.satellites.at(*SatelliteId::parse("G01")).size(), 2u);  // 00:00 and 00:30
  EXPECT_EQ(f.satellites.at(*SatelliteId::parse("G02")).size(), 3u);
  EXPECT_FALSE(f.satellites.at(*SatelliteId::parse("G02"))[1].velocity_ecef_mps.has_value());
}

TEST(Sp3ReaderMalformed, TruncatedFileKeepsWhatWasRead) {
  const Sp3File f = readFixture("truncated.txt");
  EXPECT_FALSE(f.complete);
  EXPECT_EQ(f.epochs.size(), 2u);
  EXPECT_EQ(f.satellites.at(*SatelliteId::parse("G01")).size(), 2u);
  EXPECT_EQ(f.satellites.at(*SatelliteId::parse("G02")).size(), 1u);  // the cut line is skipped
  ASSERT_EQ(f.report.problemCount(), 2u);
  EXPECT_NE(f.report.problems()[1].reason.find("without the EOF line"), std::string::npos);
}

TEST(Sp3ReaderMalformed, TruncatedGzipKeepsRecordsAndReportsTheStreamError) {
  PPP_REQUIRE_SHARED_DATA();
  std::string bytes = test::readFileBytes(test::dataPath(kWumSp3));
  ASSERT_GT(bytes.size(), 200000u);
  bytes.resize(200000);
  auto src = memoryLineSource(bytes, "cut.sp3.gz");
  const Sp3File f = readSp3(*src);
  EXPECT_FALSE(f.complete);
  EXPECT_GT(f.epochs.size(), 10u);
  EXPECT_LT(f.epochs.size(), 1440u);
  bool stream_problem = false;
  for (const auto& p : f.report.problems()) stream_problem |= p.reason.find("stream") != std::string::npos;
  EXPECT_TRUE(stream_problem) << f.report.summary();
}

}  // namespace
}  // namespace ppp
