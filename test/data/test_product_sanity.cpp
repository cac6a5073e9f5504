// Product sanity checks (models/product_sanity.h): a single bad SP3 or
// CLK value is found by leave-one-out prediction, and the clean real products of
// ../shared/data give no false alarm.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/models/product_sanity.h"
#include "test_support.h"

namespace ppp {
namespace {

const char* kZim2Sp3 = "zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3";
const char* kZim2Clk = "zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK";

Sp3File readSp3Text(const std::string& text, const std::string& name) {
  auto src = memoryLineSource(text, name);
  return readSp3(*src);
}

/// The file's text with the line `line_number` (1-based) passed through `edit`.
std::string editedLine(const std::string& path, std::size_t line_number, const std::string& from,
                       const std::string& to) {
  std::string text = test::readFileBytes(path);
  std::size_t pos = 0;
  for (std::size_t n = 1; n < line_number; ++n) pos = text.find('\n', pos) + 1;
  const std::size_t end = text.find('\n', pos);
  std::string line = text.substr(pos, end - pos);
  const std::size_t at = line.find(from);
  EXPECT_NE(at, std::string::npos) << "line " << line_number << " of " << path << ": " << line;
  if (at != std::string::npos) line.replace(at, from.size(), to);
  return text.substr(0, pos) + line + text.substr(end);
}

TEST(ProductSanity, CleanRealOrbitsGiveNoOutlier) {
  PPP_REQUIRE_SHARED_DATA();
  for (const char* rel : {kZim2Sp3, "ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz",
                          "esbc-2020-177/GRG0MGXFIN_20201770000_01D_15M_ORB.SP3.gz"}) {
    const Sp3File file = readSp3(test::dataPath(rel));
    const std::vector<OrbitOutlier> outliers = findOrbitOutliers(file);
    for (const auto& o : outliers) ADD_FAILURE() << rel << ": " << o.describe();
    // The margin: the largest miss of a clean file against its threshold.
    double worst_m = 0.0, worst_ratio = 0.0;
    for (const auto& m : orbitLeaveOneOutMisses(file)) {
      worst_m = std::max(worst_m, m.miss_m);
      worst_ratio = std::max(worst_ratio, m.miss_m / m.threshold_m);
    }
    std::printf("%s: no outlier; largest leave-one-out miss %.4f m, largest miss / threshold %.2f\n", rel, worst_m,
                worst_ratio);
  }
}

TEST(ProductSanity, OneMetreOnOneSp3ValueIsFoundAndOnlyThatNode) {
  PPP_REQUIRE_SHARED_DATA();
  // Line 104 of the ZIM2 SP3: G15 at 00:30, X 23339.029670 km (the reported case), +1 m.
  const Sp3File file =
      readSp3Text(editedLine(test::dataPath(kZim2Sp3), 104, "PG15  23339.029670", "PG15  23339.030670"), "edited.sp3");
  const std::vector<OrbitOutlier> outliers = findOrbitOutliers(file);
  for (const auto& o : outliers) std::printf("%s\n", o.describe().c_str());
  ASSERT_EQ(outliers.size(), 1u);
  EXPECT_EQ(outliers[0].satellite.toString(), "G15");
  EXPECT_EQ(outliers[0].time, test::gpst(2026, 5, 13, 0, 30));
  EXPECT_NEAR(outliers[0].miss_m, 1.0, 0.1);
  EXPECT_NE(outliers[0].describe().find("G15 orbit at 2026-05-13 00:30:00"), std::string::npos)
      << outliers[0].describe();
}

TEST(ProductSanity, MarkedOrbitOutlierIsRefusedByTheInterpolationWithItsReason) {
  PPP_REQUIRE_SHARED_DATA();
  Sp3File file =
      readSp3Text(editedLine(test::dataPath(kZim2Sp3), 104, "PG15  23339.029670", "PG15  23339.030670"), "edited.sp3");
  markOrbitOutliers(file, findOrbitOutliers(file));
  PreciseEphemeris eph;
  eph.addOrbits(file);
  const SatelliteId g15 = SatelliteId::parse("G15").value();
  const auto at = eph.orbit(g15, test::gpst(2026, 5, 13, 0, 31));
  EXPECT_FALSE(at.ok());
  EXPECT_EQ(at.status, ProductStatus::BadValueMarker) << at.reason;
  const SatelliteId g05 = SatelliteId::parse("G05").value();
  EXPECT_TRUE(eph.orbit(g05, test::gpst(2026, 5, 13, 0, 31)).ok());  // the others are untouched
}

TEST(ProductSanity, CleanRealClocksGiveNoOutlierAndOneMicrosecondIsFound) {
  PPP_REQUIRE_SHARED_DATA();
  for (const char* rel : {"ccj2-2021-210/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz",
                          "esbc-2020-177/GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz"}) {
    const RinexClockFile file = readRinexClock(test::dataPath(rel));
    std::size_t beidou = 0;
    for (const auto& o : findClockOutliers(file)) {
      // WUM's rapid BeiDou GEO clocks (C02, C03, C04, C13) hold a dozen single values
      // off by 1-2 ns from their neighbours: found, rightly, and not a false alarm.
      if (o.satellite.system == GnssSystem::BeiDou) ++beidou;
      else ADD_FAILURE() << rel << ": " << o.describe();
    }
    std::printf("%s: no GPS/Galileo/GLONASS clock outlier; BeiDou: %zu\n", rel, beidou);
  }
  const RinexClockFile clean = readRinexClock(test::dataPath(kZim2Clk));
  for (const auto& o : findClockOutliers(clean)) ADD_FAILURE() << "clean file: " << o.describe();

  // One G24 record at 00:20:00 moved by +1 microsecond, on a copy made here.
  RinexClockFile edited = clean;
  const SatelliteId g24 = SatelliteId::parse("G24").value();
  const GnssTime t = test::gpst(2026, 5, 13, 0, 20);
  bool found = false;
  for (auto& r : edited.satellite_clocks.at(g24))
    if (r.time == t) {
      r.clock_bias_s += 1e-6;
      found = true;
    }
  ASSERT_TRUE(found);
  const std::vector<ClockOutlier> outliers = findClockOutliers(edited);
  ASSERT_EQ(outliers.size(), 1u);
  EXPECT_EQ(outliers[0].satellite, g24);
  EXPECT_EQ(outliers[0].time, t);
  EXPECT_NEAR(outliers[0].miss_s, 1e-6, 1e-8);
  const std::size_t before = edited.satellite_clocks.at(g24).size();
  markClockOutliers(edited, outliers);
  EXPECT_EQ(edited.satellite_clocks.at(g24).size(), before - 1);
}

}  // namespace
}  // namespace ppp

namespace ppp {
namespace {

TEST(ProductLoad, AClockFileOfAnotherDayIsAnErrorNotAFallbackToTheSp3Clocks) {
  PPP_REQUIRE_SHARED_DATA();
  RecordFilter filter;  // the ZIM2 hour, GPS
  filter.systems = {GnssSystem::GPS};
  filter.first = test::gpst(2026, 5, 13, 0, 0);
  filter.last = test::gpst(2026, 5, 13, 0, 59, 30);
  const std::string wrong_day = test::dataPath("ccj2-2021-210/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz");
  try {
    PreciseEphemeris::load({test::dataPath(kZim2Sp3)}, {wrong_day}, filter);
    FAIL() << "a clock file of 2021 loaded for a 2026 hour";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), wrong_day);
    EXPECT_NE(std::string(e.what()).find("no satellite clock record"), std::string::npos) << e.what();
  }
  // The right day loads, with no problem.
  const PreciseEphemeris right = PreciseEphemeris::load({test::dataPath(kZim2Sp3)}, {test::dataPath(kZim2Clk)}, filter);
  EXPECT_EQ(right.clockSource(), ClockSource::RinexClock);
  EXPECT_EQ(right.mergeReport().problemCount(), 0u);
}

TEST(ProductLoad, OutliersAreReportedAsProblemsAndNotUsed) {
  PPP_REQUIRE_SHARED_DATA();
  const std::string dir = test::tempDir("product_load").string();
  const std::string edited = dir + "/edited.sp3";  // a copy made here, never committed
  std::ofstream(edited) << editedLine(test::dataPath(kZim2Sp3), 104, "PG15  23339.029670", "PG15  23339.030670");
  const PreciseEphemeris products = PreciseEphemeris::load({edited}, {test::dataPath(kZim2Clk)});
  ASSERT_EQ(products.mergeReport().problemCount(), 1u);
  EXPECT_NE(products.mergeReport().problems()[0].reason.find("G15 orbit at 2026-05-13 00:30:00"), std::string::npos);
  EXPECT_NE(products.mergeReport().summary().find("1 problem(s)"), std::string::npos);
  EXPECT_EQ(products.mergeReport().summary().find("no problems found"), std::string::npos);
  const auto g15 = products.orbit(SatelliteId::parse("G15").value(), test::gpst(2026, 5, 13, 0, 30));
  EXPECT_EQ(g15.status, ProductStatus::BadValueMarker) << g15.reason;
}

}  // namespace
}  // namespace ppp
