// The ECEF strapdown mechanization: a static noise-free IMU stays put, an analytic
// turn on the rotating Earth is reproduced to the scheme's second order, and bad
// readings are refused and counted.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <limits>

#include "ppp_bayes_tree/navigation/ins_mechanization.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"
#include "analytic_trajectory.h"

namespace ppp {
namespace {

const Eigen::Vector3d kEarthRate(0.0, 0.0, kEarthRotationRate_radps);

Eigen::Vector3d stationOrigin() {
  return geodeticToEcef(Geodetic{47.4 * kDegToRad, 8.5 * kDegToRad, 500.0});
}

using test::rotationEcefEnu;

TEST(EcefInsMechanization, StaticNoiseFreeImuStaysStillFor60sAt200Hz) {
  // A level-ish IMU (tilted and turned) at rest reads gravity and the Earth rate in
  // its own axes: f_b = -R^T g(p), w_b = R^T w_ie.
  NavState start;
  start.position_world_m = stationOrigin();
  start.rotation_world_body = rotationEcefEnu(start.position_world_m) *
                              so3::expMap(Eigen::Vector3d(0.02, -0.03, 1.1));
  const Eigen::Matrix3d& r = start.rotation_world_body;
  ImuSample reading;
  reading.specific_force_mps2 = -r.transpose() * ecefNavigationFrame(start.position_world_m).gravity_world_mps2;
  reading.angular_rate_radps = r.transpose() * kEarthRate;
  EcefInsMechanization ins(start, ImuBias{});
  const double dt = 1.0 / 200.0;
  for (int k = 0; k < 60 * 200; ++k) ASSERT_EQ(ins.propagate(reading, dt), InsStepStatus::Applied);
  const double drift_m = (ins.state().position_world_m - start.position_world_m).norm();
  const double speed_mps = ins.state().velocity_world_mps.norm();
  const double turn_rad = so3::logMap(r.transpose() * ins.state().rotation_world_body).norm();
  std::printf("static 60 s at 200 Hz: position drift %.2e m, speed %.2e m/s, attitude %.2e rad\n", drift_m,
              speed_mps, turn_rad);
  EXPECT_LT(drift_m, 1e-3);
  EXPECT_LT(speed_mps, 1e-4);
  EXPECT_LT(turn_rad, 1e-9);
  EXPECT_EQ(ins.count(InsStepStatus::Applied), 12000u);
}

// ---- A constant-rate turn at constant speed in the local tangent plane -------------
// (test/support/analytic_trajectory.h: the trajectory and its noise-free readings)
using Turn = test::AnalyticTurn;

struct RunErrors {
  double position_m, velocity_mps, attitude_rad;
};

/// Runs the turn for duration_s with mid-interval readings at rate_hz.
RunErrors runTurn(const Turn& turn, double duration_s, double rate_hz) {
  EcefInsMechanization ins(turn.state(0.0), ImuBias{});
  const double dt = 1.0 / rate_hz;
  const int n = static_cast<int>(std::lround(duration_s * rate_hz));
  for (int k = 0; k < n; ++k) ins.propagate(turn.reading((k + 0.5) * dt), dt);
  const NavState truth = turn.state(n * dt);
  const NavState& got = ins.state();
  return {(got.position_world_m - truth.position_world_m).norm(),
          (got.velocity_world_mps - truth.velocity_world_mps).norm(),
          so3::logMap(truth.rotation_world_body.transpose() * got.rotation_world_body).norm()};
}

TEST(EcefInsMechanization, ReproducesAnAnalyticTurnOnTheRotatingEarthToSecondOrder) {
  // 10 m/s on a 50 m circle (0.2 rad/s, 2 m/s^2) for 60 s. Every update is second
  // order (mid-interval readings, mean attitude for the force, trapezoid for Coriolis
  // and position, gravity at the mid-interval position), so the error grows as dt^2:
  // its leading term is of order T^2 dt^2 w^2 |a| / 12 = 60^2 (1/200)^2 0.04 2 / 12
  // = 6e-4 m at 200 Hz; halving dt must divide it by about 4.
  const Turn turn = Turn::at(stationOrigin());
  const RunErrors e100 = runTurn(turn, 60.0, 100.0);
  const RunErrors e200 = runTurn(turn, 60.0, 200.0);
  std::printf("turn 60 s: 100 Hz %.2e m %.2e m/s %.2e rad; 200 Hz %.2e m %.2e m/s %.2e rad\n", e100.position_m,
              e100.velocity_mps, e100.attitude_rad, e200.position_m, e200.velocity_mps, e200.attitude_rad);
  const double bound_m = 60.0 * 60.0 / (200.0 * 200.0) * 0.04 * 2.0 / 12.0;
  EXPECT_LT(e200.position_m, bound_m);
  EXPECT_LT(e200.velocity_mps, bound_m / 10.0);
  EXPECT_LT(e200.attitude_rad, 1e-8);
  EXPECT_NEAR(e100.position_m / e200.position_m, 4.0, 0.6);
}

TEST(EcefInsMechanization, RefusesAndCountsBadReadingsWithoutMovingTheState) {
  NavState start;
  start.position_world_m = stationOrigin();
  EcefInsMechanization ins(start, ImuBias{});
  ImuSample good;
  good.specific_force_mps2 = Eigen::Vector3d(0.0, 0.0, 9.8);
  ImuSample bad = good;
  bad.angular_rate_radps.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(ins.propagate(good, 0.0), InsStepStatus::NonPositiveInterval);
  EXPECT_EQ(ins.propagate(good, std::numeric_limits<double>::quiet_NaN()), InsStepStatus::NonPositiveInterval);
  EXPECT_EQ(ins.propagate(good, 0.5), InsStepStatus::IntervalTooLong);
  EXPECT_EQ(ins.propagate(bad, 0.01), InsStepStatus::NonFiniteReading);
  EXPECT_EQ(ins.count(InsStepStatus::NonPositiveInterval), 2u);
  EXPECT_EQ(ins.count(InsStepStatus::IntervalTooLong), 1u);
  EXPECT_EQ(ins.count(InsStepStatus::NonFiniteReading), 1u);
  EXPECT_EQ(ins.count(InsStepStatus::Applied), 0u);
  EXPECT_EQ(ins.state().position_world_m, start.position_world_m);
  EXPECT_EQ(insStepStatusText(InsStepStatus::IntervalTooLong), "interval too long");
}

TEST(EcefInsMechanization, SubtractsTheBiasFromTheReadings) {
  // A biased static reading with the bias known gives the same state as the clean one.
  NavState start;
  start.position_world_m = stationOrigin();
  start.rotation_world_body = rotationEcefEnu(start.position_world_m);
  ImuSample clean;
  clean.specific_force_mps2 = -start.rotation_world_body.transpose() *
                              ecefNavigationFrame(start.position_world_m).gravity_world_mps2;
  clean.angular_rate_radps = start.rotation_world_body.transpose() * kEarthRate;
  ImuBias bias;
  bias.accel_mps2 = Eigen::Vector3d(0.1, -0.2, 0.05);
  bias.gyro_radps = Eigen::Vector3d(0.01, 0.002, -0.003);
  ImuSample biased = clean;
  biased.specific_force_mps2 += bias.accel_mps2;
  biased.angular_rate_radps += bias.gyro_radps;
  EcefInsMechanization a(start, ImuBias{}), b(start, bias);
  for (int k = 0; k < 100; ++k) {
    a.propagate(clean, 0.01);
    b.propagate(biased, 0.01);
  }
  EXPECT_LT((a.state().position_world_m - b.state().position_world_m).norm(), 1e-9);
  EXPECT_LT((a.state().velocity_world_mps - b.state().velocity_world_mps).norm(), 1e-12);
}

}  // namespace
}  // namespace ppp
