// Broadcast ephemeris models (IS-GPS-200 table 20-IV, Galileo OS SIS ICD 5.1.1,
// GLONASS ICD A.3.1.2) and the ephemeris store.
//
// Independent reference: RTKLIB 2.4.3 b34 (Debian package rtklib, /usr/bin/rnx2rtkp),
// run on test/fixtures/rinex_nav/mixed_v304.nav and a synthetic observation file
// with one C1C pseudorange of 22000 km per satellite at the epochs
// 2020-06-24 23:40, 2020-06-25 03:00, 2021-05-26 01:00, 2025-06-15 00:30 GPST:
//     rnx2rtkp -p 0 -sys G,R,E,J -x 5 -o out.pos obs.obs nav.rnx
// The trace lines "<transmission time> sat=.. rs=X Y Z dts=<ns>" (satposs, trace
// level 4) give the reference positions (mm) and clocks (ps, relativistic term
// included) copied below. RTKLIB's default Galileo selection is I/NAV only, so
// for E01 the data-source field 258 was changed to 517 in RTKLIB's copy of the
// file; the orbit and clock values are unchanged.
#include <gtest/gtest.h>

#include <cmath>

#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"
#include "ppp_bayes_tree/types/constants.h"
#include "test_support.h"

using namespace ppp;

namespace {

using ppp::test::gpst;

const NavData& fixture() {
  static const NavData nav = readRinexNav(test::fixturePath("rinex_nav/mixed_v304.nav"));
  return nav;
}

BroadcastEphemerisStore fixtureStore(GalileoPreference pref = GalileoPreference::Any) {
  EphemerisSelectionOptions opt;
  opt.galileo = pref;
  BroadcastEphemerisStore store(opt);
  store.add(fixture());
  return store;
}

// A circular orbit (e = 0, i = 55 deg, no corrections) with toe at the start of
// GPS week 2000.
GpsLnavEphemeris circularOrbit() {
  GpsLnavEphemeris e;
  e.satellite = *SatelliteId::parse("G30");
  e.orbit.toe = GnssTime::fromGpsWeek(2000, 0.0);
  e.orbit.toe_sow = 0.0;
  e.clock.toc = e.orbit.toe;
  e.orbit.sqrt_a_sqrtm = std::sqrt(26560e3);
  e.orbit.i0_rad = 55.0 * kDegToRad;
  return e;
}

}  // namespace

struct RtklibReference {
  const char* sat;
  GnssTime t;
  double x, y, z;   // m
  double dts_ns;
};

TEST(BroadcastEphemeris, MatchesRtklibPositionsAndClocks) {
  const RtklibReference refs[] = {
      {"R01", gpst(2020, 6, 24, 23, 39, 59.926552), 13190028.882, 1048989.747, 21817620.028,
       63559.040},
      {"E01", gpst(2020, 6, 24, 23, 39, 59.927501), -8734892.637, 14552676.166, 24251062.909,
       -884697.320},
      {"G01", gpst(2020, 6, 25, 2, 59, 59.926600), -13747692.986, 14388907.250, 17189092.104,
       16015.533},
      {"G18", gpst(2021, 5, 26, 0, 59, 59.926267), -8579356.529, -12358508.010, 21877786.709,
       349331.726},
      {"G01", gpst(2025, 6, 15, 0, 29, 59.926324), -15167566.373, 1890620.688, 21718332.061,
       291478.954},
      // E04: toe 602400 s of week 2370, evaluated in week 2371 (week crossover).
      {"E04", gpst(2025, 6, 15, 0, 29, 59.926876), 27791121.570, 3068893.129, 9746757.544,
       -259818.315},
  };
  const BroadcastEphemerisStore store = fixtureStore();
  for (const auto& ref : refs) {
    SCOPED_TRACE(ref.sat);
    const BroadcastLookup s = store.state(*SatelliteId::parse(ref.sat), ref.t);
    ASSERT_TRUE(s) << s.unavailable_reason;
    // RTKLIB prints mm and the transmission time to 1 us (< 2 mm of motion).
    const double tol_m = 4e-3;
    EXPECT_NEAR(s.state->position_ecef_m.x(), ref.x, tol_m);
    EXPECT_NEAR(s.state->position_ecef_m.y(), ref.y, tol_m);
    EXPECT_NEAR(s.state->position_ecef_m.z(), ref.z, tol_m);
    EXPECT_NEAR(s.state->clock_bias_s * 1e9, ref.dts_ns, 2e-3);
  }
}

TEST(BroadcastEphemeris, OrbitRadiiAreThoseOfEachConstellation) {
  // GPS A = 26560 km (sqrt(A) ~ 5153.7), Galileo A = 29600 km (sqrt(A) ~ 5440.6):
  // |r| = A (1 - e cos E) stays within A(1 +- e) + corrections.
  for (const auto& e : fixture().gps) {
    if (e.satellite.system != GnssSystem::GPS) continue;
    const double r = satelliteState(e, e.orbit.toe + 1234.0).position_ecef_m.norm();
    EXPECT_NEAR(r, 26560e3, 26560e3 * 0.011 + 1e3) << e.satellite.toString();
  }
  for (const auto& e : fixture().galileo) {
    const double r = satelliteState(e, e.orbit.toe + 1234.0).position_ecef_m.norm();
    EXPECT_NEAR(r, 29600e3, 29600e3 * e.orbit.eccentricity + 2e3) << e.satellite.toString();
  }
}

TEST(BroadcastEphemeris, CircularOrbitMatchesAnalyticSolution) {
  const GpsLnavEphemeris e = circularOrbit();
  const double a = 26560e3;
  const double inc = 55.0 * kDegToRad;
  const double n = std::sqrt(kGmGps_m3ps2 / (a * a * a));
  const double we = kEarthRotationRate_radps;

  // At toe the satellite is at the ascending node on the X axis; its inertial
  // velocity sqrt(GM/a) points along (0, cos i, sin i), minus w x r in ECEF.
  BroadcastState s = satelliteState(e, e.orbit.toe);
  EXPECT_NEAR(s.position_ecef_m.x(), a, 1e-6);
  EXPECT_NEAR(s.position_ecef_m.y(), 0.0, 1e-6);
  EXPECT_NEAR(s.position_ecef_m.z(), 0.0, 1e-6);
  const double v = std::sqrt(kGmGps_m3ps2 / a);
  EXPECT_NEAR(s.velocity_ecef_mps.x(), 0.0, 1e-9);
  EXPECT_NEAR(s.velocity_ecef_mps.y(), v * std::cos(inc) - we * a, 1e-9);
  EXPECT_NEAR(s.velocity_ecef_mps.z(), v * std::sin(inc), 1e-9);
  EXPECT_EQ(s.relativistic_s, 0.0);  // e = 0

  // A quarter period later: argument of latitude 90 deg, node moved by -we dt.
  const double quarter = 0.5 * kPi / n;
  s = satelliteState(e, e.orbit.toe + quarter);
  const double node = -we * quarter;
  EXPECT_NEAR(s.position_ecef_m.x(), -a * std::cos(inc) * std::sin(node), 1e-6);
  EXPECT_NEAR(s.position_ecef_m.y(), a * std::cos(inc) * std::cos(node), 1e-6);
  EXPECT_NEAR(s.position_ecef_m.z(), a * std::sin(inc), 1e-6);
  EXPECT_NEAR(s.position_ecef_m.norm(), a, 1e-6);
}

TEST(BroadcastEphemeris, KeplerSolverConvergesAndIsBounded) {
  // Hand check for the G01 2025 record at toe: M = M0 = 2.172069051852 rad,
  // e = 5.672341212630e-4; the series E = M + e sin M + e^2/2 sin 2M + O(e^3).
  const double m = 2.172069051852, e = 5.672341212630e-4;
  const KeplerSolution k = solveKepler(m, e);
  ASSERT_TRUE(k.converged);
  EXPECT_LE(k.iterations, 5);
  EXPECT_NEAR(k.eccentric_anomaly_rad, m + e * std::sin(m) + 0.5 * e * e * std::sin(2 * m), 1e-9);
  EXPECT_NEAR(k.eccentric_anomaly_rad - e * std::sin(k.eccentric_anomaly_rad), m, 1e-14);

  // High eccentricity and mean anomalies many turns away still converge.
  for (double ecc : {0.0, 0.3, 0.8, 0.95, 0.999}) {
    for (double mean : {-1e4, -3.0, -1e-6, 0.0, 0.5, kPi, 1e5}) {
      const KeplerSolution s = solveKepler(mean, ecc);
      ASSERT_TRUE(s.converged) << ecc << " " << mean;
      EXPECT_NEAR(std::remainder(s.eccentric_anomaly_rad - ecc * std::sin(s.eccentric_anomaly_rad) - mean,
                                 2 * kPi),
                  0.0, 1e-9);
      EXPECT_LE(s.iterations, 30);
    }
  }
  // Invalid input: no iteration, no convergence claimed.
  EXPECT_FALSE(solveKepler(NAN, 0.01).converged);
  EXPECT_FALSE(solveKepler(1.0, 1.0).converged);
  EXPECT_FALSE(solveKepler(1.0, -0.1).converged);
  EXPECT_FALSE(solveKepler(INFINITY, 0.5).converged);
}

TEST(BroadcastEphemeris, VelocityIsTheDerivativeOfPosition) {
  // Central difference with h = 0.5 s: truncation error ~ h^2/6 * jerk ~ 1e-5 m/s.
  const double h = 0.5;
  auto check = [&](auto const& eph, const GnssTime& t, double tol, const std::string& what) {
    const BroadcastState s = satelliteState(eph, t);
    const Eigen::Vector3d numeric = (satelliteState(eph, t + h).position_ecef_m -
                                     satelliteState(eph, t - h).position_ecef_m) /
                                    (2 * h);
    EXPECT_LT((s.velocity_ecef_mps - numeric).norm(), tol) << what;
    const double drift = (satelliteState(eph, t + h).clock_bias_s -
                          satelliteState(eph, t - h).clock_bias_s) / (2 * h);
    EXPECT_NEAR(s.clock_drift_sps, drift, 1e-15) << what;
  };
  for (const auto& e : fixture().gps) {
    for (double dt : {-5000.0, 0.0, 3333.0}) check(e, e.orbit.toe + dt, 1e-4, e.satellite.toString());
  }
  for (const auto& e : fixture().galileo) {
    for (double dt : {-5000.0, 0.0, 3333.0}) check(e, e.orbit.toe + dt, 1e-4, e.satellite.toString());
  }
  // GLONASS: the velocity is integrated together with the position.
  const GlonassEphemeris& r = fixture().glonass.at(0);
  for (double dt : {-900.0, 0.0, 610.0}) check(r, r.tb + dt, 1e-4, "R01");
}

TEST(BroadcastEphemeris, RelativisticTermEqualsMinusTwoRDotVOverC2) {
  // IS-GPS-200 20.3.3.3.3.1: F e sqrt(A) sin E = -2 r.v / c^2 (exact for a
  // Keplerian orbit; r.v is the same in ECEF and inertial axes). The QZSS record
  // (e = 0.075) gives a large term.
  for (const auto& e : fixture().gps) {
    for (double dt : {-3000.0, 0.0, 1000.0, 2500.0}) {
      const BroadcastState s = satelliteState(e, e.orbit.toe + dt);
      const double expected = -2.0 * s.position_ecef_m.dot(s.velocity_ecef_mps) /
                              (kSpeedOfLight_mps * kSpeedOfLight_mps);
      EXPECT_NEAR(s.relativistic_s, expected, 1e-10) << e.satellite.toString();
      if (e.satellite.system == GnssSystem::QZSS) EXPECT_GT(std::fabs(s.relativistic_s), 1e-8);
    }
  }
}

TEST(BroadcastEphemeris, WeekCrossoverKeepsTimeDifferencesSmall) {
  // E04: toc 2025-06-14 23:20 (week 2370), evaluated in week 2371: t - toc = 4200 s.
  const GalileoEphemeris* e04 = nullptr;
  for (const auto& e : fixture().galileo) {
    if (e.satellite.toString() == "E04") e04 = &e;
  }
  ASSERT_NE(e04, nullptr);
  const GnssTime t = GnssTime::fromGpsWeek(2371, 1800.0);
  EXPECT_DOUBLE_EQ(clockPolynomial_s(e04->clock, t),
                   e04->clock.af0_s + 4200.0 * e04->clock.af1_sps);
  // Motion across the week boundary is continuous: 2 s apart -> ~2 |v| apart.
  const GnssTime boundary = GnssTime::fromGpsWeek(2371, 0.0);
  const BroadcastState before = satelliteState(*e04, boundary - 1.0);
  const BroadcastState at = satelliteState(*e04, boundary);
  const BroadcastState after = satelliteState(*e04, boundary + 1.0);
  EXPECT_LT((after.position_ecef_m - before.position_ecef_m - 2.0 * at.velocity_ecef_mps).norm(), 1e-3);

  // A record whose toc is 16 s before the week ends and whose toe is 0 s of week
  // (IS-GPS-200 20.3.3.4.3: toe belongs to the next week).
  std::string text = test::readFileBytes(test::fixturePath("rinex_nav/mixed_v400.nav"));
  const std::string from = "G01 2025 06 15 02 00 00";
  text.replace(text.find(from), from.size(), "G01 2025 06 14 23 59 44");
  const std::string toe = "     7.200000000000E+03";
  text.replace(text.find(toe), toe.size(), "     0.000000000000E+00");
  auto source = memoryLineSource(text, "crossover.nav");
  const NavData nav = readRinexNav(*source);
  ASSERT_EQ(nav.gps.size(), 1u) << nav.report.summary();
  EXPECT_EQ(nav.gps[0].orbit.toe, GnssTime::fromGpsWeek(2371, 0.0));
  EXPECT_EQ(nav.gps[0].orbit.toe - nav.gps[0].clock.toc, 16.0);
}

TEST(BroadcastEphemeris, GroupDelayAccessors) {
  const GpsLnavEphemeris& g = fixture().gps.at(0);  // G01 2020, TGD 5.122274160385e-09
  EXPECT_DOUBLE_EQ(gpsL1ClockCorrection_s(g, 1e-4), 1e-4 - 5.122274160385e-09);
  EXPECT_DOUBLE_EQ(gpsL2ClockCorrection_s(g, 1e-4), 1e-4 - (77.0 / 60.0) * (77.0 / 60.0) * 5.122274160385e-09);
  const GalileoEphemeris& fnav = fixture().galileo.at(0);  // BGD E5a/E1 -1.862645149231e-09
  EXPECT_DOUBLE_EQ(*galileoE1ClockCorrection_s(fnav, 0.0), 1.862645149231e-09);
  const GalileoEphemeris& inav = fixture().galileo.at(1);  // BGD E5b/E1 -4.656612873077E-09
  EXPECT_DOUBLE_EQ(*galileoE1ClockCorrection_s(inav, 0.0), 4.656612873077E-09);
  GalileoEphemeris no_bgd = inav;
  no_bgd.bgd_e5b_e1_s.reset();
  EXPECT_FALSE(galileoE1ClockCorrection_s(no_bgd, 0.0));
}

TEST(BroadcastEphemeris, GalileoHealthBitsDependOnMessage) {
  GalileoEphemeris e = fixture().galileo.at(1);
  e.type = GalileoNavType::INav;
  e.health = 0x010;  // E5a HS = 1: irrelevant to I/NAV
  EXPECT_TRUE(isHealthy(e));
  e.type = GalileoNavType::FNav;
  EXPECT_FALSE(isHealthy(e));
  e.health = 0x080;  // E5b HS
  EXPECT_TRUE(isHealthy(e));
  e.type = GalileoNavType::INav;
  EXPECT_FALSE(isHealthy(e));
  e.health = 0x001;  // E1-B DVS
  EXPECT_FALSE(isHealthy(e));
}

TEST(BroadcastEphemeris, ChecksRejectImplausibleElements) {
  KeplerOrbit o = circularOrbit().orbit;
  EXPECT_FALSE(checkKeplerOrbit(o));
  o.eccentricity = 1.0;
  EXPECT_EQ(checkKeplerOrbit(o), "eccentricity outside [0, 1)");
  o = circularOrbit().orbit;
  o.sqrt_a_sqrtm = 100.0;
  EXPECT_TRUE(checkKeplerOrbit(o));
  o = circularOrbit().orbit;
  o.m0_rad = NAN;
  EXPECT_EQ(checkKeplerOrbit(o), "non-finite orbital element");
  GlonassEphemeris r = fixture().glonass.at(0);
  EXPECT_FALSE(checkGlonassState(r));
  r.position_m.setZero();
  EXPECT_TRUE(checkGlonassState(r));
}

// ---------------------------------------------------------------------------
// Ephemeris store
// ---------------------------------------------------------------------------

TEST(BroadcastEphemerisStore, PicksTheNearestToeAmongValidRecords) {
  BroadcastEphemerisStore store;
  GpsLnavEphemeris a = circularOrbit(), b = circularOrbit();
  b.orbit.toe = a.orbit.toe + 7200.0;
  b.orbit.toe_sow = 7200.0;
  b.iode = 1;
  ASSERT_FALSE(store.add(a));
  ASSERT_FALSE(store.add(b));
  ASSERT_FALSE(store.add(b));  // duplicate kept once
  EXPECT_EQ(store.size(), 2u);
  const SatelliteId g30 = a.satellite;
  EXPECT_EQ(store.gps(g30, a.orbit.toe + 3000.0).record->iode, 0);
  EXPECT_EQ(store.gps(g30, a.orbit.toe + 4000.0).record->iode, 1);
  EXPECT_EQ(store.gps(g30, a.orbit.toe + 3600.0).record->iode, 1);  // tie: the later
  EXPECT_EQ(store.gps(g30, a.orbit.toe - 7200.0).record->iode, 0);  // edge of the 4 h fit
}

TEST(BroadcastEphemerisStore, SaysWhyAStateIsUnavailable) {
  const BroadcastEphemerisStore store = fixtureStore(GalileoPreference::INavOnly);
  // G01 2020: toe 2020-06-25 04:00, 4 h fit interval -> valid until 06:00.
  BroadcastLookup s = store.state(*SatelliteId::parse("G01"), gpst(2020, 6, 25, 6, 30, 0));
  EXPECT_FALSE(s);
  EXPECT_EQ(s.unavailable_reason,
            "G01 at 2020-06-25 06:30:00.0000000 GPS: nearest record is 2.50 h away, outside its "
            "validity interval");
  s = store.state(*SatelliteId::parse("G05"), gpst(2020, 6, 25, 4, 0, 0));
  EXPECT_EQ(s.unavailable_reason, "no broadcast record for G05");
  // E01 has only an F/NAV record; the store was asked for I/NAV.
  s = store.state(*SatelliteId::parse("E01"), gpst(2020, 6, 24, 23, 40, 0));
  EXPECT_FALSE(s);
  EXPECT_NE(s.unavailable_reason.find("1 of the wrong message type"), std::string::npos);
  // J01 2014 is flagged unhealthy (health 1).
  s = store.state(*SatelliteId::parse("J01"), gpst(2014, 5, 13, 8, 15, 12));
  EXPECT_NE(s.unavailable_reason.find("all 1 record(s) in the validity interval are flagged unhealthy"),
            std::string::npos)
      << s.unavailable_reason;
  s = store.state(*SatelliteId::parse("C01"), gpst(2020, 6, 25, 4, 0, 0));
  // BeiDou is modelled (models/broadcast_ephemeris.h); the fixture has no C01 record.
  EXPECT_EQ(s.unavailable_reason, "no broadcast record for C01");
  s = store.state(*SatelliteId::parse("I01"), gpst(2020, 6, 25, 4, 0, 0));
  EXPECT_EQ(s.unavailable_reason, "I01: broadcast orbits of IRNSS are not modelled");
  // GLONASS: 30 min validity around tb (23:15:18 GPST).
  EXPECT_TRUE(store.state(*SatelliteId::parse("R01"), gpst(2020, 6, 24, 23, 45, 18)));
  EXPECT_FALSE(store.state(*SatelliteId::parse("R01"), gpst(2020, 6, 24, 23, 45, 19)));
}

TEST(BroadcastEphemerisStore, AllowsUnhealthyOnlyWhenAsked) {
  EphemerisSelectionOptions opt;
  opt.allow_unhealthy = true;
  BroadcastEphemerisStore store(opt);
  store.add(fixture());
  EXPECT_TRUE(store.state(*SatelliteId::parse("J01"), gpst(2014, 5, 13, 8, 15, 12)));
}

TEST(BroadcastEphemerisStore, RefusesInvalidRecords) {
  BroadcastEphemerisStore store;
  GpsLnavEphemeris bad = circularOrbit();
  bad.orbit.eccentricity = 1.5;
  EXPECT_EQ(store.add(bad), "eccentricity outside [0, 1)");
  GalileoEphemeris gal;
  gal.satellite = *SatelliteId::parse("G01");
  gal.orbit = circularOrbit().orbit;
  EXPECT_EQ(store.add(gal), "not a Galileo satellite");
  EXPECT_EQ(store.size(), 0u);
}
