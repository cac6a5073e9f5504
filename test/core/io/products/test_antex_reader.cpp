// ANTEX 1.4 reader, antenna lookup and PCO/PCV interpolation.
// Known values are read from the trimmed IGS20 files in ../shared/data/antex
// (line numbers cited) and from the synthetic fixtures in test/fixtures.
#include <gtest/gtest.h>

#include <zlib.h>

#include <cmath>

#include "ppp_bayes_tree/io/products/antex_reader.h"
#include "ppp_bayes_tree/types/constants.h"
#include "test_support.h"

using namespace ppp;

namespace {

constexpr double kMm = 1e-3;
constexpr double kTol = 1e-9;

using ppp::test::gpst;

const AntexFile& zim2Antex() {
  static const AntexFile file = readAntexFile(test::dataPath("antex/igs20_zim2_gps_trim.atx"));
  return file;
}
const AntexFile& satelliteAntex() {
  static const AntexFile file = readAntexFile(test::dataPath("antex/igs20_gps_satellites_trim.atx"));
  return file;
}

double deg(double d) { return d * kDegToRad; }

}  // namespace

TEST(AntexReader, ReadsHeaderAndAllBlocksOfZim2File) {
  PPP_REQUIRE_SHARED_DATA();
  const AntexFile& f = zim2Antex();
  EXPECT_EQ(f.header.version, "1.4");  // line 1
  EXPECT_EQ(f.header.system, 'M');     // line 1
  EXPECT_EQ(f.header.pcv_type, 'A');   // line 2
  EXPECT_TRUE(f.report.clean()) << f.report.summary();
  // 16 TYPE / SERIAL NO lines: 14 GPS satellite blocks (lines 564-809) and 2 receiver
  // antennas (lines 826, 2770).
  EXPECT_EQ(f.receiverCount(), 2u);
  EXPECT_EQ(f.antennas.size(), 16u);
}

TEST(AntexReader, ReceiverPcoOfTrm59800None) {
  PPP_REQUIRE_SHARED_DATA();
  const auto lookup = zim2Antex().receiver("TRM59800.00     NONE");
  ASSERT_NE(lookup.antenna, nullptr);
  EXPECT_FALSE(lookup.radome_substituted);
  EXPECT_TRUE(lookup.note.empty());
  EXPECT_EQ(lookup.antenna->line, 825u);
  EXPECT_DOUBLE_EQ(lookup.antenna->azimuth_step_deg, 5.0);  // line 828
  // igs20_zim2_gps_trim.atx line 844: G01 N/E/U 0.65 1.35 89.35 mm.
  const FrequencyCalibration* g01 = lookup.antenna->frequency(GnssSystem::GPS, 1);
  ASSERT_NE(g01, nullptr);
  EXPECT_NEAR(g01->pco_m.x(), 0.65 * kMm, kTol);
  EXPECT_NEAR(g01->pco_m.y(), 1.35 * kMm, kTol);
  EXPECT_NEAR(g01->pco_m.z(), 89.35 * kMm, kTol);
  // line 1229: G02 N/E/U -0.24 0.00 117.76 mm.
  const FrequencyCalibration* g02 = lookup.antenna->frequency(GnssSystem::GPS, 2);
  ASSERT_NE(g02, nullptr);
  EXPECT_NEAR(g02->pco_m.x(), -0.24 * kMm, kTol);
  EXPECT_NEAR(g02->pco_m.y(), 0.0, kTol);
  EXPECT_NEAR(g02->pco_m.z(), 117.76 * kMm, kTol);
  // 25 frequencies (line 830), 73 azimuth rows 0..360 of 19 zenith nodes 0..90.
  EXPECT_EQ(lookup.antenna->frequencies.size(), 25u);
  EXPECT_EQ(g01->pcv.zenithCount(), 19u);
  EXPECT_EQ(g01->pcv.azimuthRowCount(), 73u);
}

TEST(AntexReader, ReceiverPcvNoAzimuthAtNodeAndBetweenNodes) {
  PPP_REQUIRE_SHARED_DATA();
  const auto* g01 = zim2Antex().receiver("TRM59800.00", "NONE").antenna->frequency(GnssSystem::GPS, 1);
  ASSERT_NE(g01, nullptr);
  // line 845, NOAZI: 0.00 -0.23 -0.90 -1.95 ... at zenith 0, 5, 10, 15 deg.
  EXPECT_NEAR(*g01->pcv.evaluateNoAzimuth_m(deg(10.0)), -0.90 * kMm, kTol);
  // By hand: halfway between 10 deg (-0.90) and 15 deg (-1.95) -> -1.425 mm.
  EXPECT_NEAR(*g01->pcv.evaluateNoAzimuth_m(deg(12.5)), -1.425 * kMm, kTol);
  // 90 deg is the last node (14.89 mm, line 845).
  EXPECT_NEAR(*g01->pcv.evaluateNoAzimuth_m(deg(90.0)), 14.89 * kMm, kTol);
  // Outside ZEN1..ZEN2 = 0..90: refused, not clamped.
  EXPECT_FALSE(g01->pcv.evaluateNoAzimuth_m(deg(90.5)).has_value());
  EXPECT_FALSE(g01->pcv.evaluateNoAzimuth_m(deg(-1.0)).has_value());
  EXPECT_FALSE(g01->pcv.evaluateNoAzimuth_m(std::nan("")).has_value());
}

TEST(AntexReader, ReceiverPcvAzimuthDependentBilinearWithWrapAround) {
  PPP_REQUIRE_SHARED_DATA();
  const auto* g01 = zim2Antex().receiver("TRM59800.00", "NONE").antenna->frequency(GnssSystem::GPS, 1);
  ASSERT_NE(g01, nullptr);
  // Node: line 847 (azimuth 5.0), zenith 15 deg: -1.98 mm.
  EXPECT_NEAR(*g01->pcv_m(deg(15.0), deg(5.0)), -1.98 * kMm, kTol);
  // Bilinear by hand at azimuth 2.5, zenith 12.5: rows 0.0 (line 846: -0.92, -1.98)
  // and 5.0 (line 847: -0.93, -1.98) -> (-1.45 + -1.455) / 2 = -1.4525 mm.
  EXPECT_NEAR(*g01->pcv_m(deg(12.5), deg(2.5)), -1.4525 * kMm, kTol);
  // Wrap-around: azimuth 357.5 (and -2.5) between rows 355.0 (line 917: -0.91 at
  // 10 deg) and 360.0 (line 918: -0.92) -> -0.915 mm.
  EXPECT_NEAR(*g01->pcv_m(deg(10.0), deg(357.5)), -0.915 * kMm, kTol);
  EXPECT_NEAR(*g01->pcv_m(deg(10.0), deg(-2.5)), -0.915 * kMm, kTol);
  EXPECT_NEAR(*g01->pcv_m(deg(10.0), deg(717.5)), -0.915 * kMm, kTol);
  EXPECT_FALSE(g01->pcv_m(deg(91.0), deg(10.0)).has_value());
}

TEST(AntexReader, SatellitePcoAndNadirPcvForMay2026) {
  PPP_REQUIRE_SHARED_DATA();
  const GnssTime t = gpst(2026, 5, 13, 0, 30);
  const AntennaCalibration* g05 = zim2Antex().satellite(*SatelliteId::parse("G05"), t);
  ASSERT_NE(g05, nullptr);
  // igs20_zim2_gps_trim.atx line 564: BLOCK IIR-M G05 G050 2009-043A.
  EXPECT_EQ(g05->model, "BLOCK IIR-M");
  EXPECT_EQ(g05->svn, "G050");
  EXPECT_EQ(g05->cospar_id, "2009-043A");
  EXPECT_FALSE(g05->valid_until.has_value());
  // line 572: G01 X/Y/Z (body frame) -3.30 -0.30 742.63 mm.
  const auto* f1 = g05->frequency(GnssSystem::GPS, 1);
  ASSERT_NE(f1, nullptr);
  EXPECT_NEAR(f1->pco_m.x(), -3.30 * kMm, kTol);
  EXPECT_NEAR(f1->pco_m.y(), -0.30 * kMm, kTol);
  EXPECT_NEAR(f1->pco_m.z(), 742.63 * kMm, kTol);
  // line 573: NOAZI 10.70 10.10 8.00 ... at nadir 0, 1, 2 deg (ZEN 0..17 step 1, line 567).
  EXPECT_NEAR(*f1->pcv_m(deg(1.0), 0.0), 10.10 * kMm, kTol);
  EXPECT_NEAR(*f1->pcv_m(deg(0.5), 1.0), 10.40 * kMm, kTol);  // (10.70 + 10.10) / 2
  EXPECT_NEAR(*f1->pcv_m(deg(1.75), 0.0), 8.525 * kMm, kTol);  // 10.10 + 0.75 * (8.00 - 10.10)
  EXPECT_FALSE(f1->pcv_m(deg(17.5), 0.0).has_value());  // beyond ZEN2 = 17: refused
}

TEST(AntexReader, PicksTheSatelliteBlockValidAtTheDate) {
  PPP_REQUIRE_SHARED_DATA();
  const AntexFile& f = satelliteAntex();
  EXPECT_TRUE(f.report.clean()) << f.report.summary();
  EXPECT_EQ(f.antennas.size(), 118u);  // 118 TYPE / SERIAL NO lines
  const SatelliteId g01 = *SatelliteId::parse("G01");
  // 2021-07-29 (CCJ2 day): SVN G063, valid 2011-07-16 .. 2024-04-11 (lines 622-629),
  // PCO z 1421.47 mm (line 631).
  const AntennaCalibration* a2021 = f.satellite(g01, gpst(2021, 7, 29));
  ASSERT_NE(a2021, nullptr);
  EXPECT_EQ(a2021->svn, "G063");
  EXPECT_NEAR(a2021->frequency(GnssSystem::GPS, 1)->pco_m.x(), 394.00 * kMm, kTol);
  EXPECT_NEAR(a2021->frequency(GnssSystem::GPS, 1)->pco_m.z(), 1421.47 * kMm, kTol);
  // 2026-05-13: SVN G080 (BLOCK IIIA), valid from 2024-12-17 (line 658), G01 PCO line 668,
  // G02 line 672 (Z 681.61 mm), three frequencies incl. G05.
  const AntennaCalibration* a2026 = f.satellite(g01, gpst(2026, 5, 13));
  ASSERT_NE(a2026, nullptr);
  EXPECT_EQ(a2026->svn, "G080");
  EXPECT_NEAR(a2026->frequency(GnssSystem::GPS, 1)->pco_m.z(), 1185.75 * kMm, kTol);
  EXPECT_NEAR(a2026->frequency(GnssSystem::GPS, 2)->pco_m.z(), 681.61 * kMm, kTol);
  EXPECT_NE(a2026->frequency(GnssSystem::GPS, 5), nullptr);
  // 2024-05-01: SVN G049 again (lines 640-646, 2024-04-22 .. 2024-10-07).
  EXPECT_EQ(f.satellite(g01, gpst(2024, 5, 1))->svn, "G049");
  // The last instant of a period is still inside it (VALID UNTIL 23:59:59.9999999, line 628).
  EXPECT_EQ(f.satellite(g01, gpst(2024, 4, 11, 23, 59, 59.5))->svn, "G063");
  // Gap between 2008-10-16 (G032 ends, line 556) and 2008-10-23 (G037 starts, line 575).
  EXPECT_EQ(f.satellite(g01, gpst(2008, 10, 20)), nullptr);
  // Before any block of G01 (first starts 1992-11-22, line 555).
  EXPECT_EQ(f.satellite(g01, gpst(1990, 1, 1)), nullptr);
}

TEST(AntexReader, FrequencyFallbackIsExplicitAndReported) {
  PPP_REQUIRE_SHARED_DATA();
  // BLOCK IIR-M G05 (line 568) has only G01 and G02.
  const AntennaCalibration* g05 = zim2Antex().satellite(*SatelliteId::parse("G05"), gpst(2026, 5, 13));
  ASSERT_NE(g05, nullptr);
  EXPECT_EQ(g05->frequency(GnssSystem::GPS, 5), nullptr);
  const FrequencyLookup none = g05->frequency(GnssSystem::GPS, 5, FrequencyFallback::None);
  EXPECT_EQ(none.calibration, nullptr);
  EXPECT_NE(none.note.find("G05 not calibrated"), std::string::npos) << none.note;
  const FrequencyLookup fb = g05->frequency(GnssSystem::GPS, 5, FrequencyFallback::NearestSameSystem);
  ASSERT_NE(fb.calibration, nullptr);
  EXPECT_TRUE(fb.substituted);
  EXPECT_EQ(fb.calibration->code(), "G02");
  EXPECT_NE(fb.note.find("using G02"), std::string::npos) << fb.note;
  // No Galileo frequency at all on a GPS satellite: absent even with fallback.
  EXPECT_EQ(g05->frequency(GnssSystem::Galileo, 1, FrequencyFallback::NearestSameSystem).calibration, nullptr);
}

TEST(AntexReader, RadomeFallbackToNoneIsReported) {
  PPP_REQUIRE_SHARED_DATA();
  const AntexFile& f = zim2Antex();
  const auto scis = f.receiver("TRM59800.00     SCIS");  // CCJ2's antenna, not in the file
  ASSERT_NE(scis.antenna, nullptr);
  EXPECT_TRUE(scis.radome_substituted);
  EXPECT_EQ(scis.antenna->radome, "NONE");
  EXPECT_EQ(scis.antenna->line, 825u);
  EXPECT_EQ(scis.note, "TRM59800.00 SCIS not found, using TRM59800.00 NONE");
  const auto blank = f.receiver("TRM59800.00", "");
  ASSERT_NE(blank.antenna, nullptr);
  EXPECT_TRUE(blank.radome_substituted);
  EXPECT_NE(blank.note.find("using TRM59800.00 NONE"), std::string::npos);
  // TRM59800.00C (line 2770) is a different model, not a prefix match.
  EXPECT_EQ(f.receiver("TRM59800.00C NONE").antenna->line, 2769u);
}

TEST(AntexReader, MissingAntennaIsExplicit) {
  PPP_REQUIRE_SHARED_DATA();
  const auto r = zim2Antex().receiver("LEIAR25.R4      LEIT");
  EXPECT_EQ(r.antenna, nullptr);
  EXPECT_FALSE(r.radome_substituted);
  EXPECT_EQ(r.note, "LEIAR25.R4 LEIT not found");
  // G33 does not exist; G02 is not in the zim2 file (trimmed to the satellites seen).
  EXPECT_EQ(zim2Antex().satellite(*SatelliteId::parse("G02"), gpst(2026, 5, 13)), nullptr);
  // In the satellite file LEIAR20 LEIM is present (line 2678).
  EXPECT_NE(satelliteAntex().receiver("LEIAR20 LEIM").antenna, nullptr);
}

TEST(AntexReader, SyntheticBlockWithAzimuthGrid) {
  const AntexFile f = readAntexFile(test::fixturePath("malformed/antex/bad_blocks_antex.txt"));
  const auto r = f.receiver("TSTANT1 NONE");
  ASSERT_NE(r.antenna, nullptr);
  const auto* g01 = r.antenna->frequency(GnssSystem::GPS, 1);
  ASSERT_NE(g01, nullptr);
  // Rows 0, 180, 360 (lines 14-16) of zenith 0, 5, 10: at azimuth 90, zenith 7.5:
  // row 0: (-2 + -4)/2 = -3, row 180: (0 + 2)/2 = 1 -> -1 mm.
  EXPECT_NEAR(*g01->pcv_m(deg(7.5), deg(90.0)), -1.0 * kMm, kTol);
  // azimuth 270: between 180 (1) and 360 (-3) -> -1 mm; azimuth 180 exactly -> 1 mm.
  EXPECT_NEAR(*g01->pcv_m(deg(7.5), deg(270.0)), -1.0 * kMm, kTol);
  EXPECT_NEAR(*g01->pcv_m(deg(7.5), deg(180.0)), 1.0 * kMm, kTol);
  EXPECT_NEAR(*g01->pcv.evaluateNoAzimuth_m(deg(7.5)), -2.0 * kMm, kTol);
}

TEST(AntexReader, MalformedBlocksAreSkippedAndReported) {
  const AntexFile f = readAntexFile(test::fixturePath("malformed/antex/bad_blocks_antex.txt"));
  // Good: TSTANT1 (line 5), TSTANT2 with an RMS block (line 59), BLOCK IIF G07 (line 95).
  ASSERT_EQ(f.antennas.size(), 3u);
  EXPECT_EQ(f.antennas[0].model, "TSTANT1");
  EXPECT_EQ(f.antennas[1].model, "TSTANT2");
  EXPECT_EQ(f.antennas[1].rms_blocks_skipped, 1u);
  EXPECT_EQ(f.report.counters().at("RMS blocks skipped"), 1u);
  ASSERT_TRUE(f.antennas[2].satellite.has_value());
  EXPECT_EQ(f.antennas[2].satellite->toString(), "G07");
  EXPECT_NE(f.satellite(*SatelliteId::parse("G07"), gpst(2026, 1, 1)), nullptr);
  EXPECT_EQ(f.satellite(*SatelliteId::parse("G07"), gpst(2019, 1, 1)), nullptr);
  // Bad: DZEN 0, DAZI 0.0001, short NOAZI row, # OF FREQUENCIES mismatch,
  // missing END OF ANTENNA, malformed PCO.
  ASSERT_EQ(f.report.problemCount(), 6u) << f.report.summary();
  const auto& p = f.report.problems();
  const auto has = [](const ParseProblem& pr, const char* what) {
    return pr.reason.find(what) != std::string::npos;
  };
  EXPECT_TRUE(has(p[0], "DZEN must be > 0")) << p[0].reason;
  EXPECT_TRUE(has(p[0], "line 26"));
  EXPECT_TRUE(has(p[1], "DAZI must divide 360")) << p[1].reason;
  EXPECT_TRUE(has(p[2], "PCV value 3 of 3")) << p[2].reason;
  EXPECT_EQ(p[2].line, 56u);
  EXPECT_TRUE(has(p[3], "# OF FREQUENCIES says 3 but 1")) << p[3].reason;
  EXPECT_TRUE(has(p[4], "START OF ANTENNA before END OF ANTENNA")) << p[4].reason;
  EXPECT_EQ(p[4].line, 95u);
  EXPECT_TRUE(has(p[5], "malformed PCO")) << p[5].reason;
  EXPECT_EQ(p[5].line, 114u);
}

TEST(AntexReader, MalformedHeadersThrowParseError) {
  const auto expectError = [](const char* fixture, std::size_t line, const char* reason) {
    try {
      readAntexFile(test::fixturePath(std::string("malformed/antex/") + fixture));
      ADD_FAILURE() << fixture << ": no ParseError";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.line(), line) << fixture;
      EXPECT_NE(e.reason().find(reason), std::string::npos) << fixture << ": " << e.reason();
      EXPECT_NE(e.file().find(fixture), std::string::npos);
    }
  };
  expectError("bad_version_antex.txt", 1, "unsupported ANTEX version '2.0'");
  expectError("bad_pcv_type_antex.txt", 2, "PCV type must be A or R");
  expectError("no_end_of_header_antex.txt", 3, "file ends before END OF HEADER");
  auto empty = memoryLineSource("", "empty");
  EXPECT_THROW(readAntex(*empty), ParseError);
  auto junk = memoryLineSource("hello\nworld\n", "junk");
  EXPECT_THROW(readAntex(*junk), ParseError);
}

TEST(AntexReader, TruncatedBlockIsReported) {
  const AntexFile f = readAntexFile(test::fixturePath("malformed/antex/truncated_block_antex.txt"));
  EXPECT_EQ(f.antennas.size(), 1u);
  ASSERT_EQ(f.report.problemCount(), 1u);
  EXPECT_NE(f.report.problems()[0].reason.find("file ends inside antenna block"), std::string::npos);
}

TEST(AntexReader, GzipAndPlainGiveTheSameResult) {
  const std::string plain = test::fixturePath("malformed/antex/bad_blocks_antex.txt");
  const std::string gz = (test::tempDir("antex_gz") / "bad_blocks.gz").string();
  gzFile out = gzopen(gz.c_str(), "wb");
  ASSERT_NE(out, nullptr);
  const std::string bytes = test::readFileBytes(plain);
  gzwrite(out, bytes.data(), static_cast<unsigned>(bytes.size()));
  gzclose(out);
  const AntexFile a = readAntexFile(plain);
  const AntexFile b = readAntexFile(gz);
  ASSERT_EQ(a.antennas.size(), b.antennas.size());
  for (std::size_t i = 0; i < a.antennas.size(); ++i) {
    EXPECT_EQ(a.antennas[i].type, b.antennas[i].type);
    EXPECT_EQ(a.antennas[i].frequencies.size(), b.antennas[i].frequencies.size());
    EXPECT_EQ(a.antennas[i].frequencies[0].pco_m, b.antennas[i].frequencies[0].pco_m);
  }
  EXPECT_EQ(a.report.problemCount(), b.report.problemCount());
}

TEST(AntexSummary, SummarizesZim2File) {
  PPP_REQUIRE_SHARED_DATA();
  const FileSummary s = summarizeAntexFile(test::dataPath("antex/igs20_zim2_gps_trim.atx"));
  EXPECT_EQ(s.type, "ANTEX");
  EXPECT_EQ(s.version, "1.4");
  EXPECT_EQ(s.epoch_count, 16u);
  EXPECT_EQ(s.satellites.at(GnssSystem::GPS).size(), 14u);
  EXPECT_TRUE(s.signals.at(GnssSystem::GPS).count("G05"));
  EXPECT_TRUE(s.signals.at(GnssSystem::Galileo).count("E05"));  // receiver antenna, line 1459
  bool found = false;
  for (const auto& fact : s.facts) found = found || fact.find("TRM59800.00 NONE") != std::string::npos;
  EXPECT_TRUE(found);
  EXPECT_TRUE(s.report.clean());
}

// A line far beyond any ANTEX record (here 20 MB inside the receiver
// antenna's block, as a broken download or a binary file gives) is cut by the line
// reader; what it held is lost, so the file's report must say so, not "clean".
TEST(AntexReader, AnOverlongLineIsAProblemNotSilence) {
  PPP_REQUIRE_SHARED_DATA();
  std::string text = ppp::test::readFileBytes(ppp::test::dataPath("antex/igs20_zim2_gps_trim.atx"));
  const std::size_t block = text.find("TRM59800.00     NONE                                        TYPE / SERIAL NO");
  ASSERT_NE(block, std::string::npos);
  const std::size_t after = text.find('\n', block) + 1;
  text.insert(after, std::string(20'000'000, 'X') + "\n");
  auto source = memoryLineSource(std::move(text), "broken.atx");
  const AntexFile file = readAntex(*source);
  ASSERT_FALSE(file.report.clean());
  std::string problems;
  for (const auto& p : file.report.problems()) problems += p.reason + "\n";
  EXPECT_NE(problems.find("1 line(s) longer than 64 KiB cut"), std::string::npos) << problems;
  EXPECT_NE(problems.find("antenna block starting at line 825 skipped"), std::string::npos) << problems;
}
