// Each error term of the simulator, enabled alone, has the statistics of its
// setting: sample sigma within 10 % over a long run, Gauss-Markov
// autocorrelation exp(-1) at lag tau, the ionosphere dispersive and removed by
// the IF combination, product errors of the configured size.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/models/troposphere.h"
#include "simulation_test_util.h"

namespace ppp {
namespace {

using test::sampleSigma;
using test::shortConfig;
using test::trueStateResiduals;

constexpr double kF1 = 1575.42e6, kF2 = 1227.60e6;  // IS-GPS-200 L1/L2 [Hz]
constexpr double kC = 299792458.0;

ErrorModelConfig only(void (*enable)(ErrorModelConfig&)) {
  ErrorModelConfig e = ErrorModelConfig::none();
  enable(e);
  return e;
}

TEST(SimulationErrors, ThermalNoiseHasTheConfiguredSigma) {
  SimulationConfig c = shortConfig(FlightProfile::Loiter, 40.0,
                                   only([](ErrorModelConfig& e) { e.thermal.enabled = true; }));
  c.quantize = false;
  const SimulatedFlight f = simulateFlight(c, 21);
  std::vector<double> c1, c2, p1, p2, code_if, phase_if;
  for (const auto& r : trueStateResiduals(f, false, 5.0 * kDegToRad)) {
    c1.push_back(r.signal->code_noise1_m);
    c2.push_back(r.signal->code_noise2_m);
    p1.push_back(r.signal->phase_noise1_m);
    p2.push_back(r.signal->phase_noise2_m);
    code_if.push_back(r.code_m);
    phase_if.push_back(r.phase_m);
  }
  ASSERT_GT(c1.size(), 15000u);
  EXPECT_NEAR(sampleSigma(c1), 0.32, 0.032);
  EXPECT_NEAR(sampleSigma(c2), 0.32, 0.032);
  EXPECT_NEAR(sampleSigma(p1), 0.003, 0.0003);
  EXPECT_NEAR(sampleSigma(p2), 0.003, 0.0003);
  // Through the observations and the model: IF sigma = sqrt(alpha^2 + beta^2) sigma (2.978 for L1/L2).
  const double factor = ionosphereFreeNoiseFactor(ionosphereFreeCoefficients(kF1, kF2));
  EXPECT_NEAR(factor, 2.978, 0.001);
  EXPECT_NEAR(sampleSigma(code_if), factor * 0.32, 0.1 * factor * 0.32);
  EXPECT_NEAR(sampleSigma(phase_if), factor * 0.003, 0.1 * factor * 0.003);
}

TEST(SimulationErrors, PhaseNoiseAsAFractionOfTheWavelength) {
  // The method's table as written: 0.16 lambda (3.0 cm on L1, 3.9 cm on L2).
  ErrorModelConfig e = only([](ErrorModelConfig& x) { x.thermal.enabled = true; });
  e.thermal.phase_mode = PhaseNoiseMode::WavelengthFraction;
  const SimulatedFlight f = simulateFlight(shortConfig(FlightProfile::Loiter, 20.0, e), 22);
  std::vector<double> p1, p2;
  for (const auto& t : f.truth)
    for (const auto& s : t.signals) p1.push_back(s.phase_noise1_m), p2.push_back(s.phase_noise2_m);
  EXPECT_NEAR(sampleSigma(p1), 0.16 * kC / kF1, 0.016 * kC / kF1);
  EXPECT_NEAR(sampleSigma(p2), 0.16 * kC / kF2, 0.016 * kC / kF2);
  EXPECT_NEAR(f.drawn.phase_sigma_l1_m, 0.0304, 0.0001);
}

TEST(SimulationErrors, MultipathIsGaussMarkovWithTheConfiguredSigmaAndTimeConstant) {
  SimulationConfig c = shortConfig(FlightProfile::Climb, 60.0,
                                   only([](ErrorModelConfig& e) { e.multipath.enabled = true; }));
  c.quantize = false;
  const SimulatedFlight f = simulateFlight(c, 23);
  // Zenith-scale states per arc, in time order (1 Hz).
  std::map<ArcId, std::vector<double>> series;
  std::vector<double> all;
  for (const auto& t : f.truth)
    for (const auto& s : t.signals) {
      series[s.arc].push_back(s.multipath_unit);
      all.push_back(s.multipath_unit);
      // Elevation scaling 1/sin(el).
      ASSERT_NEAR(s.multipath1_m * std::sin(s.elevation_rad), s.multipath_unit, 1e-9);
    }
  ASSERT_GT(all.size(), 30000u);
  EXPECT_NEAR(sampleSigma(all), 0.4, 0.04);
  // Autocorrelation at lag tau = 15 s: exp(-1) = 0.368.
  double sxy = 0.0, sxx = 0.0;
  for (const auto& [arc, x] : series)
    for (std::size_t i = 0; i + 15 < x.size(); ++i) sxy += x[i] * x[i + 15], sxx += x[i] * x[i];
  EXPECT_NEAR(sxy / sxx, std::exp(-1.0), 0.05);
  // In the observations: IF code residual = alpha MP1 + beta MP2, phase untouched.
  const auto k = ionosphereFreeCoefficients(kF1, kF2);
  for (const auto& r : trueStateResiduals(f)) {
    ASSERT_NEAR(r.code_m, k.alpha * r.signal->multipath1_m + k.beta * r.signal->multipath2_m, 1e-3);
    ASSERT_LT(std::abs(r.phase_m), 1e-3);
  }
}

TEST(SimulationErrors, IonosphereIsDispersiveAndRemovedByTheIonosphereFreeCombination) {
  SimulationConfig c = shortConfig(FlightProfile::Survey, 20.0,
                                   only([](ErrorModelConfig& e) { e.ionosphere.enabled = true; }));
  c.quantize = false;
  const SimulatedFlight f = simulateFlight(c, 24);
  EXPECT_GE(f.drawn.vtec0_tecu, 5.0);
  EXPECT_LE(f.drawn.vtec0_tecu, 40.0);
  const double gamma = kF1 * kF1 / (kF2 * kF2);
  std::size_t n = 0;
  for (std::size_t k = 0; k < f.epochs.size(); ++k) {
    const auto& e = f.epochs[k];
    for (std::size_t i = 0; i < e.satellites.size(); ++i) {
      const Observation* o = e.begin(i);  // C1C L1C C1W C2W L2W
      const SignalTruth& s = f.truth[k].signals[i];
      const double I1 = s.ionosphere_l1_m;
      // Thin shell at 350 km: I1 = 40.3 VTEC / f1^2 / cos z'.
      const double vtec = f.drawn.vtec0_tecu + f.drawn.vtec_rate_tecu_per_h * (e.time - f.epochs[0].time) / 3600.0;
      const double sz = 6371.0 / (6371.0 + 350.0) * std::cos(s.elevation_rad);
      ASSERT_NEAR(I1, 40.3e16 * vtec / (kF1 * kF1) / std::sqrt(1 - sz * sz), 1e-9);
      // Code delayed, phase advanced by the same amount: P1 - L1 = 2 I1 - lambda1 (N1 + w) with N1 = 0.
      const double p1 = o[0].value.value(), l1_m = o[1].value.value() * kC / kF1, p2 = o[3].value.value(),
                   l2_m = o[4].value.value() * kC / kF2;
      ASSERT_NEAR(p1 - l1_m + kC / kF1 * s.windup_cycles, 2.0 * I1, 1e-6);
      ASSERT_NEAR(p2 - l2_m + kC / kF2 * s.windup_cycles, 2.0 * gamma * I1, 1e-6);
      ++n;
    }
  }
  ASSERT_GT(n, 5000u);
  for (const auto& r : trueStateResiduals(f)) {
    ASSERT_LT(std::abs(r.code_m), 1e-3);
    ASSERT_LT(std::abs(r.phase_m), 1e-3);
  }
}

TEST(SimulationErrors, TroposphereScalesTheDryAndWetDelays) {
  SimulationConfig c = shortConfig(FlightProfile::Climb, 10.0,
                                   only([](ErrorModelConfig& e) { e.troposphere.enabled = true; }));
  c.quantize = false;
  const SimulatedFlight f = simulateFlight(c, 25);
  EXPECT_GE(f.drawn.dry_scale, 0.95);
  EXPECT_LE(f.drawn.dry_scale, 1.05);
  EXPECT_GE(f.drawn.wet_scale, 0.5);
  EXPECT_LE(f.drawn.wet_scale, 1.5);
  EXPECT_NE(f.drawn.dry_scale, 1.0);
  // Truth ZWD: wet scale times the Hopfield zenith wet delay of the standard atmosphere.
  for (const auto& t : f.truth) {
    const double h = ecefToGeodetic(t.trajectory.position_ecef_m).height_m;
    ASSERT_NEAR(t.zwd_m, f.drawn.wet_scale * modifiedHopfieldZenithDelays(standardAtmosphere(h), h).wet_m, 1e-9);
  }
  // With the true ZWD in the state, the only residual is the dry-scale error.
  for (const auto& r : trueStateResiduals(f)) {
    ASSERT_NEAR(r.code_m, r.signal->troposphere_error_m, 1e-3);
    ASSERT_NEAR(r.phase_m, r.signal->troposphere_error_m, 1e-3);
    // ~2.1 m dry zenith delay at 1 km height: |error| <= 5 % x slant.
    ASSERT_LT(std::abs(r.signal->troposphere_error_m), 0.05 * 2.3 / std::sin(r.elevation_rad));
  }
}

TEST(SimulationErrors, ReceiverClockRandomWalkHasTheConfiguredSigma) {
  ErrorModelConfig e = only([](ErrorModelConfig& x) { x.receiver_clock.enabled = true; });
  e.receiver_clock.steps_per_hour = 0.0;
  const SimulatedFlight f = simulateFlight(shortConfig(FlightProfile::Loiter, 60.0, e), 26);
  std::vector<double> increments;
  for (std::size_t k = 1; k < f.truth.size(); ++k)
    increments.push_back((f.truth[k].clock_m - f.truth[k - 1].clock_m) / kC - f.drawn.clock_drift_s_per_s);
  ASSERT_EQ(increments.size(), 3600u);
  EXPECT_NEAR(sampleSigma(increments), 30e-9, 3e-9);  // 30 ns / sqrt(s) at 1 s
  EXPECT_NE(f.drawn.clock_drift_s_per_s, 0.0);
}

TEST(SimulationErrors, ReceiverClockDriftAndSteps) {
  ErrorModelConfig e = only([](ErrorModelConfig& x) { x.receiver_clock.enabled = true; });
  e.receiver_clock.random_walk_sigma_s = 0.0;
  e.receiver_clock.steps_per_hour = 20.0;
  const SimulatedFlight f = simulateFlight(shortConfig(FlightProfile::Loiter, 60.0, e), 27);
  int steps = 0;
  for (std::size_t k = 1; k < f.truth.size(); ++k) {
    const double d = (f.truth[k].clock_m - f.truth[k - 1].clock_m) / kC - f.drawn.clock_drift_s_per_s;
    if (std::abs(d) > 1e-12) {
      ASSERT_NEAR(std::abs(d), 100e-9, 1e-12);
      ++steps;
    }
  }
  EXPECT_EQ(steps, f.drawn.clock_steps);
  EXPECT_GE(steps, 8);  // Poisson(20): P(< 8) = 0.08 %
  EXPECT_NEAR(f.truth.front().clock_m / kC, f.drawn.clock_initial_s, 1e-15);
}

TEST(SimulationErrors, ProductErrorsHaveTheConfiguredSize) {
  std::vector<double> orbit, clock;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const SimulatedFlight f = simulateFlight(
        shortConfig(FlightProfile::Loiter, 2.0, only([](ErrorModelConfig& e) { e.products.enabled = true; })), seed);
    const GnssTime mid = f.truth[f.truth.size() / 2].trajectory.time;
    for (const auto& sat : f.truth_products.orbitSatellites()) {
      const auto a = f.products.orbit(sat, mid), b = f.truth_products.orbit(sat, mid);
      const auto ca = f.products.clock(sat, mid), cb = f.truth_products.clock(sat, mid);
      ASSERT_TRUE(a.ok() && b.ok() && ca.ok() && cb.ok());
      for (int i = 0; i < 3; ++i) orbit.push_back(a.value->position_ecef_m(i) - b.value->position_ecef_m(i));
      clock.push_back((ca.value->clock_bias_s - cb.value->clock_bias_s) * kC);
    }
  }
  ASSERT_EQ(orbit.size(), 6u * 30u * 3u);
  EXPECT_NEAR(sampleSigma(orbit), 0.05, 0.005);
  EXPECT_NEAR(sampleSigma(clock), 0.05, 0.0075);  // 180 values: 10 % is 1.9 sigma of the estimate, allow 15 %
}

TEST(SimulationErrors, DisabledTermsAreZero) {
  const SimulatedFlight f = simulateFlight(shortConfig(FlightProfile::Loiter, 1.0, ErrorModelConfig::none()), 27);
  EXPECT_TRUE(f.breaks.empty());
  for (const auto& t : f.truth) {
    EXPECT_EQ(t.clock_m, 0.0);
    for (const auto& s : t.signals) {
      EXPECT_EQ(s.ionosphere_l1_m + s.multipath1_m + s.code_noise1_m + s.phase_noise2_m + s.troposphere_error_m, 0.0);
    }
  }
  for (const auto& a : f.arcs) EXPECT_EQ(a.bias_if_m, 0.0);
}

}  // namespace
}  // namespace ppp
