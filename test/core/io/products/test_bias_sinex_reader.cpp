// Bias-SINEX 1.00 reader: CODE and WHU products from ../shared/data (rows cited
// by their line number in the decompressed file) and synthetic fixtures.
#include <gtest/gtest.h>

#include <cmath>

#include "ppp_bayes_tree/io/products/bias_sinex_reader.h"
#include "ppp_bayes_tree/types/constants.h"
#include "test_support.h"

using namespace ppp;

namespace {

constexpr double kNsToM = 1e-9 * kSpeedOfLight_mps;

using ppp::test::gpst;

ObservationCode code(const char* c) { return *ObservationCode::parse(c); }
SatelliteId sat(const char* s) { return *SatelliteId::parse(s); }

const BiasSinexFile& codFile() {
  static const BiasSinexFile f =
      readBiasSinexFile(test::dataPath("zim2-2026-133/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz"));
  return f;
}

}  // namespace

TEST(BiasSinexReader, CodeOsbFileHeaderAndCounts) {
  PPP_REQUIRE_SHARED_DATA();
  const BiasSinexFile& f = codFile();
  EXPECT_TRUE(f.report.clean()) << f.report.summary();
  // Line 1: "%=BIA 1.00 COD 2026:138:76927 IGS 2026:133:00000 2026:134:00000 A 00014065".
  EXPECT_EQ(f.header.version, "1.00");
  EXPECT_EQ(f.header.file_agency, "COD");
  EXPECT_EQ(f.header.data_agency, "IGS");
  EXPECT_EQ(f.header.bias_mode, 'A');
  EXPECT_EQ(f.header.estimate_count, 14065u);
  EXPECT_EQ(f.records.size(), 14065u);
  EXPECT_EQ(*f.header.data_start, gpst(2026, 5, 13));
  EXPECT_EQ(*f.header.data_end, gpst(2026, 5, 14));
  // BIAS/DESCRIPTION (lines 50-62).
  EXPECT_EQ(f.description.bias_mode, "ABSOLUTE");
  EXPECT_EQ(f.description.time_system, TimeSystem::GPS);
  EXPECT_EQ(*f.description.observation_sampling_s, 300.0);
  EXPECT_EQ(f.description.apc_model, "IGS20_2415");
  EXPECT_EQ(f.description.satellite_clock_reference_observables.at(GnssSystem::GPS),
            (std::vector<std::string>{"C1W", "C2W"}));
  EXPECT_EQ(f.reference.front().first, "DESCRIPTION");
  // 1123 station rows for 324 stations (counted with awk on columns 16-24).
  EXPECT_EQ(f.stations().size(), 324u);
}

TEST(BiasSinexReader, CodeOsbValuesInMetres) {
  PPP_REQUIRE_SHARED_DATA();
  const BiasSinexFile& f = codFile();
  const GnssTime t = gpst(2026, 5, 13, 0, 30);
  // Line 67: OSB G080 G01 C1C ... ns -6.0355 0.0001.
  const auto c1c = f.osb(sat("G01"), code("C1C"), t);
  ASSERT_TRUE(c1c);
  EXPECT_EQ(c1c->unit, BiasValueUnit::Metres);
  EXPECT_NEAR(c1c->value, -6.0355 * kNsToM, 1e-12);
  EXPECT_NEAR(*c1c->std_dev, 0.0001 * kNsToM, 1e-15);
  EXPECT_EQ(c1c->line, 67u);
  // Line 74: C2W -8.4213 ns.
  EXPECT_NEAR(f.osb(sat("G01"), code("C2W"), t)->value, -8.4213 * kNsToM, 1e-12);
  // Line 13757: phase L1C -0.99559 ns, given in ns -> metres as well.
  const auto l1c = f.osb(sat("G01"), code("L1C"), t);
  ASSERT_TRUE(l1c);
  EXPECT_EQ(l1c->unit, BiasValueUnit::Metres);
  EXPECT_NEAR(l1c->value, -0.99559 * kNsToM, 1e-12);
  // DSB derived from OSBs: C1C - C1W = -6.0355 - (-5.1133) ns (lines 67, 70).
  const auto dsb = f.dsb(sat("G01"), code("C1C"), code("C1W"), t);
  ASSERT_TRUE(dsb);
  EXPECT_TRUE(dsb->derived_from_osb);
  EXPECT_NEAR(dsb->value, (-6.0355 + 5.1133) * kNsToM, 1e-12);
  // Station rows: line 389 "OSB E E ABMF C1C ... -7.8324".
  const auto abmf = f.stationOsb("abmf", GnssSystem::Galileo, code("C1C"), t);
  ASSERT_TRUE(abmf);
  EXPECT_NEAR(abmf->value, -7.8324 * kNsToM, 1e-12);
  // Absent: outside the validity (day 134 + 1 s), a code not given, GPS C5Q for G01.
  EXPECT_FALSE(f.osb(sat("G01"), code("C1C"), gpst(2026, 5, 14, 0, 0, 1.0)));
  EXPECT_FALSE(f.osb(sat("G01"), code("C5Q"), t));
  EXPECT_FALSE(f.osb(sat("G01"), code("C1C"), gpst(2026, 5, 12, 23, 59, 59.0)));
}

// A GPS-only reader keeps exactly the GPS rows of the full read (the header count
// of 14065 then holds with the skipped rows) and gives the same values.
TEST(BiasSinexReader, SystemFilterKeepsTheGpsRowsOnly) {
  PPP_REQUIRE_SHARED_DATA();
  RecordFilter gps;
  gps.systems = {GnssSystem::GPS};
  const BiasSinexFile g =
      readBiasSinexFile(test::dataPath("zim2-2026-133/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz"), gps);
  EXPECT_TRUE(g.report.clean()) << g.report.summary();
  std::size_t full_gps = 0;
  for (const auto& r : codFile().records) full_gps += r.system == GnssSystem::GPS;
  EXPECT_EQ(g.records.size(), full_gps);
  EXPECT_EQ(g.report.counters().at("rows of other systems skipped"), 14065u - full_gps);
  for (const auto& r : g.records) EXPECT_EQ(r.system, GnssSystem::GPS);
  const GnssTime t = gpst(2026, 5, 13, 0, 30);
  EXPECT_EQ(g.osb(sat("G01"), code("C1C"), t)->value, codFile().osb(sat("G01"), code("C1C"), t)->value);
  EXPECT_FALSE(g.stationOsb("abmf", GnssSystem::Galileo, code("C1C"), t));
}

TEST(BiasSinexReader, WhuAbsFileWithExponentValues) {
  PPP_REQUIRE_SHARED_DATA();
  const BiasSinexFile f =
      readBiasSinexFile(test::dataPath("ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01D_ABS.BIA.gz"));
  EXPECT_TRUE(f.report.clean()) << f.report.summary();
  EXPECT_EQ(f.records.size(), 1072u);  // header line 1: 00001072
  EXPECT_EQ(f.header.file_agency, "WHU");
  EXPECT_EQ(*f.header.data_end, gpst(2021, 7, 30));  // 2021:210:86400
  const GnssTime t = gpst(2021, 7, 29, 0, 30);
  // Line 63: OSB G063 G01 C1C ... ns 0.978760000000000E+01 .606000E-01.
  const auto c1c = f.osb(sat("G01"), code("C1C"), t);
  ASSERT_TRUE(c1c);
  EXPECT_NEAR(c1c->value, 9.7876 * kNsToM, 1e-12);
  EXPECT_NEAR(*c1c->std_dev, 0.0606 * kNsToM, 1e-14);
  // Line 71: L1C -.121539951624478E+01 ns.
  EXPECT_NEAR(f.osb(sat("G01"), code("L1C"), t)->value, -1.21539951624478 * kNsToM, 1e-12);
  // Line 412: R01 C1P 0.945850000000000E+01; line 876: C20 C2I -.441703000000000E+02.
  EXPECT_NEAR(f.osb(sat("R01"), code("C1P"), t)->value, 9.4585 * kNsToM, 1e-12);
  EXPECT_NEAR(f.osb(sat("C20"), code("C2I"), t)->value, -44.1703 * kNsToM, 1e-12);
  // End of day 210 is inclusive (2021:210:86400).
  EXPECT_TRUE(f.osb(sat("G01"), code("C1C"), gpst(2021, 7, 30)));
}

TEST(BiasSinexReader, SyntheticDsbFile) {
  const BiasSinexFile f = readBiasSinexFile(test::fixturePath("bias_sinex/synthetic_dsb.bias.txt"));
  EXPECT_TRUE(f.report.clean()) << f.report.summary();
  ASSERT_EQ(f.records.size(), 9u);
  EXPECT_EQ(f.header.bias_mode, 'R');
  EXPECT_EQ(f.description.bias_mode, "RELATIVE");
  EXPECT_EQ(f.report.counters().at("DSB rows"), 4u);
  // Line 16 (day 210) and line 17 (day 211): the interval containing t wins; at
  // the shared bound 211:00000 the later-starting row (line 17) wins.
  EXPECT_NEAR(f.dsb(sat("G01"), code("C1C"), code("C1W"), gpst(2021, 7, 29, 12))->value, -0.95 * kNsToM, 1e-12);
  EXPECT_NEAR(f.dsb(sat("G01"), code("C1C"), code("C1W"), gpst(2021, 7, 30, 12))->value, -1.05 * kNsToM, 1e-12);
  EXPECT_EQ(f.dsb(sat("G01"), code("C1C"), code("C1W"), gpst(2021, 7, 30))->line, 17u);
  EXPECT_FALSE(f.dsb(sat("G01"), code("C1C"), code("C1W"), gpst(2021, 8, 1, 0, 0, 1.0)));
  // Reversed order negates: C1W - C1C.
  const auto rev = f.dsb(sat("G01"), code("C1W"), code("C1C"), gpst(2021, 7, 29, 12));
  ASSERT_TRUE(rev);
  EXPECT_NEAR(rev->value, 0.95 * kNsToM, 1e-12);
  EXPECT_FALSE(rev->derived_from_osb);
  // Line 18 (C1W-C2W) has an open end (0000:000:00000): valid years later.
  EXPECT_NEAR(f.dsb(sat("G01"), code("C1W"), code("C2W"), gpst(2030, 1, 1))->value, -6.946 * kNsToM, 1e-12);
  // G02: a DSB row (line 19, no std dev) takes precedence over the OSB difference.
  const auto g02 = f.dsb(sat("G02"), code("C1C"), code("C1W"), gpst(2021, 7, 29));
  ASSERT_TRUE(g02);
  EXPECT_FALSE(g02->derived_from_osb);
  EXPECT_FALSE(g02->std_dev);
  EXPECT_NEAR(g02->value, 1.9205 * kNsToM, 1e-12);
  // Cycles stay cycles (line 22).
  const auto l1c = f.osb(sat("G02"), code("L1C"), gpst(2021, 7, 29));
  ASSERT_TRUE(l1c);
  EXPECT_EQ(l1c->unit, BiasValueUnit::Cycles);
  EXPECT_DOUBLE_EQ(l1c->value, 0.125);
  // OSB C1C - L1C mixes metres and cycles: no derived DSB.
  EXPECT_FALSE(f.dsb(sat("G02"), code("C1C"), code("L1C"), gpst(2021, 7, 29)));
  // Station rows: ISB (line 23) and a lower-case station name (line 24).
  EXPECT_EQ(f.stations(), (std::vector<std::string>{"ZIM2"}));
  EXPECT_NEAR(f.stationOsb("ZIM2", GnssSystem::Galileo, code("C1C"), gpst(2021, 7, 29))->value,
              -7.8324 * kNsToM, 1e-12);
  EXPECT_EQ(f.records[7].type, BiasType::ISB);
}

TEST(BiasSinexReader, UtcTimeSystemIsConverted) {
  const BiasSinexFile f = readBiasSinexFile(test::fixturePath("bias_sinex/utc_time_system.bias.txt"));
  EXPECT_TRUE(f.report.clean()) << f.report.summary();
  ASSERT_EQ(f.records.size(), 2u);
  // 2021:210:00000 UTC = 2021-07-29 00:00:18 GPST (TAI-UTC 37 s, GPST = TAI - 19 s).
  EXPECT_EQ(*f.records[0].start, gpst(2021, 7, 29, 0, 0, 18.0));
  // 2015:200:43200 UTC = 2015-07-19 12:00:00 UTC, after the 2015-06-30 leap second
  // (TAI-UTC 36 s) -> 12:00:17 GPST.
  EXPECT_EQ(*f.records[1].start, gpst(2015, 7, 19, 12, 0, 17.0));
}

TEST(BiasSinexReader, MalformedRowsAreSkippedAndCounted) {
  const BiasSinexFile f = readBiasSinexFile(test::fixturePath("malformed/bias_sinex/bad_rows.bias.txt"));
  EXPECT_EQ(f.records.size(), 9u);
  ASSERT_EQ(f.report.problemCount(), 8u) << f.report.summary();
  const char* expected[] = {"unknown bias type 'XYZ'", "malformed PRN field", "OSB row with an OBS2",
                            "DSB row without OBS2", "malformed BIAS_START", "unsupported unit 'TECU'",
                            "malformed bias value", "BIAS_END before BIAS_START"};
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(f.report.problems()[i].line, 18u + i);
    EXPECT_NE(f.report.problems()[i].reason.find(expected[i]), std::string::npos) << f.report.problems()[i].reason;
  }
  // The good rows around them are intact.
  EXPECT_NEAR(f.dsb(sat("G01"), code("C1C"), code("C1W"), gpst(2021, 7, 29, 12))->value, -0.95 * kNsToM, 1e-12);
}

TEST(BiasSinexReader, TruncatedFileIsReported) {
  const BiasSinexFile f = readBiasSinexFile(test::fixturePath("malformed/bias_sinex/truncated.bias.txt"));
  EXPECT_EQ(f.records.size(), 3u);
  std::string all;
  for (const auto& p : f.report.problems()) all += p.reason + "\n";
  EXPECT_NE(all.find("file ends inside block BIAS/SOLUTION"), std::string::npos) << all;
  EXPECT_NE(all.find("no %=ENDBIA footer"), std::string::npos) << all;
  EXPECT_NE(all.find("header announces 9 estimates, 3 read"), std::string::npos) << all;
}

TEST(BiasSinexReader, MalformedHeadersThrowParseError) {
  const auto expectError = [](const char* fixture, std::size_t line, const char* reason) {
    try {
      readBiasSinexFile(test::fixturePath(std::string("malformed/bias_sinex/") + fixture));
      ADD_FAILURE() << fixture << ": no ParseError";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.line(), line) << fixture;
      EXPECT_NE(e.reason().find(reason), std::string::npos) << fixture << ": " << e.reason();
    }
  };
  expectError("bad_first_line.bias.txt", 1, "does not start with %=BIA");
  expectError("bad_header_epoch.bias.txt", 1, "malformed epoch");
  expectError("bad_bias_mode.bias.txt", 11, "BIAS_MODE must be ABSOLUTE or RELATIVE");
  expectError("bad_time_system.bias.txt", 12, "unknown TIME_SYSTEM 'XYZ'");
  auto empty = memoryLineSource("", "empty");
  EXPECT_THROW(readBiasSinex(*empty), ParseError);
}

TEST(BiasSinexSummary, SummarizesCodeFile) {
  PPP_REQUIRE_SHARED_DATA();
  const FileSummary s =
      summarizeBiasSinexFile(test::dataPath("zim2-2026-133/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz"));
  EXPECT_EQ(s.type, "Bias-SINEX");
  EXPECT_EQ(s.version, "1.00");
  EXPECT_EQ(*s.first_epoch, gpst(2026, 5, 13));
  EXPECT_EQ(s.epoch_count, 14065u);
  EXPECT_TRUE(s.signals.at(GnssSystem::GPS).count("C2W"));
  EXPECT_TRUE(s.signals.at(GnssSystem::GPS).count("L1C"));
  EXPECT_TRUE(s.satellites.at(GnssSystem::Galileo).count(sat("E36")));  // last rows
  bool stations = false;
  for (const auto& f : s.facts) stations = stations || f == "stations: 324";
  EXPECT_TRUE(stations);
}
