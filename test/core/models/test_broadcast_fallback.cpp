// The broadcast fallback rule (models/broadcast_fallback.h), shared by the
// offline SSR products and the live input; the keys of `ssr:` that set it.
#include <gtest/gtest.h>

#include "ppp_bayes_tree/models/broadcast_fallback.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"

namespace ppp {
namespace {

TEST(BroadcastFallback, SsrServesFromMinSsrSatellitesOn) {
  BroadcastFallbackOptions o;  // defaults: on, 4 satellites
  EXPECT_EQ(chooseSsrOrBroadcast(0, o), SsrOrbitClockChoice::BroadcastFallback);
  EXPECT_EQ(chooseSsrOrBroadcast(3, o), SsrOrbitClockChoice::BroadcastFallback);
  EXPECT_EQ(chooseSsrOrBroadcast(4, o), SsrOrbitClockChoice::Ssr);
  EXPECT_EQ(chooseSsrOrBroadcast(12, o), SsrOrbitClockChoice::Ssr);
  o.min_ssr_satellites = 6;
  EXPECT_EQ(chooseSsrOrBroadcast(5, o), SsrOrbitClockChoice::BroadcastFallback);
  EXPECT_EQ(chooseSsrOrBroadcast(6, o), SsrOrbitClockChoice::Ssr);
}

TEST(BroadcastFallback, OffTheSsrAnswersAlwaysServe) {
  BroadcastFallbackOptions o;
  o.enabled = false;
  EXPECT_EQ(chooseSsrOrBroadcast(0, o), SsrOrbitClockChoice::Ssr);
  EXPECT_EQ(ssrOrbitClockChoiceName(SsrOrbitClockChoice::BroadcastFallback), "broadcast fallback");
}

TEST(BroadcastFallback, BroadcastSigmasAreWidenedNeverNarrowed) {
  BroadcastFallbackOptions o;
  o.orbit_sigma_m = 2.0;
  o.clock_sigma_m = 3.0;
  auto orbit = EphemerisAnswer<EphemerisOrbit>::success(EphemerisOrbit{});
  widenForFallback(orbit, o);  // no URA: the fallback sigma
  EXPECT_DOUBLE_EQ(*orbit.value->position_sigma_m, 2.0);
  orbit.value->position_sigma_m = 5.7;  // a URA index of 5.7 m stays
  widenForFallback(orbit, o);
  EXPECT_DOUBLE_EQ(*orbit.value->position_sigma_m, 5.7);
  EphemerisClock c;
  c.clock_sigma_m = 1.0;
  auto clock = EphemerisAnswer<EphemerisClock>::success(c);
  widenForFallback(clock, o);
  EXPECT_DOUBLE_EQ(*clock.value->clock_sigma_m, 3.0);
  auto missing = EphemerisAnswer<EphemerisClock>::unavailable(EphemerisUnavailable::NoProducts, "none");
  widenForFallback(missing, o);  // nothing to widen
  EXPECT_FALSE(missing.ok());
}

TEST(BroadcastFallback, TheSsrSectionKeysSetIt) {
  const PppConfig defaults = bindPppConfig(YAML::Load("{}"), "test");
  EXPECT_TRUE(defaults.ssr.fallback.enabled);
  EXPECT_EQ(defaults.ssr.fallback.min_ssr_satellites, 4);
  const PppConfig c = bindPppConfig(
      YAML::Load("ssr: {broadcast_fallback: false, min_ssr_satellites: 6, broadcast_orbit_sigma_m: 3.5, "
                 "broadcast_clock_sigma_m: 1.5}"),
      "test");
  EXPECT_FALSE(c.ssr.fallback.enabled);
  EXPECT_EQ(c.ssr.fallback.min_ssr_satellites, 6);
  EXPECT_DOUBLE_EQ(c.ssr.fallback.orbit_sigma_m, 3.5);
  EXPECT_DOUBLE_EQ(c.ssr.fallback.clock_sigma_m, 1.5);
  EXPECT_THROW(bindPppConfig(YAML::Load("ssr: {min_ssr_satellites: 0}"), "test"), ConfigError);
  EXPECT_THROW(bindPppConfig(YAML::Load("ssr: {broadcast_orbit_sigma_m: 5000.0}"), "test"), ConfigError);
}

}  // namespace
}  // namespace ppp
