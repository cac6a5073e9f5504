// Tests of the RINEX observation reader on the real ZIM2 / CCJ2 files
// (../shared/data, values as written in the files at the cited lines) and on
// synthetic fixtures under test/fixtures/rinex_obs and test/fixtures/malformed/rinex_obs.
#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <string>

#include "ppp_bayes_tree/app/inspection.h"
#include "ppp_bayes_tree/io/rinex/hatanaka_decoder.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "test_support.h"

namespace ppp {
namespace {

const std::string kZim2 = "zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx";
const std::string kCcj2 = "ccj2-2021-210/ccj22100.21o";

ObservationCode code(const char* text) { return *ObservationCode::parse(text); }
SatelliteId sat(const char* text) { return *SatelliteId::parse(text); }

std::string codes(const std::vector<ObservationCode>& list) {
  std::string s;
  for (const auto& c : list) s += (s.empty() ? "" : " ") + c.toString();
  return s;
}

using ppp::test::gpst;

std::vector<ObsEpoch> readAll(RinexObsReader& reader) {
  std::vector<ObsEpoch> epochs;
  ObsEpoch e;
  while (reader.next(e)) epochs.push_back(e);
  return epochs;
}

RinexObsReader openMemory(const std::string& text, const std::string& name = "<memory>") {
  return RinexObsReader(observationSource(memoryLineSource(text, name)));
}

bool hasProblemAt(const ParseReport& r, std::size_t line, const std::string& fragment) {
  for (const auto& p : r.problems()) {
    if (p.line == line && p.reason.find(fragment) != std::string::npos) return true;
  }
  return false;
}

// ---------------------------------------------------------------- ZIM2 (RINEX 3.04)

TEST(RinexObsZim2, Header) {
  PPP_REQUIRE_SHARED_DATA();
  RinexObsReader reader = RinexObsReader::open(test::dataPath(kZim2));
  const RinexObsHeader& h = reader.header();
  EXPECT_EQ(h.version_text, "3.04");  // line 1
  EXPECT_EQ(h.major_version, 3);
  EXPECT_EQ(h.file_system, 'M');
  EXPECT_EQ(h.marker_name, "ZIM2");          // line 7
  EXPECT_EQ(h.marker_number, "14001M008");   // line 8
  EXPECT_EQ(h.receiver_number, "1873177");   // line 11
  EXPECT_EQ(h.receiver_type, "LEICA GR50");
  EXPECT_EQ(h.receiver_version, "4.90/7.905");
  EXPECT_EQ(h.antenna_number, "60369");      // line 12
  EXPECT_EQ(h.antenna_type, "TRM59800.00");
  EXPECT_EQ(h.antenna_radome, "NONE");
  EXPECT_EQ(h.antexAntennaName(), "TRM59800.00     NONE");
  ASSERT_TRUE(h.approx_position_ecef_m);     // line 13
  EXPECT_DOUBLE_EQ(h.approx_position_ecef_m->x(), 4331300.1600);
  EXPECT_DOUBLE_EQ(h.approx_position_ecef_m->y(), 567537.0810);
  EXPECT_DOUBLE_EQ(h.approx_position_ecef_m->z(), 4633133.5100);
  ASSERT_TRUE(h.antenna_delta_hen_m);        // line 14: 0 0 0
  EXPECT_EQ(*h.antenna_delta_hen_m, Eigen::Vector3d::Zero());
  // Lines 15-23, exactly as in the header.
  EXPECT_EQ(codes(h.types(GnssSystem::GPS)),
            "C1C L1C D1C S1C C1L L1L D1L S1L C2S L2S D2S S2S C2W L2W D2W S2W C5Q L5Q D5Q S5Q");
  EXPECT_EQ(codes(h.types(GnssSystem::GLONASS)), "C1C L1C D1C S1C C2P L2P D2P S2P C2C L2C D2C S2C C3Q L3Q D3Q S3Q");
  EXPECT_EQ(codes(h.types(GnssSystem::Galileo)),
            "C1C L1C D1C S1C C5Q L5Q D5Q S5Q C6B L6B D6B S6B C7Q L7Q D7Q S7Q C8Q L8Q D8Q S8Q");
  EXPECT_EQ(codes(h.types(GnssSystem::BeiDou)),
            "C1P L1P D1P S1P C2I L2I D2I S2I C5P L5P D5P S5P C6I L6I D6I S6I C7D L7D D7D S7D C7I L7I D7I S7I");
  EXPECT_EQ(codes(h.types(GnssSystem::SBAS)), "C1C L1C D1C S1C C5I L5I D5I S5I");
  EXPECT_TRUE(h.types(GnssSystem::QZSS).empty());
  ASSERT_TRUE(h.interval_s);
  EXPECT_DOUBLE_EQ(*h.interval_s, 30.0);  // line 25
  ASSERT_TRUE(h.time_of_first_obs && h.time_of_last_obs);
  EXPECT_EQ(h.time_of_first_obs->time, gpst(2026, 5, 13, 0, 0, 0));     // line 26
  EXPECT_EQ(h.time_of_last_obs->time, gpst(2026, 5, 13, 23, 59, 30));   // line 27 (the day file's)
  EXPECT_EQ(h.epoch_time_system, TimeSystem::GPS);
  ASSERT_TRUE(h.leap_seconds);
  EXPECT_EQ(*h.leap_seconds, 18);  // line 55
  // SYS / PHASE SHIFT, lines 29-50: 22 records; line 30 "G L1L  0.25000", line 29 "G L1C" blank.
  ASSERT_EQ(h.phase_shifts.size(), 22u);
  EXPECT_EQ(h.phase_shifts[0].code, code("L1C"));
  EXPECT_FALSE(h.phase_shifts[0].shift_cycles);
  EXPECT_EQ(h.phase_shifts[1].code, code("L1L"));
  ASSERT_TRUE(h.phase_shifts[1].shift_cycles);
  EXPECT_DOUBLE_EQ(*h.phase_shifts[1].shift_cycles, 0.25);
  EXPECT_EQ(h.phase_shifts[2].code, code("L2S"));
  EXPECT_DOUBLE_EQ(*h.phase_shifts[2].shift_cycles, -0.25);
  EXPECT_EQ(h.phase_shifts[9].system, GnssSystem::Galileo);  // line 38 "E L1C  0.50000"
  EXPECT_DOUBLE_EQ(*h.phase_shifts[9].shift_cycles, 0.5);
  EXPECT_TRUE(h.phase_shifts[9].satellites.empty());
  // GLONASS SLOT / FRQ #, lines 51-53: 24 slots, R02 -4, R10 -7, R24 2.
  EXPECT_EQ(h.glonass_channels.size(), 24);
  EXPECT_EQ(h.glonass_channels.channel(2), -4);
  EXPECT_EQ(h.glonass_channels.channel(10), -7);
  EXPECT_EQ(h.glonass_channels.channel(24), 2);
  EXPECT_EQ(h.header_lines, 56u);  // END OF HEADER on line 56
}

TEST(RinexObsZim2, Epochs) {
  PPP_REQUIRE_SHARED_DATA();
  RinexObsReader reader = RinexObsReader::open(test::dataPath(kZim2));
  ObsEpoch e;
  ASSERT_TRUE(reader.next(e));
  // Line 57: "> 2026 05 13 00 00  0.0000000  0 45".
  EXPECT_EQ(e.line, 57u);
  EXPECT_EQ(e.time, gpst(2026, 5, 13, 0, 0, 0));
  EXPECT_EQ(e.flag, EpochFlag::Ok);
  EXPECT_FALSE(e.receiver_clock_offset_s);
  EXPECT_EQ(e.satellites.size(), 45u);
  // Line 58: "G05  24817828.909   130418582.44307     -3769.695          42.850".
  EXPECT_EQ(e.satellites[0].satellite, sat("G05"));
  const Observation* l1 = e.find(sat("G05"), code("L1C"));
  ASSERT_NE(l1, nullptr);
  EXPECT_DOUBLE_EQ(*l1->value, 130418582.443);
  EXPECT_EQ(l1->lli, 0);
  EXPECT_EQ(l1->ssi, 7);
  const Observation* c1 = e.find(sat("G05"), code("C1C"));
  EXPECT_DOUBLE_EQ(*c1->value, 24817828.909);
  EXPECT_FALSE(c1->lli);
  EXPECT_FALSE(c1->ssi);
  EXPECT_FALSE(e.find(sat("G05"), code("C1L"))->value);  // blank field
  EXPECT_DOUBLE_EQ(*e.find(sat("G05"), code("D1C"))->value, -3769.695);
  std::size_t n = 1;
  GnssTime last, last_seen = e.time;
  while (reader.next(e)) {
    ++n;
    EXPECT_GT(e.time, last_seen);
    last_seen = last = e.time;
  }
  EXPECT_EQ(n, 120u);
  EXPECT_EQ(last, gpst(2026, 5, 13, 0, 59, 30));  // line 5445
  EXPECT_TRUE(reader.report().clean()) << reader.report().summary();
  EXPECT_EQ(reader.duplicateEpochs(), 0u);
  EXPECT_EQ(reader.epochsBackwards(), 0u);
}

TEST(RinexObsZim2, LliAndSsiOfAGalileoPhase) {
  PPP_REQUIRE_SHARED_DATA();
  RinexObsReader reader = RinexObsReader::open(test::dataPath(kZim2));
  ObsEpoch e;
  ASSERT_TRUE(reader.next(e));
  // Line 79 (first epoch): "E04  23808924.667   125116866.92049": L1C LLI 4, SSI 9.
  const Observation* l1 = e.find(sat("E04"), code("L1C"));
  ASSERT_NE(l1, nullptr);
  EXPECT_DOUBLE_EQ(*l1->value, 125116866.920);
  EXPECT_EQ(l1->lli, 4);
  EXPECT_EQ(l1->ssi, 9);
}

TEST(RinexObsZim2, Summary) {
  PPP_REQUIRE_SHARED_DATA();
  const FileSummary s = summarizeObservationFile(test::dataPath(kZim2));
  EXPECT_EQ(s.type, "RINEX observation");
  EXPECT_EQ(s.version, "3.04");
  EXPECT_EQ(s.epoch_count, 120u);
  EXPECT_EQ(*s.first_epoch, gpst(2026, 5, 13, 0, 0, 0));
  EXPECT_EQ(*s.last_epoch, gpst(2026, 5, 13, 0, 59, 30));
  EXPECT_DOUBLE_EQ(*s.interval_s, 30.0);
  EXPECT_TRUE(s.satellites.at(GnssSystem::GPS).count(sat("G05")));
  EXPECT_TRUE(s.signals.at(GnssSystem::GPS).count("L2W"));
  EXPECT_TRUE(s.report.clean());
  bool antenna = false;
  for (const auto& f : s.facts) antenna = antenna || f.find("TRM59800.00 NONE") != std::string::npos;
  EXPECT_TRUE(antenna);
}

// ---------------------------------------------------------------- CCJ2 (RINEX 3.04)

TEST(RinexObsCcj2, HeaderAndEpochs) {
  PPP_REQUIRE_SHARED_DATA();
  RinexObsReader reader = RinexObsReader::open(test::dataPath(kCcj2));
  const RinexObsHeader& h = reader.header();
  EXPECT_EQ(h.marker_name, "CCJ200JPN");  // line 5
  EXPECT_EQ(h.antenna_type, "TRM59800.00");  // line 9
  EXPECT_EQ(h.antenna_radome, "SCIS");
  EXPECT_EQ(h.receiver_type, "TRIMBLE NETR9");
  // Lines 12-18.
  EXPECT_EQ(codes(h.types(GnssSystem::Galileo)), "C1X C5X D1X D5X L1X L5X S1X S5X");
  EXPECT_EQ(codes(h.types(GnssSystem::GPS)), "C1C C2W C2X C5X D1C D2W D2X D5X L1C L2W L2X L5X S1C S2W S2X S5X");
  EXPECT_EQ(codes(h.types(GnssSystem::QZSS)), "C1C C1X C2X C5X D1C D1X D2X D5X L1C L1X L2X L5X S1C S1X S2X S5X");
  EXPECT_EQ(codes(h.types(GnssSystem::GLONASS)), "C1C C1P C2C C2P D1C D1P D2C D2P L1C L1P L2C L2P S1C S1P S2C S2P");
  // GLONASS SLOT / FRQ #, lines 35-37: 23 slots (no R11), R01 1, R10 -7, R12 -1, R17 4, R24 2.
  EXPECT_EQ(h.glonass_channel_entries, 23);
  EXPECT_EQ(h.glonass_channels.size(), 23);
  EXPECT_EQ(h.glonass_channels.channel(1), 1);
  EXPECT_EQ(h.glonass_channels.channel(10), -7);
  EXPECT_FALSE(h.glonass_channels.channel(11));
  EXPECT_EQ(h.glonass_channels.channel(12), -1);
  EXPECT_EQ(h.glonass_channels.channel(17), 4);
  EXPECT_EQ(h.glonass_channels.channel(24), 2);
  EXPECT_EQ(h.phase_shifts.size(), 15u);  // lines 20-34
  ASSERT_TRUE(h.approx_position_ecef_m);
  EXPECT_DOUBLE_EQ(h.approx_position_ecef_m->x(), -4490605.4743);  // line 11

  const auto epochs = readAll(reader);
  ASSERT_EQ(epochs.size(), 120u);
  EXPECT_EQ(epochs.front().line, 183u);
  EXPECT_EQ(epochs.front().time, gpst(2021, 7, 29, 0, 0, 0));
  EXPECT_EQ(epochs.front().satellites.size(), 25u);
  EXPECT_EQ(epochs.back().time, gpst(2021, 7, 29, 0, 59, 30));   // line 3416
  EXPECT_EQ(epochs.back().satellites.size(), 28u);
  // Line 184: "E01  24700777.625 ... 129803476.624 8": L1X with blank LLI, SSI 8.
  const Observation* l1 = epochs.front().find(sat("E01"), code("L1X"));
  ASSERT_NE(l1, nullptr);
  EXPECT_DOUBLE_EQ(*l1->value, 129803476.624);
  EXPECT_FALSE(l1->lli);
  EXPECT_EQ(l1->ssi, 8);
  EXPECT_DOUBLE_EQ(*epochs.front().find(sat("E01"), code("C1X"))->value, 24700777.625);
  EXPECT_TRUE(reader.report().clean()) << reader.report().summary();
}

// ---------------------------------------------------------------- RINEX 2.11 (hatanaka pair)

TEST(RinexObsRinex2, Algo2011FromPlainAndCompact) {
  PPP_REQUIRE_SHARED_DATA();
  for (const std::string ext : {".rnx", ".crx"}) {
    RinexObsReader reader = RinexObsReader::open(test::dataPath("hatanaka/algo0010_2015001_v1_trim" + ext));
    const RinexObsHeader& h = reader.header();
    EXPECT_EQ(h.version_text, "2.11");
    EXPECT_EQ(h.marker_name, "ALGO CACS-GSD 883160 Algonquin Park ON Canada");
    EXPECT_EQ(h.antenna_type, "AOAD/M_T");
    EXPECT_EQ(h.antenna_radome, "NONE");
    EXPECT_EQ(*h.antenna_delta_hen_m, Eigen::Vector3d(0.1, 0.0, 0.0));  // line 11
    // Line 13: "8    L1    L2    C1    C2    P2    P1    S1    S2".
    ASSERT_EQ(h.rinex2_obs_types.size(), 8u);
    EXPECT_EQ(h.rinex2_obs_types[4], "P2");
    EXPECT_EQ(codes(h.types(GnssSystem::GPS)), "L1C L2W C1C C2X C2W C1W S1C S2W");
    EXPECT_EQ(codes(h.types(GnssSystem::GLONASS)), "L1C L2P C1C C2C C2P C1P S1C S2P");
    EXPECT_EQ(*h.leap_seconds, 16);
    const auto epochs = readAll(reader);
    ASSERT_GE(epochs.size(), 2u);
    // Lines 25-26: 20 satellites over two lines ("...G23G29" / "G32R15R17G25R 6G22R 5G 1").
    const ObsEpoch& e = epochs[0];
    EXPECT_EQ(e.time, gpst(2015, 1, 1, 0, 0, 0));
    ASSERT_EQ(e.satellites.size(), 20u);
    EXPECT_EQ(e.satellites[0].satellite, sat("G08"));
    EXPECT_EQ(e.satellites[12].satellite, sat("G32"));
    EXPECT_EQ(e.satellites[16].satellite, sat("R06"));
    EXPECT_EQ(e.satellites[19].satellite, sat("G01"));
    // Lines 27-28: " 118504127.18147  92340891.71646  22550576.489                    22550574.970"
    //              "  22550575.149          47.250          37.250"
    const Observation* l1 = e.find(sat("G08"), code("L1C"));
    EXPECT_DOUBLE_EQ(*l1->value, 118504127.181);
    EXPECT_EQ(l1->lli, 4);
    EXPECT_EQ(l1->ssi, 7);
    EXPECT_FALSE(e.find(sat("G08"), code("C2X"))->value);
    EXPECT_DOUBLE_EQ(*e.find(sat("G08"), code("C2W"))->value, 22550574.970);
    EXPECT_DOUBLE_EQ(*e.find(sat("G08"), code("C1W"))->value, 22550575.149);
    EXPECT_DOUBLE_EQ(*e.find(sat("G08"), code("S2W"))->value, 37.250);
    // Line 67: the second epoch, 19 satellites, at 00:00:30.
    EXPECT_EQ(epochs[1].time, gpst(2015, 1, 1, 0, 0, 30));
    EXPECT_EQ(epochs[1].satellites.size(), 19u);
    EXPECT_TRUE(reader.report().clean()) << reader.report().summary();
  }
}

// ---------------------------------------------------------------- synthetic fixtures

TEST(RinexObsSynthetic, Rinex211EventsAndContinuation) {
  RinexObsReader reader = RinexObsReader::open(test::fixturePath("rinex_obs/rinex211_events.obs"));
  EXPECT_EQ(reader.header().antenna_type, "LEIAR25.R3");
  EXPECT_EQ(reader.header().antenna_radome, "LEIT");
  EXPECT_EQ(*reader.header().antenna_delta_hen_m, Eigen::Vector3d(0.1234, 0, 0));
  const auto epochs = readAll(reader);
  ASSERT_EQ(epochs.size(), 4u);
  // Epoch 1: 14 satellites over two epoch lines, clock 0.000123456 s.
  const ObsEpoch& e0 = epochs[0];
  ASSERT_EQ(e0.satellites.size(), 14u);
  EXPECT_EQ(e0.satellites[12].satellite, sat("R01"));
  EXPECT_EQ(e0.satellites[13].satellite, sat("R12"));
  ASSERT_TRUE(e0.receiver_clock_offset_s);
  EXPECT_DOUBLE_EQ(*e0.receiver_clock_offset_s, 0.000123456);
  const Observation* l1 = e0.find(sat("R12"), code("L1C"));
  EXPECT_DOUBLE_EQ(*l1->value, 105000013.25);
  EXPECT_EQ(l1->lli, 1);
  EXPECT_EQ(l1->ssi, 7);
  EXPECT_DOUBLE_EQ(*e0.find(sat("R12"), code("S1C"))->value, 58.0);  // second line of the record
  EXPECT_FALSE(e0.find(sat("G03"), code("C1W"))->value);              // blank P1
  EXPECT_DOUBLE_EQ(*e0.find(sat("G03"), code("L2W"))->value, 82000002.75);
  // Epoch 2: power failure flag, short lines.
  EXPECT_TRUE(epochs[1].powerFailure());
  EXPECT_DOUBLE_EQ(*epochs[1].find(sat("G01"), code("S1C"))->value, 46.0);
  EXPECT_DOUBLE_EQ(*epochs[1].find(sat("G02"), code("C1C"))->value, 20001001.0);
  EXPECT_FALSE(epochs[1].find(sat("G02"), code("L1C"))->value);
  EXPECT_FALSE(epochs[1].find(sat("G02"), code("S1C"))->value);
  // Flags 5, 4, 2, 3 skipped and counted; flag 6 kept.
  EXPECT_EQ(reader.specialRecordsSkipped(), 4u);
  EXPECT_TRUE(epochs[2].cycleSlipRecords());
  EXPECT_EQ(epochs[2].time, gpst(2015, 1, 1, 0, 1, 0));
  EXPECT_EQ(epochs[3].flag, EpochFlag::Ok);
  EXPECT_EQ(epochs[3].time, gpst(2015, 1, 1, 0, 1, 0));
  EXPECT_EQ(reader.duplicateEpochs(), 0u);  // the flag-6 record shares the time legitimately
  EXPECT_TRUE(reader.report().clean()) << reader.report().summary();
}

TEST(RinexObsSynthetic, Rinex305EventsClockAndTimeOrder) {
  RinexObsReader reader = RinexObsReader::open(test::fixturePath("rinex_obs/rinex305_events.obs"));
  const RinexObsHeader& h = reader.header();
  EXPECT_EQ(h.version_text, "3.05");
  EXPECT_EQ(h.glonass_channels.channel(2), -4);
  ASSERT_EQ(h.phase_shifts.size(), 2u);
  ASSERT_EQ(h.phase_shifts[0].satellites.size(), 2u);
  EXPECT_EQ(h.phase_shifts[0].satellites[1], sat("G02"));
  EXPECT_DOUBLE_EQ(*h.phase_shifts[0].shift_cycles, 0.0);
  EXPECT_DOUBLE_EQ(*h.phase_shifts[1].shift_cycles, -0.25);
  const auto epochs = readAll(reader);
  ASSERT_EQ(epochs.size(), 6u);
  EXPECT_DOUBLE_EQ(*epochs[0].receiver_clock_offset_s, -0.000012345678);
  const Observation* l1 = epochs[0].find(sat("G01"), code("L1C"));
  EXPECT_DOUBLE_EQ(*l1->value, 110000000.456);
  EXPECT_EQ(l1->lli, 1);
  EXPECT_EQ(l1->ssi, 8);
  EXPECT_DOUBLE_EQ(*epochs[0].find(sat("G01"), code("D1C"))->value, -1234.5);
  EXPECT_FALSE(epochs[0].find(sat("G02"), code("L1C"))->value);
  EXPECT_DOUBLE_EQ(*epochs[0].find(sat("G02"), code("S1C"))->value, 40.0);
  EXPECT_FALSE(epochs[0].find(sat("G02"), code("L2W"))->value);  // beyond the short line
  EXPECT_EQ(epochs[0].find(sat("R01"), code("L1C"))->lli, 4);
  EXPECT_TRUE(epochs[1].powerFailure());
  EXPECT_EQ(reader.specialRecordsSkipped(), 4u);
  // The flag-4 record redefined the GPS types to "C1C L1C".
  EXPECT_EQ(codes(reader.header().types(GnssSystem::GPS)), "C1C L1C");
  EXPECT_TRUE(epochs[2].cycleSlipRecords());
  EXPECT_EQ(epochs[2].satellites[0].count, 2u);
  EXPECT_DOUBLE_EQ(*epochs[3].find(sat("G01"), code("L1C"))->value, 110000200.0);
  EXPECT_EQ(epochs[4].time, gpst(2021, 7, 29, 0, 0, 30));
  EXPECT_EQ(reader.epochsBackwards(), 1u);
  EXPECT_EQ(reader.duplicateEpochs(), 1u);
  EXPECT_EQ(reader.report().counters().at("epochs going back in time"), 1u);
  EXPECT_EQ(reader.report().counters().at("duplicate epochs"), 1u);
  EXPECT_EQ(reader.report().problemCount(), 0u);
}

TEST(RinexObsSynthetic, Rinex400) {
  RinexObsReader reader = RinexObsReader::open(test::fixturePath("rinex_obs/rinex400.obs"));
  EXPECT_EQ(reader.header().major_version, 4);
  EXPECT_EQ(codes(reader.header().types(GnssSystem::BeiDou)), "C2I L2I");
  const auto epochs = readAll(reader);
  ASSERT_EQ(epochs.size(), 1u);
  EXPECT_EQ(epochs[0].time, gpst(2024, 2, 29, 23, 59, 59.5));
  EXPECT_EQ(*epochs[0].find(sat("E11"), code("L1C"))->ssi, 9);
  EXPECT_DOUBLE_EQ(*epochs[0].find(sat("E11"), code("L5Q"))->value, 90000000.125);
  EXPECT_DOUBLE_EQ(*epochs[0].find(sat("C23"), code("L2I"))->value, 198000000.0);
}

struct HeaderCase {
  const char* file;
  std::size_t line;
  const char* reason;
};

TEST(RinexObsMalformed, HeadersThrowParseErrorWithLineAndReason) {
  const HeaderCase cases[] = {
      {"missing_end_of_header.obs", 11, "missing END OF HEADER"},
      {"bad_version.obs", 1, "bad RINEX version"},
      {"unsupported_version.obs", 1, "unsupported RINEX version 5.00"},
      {"navigation_file.obs", 1, "not an observation file"},
      {"not_rinex.obs", 1, "not a RINEX file"},
      {"bad_type_count.obs", 9, "bad observation type count"},
      {"short_type_list.obs", 9, "14 types short of its count"},
      {"bad_obs_code.obs", 9, "bad observation code 'Z1C'"},
      {"bad_glonass_slot.obs", 11, "bad GLONASS SLOT / FRQ # entry"},
      {"bad_time_of_first_obs.obs", 11, "invalid date in TIME OF FIRST OBS"},
      {"no_observation_types.obs", 10, "no observation types"},
  };
  for (const auto& c : cases) {
    const std::string path = test::fixturePath(std::string("malformed/rinex_obs/") + c.file);
    try {
      RinexObsReader::open(path);
      ADD_FAILURE() << c.file << ": no ParseError";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.file(), path) << c.file;
      EXPECT_EQ(e.line(), c.line) << c.file << ": " << e.what();
      EXPECT_NE(e.reason().find(c.reason), std::string::npos) << c.file << ": " << e.reason();
    }
  }
}

TEST(RinexObsMalformed, Rinex3RecordsSkippedAndReadingResumes) {
  RinexObsReader reader = RinexObsReader::open(test::fixturePath("malformed/rinex_obs/bad_records.obs"));
  const auto epochs = readAll(reader);
  // Good epochs: 00:00:00, 00:01:30 (G01 dropped for a bad value), 00:02:00.
  ASSERT_EQ(epochs.size(), 3u);
  EXPECT_EQ(epochs[0].time, gpst(2021, 7, 29, 0, 0, 0));
  EXPECT_EQ(epochs[1].time, gpst(2021, 7, 29, 0, 1, 30));
  EXPECT_EQ(epochs[1].satellites.size(), 0u);
  EXPECT_EQ(epochs[2].time, gpst(2021, 7, 29, 0, 2, 0));
  EXPECT_DOUBLE_EQ(*epochs[2].find(sat("G01"), code("L1C"))->value, 4.0);
  const ParseReport& r = reader.report();
  EXPECT_EQ(r.problemCount(), 6u) << r.summary();
  EXPECT_TRUE(hasProblemAt(r, 15, "bad epoch time")) << r.summary();
  EXPECT_TRUE(hasProblemAt(r, 20, "has 2 satellite records, expected 3")) << r.summary();
  EXPECT_TRUE(hasProblemAt(r, 21, "malformed observation value for G01")) << r.summary();
  EXPECT_TRUE(hasProblemAt(r, 22, "bad satellite 'Q07'")) << r.summary();
  EXPECT_TRUE(hasProblemAt(r, 23, "E01 of a system without observation types")) << r.summary();
  EXPECT_TRUE(hasProblemAt(r, 26, "epoch truncated at end of data")) << r.summary();
}

TEST(RinexObsMalformed, Rinex2RecordsSkippedAndReadingResumes) {
  RinexObsReader reader = RinexObsReader::open(test::fixturePath("malformed/rinex_obs/bad_records_v2.obs"));
  const auto epochs = readAll(reader);
  ASSERT_EQ(epochs.size(), 2u);
  EXPECT_EQ(epochs[0].time, gpst(2015, 1, 1, 0, 0, 0));
  EXPECT_EQ(epochs[1].time, gpst(2015, 1, 1, 0, 2, 0));
  EXPECT_DOUBLE_EQ(*epochs[1].find(sat("G01"), code("L1C"))->value, 8.0);
  const ParseReport& r = reader.report();
  EXPECT_EQ(r.problemCount(), 3u) << r.summary();
  EXPECT_TRUE(hasProblemAt(r, 18, "expected an epoch line")) << r.summary();
  EXPECT_TRUE(hasProblemAt(r, 23, "fewer observation lines than expected")) << r.summary();
  EXPECT_TRUE(hasProblemAt(r, 23, "bad satellite 'X99'")) << r.summary();
}

TEST(RinexObsMalformed, TruncatedGzipIsReportedAndEarlierEpochsKept) {
  const std::string text = test::readFileBytes(test::fixturePath("rinex_obs/rinex305_events.obs"));
  const auto dir = test::tempDir("obsgz");
  const std::string gz = (dir / "cut.rnx.gz").string();
  gzFile f = gzopen(gz.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  gzwrite(f, text.data(), static_cast<unsigned>(text.size()));
  gzclose(f);
  std::string bytes = test::readFileBytes(gz);
  bytes.resize(bytes.size() * 3 / 4);
  RinexObsReader reader = openMemory(bytes, "cut.rnx.gz");
  const auto epochs = readAll(reader);
  EXPECT_LT(epochs.size(), 6u);
  bool truncated = false;
  for (const auto& p : reader.report().problems()) truncated = truncated || p.reason.find("truncated") != std::string::npos;
  EXPECT_TRUE(truncated) << reader.report().summary();
  std::filesystem::remove_all(dir);
}

TEST(RinexObsMapping, Rinex2Codes) {
  EXPECT_EQ(mapRinex2ObsCode(GnssSystem::GPS, "P1")->toString(), "C1W");
  EXPECT_EQ(mapRinex2ObsCode(GnssSystem::GPS, "C1")->toString(), "C1C");
  EXPECT_EQ(mapRinex2ObsCode(GnssSystem::GPS, "L2")->toString(), "L2W");
  EXPECT_EQ(mapRinex2ObsCode(GnssSystem::GPS, "C2")->toString(), "C2X");
  EXPECT_EQ(mapRinex2ObsCode(GnssSystem::GPS, "L5")->toString(), "L5X");
  EXPECT_EQ(mapRinex2ObsCode(GnssSystem::GLONASS, "P2")->toString(), "C2P");
  EXPECT_EQ(mapRinex2ObsCode(GnssSystem::GLONASS, "C2")->toString(), "C2C");
  EXPECT_EQ(mapRinex2ObsCode(GnssSystem::Galileo, "L7")->toString(), "L7X");
  EXPECT_FALSE(mapRinex2ObsCode(GnssSystem::GPS, "Q1"));
  EXPECT_FALSE(mapRinex2ObsCode(GnssSystem::GPS, "L0"));
}

}  // namespace
}  // namespace ppp
