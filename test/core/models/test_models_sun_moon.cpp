// Sun/Moon positions and GMST against published almanac values.
#include <gtest/gtest.h>

#include <cmath>

#include "ppp_bayes_tree/models/sun_moon_position.h"
#include "ppp_bayes_tree/types/constants.h"

using namespace ppp;

namespace {
constexpr double kAu_m = 149597870700.0;  // IAU 2012 Resolution B2 (exact)

GnssTime utc(int y, int mo, int d, int h, int mi, double s = 0.0) {
  return GnssTime::fromCalendar({y, mo, d, h, mi, s}, TimeSystem::UTC);
}
double declinationDeg(const Eigen::Vector3d& v) { return std::asin(v.z() / v.norm()) * kRadToDeg; }
double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(a.normalized().dot(b.normalized())) * kRadToDeg;
}
}  // namespace

TEST(Gmst, J2000Epoch) {
  // GMST at 2000-01-01 12:00 UT1 (MJD 51544.5) = 18.697374558 h (USNO Circular 179
  // eq. 2.11 / Astronomical Almanac: GMST = 18.697374558 + 24.06570982441908 D).
  EXPECT_NEAR(greenwichMeanSiderealTime_rad(51544.5) * 12.0 / kPi, 18.697374558, 1e-9);
}

TEST(Gmst, ValladoExample3_5) {
  // Vallado, Fundamentals of Astrodynamics and Applications, Example 3-5:
  // 1992-08-20 12:14:00 UT1 -> GMST = 152.578787886 deg. MJD of 1992-08-20 is 48854.
  const double mjd = 48854.0 + (12.0 * 3600 + 14 * 60) / 86400.0;
  EXPECT_NEAR(greenwichMeanSiderealTime_rad(mjd) * kRadToDeg, 152.578787886, 1e-6);
}

TEST(Gmst, AdvancesOneSiderealDayPerSolarDayPlus) {
  // One solar day advances GMST by 360.98564736629 deg (USNO Circular 179 eq. 2.11
  // rate 24.06570982441908 h/day), i.e. 0.98564736629 deg mod 360.
  const double g0 = greenwichMeanSiderealTime_rad(61173.0);
  const double g1 = greenwichMeanSiderealTime_rad(61174.0);
  EXPECT_NEAR(std::remainder(g1 - g0, 2 * kPi) * kRadToDeg, 0.98564736629, 1e-8);
}

TEST(SunPosition, DeclinationAtJuneSolstice2020) {
  // USNO "Earth's Seasons and Apsides" 2020: June solstice 2020-06-20 21:44 UT.
  // Declination then equals the obliquity of date, 23.4366 deg (23.43929 - 0.013 T,
  // IAU 1976, T = 0.2047).
  const Eigen::Vector3d sun = sunPositionEcef_m(utc(2020, 6, 20, 21, 44));
  EXPECT_NEAR(declinationDeg(sun), 23.4366, 0.01);
}

TEST(SunPosition, DeclinationAtMarchEquinox2020AndDecember) {
  // USNO 2020: March equinox 2020-03-20 03:50 UT (declination 0), December solstice
  // 2020-12-21 10:02 UT (declination -23.4366 deg).
  EXPECT_NEAR(declinationDeg(sunPositionEcef_m(utc(2020, 3, 20, 3, 50))), 0.0, 0.01);
  EXPECT_NEAR(declinationDeg(sunPositionEcef_m(utc(2020, 12, 21, 10, 2))), -23.4366, 0.01);
}

TEST(SunPosition, DistanceAtPerihelionAndAphelion) {
  // USNO 2020: perihelion 2020-01-05 07:48 UT, aphelion 2020-07-04 11:35 UT.
  // Distances a(1 -/+ e) with a = 1.000001 AU, e = 0.016709 (Meeus, Astronomical
  // Algorithms ch. 25): 0.98329 AU and 1.01671 AU (the Moon moves the Earth by
  // up to 3e-5 AU about the barycentre).
  const double rp = sunPositionEcef_m(utc(2020, 1, 5, 7, 48)).norm() / kAu_m;
  const double ra = sunPositionEcef_m(utc(2020, 7, 4, 11, 35)).norm() / kAu_m;
  EXPECT_NEAR(rp, 0.98329, 2e-4);
  EXPECT_NEAR(ra, 1.01671, 2e-4);
}

TEST(SunPosition, SubsolarLongitudeMatchesEquationOfTime) {
  // Equation of time on 3 November is +16.4 min (Sun ahead of mean time; almanac
  // maximum of the year), so at 12:00 UT the Sun is over longitude
  // -16.4 / 60 * 15 = -4.1 deg. This checks the sense of the GMST rotation.
  const Eigen::Vector3d sun = sunPositionEcef_m(utc(2020, 11, 3, 12, 0));
  EXPECT_NEAR(std::atan2(sun.y(), sun.x()) * kRadToDeg, -4.1, 0.1);
}

TEST(MoonPosition, DistanceRangeOverAMonth) {
  // The geocentric lunar distance stays within about 356,400-406,700 km
  // (Meeus, Astronomical Algorithms ch. 50, extreme perigee/apogee).
  double rmin = 1e12, rmax = 0;
  for (int h = 0; h < 24 * 60; h += 1) {
    const double r = moonPositionEcef_m(utc(2020, 3, 15, 0, 0) + h * 3600.0).norm();
    rmin = std::min(rmin, r);
    rmax = std::max(rmax, r);
  }
  EXPECT_GT(rmin, 356000e3);
  EXPECT_LT(rmax, 407000e3);
  EXPECT_LT(rmin, 360000e3);  // the April 2020 perigee is in the window
  EXPECT_GT(rmax, 404000e3);
}

TEST(MoonPosition, PerigeeApril2020) {
  // Espenak, "Moon at Perigee and Apogee 2001-2100": 2020-04-07 18:08 UT, 356,907 km.
  const double r = moonPositionEcef_m(utc(2020, 4, 7, 18, 8)).norm();
  EXPECT_NEAR(r, 356907e3, 500e3);
}

TEST(MoonPosition, FullAndNewMoonElongation) {
  // USNO phases 2020: full Moon 2020-04-08 02:35 UT, new Moon 2020-04-23 02:26 UT.
  // Sun-Moon angle is 180 deg (resp. 0) minus at most the lunar latitude (5.15 deg).
  const GnssTime full = utc(2020, 4, 8, 2, 35);
  const GnssTime fresh = utc(2020, 4, 23, 2, 26);
  EXPECT_GT(angleDeg(sunPositionEcef_m(full), moonPositionEcef_m(full)), 180.0 - 5.3);
  EXPECT_LT(angleDeg(sunPositionEcef_m(fresh), moonPositionEcef_m(fresh)), 5.3);
}

TEST(SunMoonPositions, CombinedCallMatchesSeparateCalls) {
  const GnssTime t = utc(2026, 5, 13, 0, 30);
  const SunMoonPositions sm = sunMoonPositionsEcef(t, 0.1);
  EXPECT_LT((sm.sun_ecef_m - sunPositionEcef_m(t, 0.1)).norm(), 1e-3);
  EXPECT_LT((sm.moon_ecef_m - moonPositionEcef_m(t, 0.1)).norm(), 1e-6);
}
