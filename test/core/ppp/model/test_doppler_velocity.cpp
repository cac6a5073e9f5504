// The receiver velocity from Doppler range rates (doppler_velocity.h) on a
// synthetic constellation: the known velocity and clock drift recovered, a gross
// Doppler outlier rejected by the screen, too few satellites refused, and the
// satellites below the cutoff left out.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "ppp_bayes_tree/ppp/model/doppler_velocity.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace {

using Eigen::Vector3d;

const Vector3d kReceiver(4331299.5841, 567537.7070, 4633133.9645);  // ZIM2 (data README)
const Vector3d kVelocity(1.2, -0.7, 0.3);                           // ECEF [m/s]
constexpr double kDrift_mps = 45.0;

/// Satellites at (azimuth, elevation) [deg], 21000 km away, moving 3 km/s across.
std::vector<ppp::DopplerObservation> constellation(const std::vector<std::pair<double, double>>& az_el) {
  const ppp::Geodetic g = ppp::ecefToGeodetic(kReceiver);
  const Eigen::Matrix3d enu_from_ecef = ppp::rotationEnuFromEcef(g.latitude_rad, g.longitude_rad);
  std::vector<ppp::DopplerObservation> out;
  int prn = 1;
  for (const auto& [az_deg, el_deg] : az_el) {
    const double az = az_deg * ppp::kDegToRad, el = el_deg * ppp::kDegToRad;
    const Vector3d enu(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el));
    const Vector3d los = enu_from_ecef.transpose() * enu;
    ppp::DopplerObservation d;
    d.satellite = {ppp::GnssSystem::GPS, prn};
    d.satellite_position_ecef_m = kReceiver + 21.0e6 * los;
    d.satellite_velocity_ecef_mps = 3000.0 * los.cross(Vector3d(0.1 * prn, 1.0, 0.3)).normalized() + 50.0 * prn * los;
    d.satellite_clock_rate_mps = 0.01 * prn;
    const ppp::RangeRatePrediction p =
        ppp::predictRangeRate(d.satellite_position_ecef_m, d.satellite_velocity_ecef_mps, kReceiver, kVelocity);
    d.range_rate_mps = p.range_rate_mps + kDrift_mps - d.satellite_clock_rate_mps;
    out.push_back(d);
    ++prn;
  }
  return out;
}

const std::vector<std::pair<double, double>> kSky = {{0, 80}, {45, 30}, {100, 50}, {170, 20}, {220, 60},
                                                     {280, 25}, {320, 45}, {10, 15}};

TEST(DopplerVelocity, RecoversTheVelocityAndClockDrift) {
  const ppp::DopplerVelocitySolution s = ppp::solveDopplerVelocity(constellation(kSky), kReceiver, {});
  ASSERT_TRUE(s.ok()) << ppp::dopplerVelocityStatusText(s.status);
  EXPECT_LT((s.velocity_ecef_mps - kVelocity).norm(), 1e-6);
  EXPECT_NEAR(s.clock_drift_mps, kDrift_mps, 1e-6);
  EXPECT_EQ(s.used.size(), kSky.size());
  EXPECT_TRUE(s.rejected.empty());
  // The covariance of 8 satellites at 0.05 m/s (zenith): about 0.1 m/s per axis.
  EXPECT_GT(s.velocity_covariance.trace(), 0.005);
  EXPECT_LT(s.velocity_covariance.trace(), 0.1);
}

TEST(DopplerVelocity, RejectsAGrossOutlier) {
  std::vector<ppp::DopplerObservation> obs = constellation(kSky);
  obs[3].range_rate_mps += 3.0;  // a 3 m/s error (about 16 Hz at L1) on G04
  const ppp::DopplerVelocitySolution s = ppp::solveDopplerVelocity(obs, kReceiver, {});
  ASSERT_TRUE(s.ok());
  ASSERT_EQ(s.rejected.size(), 1u);
  EXPECT_EQ(s.rejected[0].prn, 4);
  EXPECT_EQ(s.used.size(), kSky.size() - 1);
  EXPECT_LT((s.velocity_ecef_mps - kVelocity).norm(), 1e-6);
}

TEST(DopplerVelocity, WrongSignOfTheDopplerIsNoSolution) {
  // Range rates of the opposite sign (D taken as +lambda D) do not fit any velocity:
  // the screen rejects down to the fewest satellites and refuses.
  std::vector<ppp::DopplerObservation> obs = constellation(kSky);
  for (auto& d : obs) d.range_rate_mps = -d.range_rate_mps;
  const ppp::DopplerVelocitySolution s = ppp::solveDopplerVelocity(obs, kReceiver, {});
  EXPECT_FALSE(s.ok() && (s.velocity_ecef_mps - kVelocity).norm() < 0.1);
}

TEST(DopplerVelocity, TooFewSatellitesAndTheCutoff) {
  const std::vector<std::pair<double, double>> sky = {{0, 80}, {90, 40}, {180, 30}, {270, 50}, {45, 3}};
  const ppp::DopplerVelocitySolution s = ppp::solveDopplerVelocity(constellation(sky), kReceiver, {});
  EXPECT_EQ(s.status, ppp::DopplerVelocityStatus::TooFewSatellites);
  EXPECT_EQ(s.below_cutoff, 1);  // the one at 3 deg, below 7 deg
  ppp::DopplerVelocityOptions low;
  low.elevation_cutoff_rad = 0.0;
  EXPECT_TRUE(ppp::solveDopplerVelocity(constellation(sky), kReceiver, low).ok());
}

}  // namespace
