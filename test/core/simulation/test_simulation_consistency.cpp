// The simulator's observations against the project's measurement model: with
// every error term off (or only terms the model represents exactly: receiver
// clock, ambiguities, ionosphere which the IF combination removes), the
// residuals at the true state are below 1 mm (first test).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/products/sp3_reader.h"
#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "simulation_test_util.h"
#include "test_support.h"

namespace ppp {
namespace {

using test::shortConfig;
using test::trueStateResiduals;

struct MaxResidual {
  double code = 0.0, phase = 0.0;
  std::size_t count = 0;
};

MaxResidual maxResiduals(const SimulatedFlight& f, bool estimator_products = false) {
  MaxResidual m;
  for (const auto& r : trueStateResiduals(f, estimator_products)) {
    m.code = std::max(m.code, std::abs(r.code_m));
    m.phase = std::max(m.phase, std::abs(r.phase_m));
    ++m.count;
  }
  return m;
}

TEST(SimulationConsistency, NoiseFreeObservationsGiveSubMillimetreResiduals) {
  for (FlightProfile p : {FlightProfile::Loiter, FlightProfile::Survey, FlightProfile::Figure8, FlightProfile::Climb}) {
    SimulationConfig c = shortConfig(p, 5.0, ErrorModelConfig::none());
    c.quantize = false;
    const SimulatedFlight f = simulateFlight(c, 11);
    const MaxResidual m = maxResiduals(f);
    ASSERT_GT(m.count, 5u * 300u) << flightProfileName(p);  // >= 5 satellites above 7 deg per epoch
    EXPECT_LT(m.code, 1e-3) << flightProfileName(p);
    EXPECT_LT(m.phase, 1e-3) << flightProfileName(p);
    std::printf("%s: %zu residuals, max |code| %.2e m, max |phase| %.2e m\n", flightProfileName(p), m.count, m.code,
                m.phase);
    // The estimator's products are the truth when product errors are off.
    const MaxResidual e = maxResiduals(f, true);
    EXPECT_LT(std::max(e.code, e.phase), 1e-3);
  }
}

TEST(SimulationConsistency, ExactlyModelledTermsKeepSubMillimetreResiduals) {
  // Receiver clock (state), integer ambiguities (truth arc bias), first-order
  // ionosphere (removed by IF), at 10 Hz.
  ErrorModelConfig e = ErrorModelConfig::none();
  e.receiver_clock.enabled = true;
  e.ambiguity.enabled = true;
  e.ionosphere.enabled = true;
  SimulationConfig c = shortConfig(FlightProfile::Climb, 2.0, e);
  c.rate_hz = 10.0;
  c.quantize = false;
  const SimulatedFlight f = simulateFlight(c, 12);
  ASSERT_EQ(f.epochs.size(), 1201u);
  const MaxResidual m = maxResiduals(f);
  EXPECT_LT(m.code, 1e-3);
  EXPECT_LT(m.phase, 1e-3);
  EXPECT_GT(std::abs(f.truth.back().clock_m), 1.0);  // the clock is really there (~1 us * c)
}

TEST(SimulationConsistency, QuantizedObservationsStayWithinTheRinexResolution) {
  // RINEX F14.3: codes to 1 mm, phases to 0.001 cycle; the IF combination
  // amplifies the rounding by at most |alpha| + |beta| = 4.09 (0.5 mm code ->
  // 2.05 mm, 0.0005 cycle * 0.244 m -> 0.5 mm phase).
  SimulationConfig c = shortConfig(FlightProfile::Loiter, 5.0, ErrorModelConfig::none());
  c.errors.ambiguity.enabled = true;
  const SimulatedFlight f = simulateFlight(c, 13);
  const MaxResidual m = maxResiduals(f);
  EXPECT_LT(m.code, 2.05e-3);
  EXPECT_LT(m.phase, 1e-3);
}

TEST(SimulationConsistency, RealProductsGiveSubMillimetreResiduals) {
  PPP_REQUIRE_SHARED_DATA();
  SimulationSources src;
  src.sp3 = readSp3(test::dataPath("zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3"));
  src.clk = readRinexClock(test::dataPath("zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK"));
  SimulationConfig c = shortConfig(FlightProfile::Survey, 10.0, ErrorModelConfig::none());
  c.quantize = false;
  const SimulatedFlight f = simulateFlight(c, 14, src);
  // Default start: 10 min after the products start (00:10 GPST).
  EXPECT_EQ(f.truth.front().trajectory.time, test::gpst(2026, 5, 13, 0, 10, 0.0));
  const MaxResidual m = maxResiduals(f);
  ASSERT_GT(m.count, 5u * 600u);
  EXPECT_LT(m.code, 1e-3);
  EXPECT_LT(m.phase, 1e-3);
}

TEST(SimulationConsistency, TruthArcBiasIsTheIonosphereFreeAmbiguity) {
  SimulationConfig c = shortConfig(FlightProfile::Loiter, 2.0, ErrorModelConfig::none());
  c.errors.ambiguity.enabled = true;
  const SimulatedFlight f = simulateFlight(c, 15);
  ASSERT_FALSE(f.arcs.empty());
  const double f1 = 1575.42e6, f2 = 1227.60e6, c_light = 299792458.0;  // IS-GPS-200 L1/L2
  const auto k = ionosphereFreeCoefficients(f1, f2);
  bool nonzero = false;
  for (const auto& a : f.arcs) {
    EXPECT_LE(std::abs(a.n1_cycles), 1000);
    EXPECT_LE(std::abs(a.n2_cycles), 1000);
    EXPECT_NEAR(a.bias_if_m, k.alpha * c_light / f1 * a.n1_cycles + k.beta * c_light / f2 * a.n2_cycles, 1e-9);
    nonzero |= a.n1_cycles != 0;
  }
  EXPECT_TRUE(nonzero);
  const SatelliteId sat = f.epochs[10].satellites[0].satellite;
  ASSERT_NE(f.signal(10, sat), nullptr);
  EXPECT_EQ(f.truthBias_m(10, sat), f.arcs[f.signal(10, sat)->arc - 1].bias_if_m);
  EXPECT_FALSE(f.truthBias_m(10, SatelliteId{GnssSystem::GPS, 99}).has_value());
  EXPECT_EQ(f.signal(f.epochs.size(), sat), nullptr);
}

}  // namespace
}  // namespace ppp
