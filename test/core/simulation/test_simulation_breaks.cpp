// Attitude-dependent phase breaks: in the banked turns of the
// figure-eight the airframe masks satellites; each reacquisition starts a new
// arc with a new ambiguity (an injected cycle slip), and the project's
// preprocessing (ArcTracker, default options) detects >= 99 % of them.
#include <gtest/gtest.h>

#include <cmath>

#include "ppp_bayes_tree/ppp/model/arc_tracker.h"
#include "ppp_bayes_tree/ppp/model/signal_selection.h"
#include "simulation_test_util.h"

namespace ppp {
namespace {

struct Detection {
  std::size_t injected = 0, detected = 0;
  std::size_t new_arcs = 0;  // all arcs the tracker started
};

Detection detectBreaks(const SimulatedFlight& f) {
  SignalSelector selector(f.header, SignalSelectionOptions{}, nullptr);
  ArcTracker tracker;
  // (satellite, reacquisition time) -> detected
  std::map<std::pair<SatelliteId, GnssTime>, bool> injected;
  for (const auto& b : f.breaks) injected[{b.satellite, b.reacquired}] = false;
  Detection d;
  for (const auto& e : f.epochs) {
    const auto sel = selector.select(e);
    const ArcEpochResult r = tracker.process(e.time, sel.observations);
    for (const auto& s : r.satellites) {
      if (!s.new_arc) continue;
      ++d.new_arcs;
      auto it = injected.find({s.satellite, e.time});
      if (it != injected.end()) it->second = true;
    }
  }
  d.injected = injected.size();
  for (const auto& [key, found] : injected) d.detected += found ? 1 : 0;
  return d;
}

TEST(SimulationBreaks, BanksOfTheFigureEightMaskSatellites) {
  SimulationConfig c;
  c.profile = FlightProfile::Figure8;
  c.duration_s = 15.0 * 60.0;
  const SimulatedFlight f = simulateFlight(c, 31);
  ASSERT_GT(f.breaks.size(), 20u);
  for (const auto& b : f.breaks) {
    // The outage happens in a bank: the roll reaches at least 10 deg, and the
    // satellite sinks below the 5-deg body mask.
    EXPECT_GT(b.max_roll_rad, 10.0 * kDegToRad);
    EXPECT_LT(b.min_body_elevation_rad, 5.0 * kDegToRad);
    EXPECT_GE(b.reacquired - b.last_tracked, 2.0);  // reacquisition time 2 s
    const TruthArc& a = f.arcs.at(b.new_arc - 1);
    const TruthArc& p = f.arcs.at(b.previous_arc - 1);
    EXPECT_EQ(a.satellite, b.satellite);
    EXPECT_TRUE(a.after_phase_break);
    EXPECT_EQ(a.first_time, b.reacquired);
    EXPECT_EQ(p.last_time, b.last_tracked);
    EXPECT_TRUE(a.n1_cycles != p.n1_cycles || a.n2_cycles != p.n2_cycles);
  }
  // A level loiter (5-deg bank) breaks far fewer arcs per hour than the figure-eight.
  SimulationConfig l = c;
  l.profile = FlightProfile::Loiter;
  const SimulatedFlight level = simulateFlight(l, 31);
  EXPECT_LT(level.breaks.size() * 5, f.breaks.size());
}

TEST(SimulationBreaks, ArcTrackerDetectsTheInjectedSlips) {
  for (FlightProfile p : {FlightProfile::Figure8, FlightProfile::Survey}) {
    SimulationConfig c;  // every error term on, as in the Monte Carlo
    c.profile = p;
    c.duration_s = 20.0 * 60.0;
    const SimulatedFlight f = simulateFlight(c, 32);
    const Detection d = detectBreaks(f);
    ASSERT_GT(d.injected, 10u) << flightProfileName(p);
    EXPECT_GE(static_cast<double>(d.detected), 0.99 * static_cast<double>(d.injected))
        << flightProfileName(p) << ": " << d.detected << " of " << d.injected;
    std::printf("%s: %zu of %zu injected slips detected, %zu arcs started by the tracker, %zu simulated arcs\n",
                flightProfileName(p), d.detected, d.injected, d.new_arcs, f.arcs.size());
  }
}

TEST(SimulationBreaks, ShortOutagesAreFoundByTheSlipTestsNotOnlyAsGaps) {
  // Immediate reacquisition: outages of one or two epochs at 1 Hz, below the
  // tracker's 3-interval gap, so the MW / GF tests must see the new ambiguity.
  SimulationConfig c;
  c.profile = FlightProfile::Figure8;
  c.duration_s = 20.0 * 60.0;
  c.errors.phase_breaks.reacquisition_s = 0.0;
  const SimulatedFlight f = simulateFlight(c, 34);
  std::size_t short_outages = 0;
  for (const auto& b : f.breaks) short_outages += (b.reacquired - b.last_tracked) <= 3.0 ? 1 : 0;
  ASSERT_GT(short_outages, 10u);
  const Detection d = detectBreaks(f);
  EXPECT_GE(static_cast<double>(d.detected), 0.99 * static_cast<double>(d.injected))
      << d.detected << " of " << d.injected;
  std::printf("figure8, immediate reacquisition: %zu of %zu detected (%zu outages <= 3 s)\n", d.detected, d.injected,
              short_outages);
}

TEST(SimulationBreaks, LossOfLockFlagsMarkReacquisitionsWhenAsked) {
  SimulationConfig c;
  c.profile = FlightProfile::Figure8;
  c.duration_s = 5.0 * 60.0;
  c.loss_of_lock_flags = true;
  const SimulatedFlight f = simulateFlight(c, 33);
  ASSERT_FALSE(f.breaks.empty());
  std::size_t flagged = 0;
  for (const auto& e : f.epochs)
    for (std::size_t i = 0; i < e.satellites.size(); ++i) {
      const Observation* o = e.begin(i);
      if (o[1].lli && (*o[1].lli & 1)) {
        ++flagged;
        bool is_break = false;
        for (const auto& b : f.breaks) is_break |= b.satellite == e.satellites[i].satellite && b.reacquired == e.time;
        EXPECT_TRUE(is_break);
      }
    }
  EXPECT_EQ(flagged, f.breaks.size());
}

}  // namespace
}  // namespace ppp
