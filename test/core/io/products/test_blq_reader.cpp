// BLQ ocean loading reader on synthetic fixtures (values as written in
// test/fixtures/blq/stations.blq.txt; line numbers cited).
#include <gtest/gtest.h>

#include "ppp_bayes_tree/io/products/blq_reader.h"
#include "test_support.h"

using namespace ppp;

namespace {
const BlqFile& stationsFile() {
  static const BlqFile f = readBlqFile(test::fixturePath("blq/stations.blq.txt"));
  return f;
}
}  // namespace

TEST(BlqReader, ReadsAllStationsWithValues) {
  const BlqFile& f = stationsFile();
  EXPECT_TRUE(f.report.clean()) << f.report.summary();
  ASSERT_EQ(f.stations.size(), 3u);
  const OceanLoadingCoefficients& z = f.stations[0];
  EXPECT_EQ(z.station, "ZIM2");
  EXPECT_EQ(z.line, 20u);
  // Line 24: radial amplitudes; M2 first (.00842), SSA last (.00023).
  EXPECT_DOUBLE_EQ(z.amplitude_radial_m[0], 0.00842);
  EXPECT_DOUBLE_EQ(z.amplitude_radial_m[10], 0.00023);
  // Line 25: west, K1 is the 5th column (.00043); line 26: south, O1 6th (.00023).
  EXPECT_DOUBLE_EQ(z.amplitude_west_m[4], 0.00043);
  EXPECT_DOUBLE_EQ(z.amplitude_south_m[5], 0.00023);
  // Lines 27-29: phases; radial M2 -74.8, west S2 102.4, south SSA 179.8 deg.
  EXPECT_DOUBLE_EQ(z.phase_radial_deg[0], -74.8);
  EXPECT_DOUBLE_EQ(z.phase_west_deg[1], 102.4);
  EXPECT_DOUBLE_EQ(z.phase_south_deg[10], 179.8);
  // Line 23: lon/lat comment.
  EXPECT_DOUBLE_EQ(*z.longitude_deg, 7.4650);
  EXPECT_DOUBLE_EQ(*z.latitude_deg, 46.8771);
  EXPECT_STREQ(kTidalConstituentNames[4], "K1");
  // ONSA0SWE (line 39) has no lon/lat comment.
  EXPECT_FALSE(f.stations[2].latitude_deg.has_value());
}

TEST(BlqReader, LookupIsCaseInsensitiveAndMatchesMarkers) {
  const BlqFile& f = stationsFile();
  // Station line 31 is "  ccj2 21741S001": the name is the first word.
  const auto ccj2 = f.find("CCJ2");
  ASSERT_NE(ccj2.coefficients, nullptr);
  EXPECT_FALSE(ccj2.matched_by_marker);
  EXPECT_DOUBLE_EQ(ccj2.coefficients->amplitude_radial_m[4], 0.02087);  // line 34, K1
  EXPECT_EQ(f.find("zim2").coefficients, &f.stations[0]);
  // 9-character long name asked, 4-character name in the file.
  const auto longname = f.find("ZIM200CHE");
  ASSERT_EQ(longname.coefficients, &f.stations[0]);
  EXPECT_TRUE(longname.matched_by_marker);
  EXPECT_NE(longname.note.find("using ZIM2"), std::string::npos);
  // 4-character name asked, long name in the file (line 39 "ONSA0SWE" is 8 chars: no match).
  EXPECT_EQ(f.find("ONSA").coefficients, nullptr);
  EXPECT_NE(f.find("onsa0swe").coefficients, nullptr);
  // Missing and too short.
  const auto missing = f.find("WTZR");
  EXPECT_EQ(missing.coefficients, nullptr);
  EXPECT_EQ(missing.note, "WTZR not found");
  EXPECT_EQ(f.find("ZI").coefficients, nullptr);
}

TEST(BlqReader, MalformedBlocksAreSkippedAndReported) {
  const BlqFile f = readBlqFile(test::fixturePath("malformed/blq/bad_blocks.blq.txt"));
  ASSERT_EQ(f.stations.size(), 1u);
  EXPECT_EQ(f.stations[0].station, "GOOD");
  ASSERT_EQ(f.report.problemCount(), 6u) << f.report.summary();
  struct Expected {
    std::size_t line;
    const char* reason;
  };
  const Expected expected[] = {
      {12, "station SHRT (line 11) skipped: row 1: expected 11 values, found 10"},
      {21, "station CUTS (line 18) skipped: only 2 of 6 rows before the next station"},
      {23, "station NEGA (line 21) skipped: row 2: negative amplitude"},
      {33, "station PHAS (line 28) skipped: row 5: phase beyond +-360 deg"},
      {38, "station TEXT (line 35) skipped: row 3: value 8 'abc' is not a number"},
      {46, "station LAST (line 42) skipped: file ends after 4 of 6 rows"},
  };
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(f.report.problems()[i].line, expected[i].line) << i;
    EXPECT_EQ(f.report.problems()[i].reason, expected[i].reason);
  }
}

TEST(BlqReader, GarbageNeverThrowsAndYieldsNoStation) {
  auto src = memoryLineSource(std::string("\x01\x02 garbage\n1 2 3\n$$\n", 21), "junk");
  const BlqFile f = readBlq(*src);
  EXPECT_TRUE(f.stations.empty());
  EXPECT_GE(f.report.problemCount(), 1u);
}

TEST(BlqSummary, SummarizesFixture) {
  const FileSummary s = summarizeBlqFile(test::fixturePath("blq/stations.blq.txt"));
  EXPECT_EQ(s.type, "BLQ ocean loading");
  EXPECT_EQ(s.epoch_count, 3u);
  ASSERT_GE(s.facts.size(), 2u);
  EXPECT_EQ(s.facts[0], "3 stations");
  EXPECT_EQ(s.facts[1], "station ZIM2 lon 7.4650 lat 46.8771, M2 radial 8.4 mm");
}
