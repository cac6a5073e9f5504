// Galileo in the simulator: the nominal Walker 24/3/1 constellation at
// 23 222 km (geometry, period, planes), E1/E5a observations with their own
// receiver clock and integer ambiguities, and a GPS+Galileo simulated flight
// solved by the EKF with one receiver clock per system.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <set>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_ekf.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/simulation/gps_constellation.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"

using namespace ppp;

namespace {

/// ECEF -> inertial (the constellation's frame: Greenwich on x at t_ref).
Eigen::Vector3d inertial(const Eigen::Vector3d& ecef, double dt_s) {
  return Eigen::AngleAxisd(kEarthRotationRate_radps * dt_s, Eigen::Vector3d::UnitZ()) * ecef;
}

}  // namespace

// The Walker parameters give the geometry: 24 satellites E01..E24 on circular
// orbits of radius 6378.137 + 23 222 km, 3 planes 120 deg apart at 56 deg
// inclination with 8 satellites each, and the period 2 pi sqrt(a^3/GM): 14 h 04 min
// 42 s, within 5 s of the published nominal 14 h 04 min 45 s (Navipedia, "Galileo
// Space Segment"; ESA quotes its semi-major axis 29 600.318 km, ours is 181 m less).
TEST(GalileoConstellation, WalkerGeometryPeriodAndPlanes) {
  WalkerConstellationOptions o = galileoWalkerOptions();
  o.reference_time = GnssTime::fromCalendar({2026, 5, 13, 0, 0, 0.0}, TimeSystem::GPS);
  const WalkerConstellation c(o);
  ASSERT_EQ(c.satellites().size(), 24u);
  EXPECT_EQ(c.satellites().front().satellite.toString(), "E01");
  EXPECT_EQ(c.satellites().back().satellite.toString(), "E24");
  const double a = 6378137.0 + 23222.0e3;
  EXPECT_DOUBLE_EQ(o.semi_major_axis_m, a);
  const double period = c.period_s();
  EXPECT_NEAR(period, 14 * 3600 + 4 * 60 + 45, 5.0);
  std::vector<Eigen::Vector3d> normals;
  for (std::size_t i = 0; i < c.satellites().size(); ++i) {
    Eigen::Vector3d p0, v0, p1, v1;
    const GnssTime t = o.reference_time + 1234.0;
    c.state(i, t, p0, v0);
    c.state(i, t + period, p1, v1);
    EXPECT_NEAR(p0.norm(), a, 1e-3);
    // One period later the satellite is back at its inertial position.
    EXPECT_LT((inertial(p1, 1234.0 + period) - inertial(p0, 1234.0)).norm(), 1e-3);
    // Orbit normal from the inertial velocity (ECEF velocity + omega x r).
    const Eigen::Vector3d vi = inertial(v0 + Eigen::Vector3d(0, 0, kEarthRotationRate_radps).cross(p0), 1234.0);
    const Eigen::Vector3d n = inertial(p0, 1234.0).cross(vi).normalized();
    EXPECT_NEAR(std::acos(n.z()) * kRadToDeg, 56.0, 1e-6);
    normals.push_back(n);
  }
  // Planes: satellites with the same orbit normal.
  std::vector<Eigen::Vector3d> planes;
  std::vector<int> members;
  for (const auto& n : normals) {
    auto it = std::find_if(planes.begin(), planes.end(), [&](const Eigen::Vector3d& p) { return (p - n).norm() < 1e-9; });
    if (it == planes.end()) {
      planes.push_back(n);
      members.push_back(1);
    } else {
      ++members[static_cast<std::size_t>(it - planes.begin())];
    }
  }
  ASSERT_EQ(planes.size(), 3u);
  for (int m : members) EXPECT_EQ(m, 8);
  for (std::size_t i = 0; i < 3; ++i) {  // ascending nodes 120 deg apart
    const Eigen::Vector3d ni = Eigen::Vector3d::UnitZ().cross(planes[i]).normalized();
    const Eigen::Vector3d nj = Eigen::Vector3d::UnitZ().cross(planes[(i + 1) % 3]).normalized();
    EXPECT_NEAR(std::acos(std::clamp(ni.dot(nj), -1.0, 1.0)) * kRadToDeg, 120.0, 1e-6);
  }
}

// Noise-free GPS+Galileo flight with integer ambiguities and phase OSBs: Galileo
// satellites carry C1C/L1C/C5Q/L5Q on E1/E5a, the IF phase minus the IF code is
// the arc's integer bias (E1/E5a wavelengths) plus the wind-up and the published
// UPDs, and the Galileo receiver clock is the GPS one plus a constant offset.
TEST(GalileoSimulation, E1E5aObservationsIntegerArcsAndOwnClock) {
  SimulationConfig c;
  c.errors = ErrorModelConfig::none();
  c.errors.ambiguity.enabled = true;
  c.errors.ambiguity.satellite_phase_biases = true;
  c.errors.receiver_clock.enabled = true;
  c.systems = {GnssSystem::GPS, GnssSystem::Galileo};
  c.duration_s = 120.0;
  c.quantize = false;
  const SimulatedFlight f = simulateFlight(c, 11);
  EXPECT_EQ(f.header.file_system, 'M');
  const auto& e_types = f.header.obs_types[static_cast<int>(GnssSystem::Galileo)];
  ASSERT_EQ(e_types.size(), 4u);
  EXPECT_EQ(e_types[2].toString(), "C5Q");
  EXPECT_EQ(e_types[3].toString(), "L5Q");
  const double f1 = *carrierFrequency_hz(GnssSystem::Galileo, '1'), f5 = *carrierFrequency_hz(GnssSystem::Galileo, '5');
  EXPECT_DOUBLE_EQ(f1, 1575.42e6);
  EXPECT_DOUBLE_EQ(f5, 1176.45e6);
  const double l1 = kSpeedOfLight_mps / f1, l5 = kSpeedOfLight_mps / f5;
  const auto k = ionosphereFreeCoefficients(f1, f5);
  std::set<SatelliteId> galileo;
  int checked = 0;
  EXPECT_NE(f.drawn.galileo_clock_offset_s, 0.0);
  for (std::size_t e = 0; e < f.epochs.size(); ++e) {
    const TruthEpoch& te = f.truth[e];
    EXPECT_NEAR(te.galileo_clock_m - te.clock_m, f.drawn.galileo_clock_offset_s * kSpeedOfLight_mps, 1e-6);
    for (const auto& so : f.epochs[e].satellites) {
      if (so.satellite.system != GnssSystem::Galileo) continue;
      galileo.insert(so.satellite);
      ASSERT_EQ(so.count, 4u);
      const auto* o = &f.epochs[e].observations[so.first];
      const double p1 = *o[0].value, L1 = *o[1].value, p5 = *o[2].value, L5 = *o[3].value;
      const SignalTruth* s = f.signal(e, so.satellite);
      ASSERT_NE(s, nullptr);
      const auto upd = f.phase_biases.upd(so.satellite);
      const double phase_if = ionosphereFree(L1 * l1, L5 * l5, k), code_if = ionosphereFree(p1, p5, k);
      const double expected = f.arcs[s->arc - 1].bias_if_m + kSpeedOfLight_mps / (f1 + f5) * s->windup_cycles +
                              ionosphereFree(upd.l1_cycles * l1, upd.l2_cycles * l5, k);
      EXPECT_NEAR(phase_if - code_if, expected, 1e-6) << so.satellite.toString();
      // The published phase OSB of L5Q is the UPD of the second frequency.
      const BiasAnswer b = f.phase_biases.phaseBias(so.satellite, o[3].code, te.trajectory.time);
      ASSERT_TRUE(b.value_m.has_value());
      EXPECT_NEAR(*b.value_m, upd.l2_cycles * l5, 1e-12);
      ++checked;
    }
  }
  std::printf("%zu Galileo satellites tracked, %d observations checked; clock offset %.2f ns\n", galileo.size(),
              checked, f.drawn.galileo_clock_offset_s * 1e9);
  EXPECT_GE(galileo.size(), 5u);
}

// A GPS+Galileo simulated 15-min loiter (the full error model, products with
// errors) solved by the EKF with one clock per system: it uses Galileo
// satellites, converges, and estimates both clocks (their difference near the
// simulated offset; the estimated clocks absorb the IF code biases, which the
// simulation does not have, so they match the truth).
TEST(GalileoSimulation, GpsGalileoFlightConvergesWithTwoClocks) {
  MonteCarloOptions o;
  o.flights = 1;
  o.seed = 3;
  o.duration_s = 900.0;
  o.profiles = {FlightProfile::Loiter};
  o.simulation.systems = {GnssSystem::GPS, GnssSystem::Galileo};
  // White code weighting, with which the bounds below were measured: first 2 min
  // 1.485 m, last 5 min 0.487 m. With the 15-s Gauss-Markov code model (1-Hz code
  // weighted 30x less) the start is better and the end a little worse on this
  // flight: 0.840 m and 0.503 m, so "halved" and "< 0.5 m" no longer both hold.
  o.ppp.stochastic.code_correlation_time_s = 0.0;
  const MonteCarloFlightSetup setup = monteCarloFlightSetup(o, 0);
  const SimulatedFlight f = simulateFlight(monteCarloSimulationConfig(o, setup), setup.seed);
  const PppConfig config = flightPppConfig(o.ppp, f);
  ASSERT_EQ(config.signals.systems.size(), 2u);
  PppInMemoryInputs in;
  in.header = &f.header;
  in.epochs = &f.epochs;
  in.products = &f.products;
  PppPipeline pipeline(in, config);
  const std::unique_ptr<PppEkf> ekf_made = makeEstimatorAs<PppEkf>("ekf", config);
  PppEkf& ekf = *ekf_made;
  std::size_t k = 0, galileo_used_epochs = 0;
  std::vector<double> error_m, offset_error_m;
  double clock_error_m = 0.0;
  pipeline.run(ekf, [&](const PppEpochRecord& rec) {
    const std::size_t e = k++;
    if (!rec.solution.position_ecef_m) return;
    int galileo = 0;
    for (const auto& s : rec.used) galileo += s.system == GnssSystem::Galileo ? 1 : 0;
    if (galileo >= 4) ++galileo_used_epochs;
    error_m.push_back((*rec.solution.position_ecef_m - f.truth[e].trajectory.position_ecef_m).norm());
    const ReceiverState x = ekf.receiverState();
    ASSERT_EQ(x.layout.clockCount(), 2);
    clock_error_m = x.clock_m(GnssSystem::GPS) - f.truth[e].clock_m;
    offset_error_m.push_back((x.clock_m(GnssSystem::Galileo) - x.clock_m(GnssSystem::GPS)) -
                             (f.truth[e].galileo_clock_m - f.truth[e].clock_m));
  });
  ASSERT_GT(error_m.size(), 600u);
  auto mean = [](const std::vector<double>& v, std::size_t from, std::size_t to) {
    double s = 0.0;
    for (std::size_t i = from; i < to; ++i) s += v[i];
    return s / static_cast<double>(to - from);
  };
  const std::size_t n = error_m.size();
  const double first = mean(error_m, 0, 120), last = mean(error_m, n - 300, n);
  const double offset_last = mean(offset_error_m, n - 300, n);
  std::printf("%zu epochs, %zu with >= 4 Galileo satellites used; mean 3D error first 2 min %.3f m, last 5 min "
              "%.3f m; GPS clock error at the end %.3f m; Galileo-GPS clock offset %.2f m, its mean error over the "
              "last 5 min %.3f m\n",
              k, galileo_used_epochs, first, last, clock_error_m, f.drawn.galileo_clock_offset_s * kSpeedOfLight_mps,
              offset_last);
  EXPECT_GT(galileo_used_epochs, k * 9 / 10);
  EXPECT_LT(last, 0.5 * first);
  EXPECT_LT(last, 0.5);
  // The offset is estimated from the codes (IF code noise ~1 m per satellite)
  // and the phases over the arcs: decimetres, against an offset of metres.
  EXPECT_LT(std::abs(offset_last), 0.5);
  EXPECT_GT(std::abs(f.drawn.galileo_clock_offset_s * kSpeedOfLight_mps), 1.0);  // seed 3: 18.7 m (a real test)
}

// Galileo has its own random streams (geometry, clocks, clock offset, per
// satellite): adding it leaves every GPS observation of a flight bit-identical,
// so GPS-only studies keep their numbers.
TEST(GalileoSimulation, AddingGalileoLeavesTheGpsObservationsUnchanged) {
  SimulationConfig c;
  c.duration_s = 60.0;
  const SimulatedFlight g = simulateFlight(c, 5);
  c.systems = {GnssSystem::GPS, GnssSystem::Galileo};
  const SimulatedFlight ge = simulateFlight(c, 5);
  ASSERT_EQ(g.epochs.size(), ge.epochs.size());
  std::size_t compared = 0, galileo = 0;
  for (std::size_t e = 0; e < g.epochs.size(); ++e) {
    std::vector<std::pair<std::string, double>> a, b;
    for (const auto& so : g.epochs[e].satellites)
      for (std::uint32_t i = 0; i < so.count; ++i) {
        const auto& o = g.epochs[e].observations[so.first + i];
        a.push_back({so.satellite.toString() + o.code.toString(), *o.value});
      }
    for (const auto& so : ge.epochs[e].satellites) {
      if (so.satellite.system != GnssSystem::GPS) {
        ++galileo;
        continue;
      }
      for (std::uint32_t i = 0; i < so.count; ++i) {
        const auto& o = ge.epochs[e].observations[so.first + i];
        b.push_back({so.satellite.toString() + o.code.toString(), *o.value});
      }
    }
    ASSERT_EQ(a, b) << "epoch " << e;
    compared += a.size();
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_GT(galileo, 100u);
  EXPECT_EQ(g.truth.back().clock_m, ge.truth.back().clock_m);
}

TEST(GalileoSimulation, ConfigurationSpellsTheSystems) {
  const SimulationConfig ge = parseSimulationConfig("constellation: { systems: GE, galileo_satellites: 22 }", "t.yaml");
  ASSERT_EQ(ge.systems.size(), 2u);
  EXPECT_TRUE(ge.simulates(GnssSystem::Galileo));
  EXPECT_EQ(ge.galileo_satellites, 22);
  EXPECT_FALSE(SimulationConfig{}.simulates(GnssSystem::Galileo));
  EXPECT_THROW(parseSimulationConfig("constellation: { systems: GR }", "t.yaml"), ConfigError);
  SimulationConfig bad;
  bad.systems = {GnssSystem::GPS, GnssSystem::BeiDou};
  EXPECT_THROW(simulateFlight(bad, 1), std::invalid_argument);
}
