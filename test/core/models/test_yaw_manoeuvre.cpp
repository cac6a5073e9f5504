// Noon and midnight yaw manoeuvres (models/yaw_manoeuvre.h): the windows in
// which the attitude departs from nominal yaw steering, against values by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "ppp_bayes_tree/models/yaw_manoeuvre.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

constexpr double kMuDot = 1.4585e-4;  // GPS orbit rate [rad/s]: 2 pi / 43080 s

OrbitSunAngles angles(double beta_deg, double mu_deg) {
  OrbitSunAngles a;
  a.beta_rad = beta_deg * kDegToRad;
  a.mu_rad = mu_deg * kDegToRad;
  return a;
}

TEST(YawManoeuvre, AngleFromTurnPointIsSignedAlongTheMotion) {
  EXPECT_NEAR(angleFromTurnPoint_rad(angles(0, 175)) * kRadToDeg, -5.0, 1e-12);   // before noon
  EXPECT_NEAR(angleFromTurnPoint_rad(angles(0, -178)) * kRadToDeg, 2.0, 1e-12);   // after noon
  EXPECT_NEAR(angleFromTurnPoint_rad(angles(0, -3)) * kRadToDeg, -3.0, 1e-12);    // before midnight
  EXPECT_NEAR(angleFromTurnPoint_rad(angles(0, 90)) * kRadToDeg, 90.0, 1e-12);
}

// Block IIF (0.11 deg/s) at beta = -1.2 deg (G26 on 2020-06-25 near 11:40 UTC):
// tan|beta| = 0.020947; sin^2 x_s = mu_dot tan|beta| / R - tan^2 beta
// = 1.4585e-4 * 0.020947 / 1.91986e-3 - 4.3878e-4 = 1.1526e-3, x_s = -1.945 deg;
// the half turn pi / R = 1636.4 s = 13.675 deg of orbit: the window is
// [-1.945, 11.730] deg about noon (and likewise about midnight).
TEST(YawManoeuvre, GpsRateLimitedNoonTurnWindowByHand) {
  const YawManoeuvreLimits gps = *yawManoeuvreLimits(GnssSystem::GPS);
  EXPECT_NEAR(gps.max_yaw_rate_radps * kRadToDeg, 0.11, 1e-12);
  EXPECT_FALSE(inYawManoeuvre(angles(-1.2, 180.0 - 2.0), kMuDot, gps));
  EXPECT_TRUE(inYawManoeuvre(angles(-1.2, 180.0 - 1.9), kMuDot, gps));
  EXPECT_TRUE(inYawManoeuvre(angles(-1.2, -180.0 + 11.7), kMuDot, gps));
  EXPECT_FALSE(inYawManoeuvre(angles(-1.2, -180.0 + 11.8), kMuDot, gps));
  EXPECT_TRUE(inYawManoeuvre(angles(1.2, 5.0), kMuDot, gps));  // midnight, either sign of beta
  // The nominal rate at the turn point, mu_dot / tan|beta|, reaches 0.11 deg/s
  // only for |beta| < atan(mu_dot / R) = 4.34 deg: no turn above.
  EXPECT_TRUE(inYawManoeuvre(angles(4.3, 180.0), kMuDot, gps));
  EXPECT_FALSE(inYawManoeuvre(angles(4.4, 180.0), kMuDot, gps));
  EXPECT_FALSE(inYawManoeuvre(angles(-1.2, 90.0), kMuDot, gps));  // far from the turn points
}

// The rate-limited yaw at the same noon turn (beta = -1.2 deg, so it turns the
// nominal way, +1 = -sign(beta)): psi_s = atan2(-tan beta, sin(pi + x_s)) =
// atan2(0.020947, 0.033944) = 31.675 deg at x_s = -1.9455 deg (where it equals
// the nominal one), then 0.11 deg/s
// for (x - x_s) / mu_dot seconds (mu_dot = 0.0083566 deg/s):
//   x = -1 deg: 31.675 + 0.11 * 113.1 s = 44.121 deg (nominal 50.200);
//   x = +5 deg: 31.675 + 0.11 * 831.1 s = 123.101 deg (nominal 166.486);
//   x = +11 deg: 202.08 deg would be past the nominal 173.74: caught up, nominal.
TEST(YawManoeuvre, RateLimitedYawByHand) {
  const YawManoeuvreLimits gps = *yawManoeuvreLimits(GnssSystem::GPS);
  const auto yaw_deg = [&](double mu_deg) {
    const std::optional<double> y = rateLimitedYaw_rad(angles(-1.2, mu_deg), kMuDot, gps);
    return y ? *y * kRadToDeg : std::nan("");
  };
  EXPECT_NEAR(yaw_deg(180.0 - 1.0), 44.121, 0.01);
  EXPECT_NEAR(yaw_deg(-180.0 + 5.0), 123.101, 0.01);
  EXPECT_FALSE(rateLimitedYaw_rad(angles(-1.2, -180.0 + 11.0), kMuDot, gps).has_value());
  EXPECT_FALSE(rateLimitedYaw_rad(angles(-1.2, 180.0 - 3.0), kMuDot, gps).has_value());  // before the turn
  // beta > 0 at noon turns the other way: the mirror image.
  EXPECT_NEAR(*rateLimitedYaw_rad(angles(1.2, -180.0 + 5.0), kMuDot, gps) * kRadToDeg, -123.101, 0.01);
  // Galileo has no rate model.
  EXPECT_FALSE(rateLimitedYaw_rad(angles(-1.2, 180.0), kMuDot, *yawManoeuvreLimits(GnssSystem::Galileo)).has_value());
}

TEST(YawManoeuvre, GalileoSmoothedYawWindow) {
  const YawManoeuvreLimits gal = *yawManoeuvreLimits(GnssSystem::Galileo);
  EXPECT_TRUE(inYawManoeuvre(angles(4.0, 170.0), kMuDot, gal));
  EXPECT_TRUE(inYawManoeuvre(angles(-4.0, -14.0), kMuDot, gal));
  EXPECT_FALSE(inYawManoeuvre(angles(4.2, 180.0), kMuDot, gal));
  EXPECT_FALSE(inYawManoeuvre(angles(1.0, 16.0), kMuDot, gal));
}

TEST(YawManoeuvre, SystemsWithoutLimitsKeepTheNominalAttitude) {
  EXPECT_FALSE(yawManoeuvreLimits(GnssSystem::BeiDou).has_value());
  const Eigen::Vector3d r(26.56e6, 0.0, 0.0), v(0.0, 3874.0, 0.0), sun(0.0, 0.0, 1.5e11);
  EXPECT_FALSE(inYawManoeuvre(GnssSystem::BeiDou, r, v, sun));
}

// A circular equatorial orbit (inertial rate 2 pi / 43080 s) with the Sun in
// the orbit plane (beta = 0): the satellite between the Earth and the Sun is at
// orbit noon: the nominal yaw flips there at once, so the turn starts at noon
// (x_s = 0): 0.38 deg past it inside the GPS window, 0.38 deg before it and a
// quarter orbit on outside.
TEST(YawManoeuvre, FromTheEcefStateAtOrbitNoon) {
  const double radius_m = 26.56e6;
  const double rate = 2.0 * kPi / 43080.0;
  const Eigen::Vector3d r(radius_m, 0.0, 0.0);
  const Eigen::Vector3d v_ecef(0.0, radius_m * (rate - kEarthRotationRate_radps), 0.0);
  EXPECT_NEAR(orbitAngularRate_radps(r, v_ecef), rate, 1e-12);
  EXPECT_TRUE(inYawManoeuvre(GnssSystem::GPS, r, v_ecef, Eigen::Vector3d(1.5e11, -1.0e9, 0.0)));
  EXPECT_FALSE(inYawManoeuvre(GnssSystem::GPS, r, v_ecef, Eigen::Vector3d(1.5e11, 1.0e9, 0.0)));
  const Eigen::Vector3d sun_quarter(0.0, 1.5e11, 0.0);
  EXPECT_FALSE(inYawManoeuvre(GnssSystem::GPS, r, v_ecef, sun_quarter));
}

}  // namespace
}  // namespace ppp
