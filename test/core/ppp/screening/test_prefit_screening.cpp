// Prefit code screening (shared by the EKF and the smoother): an outlier is
// rejected when it is identifiable, and never "found" where the geometry
// cannot tell which satellite is wrong.
#include <gtest/gtest.h>

#include <cmath>

#include "ppp_bayes_tree/ppp/screening/prefit_screening.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

/// n satellites spread in azimuth at 20-70 deg elevation; exact code residuals
/// except `outlier_m` on satellite 0.
std::vector<SatelliteMeasurement> epoch(int n, double outlier_m) {
  std::vector<SatelliteMeasurement> ms(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double az = 2 * kPi * i / n, el = (20.0 + 50.0 * (i % 3) / 2.0) * kDegToRad;
    auto& m = ms[static_cast<std::size_t>(i)];
    m.satellite = SatelliteId{GnssSystem::GPS, i + 1};
    // d(range)/d(position) = -line of sight (ENU axes used as ECEF here: geometry only).
    m.jacobian.resize(5);
    m.jacobian << -std::cos(el) * std::sin(az), -std::cos(el) * std::cos(az), -std::sin(el), 1.0 / std::sin(el), 1.0;
    m.predicted_code_m = 2.0e7;
    m.observed_code_m = 2.0e7 + (i == 0 ? outlier_m : 0.0);
    m.code_sigma_m = 0.9 / std::sin(el);
    m.phase_sigma_m = 0.009 / std::sin(el);
  }
  return ms;
}

TEST(PrefitScreening, IdentifiableOutlierIsRejected) {
  for (int n : {6, 8, 10}) {
    const auto rejected = screenCodeOutliers(epoch(n, 50.0), 30.0);
    ASSERT_EQ(rejected.size(), 1u) << n << " satellites";
    EXPECT_EQ(rejected[0].index, 0u);
    EXPECT_NEAR(rejected[0].residual_m, 50.0, 1e-6);  // deleted residual = the error itself
  }
}

TEST(PrefitScreening, CleanEpochRejectsNothing) {
  EXPECT_TRUE(screenCodeOutliers(epoch(9, 0.0), 30.0).empty());
}

TEST(PrefitScreening, RedundancyOneNeverRejects) {
  // 5 satellites, 4 unknowns: all fit residuals are proportional, so no
  // satellite can be singled out; the screening must leave the epoch alone.
  EXPECT_TRUE(screenCodeOutliers(epoch(5, 50.0), 30.0).empty());
  EXPECT_TRUE(screenCodeOutliers(epoch(4, 50.0), 30.0).empty());
}

}  // namespace
}  // namespace ppp
