// Earth shadow on a satellite: geometric cases.
#include <gtest/gtest.h>

#include "ppp_bayes_tree/models/satellite_eclipse.h"
#include "ppp_bayes_tree/types/constants.h"

using namespace ppp;

namespace {
const Eigen::Vector3d kSun(1.496e11, 0.0, 0.0);  // Sun on +x at 1 AU
constexpr double kR = 26560e3;                   // GPS orbit radius
}  // namespace

TEST(Eclipse, DaySideIsSunlit) {
  const Eigen::Vector3d sat(kR, 0, 0);
  EXPECT_FALSE(inCylindricalShadow(sat, kSun));
  EXPECT_EQ(sunlightFraction(sat, kSun), 1.0);
  EXPECT_EQ(eclipseState(sat, kSun), EclipseState::Sunlit);
  // Also sunlit beside the Earth (terminator plane), far from the shadow.
  EXPECT_EQ(eclipseState(Eigen::Vector3d(0, kR, 0), kSun), EclipseState::Sunlit);
}

TEST(Eclipse, BehindTheEarthIsUmbra) {
  const Eigen::Vector3d sat(-kR, 0, 0);
  EXPECT_TRUE(inCylindricalShadow(sat, kSun));
  EXPECT_EQ(sunlightFraction(sat, kSun), 0.0);
  EXPECT_EQ(eclipseState(sat, kSun), EclipseState::Umbra);
}

TEST(Eclipse, ShadowEdgeIsPenumbraWithMonotonicLight) {
  // Behind the Earth at GPS distance the umbra radius is about
  // R_E (1 - d / L_umbra) ~ 6256 km and the penumbra reaches ~6500 km
  // (cone half-angles (R_sun -/+ R_E) / 1 AU): light grows monotonically across.
  double last = -1.0;
  for (double y_km = 6000.0; y_km <= 6800.0; y_km += 20.0) {
    const Eigen::Vector3d sat(-kR, y_km * 1e3, 0);
    const double f = sunlightFraction(sat, kSun);
    EXPECT_GE(f, last);
    last = f;
    EXPECT_EQ(inCylindricalShadow(sat, kSun), y_km * 1e3 < kWgs84SemiMajorAxis_m);
  }
  EXPECT_EQ(eclipseState(Eigen::Vector3d(-kR, 6150e3, 0), kSun), EclipseState::Umbra);
  EXPECT_EQ(eclipseState(Eigen::Vector3d(-kR, 6378e3, 0), kSun), EclipseState::Penumbra);
  EXPECT_EQ(eclipseState(Eigen::Vector3d(-kR, 6650e3, 0), kSun), EclipseState::Sunlit);
  // On the cylinder edge the Earth limb crosses the Sun's centre: half the disc visible.
  EXPECT_NEAR(sunlightFraction(Eigen::Vector3d(-kR, kWgs84SemiMajorAxis_m, 0), kSun), 0.5, 0.05);
}

TEST(Eclipse, FrontOfEarthNeverShadowedEvenWithinOneRadius) {
  EXPECT_FALSE(inCylindricalShadow(Eigen::Vector3d(kR, 1000e3, 0), kSun));
  EXPECT_EQ(sunlightFraction(Eigen::Vector3d(kR, 1000e3, 0), kSun), 1.0);
}
