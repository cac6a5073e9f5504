// End to end on ESBC 2020-177: GRG SP3/CLK turned into an RTCM SSR stream
// against the station's real broadcast file (ppp_ssr_encode's core), written,
// decoded and applied (ppp_solve --nav --ssr's products): the PPP agrees with
// the SP3/CLK run, the only expected difference being the SSR quantisation.
// A 3-h window keeps the test short; the full day is reported by the command line.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/models/broadcast_products.h"
#include "ppp_bayes_tree/models/broadcast_ssr_ephemeris.h"
#include "ppp_bayes_tree/models/clock_wide_lane_bias_provider.h"
#include "ppp_bayes_tree/ppp/ambiguity/wide_lane_ambiguity.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/ppp/pipeline/product_set.h"
#include "esbc_stream_fixture.h"
#include "test_support.h"
#include "window_observation_source.h"

namespace ppp {
namespace {

using test::esbcPath;
using test::WindowObservationSource;

std::map<GnssTime, Eigen::Vector3d> runEkf(PppProducts products, const PppConfig& config, const GnssTime& until,
                                           PppRunSummary* summary = nullptr) {
  PppPipeline pipeline(std::make_unique<WindowObservationSource>(
                           std::make_unique<RinexObservationSource>(esbcPath("ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz")), until),
                       std::move(products), config);
  std::string why;
  auto estimator = makeEstimator("ekf", config, &why);
  EXPECT_TRUE(estimator) << why;
  std::map<GnssTime, Eigen::Vector3d> positions;
  const PppRunSummary run = pipeline.run(*estimator, [&](const PppEpochRecord& rec) {
    if (rec.status == EpochStatus::Ok && rec.solution.position_ecef_m) positions[rec.solution.time] = *rec.solution.position_ecef_m;
  });
  if (summary) *summary = run;
  return positions;
}

/// 3D RMS and max of the differences after the first hour, and their count.
struct Agreement {
  double rms_m = 0.0, max_m = 0.0;
  std::size_t n = 0;
};
Agreement agreement(const std::map<GnssTime, Eigen::Vector3d>& a, const std::map<GnssTime, Eigen::Vector3d>& b,
                    const GnssTime& start) {
  Agreement out;
  double sum2 = 0.0;
  for (const auto& [t, x] : a) {
    if (t - start < 3600.0) continue;
    const auto it = b.find(t);
    if (it == b.end()) continue;
    const double d = (it->second - x).norm();
    sum2 += d * d;
    out.max_m = std::max(out.max_m, d);
    ++out.n;
  }
  if (out.n > 0) out.rms_m = std::sqrt(sum2 / static_cast<double>(out.n));
  return out;
}

TEST(SsrEndToEnd, EsbcBroadcastPlusEncodedSsrMatchesPreciseProducts) {
  PPP_REQUIRE_SHARED_DATA();
  const PppConfig config = loadPppConfig(std::string(PPP_REPO_DIR) + "/config/ppp_real_data.yaml");
  const GnssTime start = test::gpst(2020, 6, 25, 0, 0, 0);
  const GnssTime until = test::gpst(2020, 6, 25, 3, 0, 0);
  const std::vector<std::string> atx = {test::dataPath("antex/igs20_gps_satellites_trim.atx"),
                                        test::dataPath("antex/igs05_esbc_receiver_trim.atx")};
  auto precise = std::make_shared<PreciseEphemeris>(test::esbcGrgPrecise());
  const std::string nav_path = esbcPath("ESBC00DNK_R_20201770000_01D_MN.rnx");
  const NavData nav = readRinexNav(nav_path);

  // 1. The SSR stream (GPS, centre of mass, 5 s), written as RTCM 3 frames.
  SsrFromPreciseOptions options = test::esbcGpsSsrOptions();
  const SsrFromPreciseResult ssr = ssrFromPrecise({nav}, *precise, nullptr, nullptr, start, until + 60.0, options);
  EXPECT_EQ(ssr.epochs, 3u * 720u + 13u);  // 00:00:00 .. 03:01:00 every 5 s
  const auto dir = test::tempDir("ssr_e2e");
  const std::string stream_path = (dir / "SSRC00TST_esbc.rtcm3").string();
  test::writeFileBytes(stream_path, test::ssrStreamBytes(ssr));
  // 2. Decoded and applied as ppp_solve --nav --ssr does (the name says centre of mass).
  const BroadcastProducts broadcast = loadBroadcastProducts({nav_path}, stream_path);
  EXPECT_TRUE(broadcast.problems.empty()) << broadcast.problems.front();
  const auto* corrected = broadcast.corrected.get();
  ASSERT_NE(corrected, nullptr);
  EXPECT_EQ(corrected->options().reference, EphemerisReference::CentreOfMass);

  // Quantisation: at an SSR epoch the corrected orbit equals the precise one to
  // half the field resolutions (0.05 mm radial, 0.2 mm along and cross: 0.29 mm
  // 3D) and the clock to 0.05 mm; in between, the linear rates interpolate.
  double max_orbit_m = 0.0, max_clock_m = 0.0, max_mid_orbit_m = 0.0, max_mid_clock_m = 0.0;
  std::size_t checked = 0;
  for (int k = 0; k < 360; ++k) {
    const GnssTime t = start + 30.0 * k;
    for (int prn = 1; prn <= 32; ++prn) {
      const SatelliteId sat{GnssSystem::GPS, prn};
      for (const double offset : {0.0, 2.5}) {
        const auto c = corrected->correctedState(sat, t + offset);
        const auto po = precise->satelliteOrbit(sat, t + offset);
        const auto pc = precise->satelliteClock(sat, t + offset);
        if (!c.ok() || !po.ok() || !pc.ok()) continue;
        // Only where the encoder sent this epoch's correction (where the CLK
        // file has a gap the user extrapolates an older one, up to its validity).
        if (c.value->orbit_age_s != offset) continue;
        const double dorbit = (c.value->position_ecef_m - po.value->position_ecef_m).norm();
        const double dclock = std::abs(c.value->clock_s - pc.value->clock_bias_s) * 299792458.0;
        if (offset == 0.0) {
          max_orbit_m = std::max(max_orbit_m, dorbit);
          max_clock_m = std::max(max_clock_m, dclock);
          ++checked;
        } else {
          max_mid_orbit_m = std::max(max_mid_orbit_m, dorbit);
          max_mid_clock_m = std::max(max_mid_clock_m, dclock);
        }
      }
    }
  }
  std::cout << "SSR quantisation at the SSR epochs: orbit max " << max_orbit_m * 1e3 << " mm, clock max "
            << max_clock_m * 1e3 << " mm; 2.5 s after: orbit max " << max_mid_orbit_m * 1e3 << " mm, clock max "
            << max_mid_clock_m * 1e3 << " mm (" << checked << " satellite-epochs)\n";
  EXPECT_GT(checked, 3000u);
  EXPECT_LT(max_orbit_m, 0.3e-3);
  EXPECT_LT(max_clock_m, 0.06e-3);
  EXPECT_LT(max_mid_orbit_m, 0.5e-3);  // the linear rates between two epochs
  EXPECT_LT(max_mid_clock_m, 0.1e-3);

  // 3. The two PPP runs.
  auto set = std::make_shared<ProductSet>(ProductSet::load({atx, std::nullopt, std::nullopt, {GnssSystem::GPS}}));
  PppProducts a;
  a.ephemeris = precise;
  a.antennas = set->antennas();
  PppProducts b;
  b.ephemeris = broadcast.ephemeris;
  b.antennas = set->antennas();
  const auto pa = runEkf(a, config, until);
  const auto pb = runEkf(b, config, until);
  const Agreement ab = agreement(pa, pb, start);
  ASSERT_EQ(ab.n, 241u);  // 01:00:00 .. 03:00:00
  std::cout << "ESBC 01:00-03:00, broadcast + SSR vs SP3/CLK: 3D RMS " << ab.rms_m * 1e3 << " mm, max " << ab.max_m * 1e3
            << " mm over " << ab.n << " epochs\n";

  // 4. The same in the two antenna-phase-centre conventions
  // (models/satellite_reference_point.h): the ionosphere-free phase centre
  // (declared: the name says nothing) and the L1 phase centre of the IGS SSRA
  // streams (from the SSRA name). The encoder moves the SP3 centre of mass to
  // that point, the measurement model brings it to the IF phase centre: the
  // solution is the SP3/CLK one again.
  const auto writeStream = [&](EphemerisReference reference, const std::string& name) {
    options.reference = reference;
    const SsrFromPreciseResult r = ssrFromPrecise({nav}, *precise, set->antennas().get(), nullptr, start, until + 60.0, options);
    const std::string path = (dir / name).string();
    test::writeFileBytes(path, test::ssrStreamBytes(r));
    return path;
  };
  const std::string apc_path = writeStream(EphemerisReference::AntennaPhaseCentre, "APCIF0TST_esbc.rtcm3");
  const std::string l1_path = writeStream(EphemerisReference::AntennaPhaseCentreL1, "SSRA00TST_esbc.rtcm3");
  PppProducts c_full;
  const BroadcastProducts c_products = loadBroadcastProducts({nav_path}, apc_path, EphemerisReference::AntennaPhaseCentre);
  c_full.ephemeris = c_products.ephemeris;
  c_full.antennas = set->antennas();
  const auto pc_full = runEkf(c_full, config, until);
  const Agreement ac_full = agreement(pa, pc_full, start);
  std::cout << "ESBC 01:00-03:00, broadcast + APC (IF) SSR vs SP3/CLK: 3D RMS " << ac_full.rms_m * 1e3 << " mm, max "
            << ac_full.max_m * 1e3 << " mm\n";
  const BroadcastProducts l1_products = loadBroadcastProducts({nav_path}, l1_path);
  const auto* l1_eph = l1_products.corrected.get();
  ASSERT_NE(l1_eph, nullptr);
  EXPECT_EQ(l1_eph->options().reference, EphemerisReference::AntennaPhaseCentreL1);  // from the SSRA name
  // The GPS III satellite G18 is in the stream at its L1 phase centre, as in the
  // IGS SSRA streams: igs20_gps_satellites_trim.atx G075 has z 1188.42 mm (G01) and
  // 702.29 mm (G02); the body z axis points to the Earth, so the L1 centre lies
  // 1.5457 x (1.18842 - 0.70229) = 0.7514 m further out than the IF one.
  {
    const SatelliteId g18{GnssSystem::GPS, 18};
    const GnssTime t = start + 3600.0;
    const auto l1_orbit = l1_eph->correctedState(g18, t);
    const auto if_orbit = c_products.corrected->correctedState(g18, t);
    ASSERT_TRUE(l1_orbit.ok() && if_orbit.ok());
    const Eigen::Vector3d up = if_orbit.value->position_ecef_m.normalized();
    EXPECT_NEAR((l1_orbit.value->position_ecef_m - if_orbit.value->position_ecef_m).dot(up), 0.7514, 0.002);
  }
  PppProducts l1_run;
  l1_run.ephemeris = l1_products.ephemeris;
  l1_run.antennas = set->antennas();
  const auto pl1 = runEkf(l1_run, config, until);
  const Agreement al1 = agreement(pa, pl1, start);
  const Agreement l1_if = agreement(pc_full, pl1, start);
  std::cout << "ESBC 01:00-03:00, broadcast + APC (L1) SSR vs SP3/CLK: 3D RMS " << al1.rms_m * 1e3 << " mm, max "
            << al1.max_m * 1e3 << " mm; vs the APC (IF) run: 3D RMS " << l1_if.rms_m * 1e3 << " mm, max "
            << l1_if.max_m * 1e3 << " mm\n";
  // Measured (3-h window, EKF, after the first hour): 1.12 / 1.15 / 1.15 mm 3D RMS
  // (max 3.0 mm) for centre of mass / IF / L1 against SP3/CLK, and 0.02 mm (max
  // 0.06 mm) between the IF and L1 runs: the SSR quantisation (0.28 mm orbit,
  // 0.05 mm clock per satellite) seen through a converging float solution (the
  // full day: 0.4 mm). 2 mm leaves room for the rounding of another build; a
  // wrong convention costs decimetres on the GPS III satellites.
  EXPECT_LT(ab.rms_m, 0.002);
  EXPECT_LT(ac_full.rms_m, 0.002);
  EXPECT_LT(al1.rms_m, 0.002);
  EXPECT_LT(l1_if.rms_m, 0.002);

  // 5. An antenna-phase-centre (IF) stream needs no satellite antenna calibration:
  // with an ANTEX file holding the receiver only, every satellite is still used
  // (a centre-of-mass orbit would be refused: MissingAntennaCalibration); only the
  // satellite PCV (mm to 1 cm at GPS nadir angles) is then missing.
  auto receiver_only = std::make_shared<ProductSet>(
      ProductSet::load({{test::dataPath("antex/igs05_esbc_receiver_trim.atx")}, std::nullopt, std::nullopt, {GnssSystem::GPS}}));
  PppProducts c;
  c.ephemeris = c_full.ephemeris;
  c.antennas = receiver_only->antennas();
  PppRunSummary c_run;
  const auto pc = runEkf(c, config, until, &c_run);
  for (const auto& [key, count] : c_run.rejection_counts)
    EXPECT_NE(key.reason, RejectionReason::MissingAntennaCalibration) << count;
  const Agreement ac = agreement(pa, pc, start);
  std::cout << "ESBC 01:00-03:00, broadcast + APC SSR without satellite ANTEX vs SP3/CLK: 3D RMS " << ac.rms_m * 1e3
            << " mm, max " << ac.max_m * 1e3 << " mm over " << ac.n << " epochs\n";
  EXPECT_EQ(ac.n, 241u);
  EXPECT_LT(ac.rms_m, 0.05);  // measured 2.8 cm: the missing satellite PCV in a 1-3 h float solution
  std::filesystem::remove_all(dir);
}

// The phase biases ppp_ssr_encode makes from the GRG integer-recovery clocks (the
// clock header's "WL" lines), written as RTCM 1265/1267, decoded as ppp_solve
// --nav --ssr does and given to the resolver's Melbourne-Wuebbena correction,
// correct the wide lane as the clock-header provider does, to 1e-4 cycle (the
// DF482 grid is 0.1 mm; the encoder picks the grid points that keep the wide lane).
TEST(SsrEndToEnd, EncodedPhaseBiasesCorrectTheWideLaneAsTheClockHeader) {
  PPP_REQUIRE_SHARED_DATA();
  const std::string clk = esbcPath("GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz");
  std::vector<std::string> problems;
  const auto header_biases = integerRecoveryClockBiases({readRinexClockHeader(clk)}, {clk}, problems);
  ASSERT_NE(header_biases, nullptr);
  EXPECT_TRUE(problems.empty());
  const std::string nav_path = esbcPath("ESBC00DNK_R_20201770000_01D_MN.rnx");
  const GnssTime start = test::gpst(2020, 6, 25, 1, 0, 0);
  SsrFromPreciseOptions options;
  options.systems = {GnssSystem::GPS, GnssSystem::Galileo};
  const SsrFromPreciseResult ssr = ssrFromPrecise({readRinexNav(nav_path)}, test::esbcGrgPrecise(), nullptr,
                                                  header_biases.get(), start, start + 60.0, options,
                                                  header_biases.get());
  std::map<GnssSystem, std::size_t> phase_messages;
  std::set<SatelliteId> streamed;  // satellites with SSR orbits, clocks and biases
  for (const auto& m : ssr.messages) {
    if (m.header.kind != SsrMessageKind::PhaseBias) continue;
    ++phase_messages[m.header.system];
    for (const auto& p : m.phase_biases)
      for (const auto& b : p.biases) {
        streamed.insert(p.satellite);
        EXPECT_TRUE(b.integer) << p.satellite.toString();
        EXPECT_EQ(b.widelane_integer, 2);
      }
  }
  EXPECT_GE(phase_messages[GnssSystem::GPS], 13u);  // 13 epochs 01:00:00 .. 01:01:00
  EXPECT_GE(phase_messages[GnssSystem::Galileo], 13u);
  const auto dir = test::tempDir("ssr_phase_biases");
  const std::string stream_path = (dir / "SSRC00TST_esbc.rtcm3").string();
  test::writeFileBytes(stream_path, test::ssrStreamBytes(ssr));
  const BroadcastProducts broadcast = loadBroadcastProducts({nav_path}, stream_path);
  EXPECT_TRUE(broadcast.problems.empty()) << broadcast.problems.front();
  ASSERT_TRUE(broadcast.ssr_phase_biases);
  ASSERT_NE(broadcast.ssr_biases, nullptr);

  // The signals ESBC tracks: GPS C1C/L1C + C2W/L2W, Galileo C1C/L1C + C5Q/L5Q; the
  // code OSBs as the selection leaves them (none for C1C: the MW asks the provider).
  const auto code = [](ObservableType type, char band, char attribute) {
    ObservationCode c;
    c.type = type;
    c.band = band;
    c.attribute = attribute;
    return c;
  };
  std::size_t compared = 0, corrected = 0;
  std::map<GnssSystem, std::size_t> compared_by_system;
  double max_difference_cycles = 0.0;
  for (int i = 0; i < 2; ++i) {
    const GnssSystem system = i == 0 ? GnssSystem::GPS : GnssSystem::Galileo;
    const char band2 = system == GnssSystem::GPS ? '2' : '5';
    const char attribute2 = system == GnssSystem::GPS ? 'W' : 'Q';
    for (int prn = 1; prn <= 36; ++prn) {
      DualFrequencyObservation o;
      o.satellite = SatelliteId{system, prn};
      o.time = start + 35.0;
      o.code1 = code(ObservableType::Pseudorange, '1', system == GnssSystem::GPS ? 'W' : 'C');
      o.code2 = code(ObservableType::Pseudorange, band2, attribute2);
      o.phase1 = code(ObservableType::CarrierPhase, '1', 'C');
      o.phase2 = code(ObservableType::CarrierPhase, band2, attribute2);
      o.frequency1_hz = *carrierFrequency_hz(system, '1');
      o.frequency2_hz = *carrierFrequency_hz(system, band2);
      o.code1_m = 2.2e7 + 3.1;
      o.code2_m = 2.2e7 + 4.7;
      o.phase1_cycles = 1.156e8 + 0.37;
      o.phase2_cycles = 0.9e8 + 0.81;
      const CorrectedMelbourneWuebbena by_header = correctedMelbourneWuebbena(o, header_biases.get());
      if (!by_header.mw_cycles || !streamed.count(o.satellite)) continue;
      const CorrectedMelbourneWuebbena by_ssr = correctedMelbourneWuebbena(o, broadcast.ssr_biases.get());
      ASSERT_TRUE(by_ssr.mw_cycles) << o.satellite.toString() << ": " << toString(by_ssr.issue);
      const double d = std::abs(*by_ssr.mw_cycles - *by_header.mw_cycles);
      max_difference_cycles = std::max(max_difference_cycles, d);
      EXPECT_LT(d, 1e-4) << o.satellite.toString();
      ++compared;
      ++compared_by_system[system];
      if (std::abs(*by_header.mw_cycles - melbourneWuebbena_cycles(o)) > 0.01) ++corrected;
    }
  }
  std::printf("[ figures  ] %zu satellites compared (%zu with a wide-lane bias above 0.01 cycle), max |MW ssr - MW header| %.2e cycle\n",
              compared, corrected, max_difference_cycles);
  std::printf("[ figures  ] GPS %zu, Galileo %zu\n", compared_by_system[GnssSystem::GPS], compared_by_system[GnssSystem::Galileo]);
  EXPECT_GE(compared_by_system[GnssSystem::GPS], 10u);  // satellites with a header bias and SSR records
  EXPECT_GE(compared_by_system[GnssSystem::Galileo], 10u);
  EXPECT_GE(corrected, 25u);  // 29 of 55
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ppp
