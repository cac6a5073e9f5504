// Signal geometry (light time, Sagnac, line of sight) and relativistic terms.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include <Eigen/Geometry>

#include "ppp_bayes_tree/models/relativity.h"
#include "ppp_bayes_tree/models/signal_geometry.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

using namespace ppp;

namespace {
const Eigen::Vector3d kZim2(4331299.5841, 567537.7070, 4633133.9645);  // dataset README truth
const GnssTime kT0 = GnssTime::fromCalendar({2026, 5, 13, 0, 0, 0.0});

/// Circular GPS-like orbit (a = 26560 km, i = 55 deg) in inertial axes, returned in
/// ECEF by rotating with the Earth (ECEF = R3(omega t) inertial).
Eigen::Vector3d circularOrbitEcef(const GnssTime& t, double raan_rad, double phase_rad) {
  constexpr double a = 26560e3, inc = 55.0 * kDegToRad;
  const double n = std::sqrt(kGmGps_m3ps2 / (a * a * a));
  const double dt = t - kT0;
  const double u = phase_rad + n * dt;
  const Eigen::Vector3d orbital(a * std::cos(u), a * std::sin(u) * std::cos(inc), a * std::sin(u) * std::sin(inc));
  const double co = std::cos(raan_rad), so = std::sin(raan_rad);
  const Eigen::Vector3d inertial(co * orbital.x() - so * orbital.y(), so * orbital.x() + co * orbital.y(),
                                 orbital.z());
  return rotateForEarthRotation(inertial, dt);  // R3(omega dt)
}
}  // namespace

TEST(Sagnac, RotationFormEqualsClosedFormAndIsBounded) {
  // Scan a grid of GPS-like satellites above ZIM2 (elevation > 0): the closed form
  // omega (xs yr - ys xr)/c agrees with rotating the satellite by omega tau to 1 mm,
  // and its magnitude stays below omega r_s r_r / c = 41 m (< 45 m).
  double max_abs = 0.0;
  int visible = 0;
  for (int raan = 0; raan < 360; raan += 15) {
    for (int ph = 0; ph < 360; ph += 10) {
      const Eigen::Vector3d s = circularOrbitEcef(kT0, raan * kDegToRad, ph * kDegToRad);
      if (azimuthElevation(kZim2, s).elevation_rad <= 0.0) continue;
      ++visible;
      const double tau = geometricRange_m(s, kZim2) / kSpeedOfLight_mps;
      const double rotated = geometricRange_m(rotateForEarthRotation(s, tau), kZim2) - geometricRange_m(s, kZim2);
      const double closed = sagnacCorrection_m(s, kZim2);
      EXPECT_NEAR(rotated, closed, 1e-3);
      max_abs = std::max(max_abs, std::abs(closed));
    }
  }
  EXPECT_GT(visible, 50);
  EXPECT_LT(max_abs, 45.0);
  EXPECT_GT(max_abs, 10.0);  // a real effect of tens of metres
}

TEST(LightTime, ConvergesInThreeIterations) {
  const auto orbit = [](const GnssTime& t) { return circularOrbitEcef(t, 0.3, 0.2); };
  const GnssTime t_rx = kT0 + 1234.5;
  const auto fast = solveLightTime(kZim2, t_rx, orbit, 1e-9);
  const auto ref = solveLightTime(kZim2, t_rx, orbit, 1e-15, 20);
  ASSERT_TRUE(fast && ref);
  EXPECT_LE(fast->iterations, 3);
  EXPECT_LT(std::abs(fast->flight_time_s - ref->flight_time_s), 1e-9);
  // Self-consistency: range = c tau and the transmission time is t_rx - tau.
  EXPECT_NEAR(ref->range_m, ref->flight_time_s * kSpeedOfLight_mps, 1e-6);
  EXPECT_NEAR(t_rx - ref->transmission_time, ref->flight_time_s, 1e-12);
  EXPECT_GT(ref->flight_time_s, 0.066);  // 20,000-26,000 km
  EXPECT_LT(ref->flight_time_s, 0.090);
  // The rotated position is the unrotated one turned by omega tau about z.
  EXPECT_LT((ref->satellite_ecef_m - rotateForEarthRotation(ref->satellite_ecef_at_transmission_m,
                                                            ref->flight_time_s)).norm(), 1e-6);
}

TEST(LightTime, UnavailablePositionGivesNullopt) {
  const auto missing = [](const GnssTime&) -> std::optional<Eigen::Vector3d> { return std::nullopt; };
  EXPECT_FALSE(solveLightTime(kZim2, kT0, missing).has_value());
  const auto present = [](const GnssTime& t) -> std::optional<Eigen::Vector3d> {
    return circularOrbitEcef(t, 1.0, 1.0);
  };
  EXPECT_TRUE(solveLightTime(kZim2, kT0, present).has_value());
}

TEST(LineOfSight, RangeJacobianIsMinusLosByCentralDifferences) {
  const Eigen::Vector3d s = circularOrbitEcef(kT0, 0.3, 0.2);
  const Eigen::Vector3d J = rangeJacobianWrtReceiver(kZim2, s);
  EXPECT_NEAR(lineOfSight(kZim2, s).norm(), 1.0, 1e-15);
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d dp = Eigen::Vector3d::Zero();
    dp[k] = 0.5;
    const double numeric = (geometricRange_m(s, kZim2 + dp) - geometricRange_m(s, kZim2 - dp)) / 1.0;
    EXPECT_NEAR(J[k], numeric, 1e-8);
  }
}

TEST(Relativity, ClockCorrectionEqualsKeplerFormAndIs23ns) {
  // IS-GPS-200 20.3.3.3.3.1: dt_r = F e sqrt(A) sin E, F = -4.442807633e-10 s/sqrt(m).
  // For e = 0.01, A = 26560 km: max |dt_r| = 4.4428e-10 * 0.01 * 5153.6 = 22.9 ns.
  constexpr double a = 26560e3, e = 0.01;
  const double n = std::sqrt(kGmGps_m3ps2 / (a * a * a)), b = a * std::sqrt(1 - e * e);
  double max_abs = 0.0;
  for (int k = 0; k < 360; k += 5) {
    const double E = k * kDegToRad;
    const double Edot = n / (1 - e * std::cos(E));
    const Eigen::Vector3d r(a * (std::cos(E) - e), b * std::sin(E), 0.0);
    const Eigen::Vector3d v(-a * std::sin(E) * Edot, b * std::cos(E) * Edot, 0.0);
    const double dt = relativisticClockCorrection_s(r, v);
    EXPECT_NEAR(dt, kRelativisticF_GPS * e * std::sqrt(a) * std::sin(E), 1e-14);
    max_abs = std::max(max_abs, std::abs(dt));
    // ECEF velocity v - omega x r gives the same value.
    const Eigen::Vector3d v_ecef = v - Eigen::Vector3d(0, 0, kEarthRotationRate_radps).cross(r);
    EXPECT_NEAR(relativisticClockCorrection_s(r, v_ecef), dt, 1e-18);
  }
  EXPECT_NEAR(max_abs, 22.9e-9, 0.1e-9);
}

TEST(Relativity, ShapiroDelayMagnitudes) {
  // IERS 2010 eq. 11.17 with GM = 3.986004418e14: zenith GPS (r_s = 26560 km,
  // station on a 6371 km sphere, rho = 20189 km): 2GM/c^2 ln(53120/12742) = 12.7 mm;
  // horizon (rho = 25785 km): 18.7 mm.
  const Eigen::Vector3d station(6371e3, 0, 0);
  const double zen = shapiroDelay_m(Eigen::Vector3d(26560e3, 0, 0), station);
  EXPECT_NEAR(zen, 0.01266, 0.0001);
  const double rho_h = std::sqrt(26560e3 * 26560e3 - 6371e3 * 6371e3);
  const double hor = shapiroDelay_m(Eigen::Vector3d(6371e3, rho_h, 0), station);
  EXPECT_NEAR(hor, 0.0187, 0.0002);
  // Real satellites above ZIM2: always 1-2 cm, growing toward the horizon.
  for (int ph = 0; ph < 360; ph += 5) {
    const Eigen::Vector3d s = circularOrbitEcef(kT0, 0.5, ph * kDegToRad);
    if (azimuthElevation(kZim2, s).elevation_rad < 0) continue;
    const double d = shapiroDelay_m(s, kZim2);
    EXPECT_GT(d, 0.012);
    EXPECT_LT(d, 0.0195);
  }
}
