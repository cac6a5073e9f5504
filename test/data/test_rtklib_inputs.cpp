// RTKLIB inputs written from our readers: the GPS navigation file with precise
// clock terms and the GPS-only SP3-c copy, read back by our own readers.
#include <gtest/gtest.h>

#include <cmath>

#include "ppp_bayes_tree/evaluation/rtklib_navigation.h"
#include "ppp_bayes_tree/io/products/sp3_writer.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "test_support.h"

namespace ppp {
namespace {

TEST(RtklibInputs, NavigationClockTermsFollowThePreciseClocks) {
  PPP_REQUIRE_SHARED_DATA();
  const auto clk = readRinexClock(test::dataPath("zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK"));
  const auto nav = gpsNavigationFromClocks({&clk});
  // The IGS clock file covers 00:00-01:30 for 32 GPS satellites: records at 00:00
  // and 01:00 (02:00 has no sample within 15 min).
  EXPECT_EQ(nav.satellites, 32u);
  EXPECT_EQ(nav.records, 64u);
  auto src = memoryLineSource(nav.text, "nav");
  const auto back = readRinexNav(*src);
  EXPECT_TRUE(back.report.clean()) << back.report.summary();
  ASSERT_EQ(back.gps.size(), 64u);
  std::size_t checked = 0;
  for (const auto& e : back.gps) {
    EXPECT_EQ(e.health, 0);
    EXPECT_EQ(e.iode, e.iodc);
    EXPECT_EQ(e.clock.toc, e.orbit.toe);
    for (const auto& r : clk.satellite_clocks.at(e.satellite)) {
      const double dt = r.time - e.clock.toc;
      if (std::abs(dt) > 900.0) continue;
      // A line through 30 min of GPS clock samples: within 2 ns of each sample
      // (clock noise and curvature over 15 min are well below that).
      EXPECT_NEAR(e.clock.af0_s + e.clock.af1_sps * dt, r.clock_bias_s, 2e-9) << e.satellite.toString();
      ++checked;
    }
  }
  EXPECT_GT(checked, 1500u);
}

TEST(RtklibInputs, GpsOnlySp3KeepsEveryGpsRecord) {
  PPP_REQUIRE_SHARED_DATA();
  const auto sp3 = readSp3(test::dataPath("ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz"));
  const auto gps = gpsOnlySp3(sp3);
  // The WUM file lists 106 satellites (data README), 30 of them GPS, 1440 epochs.
  EXPECT_EQ(gps.satellites, 30u);
  EXPECT_EQ(gps.epochs, 1440u);
  auto src = memoryLineSource(gps.text, "gps.sp3");
  const auto back = readSp3(*src);
  EXPECT_TRUE(back.report.clean()) << back.report.summary();
  EXPECT_TRUE(back.complete);
  EXPECT_EQ(back.header.version, 'c');
  EXPECT_EQ(back.header.satellites.size(), 30u);
  EXPECT_EQ(back.epochs.size(), 1440u);
  for (const auto& [sat, records] : back.satellites) {
    ASSERT_EQ(sat.system, GnssSystem::GPS);
    const auto& orig = sp3.satellites.at(sat);
    ASSERT_EQ(records.size(), orig.size()) << sat.toString();
    for (std::size_t i = 0; i < records.size(); i += 97) {
      EXPECT_EQ(records[i].time, orig[i].time);
      ASSERT_EQ(records[i].position_ecef_m.has_value(), orig[i].position_ecef_m.has_value());
      if (orig[i].position_ecef_m)  // written %14.6f km: 1 mm
        EXPECT_LT((*records[i].position_ecef_m - *orig[i].position_ecef_m).norm(), 1e-3);
      ASSERT_EQ(records[i].clock_bias_s.has_value(), orig[i].clock_bias_s.has_value());
      if (orig[i].clock_bias_s) EXPECT_NEAR(*records[i].clock_bias_s, *orig[i].clock_bias_s, 1e-12);
    }
  }
}

TEST(RtklibInputs, Sp3RecordAccuraciesAreKept) {
  PPP_REQUIRE_SHARED_DATA();
  // The IGS final SP3 holds record exponents (e.g. "PG01 ... 8  9 10  69", base 1.25 mm / 1.025 ps).
  const auto sp3 = readSp3(test::dataPath("zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3"));
  auto src = memoryLineSource(gpsOnlySp3(sp3).text, "gps.sp3");
  const auto back = readSp3(*src);
  const auto sat = *SatelliteId::parse("G01");
  const auto& a = sp3.satellites.at(sat).front();
  const auto& b = back.satellites.at(sat).front();
  ASSERT_TRUE(a.position_sigma_m[0] && b.position_sigma_m[0] && a.clock_sigma_s && b.clock_sigma_s);
  EXPECT_DOUBLE_EQ(*b.position_sigma_m[0], *a.position_sigma_m[0]);
  EXPECT_DOUBLE_EQ(*b.clock_sigma_s, *a.clock_sigma_s);
}

}  // namespace
}  // namespace ppp
