// Coarse alignment: levelling from a noisy static interval within the accelerometer
// noise bound, refusal of moving or bad intervals with their reason, heading from a
// noisy GNSS velocity within the course error its noise implies, and the alignment state.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp {
namespace {

const Eigen::Vector3d kEarthRate(0.0, 0.0, kEarthRotationRate_radps);

Eigen::Vector3d stationOrigin() { return geodeticToEcef(Geodetic{47.4 * kDegToRad, 8.5 * kDegToRad, 500.0}); }

double wrapped(double angle_rad) { return std::remainder(angle_rad, 2.0 * kPi); }

/// Readings of an IMU at rest with attitude R_ecef_body and the noise densities, at
/// rate_hz for duration_s, plus an optional motion disturbance.
struct StaticInterval {
  Eigen::Vector3d position = stationOrigin();
  Eigen::Matrix3d rotation_ecef_body = Eigen::Matrix3d::Identity();
  ImuNoise noise = imuNoisePreset(ImuGrade::ConsumerMems);
  double rate_hz = 200.0;
  double duration_s = 10.0;
  double sway_mps2 = 0.0;       ///< amplitude of a 2 Hz body-x acceleration (walking)
  double turn_rate_radps = 0.0;  ///< a steady turn about body z

  std::vector<ImuSample> readings(std::mt19937& rng) const {
    const double dt = 1.0 / rate_hz;
    const Eigen::Vector3d force = -rotation_ecef_body.transpose() * ecefNavigationFrame(position).gravity_world_mps2;
    const Eigen::Vector3d rate = rotation_ecef_body.transpose() * kEarthRate;
    const double accel_sigma = noise.accel_noise_density_mps2_per_sqrthz / std::sqrt(dt);
    const double gyro_sigma = noise.gyro_noise_density_radps_per_sqrthz / std::sqrt(dt);
    std::normal_distribution<double> normal;
    std::vector<ImuSample> out;
    const int n = static_cast<int>(std::lround(duration_s * rate_hz));
    for (int k = 0; k < n; ++k) {
      ImuSample s;
      s.specific_force_mps2 = force + Eigen::Vector3d::UnitX() * sway_mps2 * std::sin(2.0 * kPi * 2.0 * k * dt);
      s.angular_rate_radps = rate + Eigen::Vector3d::UnitZ() * turn_rate_radps;
      for (int i = 0; i < 3; ++i) {
        s.specific_force_mps2[i] += accel_sigma * normal(rng);
        s.angular_rate_radps[i] += gyro_sigma * normal(rng);
      }
      out.push_back(s);
    }
    return out;
  }
};

// ENU east (1,0,0) is NED (0,1,0), ENU up is NED down; the swap is its own inverse.
TEST(InsAlignment, NedFromEnuSwapsEastAndNorthAndFlipsUp) {
  const Eigen::Matrix3d m = rotationNedEnu();
  EXPECT_TRUE((m * Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(0, 1, 0)));
  EXPECT_TRUE((m * Eigen::Vector3d(0, 1, 0)).isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_TRUE((m * Eigen::Vector3d(0, 0, 1)).isApprox(Eigen::Vector3d(0, 0, -1)));
  EXPECT_TRUE((m * m).isApprox(Eigen::Matrix3d::Identity()));
}

TEST(InsAlignment, EulerAnglesRoundTripAndYawIsTheHeadingOfBodyX) {
  const EulerAngles e = eulerAngles(rotationNedBody(0.1, -0.2, 2.5));
  EXPECT_NEAR(e.roll_rad, 0.1, 1e-12);
  EXPECT_NEAR(e.pitch_rad, -0.2, 1e-12);
  EXPECT_NEAR(e.yaw_rad, 2.5, 1e-12);
  // An IMU with z up (roll 180 deg): yaw is still the heading of its x axis.
  const Eigen::Vector3d x_ned = rotationNedBody(kPi, 0.1, 0.7).col(0);
  EXPECT_NEAR(std::atan2(x_ned.y(), x_ned.x()), 0.7, 1e-12);
  // ECEF -> NED: north is along the meridian, down towards the Earth's inside.
  const Eigen::Matrix3d ecef_ned = rotationEcefNed(stationOrigin());
  EXPECT_GT(ecef_ned.col(0).z(), 0.0);                                 // north has +z at 47 N
  EXPECT_LT(ecef_ned.col(2).dot(stationOrigin().normalized()), -0.99);  // down
}

TEST(InsAlignment, StaticLevellingIsWithinTheAccelerometerNoiseBound) {
  // The mean of N readings has per-axis noise s_f = density / sqrt(dt N); roll and
  // pitch then err by s_f / g (s_f / (g cos pitch) for roll). For the BMI088
  // (175 ug/sqrt(Hz)) over 10 s: 5.5e-5 rad. Over 50 intervals the RMS error must be
  // that bound within 25 % and every error below 4 sigma.
  StaticInterval interval;
  const double roll = 3.0 * kDegToRad, pitch = -5.0 * kDegToRad, yaw = 40.0 * kDegToRad;
  interval.rotation_ecef_body = rotationEcefNed(interval.position) * rotationNedBody(roll, pitch, yaw);
  const double g = ecefNavigationFrame(interval.position).gravity_world_mps2.norm();
  const double sigma = interval.noise.accel_noise_density_mps2_per_sqrthz / std::sqrt(interval.duration_s) / g;
  std::mt19937 rng(7);
  double sum_sq_roll = 0.0, sum_sq_pitch = 0.0;
  const int intervals = 50;
  for (int i = 0; i < intervals; ++i) {
    const LevelingResult r = levelFromStaticInterval(interval.readings(rng), interval.position);
    ASSERT_EQ(r.status, LevelingStatus::Level) << levelingStatusText(r.status);
    const double roll_error = r.roll_rad - roll, pitch_error = r.pitch_rad - pitch;
    EXPECT_LT(std::abs(roll_error), 4.0 * sigma / std::cos(pitch));
    EXPECT_LT(std::abs(pitch_error), 4.0 * sigma);
    EXPECT_NEAR(r.tilt_sigma_rad / sigma, 1.0, 0.1);  // the result states the bound
    sum_sq_roll += roll_error * roll_error;
    sum_sq_pitch += pitch_error * pitch_error;
  }
  const double rms_roll = std::sqrt(sum_sq_roll / intervals), rms_pitch = std::sqrt(sum_sq_pitch / intervals);
  std::printf("levelling over 10 s: bound %.2e rad, RMS roll %.2e, pitch %.2e\n", sigma, rms_roll, rms_pitch);
  EXPECT_NEAR(rms_roll / (sigma / std::cos(pitch)), 1.0, 0.25);
  EXPECT_NEAR(rms_pitch / sigma, 1.0, 0.25);
}

TEST(InsAlignment, LevellingWithZUpGivesRoll180) {
  StaticInterval interval;
  interval.rotation_ecef_body = rotationEcefNed(interval.position) * rotationNedBody(kPi + 0.02, 0.01, 1.0);
  std::mt19937 rng(8);
  const LevelingResult r = levelFromStaticInterval(interval.readings(rng), interval.position);
  ASSERT_EQ(r.status, LevelingStatus::Level);
  EXPECT_NEAR(wrapped(r.roll_rad - (kPi + 0.02)), 0.0, 4.0 * r.tilt_sigma_rad);
  EXPECT_NEAR(r.pitch_rad, 0.01, 4.0 * r.tilt_sigma_rad);
}

TEST(InsAlignment, RefusesIntervalsThatAreNotStaticWithTheReason) {
  std::mt19937 rng(9);
  StaticInterval walking;
  walking.sway_mps2 = 1.0;
  const LevelingResult sway = levelFromStaticInterval(walking.readings(rng), walking.position);
  EXPECT_EQ(sway.status, LevelingStatus::AccelerometerSpread);
  EXPECT_GT(sway.accel_spread_mps2, 0.5);
  EXPECT_EQ(levelingStatusText(sway.status), "accelerometer spread over the threshold");

  StaticInterval turning;
  turning.turn_rate_radps = 0.3;
  EXPECT_EQ(levelFromStaticInterval(turning.readings(rng), turning.position).status, LevelingStatus::GyroRate);

  StaticInterval short_one;
  short_one.duration_s = 0.2;  // 40 readings
  EXPECT_EQ(levelFromStaticInterval(short_one.readings(rng), short_one.position).status,
            LevelingStatus::TooFewSamples);

  StaticInterval quiet;
  std::vector<ImuSample> in_g = quiet.readings(rng);  // readings logged in g, not m/s^2
  for (ImuSample& s : in_g) s.specific_force_mps2 /= kStandardGravity_mps2;
  EXPECT_EQ(levelFromStaticInterval(in_g, quiet.position).status, LevelingStatus::NotGravity);

  std::vector<ImuSample> with_nan = quiet.readings(rng);
  with_nan[17].angular_rate_radps.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(levelFromStaticInterval(with_nan, quiet.position).status, LevelingStatus::NonFiniteReading);
}

TEST(InsAlignment, HeadingFromGnssVelocityIsWithinTheCourseErrorOfItsNoise) {
  // Course over ground at 5 m/s with 0.05 m/s noise per component: sigma = 0.05 / 5
  // = 0.01 rad (the cross-track component turns the course). 500 draws.
  const Eigen::Vector3d position = stationOrigin();
  const Eigen::Matrix3d ecef_ned = rotationEcefNed(position);
  const double course = 30.0 * kDegToRad, speed = 5.0, sigma_v = 0.05;
  const Eigen::Vector3d ned(speed * std::cos(course), speed * std::sin(course), 0.3);
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  double sum_sq = 0.0, max_error = 0.0;
  const int draws = 500;
  for (int i = 0; i < draws; ++i) {
    const Eigen::Vector3d noisy = ned + sigma_v * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    const HeadingResult h = headingFromGnssVelocity(ecef_ned * noisy, position, sigma_v);
    ASSERT_EQ(h.status, HeadingStatus::Heading);
    const double error = wrapped(h.heading_rad - course);
    sum_sq += error * error;
    max_error = std::max(max_error, std::abs(error));
    EXPECT_NEAR(h.heading_sigma_rad, sigma_v / speed, 1e-3);
  }
  const double rms = std::sqrt(sum_sq / draws);
  std::printf("course over ground: expected sigma %.4f rad, RMS %.4f, max %.4f\n", sigma_v / speed, rms, max_error);
  EXPECT_NEAR(rms / (sigma_v / speed), 1.0, 0.15);  // 500 draws: 3 % standard deviation of the RMS
  EXPECT_LT(max_error, 4.0 * sigma_v / speed);

  const HeadingResult slow = headingFromGnssVelocity(ecef_ned * Eigen::Vector3d(1.0, 0.5, 0.0), position, sigma_v);
  EXPECT_EQ(slow.status, HeadingStatus::SpeedTooLow);
  EXPECT_EQ(headingStatusText(slow.status), "horizontal speed below the threshold");
  const Eigen::Vector3d bad(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0);
  EXPECT_EQ(headingFromGnssVelocity(bad, position, sigma_v).status, HeadingStatus::NonFiniteVelocity);
}

TEST(InsAlignment, StateGoesFromNotAlignedToLevelOnlyToAligned) {
  StaticInterval interval;
  const double roll = 2.0 * kDegToRad, pitch = 4.0 * kDegToRad, yaw = -120.0 * kDegToRad;
  interval.rotation_ecef_body = rotationEcefNed(interval.position) * rotationNedBody(roll, pitch, yaw);
  std::mt19937 rng(12);
  CoarseAlignment alignment;
  EXPECT_EQ(alignment.state(), AlignmentState::NotAligned);
  StaticInterval moving = interval;
  moving.sway_mps2 = 2.0;
  EXPECT_EQ(alignment.addStaticInterval(moving.readings(rng), interval.position).status,
            LevelingStatus::AccelerometerSpread);
  EXPECT_EQ(alignment.state(), AlignmentState::NotAligned);  // refused: nothing changes
  ASSERT_EQ(alignment.addStaticInterval(interval.readings(rng), interval.position).status, LevelingStatus::Level);
  EXPECT_EQ(alignment.state(), AlignmentState::LevelOnly);
  EXPECT_FALSE(attitudePublishable(alignment.state()));
  const Eigen::Matrix3d ecef_ned = rotationEcefNed(interval.position);
  EXPECT_EQ(alignment.addGnssVelocity(ecef_ned * Eigen::Vector3d(0.3, 0.2, 0.0), interval.position, 0.05).status,
            HeadingStatus::SpeedTooLow);
  EXPECT_EQ(alignment.state(), AlignmentState::LevelOnly);
  const Eigen::Vector3d along_x = 8.0 * Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0.0);
  ASSERT_EQ(alignment.addGnssVelocity(ecef_ned * along_x, interval.position, 0.05).status, HeadingStatus::Heading);
  EXPECT_EQ(alignment.state(), AlignmentState::Aligned);
  EXPECT_TRUE(attitudePublishable(alignment.state()));
  EXPECT_EQ(alignmentStateText(alignment.state()), "aligned");
  EXPECT_EQ(alignmentStateText(AlignmentState::LevelOnly), "level only (roll and pitch, no heading)");
  const Eigen::Matrix3d error =
      interval.rotation_ecef_body.transpose() * alignment.rotationEcefBody(interval.position);
  EXPECT_LT(so3::logMap(error).norm(), 5.0 * alignment.leveling().tilt_sigma_rad + 1e-9);
  // withYaw keeps roll and pitch and sets the heading of body x.
  const Eigen::Matrix3d turned = withYaw(interval.rotation_ecef_body, interval.position, 0.5);
  const EulerAngles e = eulerAngles(ecef_ned.transpose() * turned);
  EXPECT_NEAR(e.roll_rad, roll, 1e-12);
  EXPECT_NEAR(e.pitch_rad, pitch, 1e-12);
  EXPECT_NEAR(e.yaw_rad, 0.5, 1e-12);
}

// A start in motion: 2 s at rest (roll 0.02, pitch -0.03 rad), then 2 s turning at
// 0.5 rad/s (over the gyro threshold): the latest interval that levels ends with the
// rest; all turning is refused with the gyro's reason.
TEST(InsAlignment, LevelsAtTheLatestStaticIntervalBeforeTheMotion) {
  std::mt19937 rng(7);
  StaticInterval rest;
  rest.rotation_ecef_body = rotationEcefNed(rest.position) * rotationNedBody(0.02, -0.03, 1.0);
  rest.duration_s = 2.0;
  StaticInterval turning = rest;
  turning.turn_rate_radps = 0.5;
  std::vector<ImuSample> readings = rest.readings(rng);
  const std::vector<ImuSample> turn = turning.readings(rng);
  readings.insert(readings.end(), turn.begin(), turn.end());
  std::size_t end = 0;
  const LevelingResult level = levelAtLatestStaticInterval(readings, rest.position, StaticIntervalThresholds{}, &end);
  ASSERT_EQ(level.status, LevelingStatus::Level);
  EXPECT_LE(end, 400u);  // the window holds no turning reading...
  EXPECT_GE(end, 400u - 100u / 2);  // ...and is the latest (searched back in steps of 50)
  EXPECT_NEAR(level.roll_rad, 0.02, 4 * level.tilt_sigma_rad + 1e-4);
  EXPECT_NEAR(level.pitch_rad, -0.03, 4 * level.tilt_sigma_rad + 1e-4);
  std::size_t none = 0;
  EXPECT_EQ(levelAtLatestStaticInterval(turn, rest.position, StaticIntervalThresholds{}, &none).status,
            LevelingStatus::GyroRate);
  EXPECT_EQ(levelAtLatestStaticInterval({}, rest.position, StaticIntervalThresholds{}, &none).status,
            LevelingStatus::TooFewSamples);
}

// The gyros carry the attitude: noise-free readings of a steady 0.3 rad/s turn about
// body z relative to the Earth, R(t) = R0 Exp((0, 0, 0.3 t)), read with the Earth
// rate (w_ib = w_eb + R^T w_ie) and held each for its 5 ms, give R(2 s) to rounding.
TEST(InsAlignment, PropagatesTheAttitudeThroughTheGyroReadings) {
  const Eigen::Vector3d position = stationOrigin();
  const Eigen::Matrix3d r0 = rotationEcefNed(position) * rotationNedBody(0.1, -0.2, 0.3);
  const double dt = 0.005, rate = 0.3;
  const GnssTime t0 = GnssTime::fromGpsWeek(2381, 1000.0);
  std::vector<ImuSample> readings;
  for (int k = 0; k < 400; ++k) {
    const double t = k * dt;
    const Eigen::Matrix3d r = r0 * so3::expMap(Eigen::Vector3d(0, 0, rate * t));
    ImuSample s;
    s.time = t0 + t;
    s.angular_rate_radps = Eigen::Vector3d(0, 0, rate) + r.transpose() * kEarthRate;
    readings.push_back(s);
  }
  const Eigen::Matrix3d r2 = propagateAttitude(r0, readings, 0, t0 + 2.0);
  const Eigen::Matrix3d expected = r0 * so3::expMap(Eigen::Vector3d(0, 0, rate * 2.0));
  const double error_rad = so3::logMap(expected.transpose() * r2).norm();
  std::printf("attitude after 2 s of a 0.3 rad/s turn: %.2e rad\n", error_rad);
  // The Earth-rate term held over each 5 ms while the body turns: at most
  // w_ie x 0.3 x dt / 2 per second, 1.1e-7 rad over the 2 s (measured 6.2e-8).
  EXPECT_LT(error_rad, kEarthRotationRate_radps * rate * dt / 2.0 * 2.0);
  // Up to a time before the first reading: unchanged.
  EXPECT_TRUE(propagateAttitude(r0, readings, 0, t0).isApprox(r0, 0.0));
}

}  // namespace
}  // namespace ppp
