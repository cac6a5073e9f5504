// Simulator files: determinism (same seed -> identical bytes), RINEX 3 / SP3 /
// RINEX clock round trips through our readers, configuration loading.
#include <gtest/gtest.h>

#include <filesystem>
#include <thread>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/products/sp3_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "ppp_bayes_tree/simulation/simulation_writers.h"
#include "simulation_test_util.h"
#include "test_support.h"

namespace ppp {
namespace {

SimulationConfig smallConfig() {
  SimulationConfig c;
  c.profile = FlightProfile::Figure8;
  c.duration_s = 120.0;
  return c;
}

std::map<std::string, std::string> writeAndRead(const SimulatedFlight& f, const std::string& tag) {
  const auto dir = test::tempDir(tag);
  std::map<std::string, std::string> bytes;
  for (const auto& p : writeSimulatedFlight(f, dir.string()))
    bytes[std::filesystem::path(p).filename().string()] = test::readFileBytes(p);
  std::filesystem::remove_all(dir);
  return bytes;
}

TEST(SimulationIo, SameSeedGivesIdenticalFilesDifferentSeedDifferent) {
  const auto a = writeAndRead(simulateFlight(smallConfig(), 41), "sim_a");
  const auto b = writeAndRead(simulateFlight(smallConfig(), 41), "sim_b");
  const auto c = writeAndRead(simulateFlight(smallConfig(), 42), "sim_c");
  ASSERT_EQ(a.size(), 10u);
  for (const auto& [name, text] : a) {
    EXPECT_FALSE(text.empty()) << name;
    EXPECT_EQ(text, b.at(name)) << name;
  }
  for (const char* name : {"SIM1.obs", "products.sp3", "products.clk", "truth.csv", "truth_arcs.csv"})
    EXPECT_NE(a.at(name), c.at(name)) << name;
}

TEST(SimulationIo, ConcurrentSimulationsEqualSequentialOnes) {
  // The Monte Carlo runs flights on several threads: no shared state.
  SimulatedFlight a, b;
  std::thread ta([&] { a = simulateFlight(smallConfig(), 48); });
  std::thread tb([&] { b = simulateFlight(smallConfig(), 49); });
  ta.join();
  tb.join();
  EXPECT_EQ(rinexObsText(a.header, a.epochs), rinexObsText(simulateFlight(smallConfig(), 48).header,
                                                           simulateFlight(smallConfig(), 48).epochs));
  EXPECT_EQ(b.products_sp3_text, simulateFlight(smallConfig(), 49).products_sp3_text);
}

TEST(SimulationIo, ErrorTermsUseIndependentStreams) {
  // Switching the multipath off changes neither the ambiguities nor the clock.
  SimulationConfig no_mp = smallConfig();
  no_mp.errors.multipath.enabled = false;
  const SimulatedFlight a = simulateFlight(smallConfig(), 43), b = simulateFlight(no_mp, 43);
  ASSERT_EQ(a.arcs.size(), b.arcs.size());
  for (std::size_t i = 0; i < a.arcs.size(); ++i) EXPECT_EQ(a.arcs[i].n1_cycles, b.arcs[i].n1_cycles);
  EXPECT_EQ(a.truth.back().clock_m, b.truth.back().clock_m);
  EXPECT_EQ(a.truth.back().signals.front().code_noise1_m, b.truth.back().signals.front().code_noise1_m);
}

TEST(SimulationIo, RinexObservationRoundTrip) {
  SimulationConfig c = smallConfig();
  c.loss_of_lock_flags = true;
  const SimulatedFlight f = simulateFlight(c, 44);
  const auto dir = test::tempDir("sim_obs");
  const std::string path = (dir / "SIM1.obs").string();
  { std::ofstream(path) << rinexObsText(f.header, f.epochs); }
  RinexObsReader reader = RinexObsReader::open(path);
  const RinexObsHeader& h = reader.header();
  EXPECT_EQ(h.major_version, 3);
  EXPECT_EQ(h.version_text, "3.04");
  EXPECT_EQ(h.marker_name, "SIM1");
  EXPECT_EQ(h.antenna_type, "SIMULATED");
  EXPECT_EQ(h.types(GnssSystem::GPS).size(), 5u);
  EXPECT_EQ(h.types(GnssSystem::GPS)[3].toString(), "C2W");
  EXPECT_NEAR((*h.approx_position_ecef_m - *f.header.approx_position_ecef_m).norm(), 0.0, 1e-4);
  EXPECT_EQ(h.time_of_first_obs->time, f.epochs.front().time);
  EXPECT_EQ(h.interval_s.value_or(0.0), 1.0);
  ObsEpoch e;
  std::size_t k = 0, values = 0, flags = 0;
  while (reader.next(e)) {
    ASSERT_LT(k, f.epochs.size());
    const ObsEpoch& w = f.epochs[k++];
    ASSERT_EQ(e.time, w.time);
    ASSERT_EQ(e.satellites.size(), w.satellites.size());
    for (std::size_t i = 0; i < e.satellites.size(); ++i) {
      ASSERT_EQ(e.satellites[i].satellite, w.satellites[i].satellite);
      ASSERT_EQ(e.satellites[i].count, 5u);
      for (std::size_t j = 0; j < 5; ++j) {
        const Observation& r = e.begin(i)[j];
        const Observation& x = w.begin(i)[j];
        ASSERT_EQ(r.code.toString(), x.code.toString());
        ASSERT_EQ(r.value, x.value);  // quantized in-process: bit-identical after the round trip
        ASSERT_EQ(r.lli.value_or(0), x.lli.value_or(0));
        flags += r.lli.value_or(0) ? 1 : 0;
        ++values;
      }
    }
  }
  EXPECT_EQ(k, f.epochs.size());
  EXPECT_TRUE(reader.report().clean()) << reader.report().summary();
  EXPECT_GT(values, 121u * 5u * 5u);
  EXPECT_EQ(flags, 2 * f.breaks.size());  // L1C and L2W of every reacquisition
  std::filesystem::remove_all(dir);
}

TEST(SimulationIo, ProductsRoundTripThroughTheSp3AndClockReaders) {
  const SimulatedFlight f = simulateFlight(smallConfig(), 45);
  auto sp3_src = memoryLineSource(f.products_sp3_text, "products.sp3");
  const Sp3File sp3 = readSp3(*sp3_src);
  EXPECT_TRUE(sp3.report.clean()) << sp3.report.summary();
  EXPECT_TRUE(sp3.complete);
  EXPECT_EQ(sp3.header.version, 'c');
  EXPECT_EQ(sp3.header.satellites.size(), 30u);
  EXPECT_EQ(sp3.header.interval_s, 300.0);
  // 2 min flight from 10:00 with 1 h of margin each side: 08:55 .. 11:05 at 5 min? first = floor(09:00) = 09:00.
  EXPECT_EQ(sp3.epochs.front(), test::gpst(2026, 5, 13, 9, 0, 0.0));
  EXPECT_EQ(sp3.epochs.back(), test::gpst(2026, 5, 13, 11, 5, 0.0));
  auto clk_src = memoryLineSource(f.products_clk_text, "products.clk");
  const RinexClockFile clk = readRinexClock(*clk_src);
  EXPECT_TRUE(clk.report.clean()) << clk.report.summary();
  EXPECT_EQ(clk.satellite_clocks.size(), 30u);
  EXPECT_EQ(clk.satellite_clocks.begin()->second.size(), 2u * 3600u / 30u + 1u + 10u);
  // SP3 and CLK give the same clock at a common epoch (SP3: 1 ps resolution).
  const SatelliteId g01{GnssSystem::GPS, 1};
  const GnssTime t = test::gpst(2026, 5, 13, 10, 0, 0.0);
  double sp3_clock = 0.0;
  for (const auto& r : sp3.satellites.at(g01))
    if (r.time == t) sp3_clock = r.clock_bias_s.value();
  for (const auto& r : clk.satellite_clocks.at(g01))
    if (r.time == t) EXPECT_NEAR(r.clock_bias_s, sp3_clock, 1e-12);
  // And the in-process products are these files: same orbit at any time.
  PreciseEphemeris eph;
  eph.addOrbits(sp3);
  eph.addClocks(clk);
  const GnssTime q = t + 37.3;
  EXPECT_EQ(eph.orbit(g01, q).value->position_ecef_m, f.products.orbit(g01, q).value->position_ecef_m);
  EXPECT_EQ(eph.clock(g01, q).value->clock_bias_s, f.products.clock(g01, q).value->clock_bias_s);
  // The truth orbit radius is the Walker semi-major axis (circular orbits), to the SP3 resolution.
  auto truth_src = memoryLineSource(f.truth_sp3_text, "truth.sp3");
  const Sp3File truth = readSp3(*truth_src);
  for (const auto& [sat, records] : truth.satellites)
    for (const auto& r : records) {
      ASSERT_TRUE(r.position_ecef_m.has_value()) << sat.toString() << " " << r.time.toString();
      EXPECT_NEAR(r.position_ecef_m->norm(), 26559.7e3, 2e-3);
    }
}

// Product errors as an analysis centre's (errors.products.model analysis_centre):
// the clock absorbs the radial orbit error, so a user's range error from the
// products is (cos(nadir) - 1) dr + the along/cross part x sin(nadir) + the
// clock residual: centimetres where the independent errors give decimetres.
TEST(SimulationIo, AnalysisCentreProductErrorsLeaveTheRangeTheAlongCrossPart) {
  SimulationConfig independent = smallConfig();
  SimulationConfig centre = smallConfig();
  centre.errors.products.model = ErrorModelConfig::ProductErrorModel::AnalysisCentre;
  centre.errors.products.clock_residual_sigma_m = 0.0;
  centre.errors.products.radial_sigma_m = 0.10;  // large radial errors: the clocks must take them
  const SimulatedFlight fi = simulateFlight(independent, 45), fc = simulateFlight(centre, 45);
  // A receiver on the ground below the flight's start, the range error of each
  // satellite in view at the flight's middle: projected orbit error minus clock error.
  const GnssTime t = fc.epochs[fc.epochs.size() / 2].time;
  const Eigen::Vector3d rx = fc.truth.front().trajectory.position_ecef_m;
  const auto rangeErrors_m = [&](const SimulatedFlight& f) {
    std::vector<double> out;
    for (const SatelliteId& sat : f.truth_products.orbitSatellites()) {
      const auto truth_orbit = f.truth_products.orbit(sat, t), orbit = f.products.orbit(sat, t);
      const auto truth_clock = f.truth_products.clock(sat, t), clock = f.products.clock(sat, t);
      if (!truth_orbit.value || !orbit.value || !truth_clock.value || !clock.value) continue;
      const Eigen::Vector3d los = (truth_orbit.value->position_ecef_m - rx).normalized();
      if (los.dot(rx.normalized()) < std::sin(10.0 * kDegToRad)) continue;  // below 10 deg
      const double orbit_m = los.dot(orbit.value->position_ecef_m - truth_orbit.value->position_ecef_m);
      const double clock_m = kSpeedOfLight_mps * (clock.value->clock_bias_s - truth_clock.value->clock_bias_s);
      out.push_back(orbit_m - clock_m);
    }
    return out;
  };
  const auto rms = [](const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x * x;
    return std::sqrt(s / static_cast<double>(std::max<std::size_t>(1, v.size())));
  };
  const std::vector<double> ei = rangeErrors_m(fi), ec = rangeErrors_m(fc);
  ASSERT_GE(ec.size(), 6u);
  std::printf("range error from the products, RMS over %zu satellites: independent %.4f m, analysis centre %.4f m\n",
              ec.size(), rms(ei), rms(ec));
  // Bound of the along/cross part: sin(nadir) <= 0.24 times |(along, cross)| (3.5 / 2.5 cm sigmas, with
  // the drift 1 + k (t - t_mid) / T <= 1.5), plus (1 - cos(nadir)) <= 0.03 of the radial; 1 mm of SP3 rounding.
  for (double e : ec) EXPECT_LT(std::abs(e), 0.24 * 1.5 * 4.0 * 0.043 + 0.03 * 1.5 * 4.0 * 0.10 + 0.002);
  EXPECT_LT(rms(ec), 0.5 * rms(ei));
}

TEST(SimulationIo, ConfigurationFromYaml) {
  const SimulationConfig c = parseSimulationConfig(R"(
flight: { rate_hz: 10, duration_min: 3, start: "2026-05-13 12:00:00", origin: { latitude_deg: 47, longitude_deg: 8, height_m: 500 } }
constellation: { satellites: 24 }
observations: { loss_of_lock_flags: true, elevation_mask_deg: 10 }
errors:
  thermal: { phase: wavelength_fraction }
  multipath: { enabled: false, time_constant_s: 30 }
  products: { orbit_sigma_m: 0.02 }
)",
                                                   "test.yaml");
  EXPECT_EQ(c.rate_hz, 10.0);
  EXPECT_EQ(*c.duration_s, 180.0);
  EXPECT_EQ(*c.start, test::gpst(2026, 5, 13, 12, 0, 0.0));
  EXPECT_NEAR(c.origin.latitude_rad * kRadToDeg, 47.0, 1e-12);
  EXPECT_EQ(c.satellites, 24);
  EXPECT_TRUE(c.loss_of_lock_flags);
  EXPECT_NEAR(c.elevation_mask_rad * kRadToDeg, 10.0, 1e-12);
  EXPECT_EQ(c.errors.thermal.phase_mode, PhaseNoiseMode::WavelengthFraction);
  EXPECT_FALSE(c.errors.multipath.enabled);
  EXPECT_EQ(c.errors.multipath.time_constant_s, 30.0);
  EXPECT_EQ(c.errors.products.orbit_sigma_m, 0.02);
  EXPECT_TRUE(c.errors.ionosphere.enabled);  // untouched default
  const SimulatedFlight f = simulateFlight(c, 46);
  EXPECT_EQ(f.epochs.size(), 1801u);
  EXPECT_EQ(f.truth_products.orbitSatellites().size(), 24u);

  auto error = [](const std::string& text) {
    try {
      parseSimulationConfig(text, "bad.yaml");
    } catch (const ConfigError& e) {
      return e.keyPath() + ": " + e.reason();
    }
    return std::string("no error");
  };
  EXPECT_NE(error("errors: { thermal: { code_sigma: 1 } }").find("errors.thermal"), std::string::npos);
  EXPECT_NE(error("errors: { multipath: { sigma_m: -1 } }").find("errors.multipath.sigma_m"), std::string::npos);
  EXPECT_NE(error("flight: { start: \"2026-13-01 00:00:00\" }").find("flight.start"), std::string::npos);
  EXPECT_NE(error("constellation: { satellites: 40 }").find("constellation.satellites"), std::string::npos);
  EXPECT_NE(error("errors: { troposphere: { wet_scale_min: 2 } }").find("wet_scale_max"), std::string::npos);
  EXPECT_NE(error("flight: [1, 2").find("syntax"), std::string::npos);
  EXPECT_NE(error("thermal: {}").find("thermal"), std::string::npos);  // unknown top-level key
}

TEST(SimulationIo, TemplateConfigurationHoldsTheDefaults) {
  const SimulationConfig t = loadSimulationConfig(std::string(PPP_REPO_DIR) + "/config/simulation.yaml");
  const SimulationConfig d;
  EXPECT_EQ(t.rate_hz, d.rate_hz);
  EXPECT_NEAR(t.origin.latitude_rad, d.origin.latitude_rad, 1e-15);
  EXPECT_EQ(t.satellites, d.satellites);
  EXPECT_NEAR(t.elevation_mask_rad, d.elevation_mask_rad, 1e-15);
  EXPECT_EQ(t.errors.thermal.code_sigma_m, d.errors.thermal.code_sigma_m);
  EXPECT_EQ(t.errors.multipath.time_constant_s, d.errors.multipath.time_constant_s);
  EXPECT_EQ(t.errors.receiver_clock.random_walk_sigma_s, d.errors.receiver_clock.random_walk_sigma_s);
  EXPECT_EQ(t.errors.ionosphere.vtec_max_tecu, d.errors.ionosphere.vtec_max_tecu);
  EXPECT_EQ(t.errors.troposphere.wet_scale_max, d.errors.troposphere.wet_scale_max);
  EXPECT_NEAR(t.errors.phase_breaks.body_elevation_mask_rad, d.errors.phase_breaks.body_elevation_mask_rad, 1e-15);
  EXPECT_EQ(t.errors.products.scale_half_range, d.errors.products.scale_half_range);
  EXPECT_EQ(t.errors.products.model, d.errors.products.model);
  EXPECT_EQ(t.errors.products.radial_sigma_m, d.errors.products.radial_sigma_m);
  EXPECT_EQ(t.errors.products.along_sigma_m, d.errors.products.along_sigma_m);
  EXPECT_EQ(t.errors.products.cross_sigma_m, d.errors.products.cross_sigma_m);
  EXPECT_EQ(t.errors.products.clock_residual_sigma_m, d.errors.products.clock_residual_sigma_m);
  EXPECT_EQ(t.errors.ambiguity.max_abs_cycles, d.errors.ambiguity.max_abs_cycles);
  EXPECT_EQ(t.errors.ambiguity.satellite_phase_biases, d.errors.ambiguity.satellite_phase_biases);
  EXPECT_TRUE(t.outages.empty());
  EXPECT_EQ(t.imu.enabled, d.imu.enabled);
  EXPECT_EQ(t.imu.grade, d.imu.grade);
  EXPECT_EQ(t.imu.rate_hz, d.imu.rate_hz);
  EXPECT_EQ(t.imu.errors, d.imu.errors);
}

// The demo's preset (scripts/demo.sh): GPS + Galileo, integer ambiguities, the
// phase biases published, products consistent with them; the rest the defaults.
TEST(SimulationIo, ArPresetIsGpsGalileoWithPhaseBiasesAndConsistentProducts) {
  const SimulationConfig t = loadSimulationConfig(std::string(PPP_REPO_DIR) + "/config/simulation_ar.yaml");
  const SimulationConfig d;
  EXPECT_EQ(t.systems, (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::Galileo}));
  EXPECT_TRUE(t.errors.ambiguity.enabled);
  EXPECT_TRUE(t.errors.ambiguity.satellite_phase_biases);
  EXPECT_FALSE(t.errors.products.enabled);
  EXPECT_EQ(t.errors.multipath.sigma_m, d.errors.multipath.sigma_m);
  EXPECT_EQ(t.errors.thermal.code_sigma_m, d.errors.thermal.code_sigma_m);
}

TEST(SimulationIo, ProductsMustCoverTheFlight) {
  PPP_REQUIRE_SHARED_DATA();
  SimulationSources src;
  src.sp3 = readSp3(test::dataPath("zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3"));
  src.clk = readRinexClock(test::dataPath("zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK"));
  SimulationConfig c = smallConfig();
  c.duration_s = 90.0 * 60.0;  // the clocks end at 01:30, the flight would end at 01:40
  EXPECT_THROW(simulateFlight(c, 47, src), std::invalid_argument);
  src.clk.reset();
  EXPECT_THROW(simulateFlight(smallConfig(), 47, src), std::invalid_argument);
}

}  // namespace
}  // namespace ppp
