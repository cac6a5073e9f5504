// RINEX navigation reader: header fields, GPS/QZSS/Galileo/GLONASS records in
// RINEX 2.10/2.11, 3.04 and 4.00 layouts, skipped record types, malformed input.
//
// Fixture provenance (test/fixtures/rinex_nav/):
//  - mixed_v304.nav: header lines from the example navigation file of the RINEX
//    3.05 specification (IONOSPHERIC CORR GPSA/GPSB, TIME SYSTEM CORR, LEAP
//    SECONDS 14; the GAL line is ours). Records are real broadcast records
//    published in open-source test suites: G01/E01(F/NAV)/R01 of 2020-06-24/25
//    (IGS BRDC), G01/E04(I/NAV) of 2025-06-15 (ESA ESOC00DEU_R_20251660000_01D_MN),
//    G18 of 2021-05-26 (Trimble NetR9 RINEX 3.02 output, ".nnnD" style numbers),
//    J01 of 2014-05-13 (QZSS, GR25 receiver), S22 of 2003-10-18 (RINEX 3.04
//    SBAS example). Values asserted below are as written in those lines.
//  - mixed_v400.nav: the 2025 records wrapped in RINEX 4.00 "> EPH" headers, plus
//    STO / ION / EOP records and a G01 CNAV record written by us in the RINEX 4.00
//    layout (skipped by the reader).
//  - gps_v210.nav: the RINEX 2.10 GPS navigation example of the RINEX 2.10 spec.
//  - glonass_v211.nav: the RINEX 2.11 GLONASS navigation example of the RINEX 2.11 spec.
#include <gtest/gtest.h>

#include <cmath>

#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/models/broadcast_products.h"
#include "fuzz/rinex_nav_fuzz_entry.h"
#include "test_support.h"

using namespace ppp;
using ppp::test::fixturePath;
using ppp::test::readFileBytes;

namespace {

NavData readFixture(const std::string& name) { return readRinexNav(fixturePath(name)); }

using ppp::test::gpst;

const GpsLnavEphemeris* findGps(const NavData& nav, const std::string& sat, int year) {
  for (const auto& e : nav.gps) {
    if (e.satellite.toString() == sat && e.clock.toc.toCalendar().year == year) return &e;
  }
  return nullptr;
}

std::string gzipOf(const std::string& path) {
  // Compressed with the system gzip: LineSource detects gzip by content.
  const auto dir = ppp::test::tempDir("nav_gz");
  const std::string out = (dir / "nav.gz").string();
  const std::string cmd = "gzip -n -c '" + path + "' > '" + out + "'";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
  return readFileBytes(out);
}

}  // namespace

TEST(RinexNavReader, ReadsHeaderOfVersion3) {
  const NavData nav = readFixture("rinex_nav/mixed_v304.nav");
  const RinexNavHeader& h = nav.header;
  EXPECT_EQ(h.version_text, "3.04");
  EXPECT_DOUBLE_EQ(h.version, 3.04);
  EXPECT_EQ(h.system, 'M');
  ASSERT_EQ(h.ionospheric_corrections.count("GPSA"), 1u);
  ASSERT_EQ(h.ionospheric_corrections.at("GPSA").size(), 4u);
  EXPECT_DOUBLE_EQ(h.ionospheric_corrections.at("GPSA")[0], 0.1025e-07);
  EXPECT_DOUBLE_EQ(h.ionospheric_corrections.at("GPSB")[3], -0.6554e+05);
  // The GAL line has three coefficients (ai0..ai2) and a blank fourth field.
  ASSERT_EQ(h.ionospheric_corrections.at("GAL").size(), 3u);
  EXPECT_DOUBLE_EQ(h.ionospheric_corrections.at("GAL")[1], 0.5039);  // "0.5039D+00"
  ASSERT_EQ(h.time_system_corrections.size(), 2u);
  const TimeSystemCorrection& gput = h.time_system_corrections[0];
  EXPECT_EQ(gput.type, "GPUT");
  EXPECT_DOUBLE_EQ(gput.a0_s, 0.2793967723e-08);
  EXPECT_EQ(gput.reference_sow, 147456);
  EXPECT_EQ(gput.reference_week, 1395);
  EXPECT_EQ(gput.source, "G10");
  EXPECT_EQ(gput.utc_id, 2);
  EXPECT_EQ(h.time_system_corrections[1].type, "GLUT");
  EXPECT_EQ(h.leap_seconds, 14);
}

TEST(RinexNavReader, DecodesGpsLnavRecordFields) {
  const NavData nav = readFixture("rinex_nav/mixed_v304.nav");
  const GpsLnavEphemeris* g = findGps(nav, "G01", 2020);
  ASSERT_NE(g, nullptr);
  // "G01 2020 06 25 04 00 00 1.604342833161e-05 7.048583938740e-12 0.000000000000e+00"
  EXPECT_EQ(g->clock.toc, gpst(2020, 6, 25, 4, 0, 0));
  EXPECT_DOUBLE_EQ(g->clock.af0_s, 1.604342833161e-05);
  EXPECT_DOUBLE_EQ(g->clock.af1_sps, 7.048583938740e-12);
  EXPECT_EQ(g->iode, 58);
  EXPECT_DOUBLE_EQ(g->orbit.crs_m, -3.968750000000e+01);
  EXPECT_DOUBLE_EQ(g->orbit.m0_rad, 6.342094507864e-01);
  EXPECT_DOUBLE_EQ(g->orbit.eccentricity, 1.000394229777e-02);
  EXPECT_DOUBLE_EQ(g->orbit.sqrt_a_sqrtm, 5.153707128525e+03);
  EXPECT_DOUBLE_EQ(g->orbit.toe_sow, 3.6e5);
  EXPECT_EQ(g->orbit.toe, GnssTime::fromGpsWeek(2111, 360000.0));
  EXPECT_DOUBLE_EQ(g->orbit.omega_dot_radps, -8.384634967987e-09);
  EXPECT_DOUBLE_EQ(g->orbit.idot_radps, -5.714523747137e-11);
  EXPECT_EQ(g->codes_on_l2, 1);
  EXPECT_EQ(g->week, 2111);
  EXPECT_DOUBLE_EQ(g->ura_m, 2.0);
  EXPECT_EQ(g->health, 0);
  EXPECT_DOUBLE_EQ(g->tgd_s, 5.122274160385e-09);
  EXPECT_EQ(g->iodc, 58);
  EXPECT_EQ(g->transmission_sow, 356106.0);
  EXPECT_DOUBLE_EQ(g->fit_interval_h, 4.0);

  // The NetR9 record writes numbers as " .349333044142D-03".
  const GpsLnavEphemeris* g18 = findGps(nav, "G18", 2021);
  ASSERT_NE(g18, nullptr);
  EXPECT_DOUBLE_EQ(g18->clock.af0_s, 0.349333044142e-03);
  EXPECT_DOUBLE_EQ(g18->orbit.m0_rad, -0.186204225475e+01);
  EXPECT_EQ(g18->iodc, 921);
  EXPECT_DOUBLE_EQ(g18->tgd_s, -0.838190317154e-08);
}

TEST(RinexNavReader, DecodesQzssAsLnavWithItsFitFlag) {
  const NavData nav = readFixture("rinex_nav/mixed_v304.nav");
  const GpsLnavEphemeris* j = findGps(nav, "J01", 2014);
  ASSERT_NE(j, nullptr);
  EXPECT_EQ(j->satellite.system, GnssSystem::QZSS);
  EXPECT_EQ(j->clock.toc, gpst(2014, 5, 13, 8, 15, 12));
  EXPECT_DOUBLE_EQ(j->orbit.eccentricity, 7.542252133135e-02);  // QZO: e ~ 0.075
  EXPECT_EQ(j->health, 1);
  EXPECT_DOUBLE_EQ(j->fit_interval_h, 2.0);  // fit flag 0 -> 2 h (IS-QZSS-PNT)
}

TEST(RinexNavReader, KeepsGalileoInavAndFnavApart) {
  const NavData nav = readFixture("rinex_nav/mixed_v304.nav");
  ASSERT_EQ(nav.galileo.size(), 2u);
  const GalileoEphemeris& fnav = nav.galileo[0];
  EXPECT_EQ(fnav.satellite.toString(), "E01");
  EXPECT_EQ(fnav.data_sources, 258);  // bits 1 (F/NAV E5a-I) and 8
  EXPECT_EQ(fnav.type, GalileoNavType::FNav);
  EXPECT_EQ(fnav.iod_nav, 61);
  EXPECT_DOUBLE_EQ(fnav.bgd_e5a_e1_s, -1.862645149231e-09);
  EXPECT_EQ(fnav.sisa_m, 3.12);
  // The orbit-5 line "    -6.996720012901e-10 2.580000000000e+02 2.111000000000e+03"
  // is short (no spare field): still decoded.
  EXPECT_DOUBLE_EQ(fnav.orbit.idot_radps, -6.996720012901e-10);
  EXPECT_EQ(fnav.week, 2111);

  const GalileoEphemeris& inav = nav.galileo[1];
  EXPECT_EQ(inav.satellite.toString(), "E04");
  EXPECT_EQ(inav.data_sources, 517);  // bits 0, 2 (I/NAV E1-B, E5b-I) and 9
  EXPECT_EQ(inav.type, GalileoNavType::INav);
  ASSERT_TRUE(inav.bgd_e5b_e1_s);
  EXPECT_DOUBLE_EQ(*inav.bgd_e5b_e1_s, -4.656612873077E-09);
  // toc 2025-06-14 23:20 (Saturday, week 2370) with toe 602400 s of week 2370.
  EXPECT_EQ(inav.orbit.toe, GnssTime::fromGpsWeek(2370, 602400.0));
}

TEST(RinexNavReader, DecodesGlonassAndFillsChannels) {
  const NavData nav = readFixture("rinex_nav/mixed_v304.nav");
  ASSERT_EQ(nav.glonass.size(), 1u);
  const GlonassEphemeris& r = nav.glonass[0];
  EXPECT_EQ(r.satellite.toString(), "R01");
  // toc "2020 06 24 23 15 00" is UTC: GPST = UTC + 18 s in 2020.
  EXPECT_EQ(r.tb, gpst(2020, 6, 24, 23, 15, 18));
  EXPECT_DOUBLE_EQ(r.minus_tau_n_s, 6.355904042721e-05);
  EXPECT_DOUBLE_EQ(r.position_m.x(), 1.090894238281e+04 * 1e3);
  EXPECT_DOUBLE_EQ(r.velocity_mps.y(), 2.795855522156e+00 * 1e3);
  EXPECT_DOUBLE_EQ(r.acceleration_mps2.z(), -2.793967723846e-09 * 1e3);
  EXPECT_EQ(r.frequency_channel, 1);
  EXPECT_EQ(r.health, 0);
  // The "GLONASS FDMA channels from navigation data".
  EXPECT_EQ(nav.glonass_channels.channel(1), 1);
  EXPECT_EQ(nav.glonass_channels.size(), 1);
}

// The broadcast products hand the records' channels on (the product assembly gives
// them to the GLONASS signal selection where the observation header has none).
TEST(RinexNavReader, BroadcastProductsCarryTheGlonassChannels) {
  const BroadcastProducts products = loadBroadcastProducts({fixturePath("rinex_nav/mixed_v304.nav")}, std::nullopt);
  EXPECT_EQ(products.glonass_channels.channel(1), 1);
  EXPECT_EQ(products.glonass_channels.size(), 1);
}

TEST(RinexNavReader, CountsSkippedSystemsAndSpansToc) {
  const NavData nav = readFixture("rinex_nav/mixed_v304.nav");
  EXPECT_TRUE(nav.report.clean()) << nav.report.summary();
  EXPECT_EQ(nav.gps.size(), 4u);  // G01 2020, G01 2025, G18 2021, J01 2014
  EXPECT_EQ(nav.report.counters().at("SBAS records skipped (not modelled)"), 1u);
  EXPECT_EQ(nav.recordCount(), 7u);
  EXPECT_EQ(nav.satellites.size(), 7u);  // G01 G18 R01 E01 E04 J01 S22
  EXPECT_EQ(nav.first_toc, gpst(2014, 5, 13, 8, 15, 12));
  EXPECT_EQ(nav.last_toc, gpst(2025, 6, 15, 2, 0, 0));
}

TEST(RinexNavReader, ReadsRinex4RecordsAndSkipsOthers) {
  const NavData nav = readFixture("rinex_nav/mixed_v400.nav");
  EXPECT_TRUE(nav.report.clean()) << nav.report.summary();
  EXPECT_EQ(nav.header.version_text, "4.00");
  EXPECT_EQ(nav.header.leap_seconds, 18);
  ASSERT_EQ(nav.gps.size(), 1u);
  EXPECT_EQ(nav.gps[0].iode, 50);
  EXPECT_DOUBLE_EQ(nav.gps[0].orbit.toe_sow, 7200.0);
  ASSERT_EQ(nav.galileo.size(), 1u);
  EXPECT_EQ(nav.galileo[0].type, GalileoNavType::INav);  // from "> EPH E04 INAV"
  // The R01 record carries the RINEX 4 fifth line (status flags...): ignored.
  ASSERT_EQ(nav.glonass.size(), 1u);
  EXPECT_EQ(nav.glonass[0].frequency_channel, 1);
  const auto& c = nav.report.counters();
  EXPECT_EQ(c.at("RINEX 4 STO records skipped"), 1u);
  EXPECT_EQ(c.at("RINEX 4 ION records skipped"), 1u);
  EXPECT_EQ(c.at("RINEX 4 EOP records skipped"), 1u);
  EXPECT_EQ(c.at("GPS CNAV records skipped (not modelled)"), 1u);
}

TEST(RinexNavReader, ReadsRinex2GpsExample) {
  const NavData nav = readFixture("rinex_nav/gps_v210.nav");
  EXPECT_TRUE(nav.report.clean()) << nav.report.summary();
  EXPECT_EQ(nav.header.version_text, "2.10");
  EXPECT_DOUBLE_EQ(nav.header.ionospheric_corrections.at("GPSA")[0], 0.1676e-07);
  EXPECT_DOUBLE_EQ(nav.header.ionospheric_corrections.at("GPSB")[3], -0.1966e+06);
  ASSERT_EQ(nav.header.time_system_corrections.size(), 1u);
  EXPECT_DOUBLE_EQ(nav.header.time_system_corrections[0].a0_s, 0.133179128170e-06);
  EXPECT_EQ(nav.header.time_system_corrections[0].reference_week, 1025);
  EXPECT_EQ(nav.header.leap_seconds, 13);
  ASSERT_EQ(nav.gps.size(), 1u);
  const GpsLnavEphemeris& g = nav.gps[0];
  // " 6 99  9  2 17 51 44.0 -.839701388031D-03 ..."
  EXPECT_EQ(g.satellite.toString(), "G06");
  EXPECT_EQ(g.clock.toc, gpst(1999, 9, 2, 17, 51, 44.0));
  EXPECT_DOUBLE_EQ(g.clock.af0_s, -0.839701388031e-03);
  EXPECT_EQ(g.iode, 91);
  EXPECT_DOUBLE_EQ(g.orbit.sqrt_a_sqrtm, 0.515365489006e+04);
  EXPECT_DOUBLE_EQ(g.orbit.toe_sow, 0.409904e+06);
  EXPECT_EQ(g.week, 1025);
  EXPECT_EQ(g.iodc, 91);
  EXPECT_EQ(g.transmission_sow, 406800.0);
}

TEST(RinexNavReader, ReadsRinex2GlonassExample) {
  const NavData nav = readFixture("rinex_nav/glonass_v211.nav");
  EXPECT_TRUE(nav.report.clean()) << nav.report.summary();
  ASSERT_EQ(nav.glonass.size(), 1u);
  const GlonassEphemeris& r = nav.glonass[0];
  EXPECT_EQ(r.satellite.toString(), "R03");
  // " 3 98  2 15  0 15  0.0": UTC; GPST - UTC = 12 s in February 1998.
  EXPECT_EQ(r.tb, gpst(1998, 2, 15, 0, 15, 12.0));
  EXPECT_DOUBLE_EQ(r.position_m.z(), 0.212257280273e+05 * 1e3);
  // Frequency number 21 (".210000000000D+02"): a pre-2005 channel, kept on the
  // record but outside the -7..+6 range of GlonassChannels.
  EXPECT_EQ(r.frequency_channel, 21);
  EXPECT_EQ(nav.glonass_channels.size(), 0);
  EXPECT_EQ(nav.report.counters().at(
                "GLONASS channels not recorded (slot above 30 or channel outside -7..+6)"),
            1u);
}

TEST(RinexNavReader, GzipAndPlainGiveTheSameRecords) {
  const std::string path = fixturePath("rinex_nav/mixed_v304.nav");
  auto source = memoryLineSource(gzipOf(path), "mixed.nav.gz");
  const NavData gz = readRinexNav(*source);
  const NavData plain = readRinexNav(path);
  ASSERT_EQ(gz.recordCount(), plain.recordCount());
  EXPECT_EQ(gz.gps[0].orbit.m0_rad, plain.gps[0].orbit.m0_rad);
}

TEST(RinexNavReader, SummaryListsSpanSatellitesAndFacts) {
  const FileSummary s = summarizeNavFile(fixturePath("rinex_nav/mixed_v304.nav"));
  EXPECT_EQ(s.type, "RINEX navigation");
  EXPECT_EQ(s.version, "3.04");
  EXPECT_EQ(s.epoch_count, 7u);
  EXPECT_EQ(s.first_epoch, gpst(2014, 5, 13, 8, 15, 12));
  EXPECT_EQ(s.satellites.at(GnssSystem::Galileo).size(), 2u);
  EXPECT_EQ(s.satellites.at(GnssSystem::SBAS).size(), 1u);
  auto has = [&](const std::string& fact) {
    for (const auto& f : s.facts) {
      if (f == fact) return true;
    }
    return false;
  };
  EXPECT_TRUE(has("ionospheric corrections: GAL GPSA GPSB"));
  EXPECT_TRUE(has("leap seconds 14"));
  EXPECT_TRUE(has("records: GPS LNAV 3, QZSS LNAV 1, Galileo I/NAV 1, Galileo F/NAV 1, GLONASS 1, BeiDou 0"));
}

// ---------------------------------------------------------------------------
// Malformed input (test/fixtures/malformed/rinex_nav/)
// ---------------------------------------------------------------------------

namespace {
ParseError expectParseError(const std::string& name) {
  try {
    readRinexNav(fixturePath("malformed/rinex_nav/" + name));
  } catch (const ParseError& e) {
    return e;
  }
  ADD_FAILURE() << name << ": no ParseError";
  return ParseError("", 0, "");
}
}  // namespace

TEST(RinexNavReaderMalformed, HeaderErrorsNameFileLineAndReason) {
  ParseError e = expectParseError("not_rinex.nav");
  EXPECT_EQ(e.line(), 1u);
  EXPECT_NE(e.file().find("not_rinex.nav"), std::string::npos);
  EXPECT_EQ(e.reason(), "first line is not RINEX VERSION / TYPE");

  e = expectParseError("observation_file.nav");
  EXPECT_EQ(e.line(), 1u);
  EXPECT_EQ(e.reason(), "not a navigation file (type 'O')");

  e = expectParseError("missing_end_of_header.nav");
  EXPECT_EQ(e.reason(), "end of data before END OF HEADER");

  e = expectParseError("bad_iono_corr.nav");
  EXPECT_EQ(e.line(), 4u);  // the GPSA line
  EXPECT_EQ(e.reason(), "malformed GPSA coefficient");

  e = expectParseError("bad_leap_seconds.nav");
  EXPECT_EQ(e.line(), 9u);
  EXPECT_EQ(e.reason(), "malformed LEAP SECONDS");
}

TEST(RinexNavReaderMalformed, EmptyInputIsAHeaderError) {
  auto source = memoryLineSource("", "empty.nav");
  EXPECT_THROW(readRinexNav(*source), ParseError);
}

TEST(RinexNavReaderMalformed, BadRecordsAreSkippedAndReported) {
  const NavData nav = readRinexNav(fixturePath("malformed/rinex_nav/bad_records.nav"));
  // Only the intact G18 record survives.
  ASSERT_EQ(nav.gps.size(), 1u);
  EXPECT_EQ(nav.gps[0].satellite.toString(), "G18");
  EXPECT_TRUE(nav.galileo.empty());
  EXPECT_TRUE(nav.glonass.empty());
  EXPECT_EQ(nav.glonass_channels.size(), 0);
  const auto& p = nav.report.problems();
  ASSERT_EQ(nav.report.problemCount(), 8u) << nav.report.summary();
  // Line numbers as in the fixture file.
  EXPECT_EQ(p[0].line, 11u);
  EXPECT_EQ(p[0].reason, "continuation line(s) without a record header skipped");
  EXPECT_EQ(p[1].line, 15u);
  EXPECT_EQ(p[1].reason, "malformed number in record field 9");  // "1.000394229777e-0x"
  EXPECT_EQ(p[2].line, 21u);
  EXPECT_EQ(p[2].reason, "missing i0 (record truncated or field blank)");
  EXPECT_EQ(p[3].line, 25u);
  EXPECT_EQ(p[3].reason, "eccentricity outside [0, 1)");
  EXPECT_EQ(p[4].line, 35u);
  EXPECT_EQ(p[4].reason, "frequency number out of range or not an integer");
  EXPECT_EQ(p[5].line, 42u);
  EXPECT_EQ(p[5].reason, "Galileo data sources 0 name neither or both of I/NAV and F/NAV");
  EXPECT_EQ(p[6].line, 53u);
  EXPECT_EQ(p[6].reason, "epoch out of range");
  EXPECT_EQ(p[7].line, 61u);
  EXPECT_EQ(p[7].reason, "malformed satellite 'X01'");
}

TEST(RinexNavReaderMalformed, TruncatedGzipIsReportedNotThrown) {
  const std::string gz = gzipOf(fixturePath("rinex_nav/mixed_v304.nav"));
  auto source = memoryLineSource(gz.substr(0, gz.size() * 3 / 4), "cut.nav.gz");
  const NavData nav = readRinexNav(*source);
  EXPECT_GE(nav.report.problemCount(), 1u);
  EXPECT_LT(nav.recordCount(), 7u);
}

TEST(RinexNavReader, AcceptsTheFifthGlonassLineOfRinex305) {
  // RINEX 3.05 table A10 adds "BROADCAST ORBIT - 4" (status flags, L1/L2 group
  // delay difference, URAI, health flags) to GLONASS records.
  std::string text = readFileBytes(fixturePath("rinex_nav/mixed_v304.nav"));
  text.replace(text.find("3.04"), 4, "3.05");
  const std::string last = "     2.288353955078e+04-3.169984817505e-01-2.793967723846e-09 0.000000000000e+00\n";
  text.insert(text.find(last) + last.size(),
              "     1.790000000000e+02 0.000000000000e+00 0.000000000000e+00 0.000000000000e+00\n");
  auto source = memoryLineSource(text, "v305.nav");
  const NavData nav = readRinexNav(*source);
  EXPECT_TRUE(nav.report.clean()) << nav.report.summary();
  EXPECT_EQ(nav.recordCount(), 7u);
  ASSERT_EQ(nav.glonass.size(), 1u);
  EXPECT_DOUBLE_EQ(nav.glonass[0].age_days, 0.0);
}

TEST(RinexNavReader, FuzzCorpusReplaysWithoutCrashing) {
  // The seed corpus of test/fuzz/corpus/rinex_nav, plus cut-down variants of
  // each file, through the fuzz entry (which catches only ParseError / FileOpenError).
  std::size_t files = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(PPP_FUZZ_DIR) + "/corpus/rinex_nav")) {
    const std::string bytes = readFileBytes(entry.path().string());
    for (std::size_t cut : {bytes.size(), bytes.size() / 2, bytes.size() / 3, std::size_t{81}}) {
      const std::string part = bytes.substr(0, cut);
      ppp::fuzz::fuzzRinexNav(reinterpret_cast<const std::uint8_t*>(part.data()), part.size());
    }
    ++files;
  }
  EXPECT_GE(files, 5u);
}

// BeiDou records (RINEX 3.05 table A14; RINEX 4 "> EPH C.. D1/D2"). Values from
// ESBC00DNK_R_20201770000_01D_MN.rnx (esbc-2020-177), copied into the text.
namespace {
const char* kBeidouHeader =
    "     3.05           NAVIGATION DATA     MIXED               RINEX VERSION / TYPE\n"
    "                                                            END OF HEADER\n";
const char* kC05 =
    "C05 2020 06 25 00 00 00-5.159442080185e-04-6.710987321412e-11 0.000000000000e+00\n"
    "     1.000000000000e+00-5.662656250000e+02-1.811504027843e-09-5.810297336492e-01\n"
    "    -1.882389187813e-05 3.793594660237e-04 5.378387868404e-07 6.493369304657e+03\n"
    "     3.456000000000e+05-3.911554813385e-08 3.102197701912e+00 6.286427378654e-08\n"
    "     1.114144101831e-01-1.862500000000e+01-1.428005199908e+00 2.799759478363e-09\n"
    "     4.578762152394e-10 0.000000000000e+00 7.550000000000e+02\n"
    "     2.000000000000e+00 0.000000000000e+00 1.000000000000e-10-9.300000000000e-09\n"
    "     3.456276000000e+05 0.000000000000e+00\n";
}  // namespace

TEST(RinexNavReader, DecodesBeidouRecordsInBdt) {
  auto source = memoryLineSource(std::string(kBeidouHeader) + kC05, "bds.nav");
  const NavData nav = readRinexNav(*source);
  EXPECT_TRUE(nav.report.clean()) << nav.report.summary();
  ASSERT_EQ(nav.beidou.size(), 1u);
  const BeidouEphemeris& e = nav.beidou[0];
  EXPECT_EQ(e.satellite.toString(), "C05");
  EXPECT_TRUE(e.isGeo());
  // toc 2020-06-25 00:00:00 BDT = 00:00:14 GPST; toe 345600 s of BDT week 755 is the same instant.
  EXPECT_EQ(e.clock.toc, gpst(2020, 6, 25, 0, 0, 14));
  EXPECT_EQ(e.orbit.toe, e.clock.toc);
  EXPECT_EQ(e.bdt_week, 755);
  EXPECT_EQ(e.aode, 1);
  EXPECT_DOUBLE_EQ(e.ura_m, 2.0);
  EXPECT_DOUBLE_EQ(e.tgd1_s, 1.0e-10);
  EXPECT_DOUBLE_EQ(e.tgd2_s, -9.3e-09);
  ASSERT_TRUE(e.transmission_sow);
  EXPECT_DOUBLE_EQ(*e.transmission_sow, 345627.6);
  EXPECT_EQ(e.aodc, 0);
  EXPECT_EQ(nav.recordCount(), 1u);
}

TEST(RinexNavReaderMalformed, TruncatedBeidouRecordIsReportedAndTheNextKept) {
  // The first C05 record loses its last two lines (BROADCAST ORBIT - 6 and - 7).
  std::string cut(kC05);
  cut = cut.substr(0, cut.find("     2.000000000000e+00"));
  auto source = memoryLineSource(std::string(kBeidouHeader) + cut + kC05, "bds_cut.nav");
  const NavData nav = readRinexNav(*source);
  EXPECT_EQ(nav.beidou.size(), 1u);
  ASSERT_EQ(nav.report.problemCount(), 1u);
  EXPECT_EQ(nav.report.problems()[0].line, 3u);
  EXPECT_NE(nav.report.problems()[0].reason.find("SV accuracy"), std::string::npos) << nav.report.problems()[0].reason;
}

TEST(RinexNavReader, ReadsRinex4BeidouD2Records) {
  std::string body(kC05);
  const std::string text = "     4.00           NAVIGATION DATA     MIXED               RINEX VERSION / TYPE\n"
                           "                                                            END OF HEADER\n"
                           "> EPH C05 D2\n" + body +
                           "> EPH C05 CNV1\n" + body;
  auto source = memoryLineSource(text, "bds_v4.nav");
  const NavData nav = readRinexNav(*source);
  ASSERT_EQ(nav.beidou.size(), 1u);
  EXPECT_EQ(nav.report.counters().at("BeiDou CNV1 records skipped (not modelled)"), 1u);
}
