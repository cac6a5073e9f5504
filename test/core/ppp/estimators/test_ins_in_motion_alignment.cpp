// The alignment in motion shared by ekf_ins and smoother_ins (ins_in_motion_alignment.h):
// the course of an antenna track (no heading before the interval or below the speed;
// then the course, its sigma velocity sigma / speed, and the track's velocity); the
// attitude covariance with the heading's variance set in NED, the tilt kept; the state
// turned to the course with its antenna kept; the levelling history's two minutes; the
// gyro bias from the static interval, and the tilt carried to the start without it; a
// mean rate at rest that the grade's bias instability and the Earth's horizontal rate
// explain leaves the grade's prior.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/ppp/estimators/ins_in_motion_alignment.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

const Eigen::Vector3d kPosition_m(4331297.0, 567555.0, 4633133.0);

GnssTime start() { return GnssTime::fromGpsWeek(2300, 1000.0); }

/// The antenna track at 4 Hz moving `speed_mps` towards `course_rad` (NED) from kPosition_m;
/// the course found by `track` at each position: the first one (time from the start) and its result.
std::pair<double, std::optional<CourseHeading>> firstCourse(CourseHeadingTrack& track, double speed_mps,
                                                            double course_rad) {
  const Eigen::Matrix3d ecef_ned = rotationEcefNed(kPosition_m);
  const Eigen::Vector3d v_ecef = ecef_ned * Eigen::Vector3d(std::cos(course_rad), std::sin(course_rad), 0.0) * speed_mps;
  for (int k = 0; k <= 20; ++k) {
    const double t_s = 0.25 * k;
    if (auto c = track.add(start() + t_s, kPosition_m + v_ecef * t_s)) return {t_s, c};
  }
  return {-1.0, std::nullopt};
}

TEST(InsInMotionAlignment, CourseOfTheTrackOnceItSpansTheIntervalFastEnough) {
  InsEkfOptions::HeadingAlignment o;  // 0.5 m/s over 1 s, velocity sigma 0.1 m/s
  CourseHeadingTrack track(o);
  const double course_rad = 2.0;
  const auto [t_s, c] = firstCourse(track, 1.25, course_rad);
  ASSERT_TRUE(c);
  EXPECT_DOUBLE_EQ(t_s, o.course_interval_s);  // not before the track spans the interval
  EXPECT_NEAR(c->heading.heading_rad, course_rad, 1e-6);  // the NED frame of the end, 1.25 m on: 2e-7 rad
  EXPECT_NEAR(c->heading.heading_sigma_rad, o.velocity_sigma_mps / 1.25, 1e-9);
  EXPECT_NEAR(c->velocity_ecef_mps.norm(), 1.25, 1e-9);
  // Too slow: no course in 5 s.
  CourseHeadingTrack slow(o);
  EXPECT_FALSE(firstCourse(slow, 0.4, course_rad).second);
}

TEST(InsInMotionAlignment, HeadingVarianceSetAboutDownWithTheTiltKept) {
  const Eigen::Matrix3d ned_body = rotationNedBody(0.1, -0.2, 1.0);
  const Eigen::Matrix3d body = 4e-4 * Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d c = attitudeCovarianceWithHeading(ned_body, body, 0.3);
  const Eigen::Matrix3d ned = ned_body * c * ned_body.transpose();
  EXPECT_NEAR(ned(2, 2), 0.09, 1e-12);
  EXPECT_NEAR(ned(0, 0), 4e-4, 1e-12);
  EXPECT_NEAR(ned(1, 1), 4e-4, 1e-12);
  EXPECT_NEAR(ned(0, 2), 0.0, 1e-12);
  EXPECT_NEAR(ned(1, 2), 0.0, 1e-12);
}

TEST(InsInMotionAlignment, TurnedToTheCourseWithTheAntennaKept) {
  NavState nav;
  nav.position_world_m = kPosition_m;
  const Eigen::Matrix3d ecef_ned = rotationEcefNed(kPosition_m);
  nav.rotation_world_body = ecef_ned * rotationNedBody(0.05, -0.03, 0.7);
  const Eigen::Vector3d lever_m(0.5, 0.2, -1.0), antenna_m = kPosition_m + Eigen::Vector3d(1.0, 2.0, 3.0);
  const NavState aligned = alignedToCourse(nav, -2.5, antenna_m, lever_m);
  const EulerAngles e = eulerAngles(ecef_ned.transpose() * aligned.rotation_world_body);
  EXPECT_NEAR(e.yaw_rad, -2.5, 1e-12);
  EXPECT_NEAR(e.roll_rad, 0.05, 1e-12);
  EXPECT_NEAR(e.pitch_rad, -0.03, 1e-12);
  EXPECT_LT((aligned.position_world_m + aligned.rotation_world_body * lever_m - antenna_m).norm(), 1e-9);
}

TEST(InsInMotionAlignment, LevellingHistoryKeepsTwoMinutes) {
  std::vector<ImuSample> history, readings;
  for (int k = 0; k < 200; ++k) readings.push_back(ImuSample{start() + k * 1.0, {}, {}});
  keepLevellingHistory(history, readings, start() + 199.0);
  ASSERT_FALSE(history.empty());
  EXPECT_DOUBLE_EQ(history.front().time - start(), 199.0 - kLevellingHistory_s);
  EXPECT_EQ(history.size(), 121u);
}

TEST(InsInMotionAlignment, GyroBiasFromTheStaticIntervalAndTiltCarriedWithoutIt) {
  // 2 s at rest, then 5 s turning about the body z axis at 0.5 rad/s, at 150 Hz. The
  // gyros read the body rate, the Earth's rate and a bias of (0.094, -0.153, 0.189)
  // deg/s (the walk's gyros at rest, doc/studies/ins_walk.md).
  const Eigen::Vector3d bias_radps(0.00164, -0.00267, 0.00330), earth_rate_ecef(0.0, 0.0, kEarthRotationRate_radps);
  const Eigen::Matrix3d ecef_ned = rotationEcefNed(kPosition_m), ned_body0 = rotationNedBody(0.1, -0.05, 0.6);
  const double gravity_mps2 = ecefNavigationFrame(kPosition_m).gravity_world_mps2.norm();
  const double dt_s = 1.0 / 150.0, rate_radps = 0.5;
  const auto ned_body = [&](double t_s) {
    return Eigen::Matrix3d(ned_body0 * so3::expMap(Eigen::Vector3d(0.0, 0.0, rate_radps * std::max(0.0, t_s - 2.0))));
  };
  std::vector<ImuSample> readings;
  for (int k = 0; k <= 7 * 150; ++k) {
    const double t_s = k * dt_s;
    const Eigen::Matrix3d body_ecef = (ecef_ned * ned_body(t_s)).transpose();
    ImuSample s;
    s.time = start() + t_s;
    s.angular_rate_radps = Eigen::Vector3d(0.0, 0.0, t_s >= 2.0 ? rate_radps : 0.0) + body_ecef * earth_rate_ecef + bias_radps;
    s.specific_force_mps2 = ned_body(t_s).transpose() * Eigen::Vector3d(0.0, 0.0, -gravity_mps2);
    readings.push_back(s);
  }
  const ImuNoise consumer = imuNoisePreset(ImuGrade::ConsumerMems);
  const InMotionLevel level = levelInMotion(readings, kPosition_m, start() + 7.0, consumer);
  ASSERT_TRUE(level.rotation_ecef_body) << level.problem;
  // Taken, with the sigma of the Earth's horizontal rate (7.292e-5 cos(46.9 deg) = 4.98e-5
  // rad/s; the readings have no noise) and the grade's 2 deg/h, root-sum-squared.
  ASSERT_TRUE(level.gyro_bias_sigma_radps);
  const double expected_radps = std::hypot(4.98e-5, consumer.gyro_bias_instability_radps);
  EXPECT_NEAR(*level.gyro_bias_sigma_radps, expected_radps, 0.01 * expected_radps);
  // The Earth's horizontal rate stays in the bias: 15 deg/h cos(latitude 46.9 deg) = 5.0e-5 rad/s.
  EXPECT_LT((level.gyro_bias_radps - bias_radps).norm(), 5.1e-5);
  // Roll and pitch carried by the gyros less that bias: the bias left over 5 s of turning
  // tilts by at most 5.1e-5 rad/s x 5 s (3e-4 found); with the whole bias left, 9e-3 in roll and 6e-3 in pitch.
  const EulerAngles truth = eulerAngles(ned_body(7.0)), carried = eulerAngles(ecef_ned.transpose() * *level.rotation_ecef_body);
  EXPECT_NEAR(carried.roll_rad, truth.roll_rad, 5e-4);
  EXPECT_NEAR(carried.pitch_rad, truth.pitch_rad, 5e-4);
  // A slow turn the levelling accepts (2 deg/s about z, below its 2.9 deg/s) is not a bias.
  for (ImuSample& s : readings) s.angular_rate_radps.z() += 2.0 * kDegToRad;
  const InMotionLevel turning = levelInMotion(readings, kPosition_m, start() + 7.0, consumer);
  ASSERT_TRUE(turning.rotation_ecef_body) << turning.problem;
  EXPECT_EQ(turning.gyro_bias_radps, Eigen::Vector3d::Zero());
  EXPECT_FALSE(turning.gyro_bias_sigma_radps);
}

/// 2 s at rest at 150 Hz with the attitude rotationNedBody(0.1, -0.05, 0.6): gravity, and the
/// Earth's rate plus `bias_radps` in the body axes (no noise).
std::vector<ImuSample> atRest(const Eigen::Vector3d& bias_radps) {
  const Eigen::Matrix3d ned_body = rotationNedBody(0.1, -0.05, 0.6);
  const Eigen::Matrix3d body_ecef = (rotationEcefNed(kPosition_m) * ned_body).transpose();
  const double gravity_mps2 = ecefNavigationFrame(kPosition_m).gravity_world_mps2.norm();
  std::vector<ImuSample> readings;
  for (int k = 0; k <= 2 * 150; ++k) {
    ImuSample s;
    s.time = start() + k / 150.0;
    s.angular_rate_radps = body_ecef * Eigen::Vector3d(0.0, 0.0, kEarthRotationRate_radps) + bias_radps;
    s.specific_force_mps2 = ned_body.transpose() * Eigen::Vector3d(0.0, 0.0, -gravity_mps2);
    readings.push_back(s);
  }
  return readings;
}

TEST(InsInMotionAlignment, MeanRateTheGradeAndTheEarthExplainLeavesThePrior) {
  // Readings at rest without a bias: the mean rate less the Earth's rate about down is the
  // Earth's horizontal rate, 15.04 deg/h cos(46.9 deg) = 10.3 deg/h, which the unknown
  // heading leaves in it. Taken as the industrial gyro's bias (its sigma 2 deg/h), it would
  // start the estimators 5 sigmas off: the prior stands.
  const ImuNoise industrial = imuNoisePreset(ImuGrade::IndustrialMems);
  const InMotionLevel level = levelInMotion(atRest(Eigen::Vector3d::Zero()), kPosition_m, start() + 2.0, industrial);
  ASSERT_TRUE(level.rotation_ecef_body) << level.problem;
  EXPECT_FALSE(level.gyro_bias_sigma_radps);
  EXPECT_EQ(level.gyro_bias_radps, Eigen::Vector3d::Zero());
  // A tactical gyro 20 deg/h off its zero (within what 1 deg/h and the Earth's 10.3 deg/h
  // allow at chi-square 0.999: 4.03 x 10.35 = 41.7 deg/h): the prior stands.
  const Eigen::Vector3d small_radps = Eigen::Vector3d(1.0, 0.0, 0.0) * degPerHourToRadps(20.0);
  EXPECT_FALSE(levelInMotion(atRest(small_radps), kPosition_m, start() + 2.0, imuNoisePreset(ImuGrade::Tactical))
                   .gyro_bias_sigma_radps);
  // 100 deg/h is more than they explain: taken, within the Earth's horizontal rate of it.
  const Eigen::Vector3d large_radps = Eigen::Vector3d(1.0, 0.0, 0.0) * degPerHourToRadps(100.0);
  const InMotionLevel taken = levelInMotion(atRest(large_radps), kPosition_m, start() + 2.0, industrial);
  ASSERT_TRUE(taken.gyro_bias_sigma_radps);
  EXPECT_LT((taken.gyro_bias_radps - large_radps).norm(), degPerHourToRadps(10.4));
}

}  // namespace
}  // namespace ppp
