// Solid Earth tide (IERS 2010 7.1.1 step 1) and ocean loading (11 BLQ waves).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "ppp_bayes_tree/models/ocean_loading.h"
#include "ppp_bayes_tree/models/solid_earth_tide.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

using namespace ppp;

namespace {
// ZIM2 truth from the dataset README (ITRF2020 at 2026-05-13).
const Eigen::Vector3d kZim2(4331299.5841, 567537.7070, 4633133.9645);

Eigen::Vector3d toEnu(const Eigen::Vector3d& d_ecef, const Eigen::Vector3d& station) {
  const Geodetic g = ecefToGeodetic(station);
  return rotationEnuFromEcef(g.latitude_rad, g.longitude_rad) * d_ecef;
}
GnssTime utc(int y, int mo, int d, int h, int mi, double s = 0.0) {
  return GnssTime::fromCalendar({y, mo, d, h, mi, s}, TimeSystem::UTC);
}
}  // namespace

TEST(SolidEarthTide, BodyAtZenithIsPureRadialWithClosedFormValue) {
  // IERS 2010 eqs. 7.5/7.6 with the body on the station's zenith (cos = 1):
  // radial = GMr R^4/d^3 h2 + GMr R^5/d^4 h3, horizontal 0. Station on the equator
  // (sin phi = 0 -> h2 = 0.6078 + 0.0003 = 0.6081). Moon at 384400 km.
  const Eigen::Vector3d station(kIersEarthRadius_m, 0, 0);
  const double d = 384400e3;
  const Eigen::Vector3d disp = bodyTideDisplacementEcef_m(station, Eigen::Vector3d(d, 0, 0), kMoonEarthMassRatio);
  const double R = kIersEarthRadius_m;
  const double expected = kMoonEarthMassRatio * std::pow(R, 4) / std::pow(d, 3) * 0.6081 +
                          kMoonEarthMassRatio * std::pow(R, 5) / std::pow(d, 4) * 0.292;
  EXPECT_NEAR(disp.x(), expected, 1e-12);
  EXPECT_NEAR(expected, 0.2196, 0.001);  // ~22 cm lunar bulge
  EXPECT_NEAR(disp.y(), 0.0, 1e-15);
  EXPECT_NEAR(disp.z(), 0.0, 1e-15);
}

TEST(SolidEarthTide, BodyOnHorizonLowersTheStation) {
  // cos = 0: degree 2 radial h2 (-1/2) GMr R^4/d^3, no horizontal degree-2 part;
  // degree 3 only horizontal l3 (-3/2) GMr R^5/d^4 along the body direction.
  const Eigen::Vector3d station(kIersEarthRadius_m, 0, 0);
  const double d = 384400e3;
  const Eigen::Vector3d disp = bodyTideDisplacementEcef_m(station, Eigen::Vector3d(0, d, 0), kMoonEarthMassRatio);
  const double R = kIersEarthRadius_m, g = kMoonEarthMassRatio;
  EXPECT_NEAR(disp.x(), -0.5 * 0.6081 * g * std::pow(R, 4) / std::pow(d, 3), 1e-12);
  EXPECT_NEAR(disp.y(), -1.5 * 0.015 * g * std::pow(R, 5) / std::pow(d, 4), 1e-12);
  EXPECT_NEAR(disp.z(), 0.0, 1e-15);
}

TEST(SolidEarthTide, ZeroMassGivesZero) {
  const Eigen::Vector3d body(1.0e11, 5.0e10, 2.0e10);
  EXPECT_EQ(bodyTideDisplacementEcef_m(kZim2, body, 0.0), Eigen::Vector3d::Zero());
}

TEST(SolidEarthTide, Degree2IsSymmetricUnderBodyReflection) {
  // Degree-2 terms are even in the body direction and degree-3 terms odd, so
  // d(+b) + d(-b) = 2 d2 and d(+b) - d(-b) = 2 d3 (much smaller, ratio ~ R/d).
  const Eigen::Vector3d moon(2.0e8, -3.0e8, 1.0e8);
  const Eigen::Vector3d plus = bodyTideDisplacementEcef_m(kZim2, moon, kMoonEarthMassRatio);
  const Eigen::Vector3d minus = bodyTideDisplacementEcef_m(kZim2, -moon, kMoonEarthMassRatio);
  EXPECT_LT((plus - minus).norm(), 0.05 * (plus + minus).norm());
  EXPECT_GT((plus - minus).norm(), 0.0);
}

TEST(SolidEarthTide, DailyRadialAmplitudeAndSemidiurnalPeriodAtZim2) {
  // Scan 24 h at ZIM2 (2026-05-13, 10 min steps): the radial tide at mid-latitude
  // reaches about 15-45 cm (IERS 2010 sec. 7.1.1: "can reach about 30 cm"). The
  // spectrum holds the semi-diurnal band (M2 period 12.4206 h, Doodson) with a
  // decimetre amplitude and the diurnal band, but next to nothing at 8 h (only
  // the tiny degree-3 ter-diurnal wave lives there).
  const GnssTime t0 = GnssTime::fromCalendar({2026, 5, 13, 0, 0, 0.0});
  double max_up = 0.0, c2 = 0, s2 = 0, c1 = 0, s1 = 0, c3 = 0, s3 = 0, mean = 0;
  const int n = 3 * 144;  // 3 days for the frequency analysis
  std::vector<double> up(n);
  for (int i = 0; i < n; ++i) {
    up[i] = toEnu(solidEarthTideDisplacementEcef_m(kZim2, t0 + i * 600.0), kZim2).z();
    if (i < 144) max_up = std::max(max_up, std::abs(up[i]));
    mean += up[i] / n;
  }
  for (int i = 0; i < n; ++i) {
    const double t_h = i / 6.0;
    c2 += (up[i] - mean) * std::cos(2 * kPi * t_h / 12.4206);
    s2 += (up[i] - mean) * std::sin(2 * kPi * t_h / 12.4206);
    c1 += (up[i] - mean) * std::cos(2 * kPi * t_h / 24.0);
    s1 += (up[i] - mean) * std::sin(2 * kPi * t_h / 24.0);
    c3 += (up[i] - mean) * std::cos(2 * kPi * t_h / 8.0);
    s3 += (up[i] - mean) * std::sin(2 * kPi * t_h / 8.0);
  }
  const double amp2 = 2.0 / n * std::hypot(c2, s2), amp1 = 2.0 / n * std::hypot(c1, s1);
  const double amp3 = 2.0 / n * std::hypot(c3, s3);
  std::printf("ZIM2 tide: max|up| %.3f m, amplitude 12.42 h %.3f m, 24 h %.3f m, 8 h %.4f m\n", max_up,
              amp2, amp1, amp3);
  EXPECT_GT(max_up, 0.15);
  EXPECT_LT(max_up, 0.45);
  EXPECT_GT(amp2, 0.08);
  EXPECT_GT(amp1, 0.02);
  EXPECT_LT(amp3, 0.01);
}

TEST(OceanLoading, M2ArgumentAgreesWithDoodsonFromMeeus) {
  // Doodson: M2 = 2 tau, tau = GMST + 180 deg - s. At 2000-01-01 12:00 UT:
  // GMST = 280.46061837 deg (Meeus, Astronomical Algorithms eq. 12.4) and the
  // Moon's mean longitude s = 218.3164477 deg (Meeus eq. 47.1), so
  // M2 = 2 (280.46061837 + 180 - 218.3164477) mod 360 = 124.2883 deg.
  const auto chi = oceanLoadingArguments_rad(utc(2000, 1, 1, 12, 0));
  const double m2_deg = chi[static_cast<std::size_t>(TidalConstituent::M2)] * kRadToDeg;
  EXPECT_NEAR(std::remainder(m2_deg - 124.2883, 360.0), 0.0, 0.05);
  // S2 = 2 x (mean solar hour angle from midnight) = 2 x 180 deg at noon -> 0 deg.
  const double s2_deg = chi[static_cast<std::size_t>(TidalConstituent::S2)] * kRadToDeg;
  EXPECT_NEAR(std::remainder(s2_deg, 360.0), 0.0, 0.01);
}

TEST(OceanLoading, SingleM2ConstituentIsA12_42HourSinusoid) {
  OceanLoadingCoefficients c;
  const std::size_t m2 = static_cast<std::size_t>(TidalConstituent::M2);
  c.amplitude_radial_m[m2] = 0.0123;
  c.phase_radial_deg[m2] = -37.0;
  const double period_s = 12.4206012 * 3600.0;  // Doodson M2 period
  const GnssTime t0 = GnssTime::fromCalendar({2026, 5, 13, 0, 0, 0.0});
  double max_up = 0.0;
  for (int i = 0; i < 2 * 24 * 12; ++i) {  // two days, 5 min steps, across midnight
    const GnssTime t = t0 + i * 300.0;
    const Eigen::Vector3d d = oceanLoadingDisplacementEnu_m(c, t);
    EXPECT_EQ(d.x(), 0.0);
    EXPECT_EQ(d.y(), 0.0);
    EXPECT_NEAR(oceanLoadingDisplacementEnu_m(c, t + period_s).z(), d.z(), 2e-5);
    max_up = std::max(max_up, std::abs(d.z()));
  }
  EXPECT_NEAR(max_up, 0.0123, 0.0123 * (1 - std::cos(kPi * 300.0 / period_s)) + 1e-9);
}

TEST(OceanLoading, WestAndSouthMapToMinusEastAndMinusNorth) {
  // BLQ gives west and south (IERS 2010 sec. 7.1.2): east = -west, north = -south.
  OceanLoadingCoefficients c;
  const std::size_t k1 = static_cast<std::size_t>(TidalConstituent::K1);
  c.amplitude_west_m[k1] = 0.004;
  c.amplitude_south_m[k1] = 0.002;
  c.phase_west_deg[k1] = 10.0;
  c.phase_south_deg[k1] = 10.0;
  const GnssTime t = GnssTime::fromCalendar({2026, 5, 13, 6, 0, 0.0});
  const double chi = oceanLoadingArguments_rad(t)[k1];
  const Eigen::Vector3d d = oceanLoadingDisplacementEnu_m(c, t);
  EXPECT_NEAR(d.x(), -0.004 * std::cos(chi - 10.0 * kDegToRad), 1e-15);
  EXPECT_NEAR(d.y(), -0.002 * std::cos(chi - 10.0 * kDegToRad), 1e-15);
  EXPECT_EQ(d.z(), 0.0);
}

TEST(OceanLoading, ArgumentsContinuousAcrossMidnight) {
  // The daily restart of the UT-seconds term must not make the arguments jump.
  const GnssTime midnight = utc(2026, 5, 14, 0, 0);
  const auto before = oceanLoadingArguments_rad(midnight - 0.001);
  const auto after = oceanLoadingArguments_rad(midnight + 0.001);
  for (std::size_t k = 0; k < kOceanLoadingConstituents; ++k)
    EXPECT_NEAR(std::remainder(after[k] - before[k], 2 * kPi), 0.0, 1e-4) << kTidalConstituentNames[k];
}
