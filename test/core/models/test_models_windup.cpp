// Satellite attitude (nominal yaw steering) and carrier phase wind-up.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include <Eigen/Geometry>

#include "ppp_bayes_tree/models/phase_windup.h"
#include "ppp_bayes_tree/models/satellite_attitude.h"
#include "ppp_bayes_tree/models/signal_geometry.h"
#include "ppp_bayes_tree/models/sun_moon_position.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

using namespace ppp;

namespace {
const Eigen::Vector3d kZim2(4331299.5841, 567537.7070, 4633133.9645);  // dataset README truth
const GnssTime kT0 = GnssTime::fromCalendar({2026, 5, 13, 0, 0, 0.0});

Eigen::Vector3d orbitEcef(double dt, double raan, double phase) {
  constexpr double a = 26560e3, inc = 55.0 * kDegToRad;
  const double u = phase + std::sqrt(kGmGps_m3ps2 / (a * a * a)) * dt;
  const Eigen::Vector3d o(a * std::cos(u), a * std::sin(u) * std::cos(inc), a * std::sin(u) * std::sin(inc));
  const Eigen::Vector3d inertial(std::cos(raan) * o.x() - std::sin(raan) * o.y(),
                                 std::sin(raan) * o.x() + std::cos(raan) * o.y(), o.z());
  return rotateForEarthRotation(inertial, dt);
}
struct State {
  Eigen::Vector3d r, v;
};
State orbitState(double dt, double raan, double phase) {
  return {orbitEcef(dt, raan, phase), (orbitEcef(dt + 0.01, raan, phase) - orbitEcef(dt - 0.01, raan, phase)) / 0.02};
}
void expectOrthonormalRightHanded(const SatelliteBodyAxes& a) {
  EXPECT_NEAR(a.x_ecef.norm(), 1.0, 1e-12);
  EXPECT_NEAR(a.y_ecef.norm(), 1.0, 1e-12);
  EXPECT_NEAR(a.z_ecef.norm(), 1.0, 1e-12);
  EXPECT_NEAR(a.x_ecef.dot(a.y_ecef), 0.0, 1e-12);
  EXPECT_NEAR(a.x_ecef.dot(a.z_ecef), 0.0, 1e-12);
  EXPECT_NEAR(a.y_ecef.dot(a.z_ecef), 0.0, 1e-12);
  EXPECT_LT((a.x_ecef.cross(a.y_ecef) - a.z_ecef).norm(), 1e-12);
}
}  // namespace

TEST(SatelliteAttitude, NominalAxesOrthonormalAndSunPointing) {
  const Eigen::Vector3d sun = sunPositionEcef_m(kT0);
  for (int ph = 0; ph < 360; ph += 7) {
    const State s = orbitState(0.0, 0.7, ph * kDegToRad);
    const SatelliteBodyAxes a = nominalSatelliteAxes(s.r, s.v, sun);
    expectOrthonormalRightHanded(a);
    EXPECT_LT((a.z_ecef + s.r.normalized()).norm(), 1e-12);  // boresight to Earth centre
    EXPECT_GE(a.x_ecef.dot((sun - s.r).normalized()), 0.0);   // +x towards the Sun side
    EXPECT_NEAR(a.y_ecef.dot(sun - s.r), 0.0, 1e-6 * sun.norm());  // panel axis normal to the Sun
  }
}

TEST(SatelliteAttitude, YawAngleFormEqualsSunForm) {
  // Kouba (2009): psi = atan2(-tan beta, sin mu) reproduces the Sun-based triad.
  const Eigen::Vector3d sun = sunPositionEcef_m(kT0 + 7200.0);
  for (int ph = 0; ph < 360; ph += 11) {
    const State s = orbitState(7200.0, 2.1, ph * kDegToRad);
    const SatelliteBodyAxes from_sun = nominalSatelliteAxes(s.r, s.v, sun);
    const SatelliteBodyAxes from_yaw =
        satelliteAxesFromYaw(s.r, s.v, nominalYawAngle_rad(orbitSunAngles(s.r, s.v, sun)));
    expectOrthonormalRightHanded(from_yaw);
    EXPECT_LT((from_sun.x_ecef - from_yaw.x_ecef).norm(), 1e-9) << ph;
    EXPECT_LT((from_sun.y_ecef - from_yaw.y_ecef).norm(), 1e-9) << ph;
  }
}

TEST(SatelliteAttitude, BetaAndMuGeometry) {
  // Sun in the orbit plane on +x of the orbit: beta = 0; satellite on the far side
  // is at orbit midnight (mu = 0), on the near side at noon (|mu| = pi).
  const Eigen::Vector3d r(-26560e3, 0, 0), v(0, -3874.0, 0);  // normal r x v = +z
  const Eigen::Vector3d v_ecef = v - Eigen::Vector3d(0, 0, kEarthRotationRate_radps).cross(r);
  const Eigen::Vector3d sun(1.496e11, 0, 0);
  const OrbitSunAngles mid = orbitSunAngles(r, v_ecef, sun);
  EXPECT_NEAR(mid.beta_rad, 0.0, 1e-9);
  EXPECT_NEAR(mid.mu_rad, 0.0, 1e-9);
  const OrbitSunAngles noon = orbitSunAngles(-r, -v_ecef, sun);
  EXPECT_NEAR(std::abs(noon.mu_rad), kPi, 1e-9);
  // Sun 30 deg above the plane on the normal (+z) side.
  const Eigen::Vector3d sun_up(1.496e11 * std::cos(kPi / 6), 0, 1.496e11 * std::sin(kPi / 6));
  EXPECT_NEAR(orbitSunAngles(r, v_ecef, sun_up).beta_rad, kPi / 6, 1e-3);  // 1e-3: parallax
}

TEST(PhaseWindup, ReceiverRotationSignConvention) {
  // Satellite at the receiver's zenith; turning the antenna +90 deg about up
  // (north -> west, counter-clockwise seen from above) changes the wind-up by
  // -0.25 cycle (convention documented in phase_windup.h).
  const Geodetic g = ecefToGeodetic(kZim2);
  const Eigen::Matrix3d R = rotationEnuFromEcef(g.latitude_rad, g.longitude_rad);
  const Eigen::Vector3d east = R.row(0).transpose(), north = R.row(1).transpose(), up = R.row(2).transpose();
  const Eigen::Vector3d sat = kZim2 + 20200e3 * up;
  const State s = orbitState(0.0, 0.0, 0.0);  // only the velocity direction matters for the axes
  const SatelliteBodyAxes sat_axes = nominalSatelliteAxes(sat, s.v, sunPositionEcef_m(kT0));
  const ReceiverAntennaAxes nw = northWestAntennaAxes(g.latitude_rad, g.longitude_rad);
  EXPECT_LT((nw.x_ecef - north).norm(), 1e-12);
  EXPECT_LT((nw.y_ecef + east).norm(), 1e-12);
  const double w0 = *phaseWindup_cycles(sat_axes, nw, sat, kZim2);
  const ReceiverAntennaAxes turned{-east, -north};  // x: west, y: south
  const double w90 = *phaseWindup_cycles(sat_axes, turned, sat, kZim2, w0);
  EXPECT_NEAR(w90 - w0, -0.25, 1e-9);
}

TEST(PhaseWindup, FullAntennaTurnIsOneCycleAtAnyElevation) {
  const Geodetic g = ecefToGeodetic(kZim2);
  const Eigen::Matrix3d R = rotationEnuFromEcef(g.latitude_rad, g.longitude_rad);
  const Eigen::Vector3d east = R.row(0).transpose(), north = R.row(1).transpose();
  const State s = orbitState(0.0, 0.4, 0.9);
  ASSERT_GT(azimuthElevation(kZim2, s.r).elevation_rad, 0.0);
  const SatelliteBodyAxes sat_axes = nominalSatelliteAxes(s.r, s.v, sunPositionEcef_m(kT0));
  std::optional<double> w;
  double first = 0.0;
  for (int deg = 0; deg <= 360; deg += 10) {
    const double a = deg * kDegToRad;
    // x turned counter-clockwise from north by a; y = z x x.
    const Eigen::Vector3d x = std::cos(a) * north - std::sin(a) * east;
    const Eigen::Vector3d y = -std::cos(a) * east - std::sin(a) * north;
    const auto now = phaseWindup_cycles(sat_axes, {x, y}, s.r, kZim2, w);
    ASSERT_TRUE(now);
    if (w) EXPECT_LT(std::abs(*now - *w), 0.1);
    if (!w) first = *now;
    w = now;
  }
  EXPECT_NEAR(*w - first, -1.0, 1e-9);
}

TEST(PhaseWindup, ContinuousOverAPass) {
  // Follow a satellite over ZIM2 for 12 h at 30 s while it is above 5 deg: the
  // unwrapped wind-up never jumps (|step| well below a cycle), stays an integer
  // away from the raw value in [-0.5, 0.5], and the antenna/attitude are fixed
  // so the total change stays within a couple of cycles.
  const Geodetic g = ecefToGeodetic(kZim2);
  const ReceiverAntennaAxes rcv = northWestAntennaAxes(g.latitude_rad, g.longitude_rad);
  std::optional<double> w;
  int samples = 0;
  double w_min = 1e9, w_max = -1e9;
  for (double dt = 0.0; dt < 12 * 3600.0; dt += 30.0) {
    const State s = orbitState(dt, 0.2, 1.3);
    if (azimuthElevation(kZim2, s.r).elevation_rad < 5 * kDegToRad) {
      w.reset();  // a new arc starts after the satellite sets
      continue;
    }
    const SatelliteBodyAxes a = nominalSatelliteAxes(s.r, s.v, sunPositionEcef_m(kT0 + dt));
    const auto raw = phaseWindup_cycles(a, rcv, s.r, kZim2);
    const auto now = phaseWindup_cycles(a, rcv, s.r, kZim2, w);
    ASSERT_TRUE(raw && now);
    EXPECT_LE(std::abs(*raw), 0.5);
    EXPECT_NEAR(*now - *raw, std::round(*now - *raw), 1e-12);
    if (w) EXPECT_LT(std::abs(*now - *w), 0.1) << dt;
    w = now;
    w_min = std::min(w_min, *now);
    w_max = std::max(w_max, *now);
    ++samples;
  }
  EXPECT_GT(samples, 200);
  EXPECT_LT(w_max - w_min, 2.0);
}
