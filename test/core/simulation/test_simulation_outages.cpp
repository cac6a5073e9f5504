// GNSS outages of the simulation (observations.outages): no epoch inside an
// outage, every satellite reacquired on a new arc afterwards, the header's
// first/last observation those written, the configuration checked.
#include <gtest/gtest.h>

#include <set>

#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/simulation/simulation_config.h"
#include "ppp_bayes_tree/simulation/simulation_writers.h"

namespace ppp {
namespace {

SimulationConfig tenMinutes() {
  SimulationConfig c;
  c.duration_s = 600.0;
  return c;
}

std::string configError(const std::string& yaml) {
  try {
    parseSimulationConfig(yaml, "test.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(SimulationOutages, ParsedFromTheYamlAndChecked) {
  const SimulationConfig c = parseSimulationConfig(
      "observations: { outages: { start_s: [60, 200, 400], duration_s: [10, 30, 60] } }", "test.yaml");
  ASSERT_EQ(c.outages.size(), 3u);
  EXPECT_EQ(c.outages[1].start_s, 200.0);
  EXPECT_EQ(c.outages[2].duration_s, 60.0);
  EXPECT_TRUE(c.inOutage(60.0));
  EXPECT_TRUE(c.inOutage(69.0));
  EXPECT_FALSE(c.inOutage(70.0));
  EXPECT_FALSE(c.inOutage(59.0));
  EXPECT_TRUE(SimulationConfig{}.outages.empty());  // off by default
  EXPECT_NE(configError("observations: { outages: { start_s: [60, 200], duration_s: [10] } }")
                .find("observations.outages.duration_s"),
            std::string::npos);
  EXPECT_NE(configError("observations: { outages: { start_s: [-5], duration_s: [10] } }").find("start_s"),
            std::string::npos);
  EXPECT_NE(configError("observations: { outages: { start_s: [5], duration_s: [0] } }").find("duration_s"),
            std::string::npos);
  EXPECT_NE(configError("observations: { outages: { start_s: [5], duration_s: [ten] } }").find("\"ten\""),
            std::string::npos);
}

bool sameEpoch(const ObsEpoch& a, const ObsEpoch& b) {
  if (!(a.time == b.time) || a.observations.size() != b.observations.size()) return false;
  for (std::size_t i = 0; i < a.observations.size(); ++i)
    if (a.observations[i].value != b.observations[i].value) return false;
  return true;
}

// 601 epochs; outages of 10, 30 and 60 s, each followed by the 2-s reacquisition:
// 601 - 100 - 3 * 2 = 495 epochs. Before the first outage the observations are
// those of the flight without outages.
TEST(SimulationOutages, NoEpochInAnOutageAndNewArcsAfterIt) {
  const SimulatedFlight plain = simulateFlight(tenMinutes(), 4);
  SimulationConfig c = tenMinutes();
  c.outages = {{60.0, 10.0}, {200.0, 30.0}, {400.0, 60.0}};
  const SimulatedFlight f = simulateFlight(c, 4);
  const GnssTime t0 = plain.epochs.front().time;
  ASSERT_EQ(plain.epochs.size(), 601u);
  EXPECT_EQ(f.epochs.size(), 495u);
  ASSERT_EQ(f.truth.size(), f.epochs.size());
  for (std::size_t k = 0; k < f.epochs.size(); ++k) {
    const double since = f.epochs[k].time - t0;
    EXPECT_FALSE(c.inOutage(since)) << since;
    EXPECT_FALSE(f.epochs[k].satellites.empty()) << since;
    EXPECT_TRUE(f.truth[k].trajectory.time == f.epochs[k].time);
    if (since < 60.0) EXPECT_TRUE(sameEpoch(f.epochs[k], plain.epochs[k])) << since;
  }
  for (const auto& o : c.outages) {
    const GnssTime end = t0 + (o.start_s + o.duration_s);
    std::size_t k = 0;
    while (f.epochs[k].time < end) ++k;
    EXPECT_NEAR(f.epochs[k].time - end, 2.0, 1e-9);  // reacquisition_s
    for (const SignalTruth& s : f.truth[k].signals) EXPECT_TRUE(f.arcs[s.arc - 1].first_time == f.epochs[k].time);
  }
}

TEST(SimulationOutages, KeepsLockParsedPerOutageOrForAll) {
  const SimulationConfig none = parseSimulationConfig(
      "observations: { outages: { start_s: [60, 200], duration_s: [5, 5] } }", "test.yaml");
  EXPECT_FALSE(none.outages[0].keeps_lock);  // default: new ambiguities
  const SimulationConfig all = parseSimulationConfig(
      "observations: { outages: { start_s: [60, 200], duration_s: [5, 5], keeps_lock: [true] } }", "test.yaml");
  EXPECT_TRUE(all.outages[0].keeps_lock && all.outages[1].keeps_lock);
  const SimulationConfig each = parseSimulationConfig(
      "observations: { outages: { start_s: [60, 200], duration_s: [5, 5], keeps_lock: [false, true] } }",
      "test.yaml");
  EXPECT_FALSE(each.outages[0].keeps_lock);
  EXPECT_TRUE(each.outages[1].keeps_lock);
  EXPECT_NE(configError("observations: { outages: { start_s: [60, 200, 300], duration_s: [5, 5, 5], "
                        "keeps_lock: [true, false] } }")
                .find("observations.outages.keeps_lock"),
            std::string::npos);
  EXPECT_NE(configError("observations: { outages: { start_s: [60], duration_s: [5], keeps_lock: [yes] } }")
                .find("\"yes\""),
            std::string::npos);
}

// An outage that keeps lock: no epoch inside it, and at the first epoch after it
// (at once, no reacquisition time) every satellite tracked before and still
// visible is on the arc it had before (same ambiguities).
TEST(SimulationOutages, OutageThatKeepsLockKeepsTheArcs) {
  const SimulatedFlight plain = simulateFlight(tenMinutes(), 4);
  SimulationConfig c = tenMinutes();
  c.outages = {{200.0, 5.0, true}};
  const SimulatedFlight f = simulateFlight(c, 4);
  const GnssTime t0 = plain.epochs.front().time;
  EXPECT_EQ(f.epochs.size(), plain.epochs.size() - 5u);
  std::size_t k = 0;
  while (f.epochs[k].time - t0 < 205.0 - 1e-9) ++k;
  EXPECT_NEAR(f.epochs[k].time - t0, 205.0, 1e-9);
  EXPECT_NEAR(f.epochs[k - 1].time - t0, 199.0, 1e-9);
  std::set<ArcId> before;
  for (const SignalTruth& s : f.truth[k - 1].signals) before.insert(s.arc);
  ASSERT_FALSE(before.empty());
  for (const SignalTruth& s : f.truth[k].signals) EXPECT_EQ(before.count(s.arc), 1u) << s.satellite.toString();
}

TEST(SimulationOutages, HeaderSpansTheEpochsWrittenAndAllOutageIsRefused) {
  SimulationConfig c = tenMinutes();
  c.outages = {{0.0, 20.0}, {590.0, 100.0}};
  const SimulatedFlight f = simulateFlight(c, 5);
  const GnssTime t0 = simulateFlight(tenMinutes(), 5).epochs.front().time;
  ASSERT_TRUE(f.header.time_of_first_obs.has_value());
  EXPECT_TRUE(f.header.time_of_first_obs->time == f.epochs.front().time);
  EXPECT_TRUE(f.header.time_of_last_obs->time == f.epochs.back().time);
  EXPECT_NEAR(f.epochs.front().time - t0, 22.0, 1e-9);
  EXPECT_LT(f.epochs.back().time - t0, 590.0);
  c.outages = {{0.0, 1000.0}};
  EXPECT_THROW(simulateFlight(c, 5), std::invalid_argument);
}

}  // namespace
}  // namespace ppp
