// The IMU input screen (navigation/imu_input_screen.h): a clean stream passes
// whole and in order; readings in g are found from their first 50 readings and
// refused; backwards, repeated and non-finite stamps are refused, gaps kept and
// counted; saturated axes and a time base far from the GNSS time are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "ppp_bayes_tree/navigation/imu_input_screen.h"
#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

const GnssTime kStart = GnssTime::fromGpsWeek(2111, 345600.0);

/// A reading at rest, z axis down (the specific force points up: -g on z), `t_s` after the start.
ImuSample atRest(double t_s, double gravity = kStandardGravity_mps2) {
  ImuSample s;
  s.time = kStart + t_s;
  s.specific_force_mps2 = Eigen::Vector3d(0.01, -0.02, -gravity);
  s.angular_rate_radps = Eigen::Vector3d(1e-4, -2e-4, 5e-5);
  return s;
}

/// Pushes 200 Hz readings at rest from t0_s; returns every released reading.
std::vector<ImuSample> pushStream(ImuInputScreen& screen, int n, double t0_s = 0.0,
                                  double gravity = kStandardGravity_mps2) {
  std::vector<ImuSample> out;
  for (int i = 0; i < n; ++i)
    for (const ImuSample& s : screen.push(atRest(t0_s + 0.005 * i, gravity))) out.push_back(s);
  return out;
}

TEST(ImuInputScreen, ACleanStreamPassesWholeAndInOrderAfterTheUnitsAreDecided) {
  ImuInputScreen screen;
  // The first 49 are held while the units are undecided.
  for (int i = 0; i < 49; ++i) EXPECT_TRUE(screen.push(atRest(0.005 * i)).empty());
  EXPECT_EQ(screen.units(), ImuAccelerationUnits::Undecided);
  const std::vector<ImuSample> first = screen.push(atRest(0.005 * 49));
  ASSERT_EQ(first.size(), 50u);
  EXPECT_EQ(screen.units(), ImuAccelerationUnits::MetresPerSecondSquared);
  for (std::size_t i = 0; i < first.size(); ++i) EXPECT_DOUBLE_EQ(first[i].time - kStart, 0.005 * i);
  const std::vector<ImuSample> rest = pushStream(screen, 50, 0.25);
  EXPECT_EQ(rest.size(), 50u);
  EXPECT_EQ(screen.accepted(), 100u);
  EXPECT_TRUE(screen.problems().empty());
  EXPECT_EQ(screen.summary(), "100 IMU readings accepted; 0 refused; 0 gaps; units m/s^2");
}

TEST(ImuInputScreen, AccelerationsInGAreRefusedWithTheReason) {
  ImuInputScreen screen;
  EXPECT_TRUE(pushStream(screen, 120, 0.0, 1.0).empty());  // at rest the specific force reads 1 (g)
  EXPECT_EQ(screen.units(), ImuAccelerationUnits::Gravity);
  EXPECT_EQ(screen.accepted(), 0u);
  EXPECT_EQ(screen.count(ImuInputProblem::InGravityUnits), 120u);
  const std::string first = screen.problems().at(ImuInputProblem::InGravityUnits).first;
  EXPECT_NE(first.find("accelerations in g, not m/s^2"), std::string::npos) << first;
  EXPECT_NE(first.find("mean specific force 1.000 over the first 50 readings"), std::string::npos) << first;
  EXPECT_NE(screen.summary().find("120 refused (120 accelerations in g, not m/s^2)"), std::string::npos)
      << screen.summary();
}

TEST(ImuInputScreen, BadStampsAndValuesAreRefusedAndGapsKept) {
  ImuInputScreenOptions o;
  o.units_readings = 1;  // decide on the first reading
  ImuInputScreen screen(o);
  EXPECT_EQ(screen.push(atRest(1.0)).size(), 1u);
  EXPECT_TRUE(screen.push(atRest(1.0)).empty());    // duplicate
  EXPECT_TRUE(screen.push(atRest(0.995)).empty());  // backwards
  ImuSample nan = atRest(1.005);
  nan.angular_rate_radps.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(screen.push(nan).empty());
  EXPECT_EQ(screen.push(atRest(1.005)).size(), 1u);  // the stream goes on
  EXPECT_EQ(screen.push(atRest(1.5)).size(), 1u);    // 0.495 s later: a gap, kept
  EXPECT_EQ(screen.count(ImuInputProblem::DuplicateTime), 1u);
  EXPECT_EQ(screen.count(ImuInputProblem::TimeBackwards), 1u);
  EXPECT_EQ(screen.count(ImuInputProblem::NonFinite), 1u);
  EXPECT_EQ(screen.count(ImuInputProblem::Gap), 1u);
  EXPECT_NE(screen.problems().at(ImuInputProblem::Gap).first.find("0.495 s since the previous reading"),
            std::string::npos);
  EXPECT_EQ(screen.accepted(), 3u);
}

TEST(ImuInputScreen, SaturatedAxesAreRefused) {
  ImuInputScreenOptions o;
  o.units_readings = 1;
  o.accel_full_scale_mps2 = 16.0 * kStandardGravity_mps2;  // a +-16 g setting
  o.gyro_full_scale_radps = 2000.0 * kDegToRad;          // +-2000 deg/s
  ImuInputScreen screen(o);
  ImuSample s = atRest(0.0);
  s.specific_force_mps2.x() = 15.0 * kStandardGravity_mps2;
  EXPECT_EQ(screen.push(s).size(), 1u);
  s.time += 0.005;
  s.specific_force_mps2.x() = -16.0 * kStandardGravity_mps2;  // pinned at the negative full scale
  EXPECT_TRUE(screen.push(s).empty());
  s.time += 0.005;
  s.specific_force_mps2.x() = 0.0;
  s.angular_rate_radps.z() = 2000.0 * kDegToRad;
  EXPECT_TRUE(screen.push(s).empty());
  EXPECT_EQ(screen.count(ImuInputProblem::Saturated), 2u);
  // Without a full scale nothing is taken as saturated.
  ImuInputScreen unchecked(ImuInputScreenOptions{});
  EXPECT_EQ(unchecked.count(ImuInputProblem::Saturated), 0u);
}

TEST(ImuInputScreen, ATimeBaseFarFromTheGnssTimeIsRefused) {
  ImuInputScreenOptions o;
  o.units_readings = 1;
  ImuInputScreen screen(o);
  const GnssTime gnss = kStart + 1.0;
  EXPECT_EQ(screen.push(atRest(0.5), gnss).size(), 1u);  // 0.5 s from the GNSS epoch
  ImuSample since_boot = atRest(0.505);
  since_boot.time = GnssTime::fromGpsWeek(2111, 312.0);  // seconds since boot taken as GPS time
  EXPECT_TRUE(screen.push(since_boot, gnss).empty());
  EXPECT_EQ(screen.count(ImuInputProblem::FarFromGnssTime), 1u);
}

TEST(ImuInputScreen, AShortStreamIsReleasedAtTheEnd) {
  ImuInputScreen screen;
  EXPECT_TRUE(pushStream(screen, 10).empty());
  EXPECT_EQ(screen.finish().size(), 10u);
  EXPECT_EQ(screen.accepted(), 10u);
  EXPECT_TRUE(screen.finish().empty());
}

TEST(ImuInputScreen, OptionsOutOfRangeAreRefused) {
  ImuInputScreenOptions o;
  o.max_gap_s = 0.0;
  EXPECT_THROW(ImuInputScreen{o}, std::invalid_argument);
  o = {};
  o.saturation_fraction = 1.5;
  EXPECT_THROW(ImuInputScreen{o}, std::invalid_argument);
  o = {};
  o.units_readings = 0;
  EXPECT_THROW(ImuInputScreen{o}, std::invalid_argument);
}

}  // namespace
}  // namespace ppp
