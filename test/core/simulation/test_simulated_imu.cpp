// Simulated IMU readings along the flight profiles: the true readings integrated
// give back the trajectory, the readings at rest, the statistics of the errors,
// the CSV round trip through the plain IMU reader, reproducibility per seed.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "ppp_bayes_tree/io/imu/imu_csv_reader.h"
#include "ppp_bayes_tree/navigation/imu_preintegration.h"
#include "ppp_bayes_tree/navigation/ins_mechanization.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/simulation/simulated_imu.h"
#include "ppp_bayes_tree/simulation/simulation_config.h"
#include "ppp_bayes_tree/simulation/simulation_writers.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"
#include "test_support.h"

namespace ppp {
namespace {

/// WGS 84 Earth rotation rate (NIMA TR8350.2, 3rd ed., table 3.1) [rad/s].
constexpr double kWgs84EarthRate_radps = 7.292115e-5;

std::vector<TrajectorySample> profile(FlightProfile p, double duration_s, double rate_hz = 1.0) {
  TrajectoryOptions o;
  o.profile = p;
  o.start = test::gpst(2026, 5, 13, 10);
  o.duration_s = duration_s;
  o.rate_hz = rate_hz;
  return generateTrajectory(o);
}

/// A body at rest at the default origin with the given attitude, sampled at 1 Hz.
std::vector<TrajectorySample> atRest(double roll_rad, double pitch_rad, double yaw_rad, double duration_s) {
  std::vector<TrajectorySample> out;
  for (int k = 0; k <= static_cast<int>(duration_s); ++k) {
    TrajectorySample s;
    s.time = test::gpst(2026, 5, 13, 10) + static_cast<double>(k);
    s.position_ecef_m = geodeticToEcef(defaultSimulationOrigin());
    s.roll_rad = roll_rad, s.pitch_rad = pitch_rad, s.yaw_rad = yaw_rad;
    out.push_back(s);
  }
  return out;
}

struct Worst {
  double rotation_rad = 0.0, max_roll_rad = 0.0;
  double velocity_mps = 0.0, position_m = 0.0;
};

/// The true readings preintegrated over each 1-s interval and predicted in ECEF
/// (Earth rate and normal gravity) against the trajectory's next sample.
Worst preintegrationAgainstTrajectory(const std::vector<TrajectorySample>& traj, const std::vector<ImuSample>& imu) {
  Worst w;
  const ImuNoise noise = imuNoisePreset(ImuGrade::Tactical);
  for (std::size_t i = 0; i + 1 < traj.size(); ++i) {
    ImuPreintegration pim(noise, ImuBias{});
    EXPECT_EQ(pim.integrateBetween(imu, traj[i].time, traj[i + 1].time), 200u) << "interval " << i;
    const NavState predicted =
        predictNavState(pim, trueNavState(traj[i]), ImuBias{}, ecefNavigationFrame(traj[i].position_ecef_m));
    const NavState truth = trueNavState(traj[i + 1]);
    const Eigen::Matrix<double, 9, 1> e = truth.localCoordinates(predicted);
    w.rotation_rad = std::max(w.rotation_rad, e.segment<3>(0).norm());
    w.velocity_mps = std::max(w.velocity_mps, e.segment<3>(3).norm());
    w.position_m = std::max(w.position_m, e.segment<3>(6).norm());
    w.max_roll_rad = std::max(w.max_roll_rad, std::abs(traj[i].roll_rad));
  }
  return w;
}

// The true readings preintegrated over 1 s reproduce the trajectory. Rotation: the
// gyro readings' product telescopes to the sampled attitudes (rounding only:
// 1e-9 rad; seen: 7e-15). Velocity and position: ImuPreintegration applies each
// reading at the interval's mid attitude, as the reading is the mean specific
// force in the turning axes, so the first-order term sum |w x f| dt^2 / 2 that
// the axes at the reading's start would leave (up to 1.3e-2 m/s over 1 s at the
// figure8's bank reversals) is gone; what is left is second order: the
// prediction's gravitation held at the interval's start: its gradient (g/R =
// 1.5e-6 /s^2 horizontally, 2g/R vertically) times the displacement,
// |grad g| * |v| * T^2 / 2 = 1.7e-5 m/s at 22 m/s, about as much in position, and
// the trapezoidal rule on the velocity (dt^2 / 12 * T * jerk < 1e-6 m). Seen: at
// most 1.8e-5 m/s and 1.3e-5 m (figure8); bounds 5e-5 (under 1/200 of the
// first-order term the axes at the reading's start leave).
TEST(SimulatedImu, TrueReadingsIntegrateToTheTrajectoryOnEveryProfile) {
  const FlightProfile profiles[] = {FlightProfile::Loiter, FlightProfile::Survey, FlightProfile::Figure8,
                                    FlightProfile::Climb};
  double max_roll_rad = 0.0;
  for (FlightProfile p : profiles) {
    const auto traj = profile(p, 300.0);
    const auto imu = trueImuReadings(traj, 200.0);
    ASSERT_EQ(imu.size(), 300u * 200u) << flightProfileName(p);
    const Worst w = preintegrationAgainstTrajectory(traj, imu);
    EXPECT_LT(w.rotation_rad, 1e-9) << flightProfileName(p);
    EXPECT_LT(w.velocity_mps, 5e-5) << flightProfileName(p);
    EXPECT_LT(w.position_m, 5e-5) << flightProfileName(p);
    max_roll_rad = std::max(max_roll_rad, w.max_roll_rad);
    std::cout << flightProfileName(p) << ": worst over 1 s " << w.rotation_rad << " rad, " << w.velocity_mps
              << " m/s, " << w.position_m << " m; max |roll| " << w.max_roll_rad * kRadToDeg << " deg\n";
  }
  EXPECT_GT(max_roll_rad, 20.0 * kDegToRad);  // banking turns were flown
}

// A 10-Hz trajectory gives the same: the interpolation does not depend on the rate.
TEST(SimulatedImu, TrueReadingsFollowTenHertzTrajectoryThroughBankingTurns) {
  const auto traj = profile(FlightProfile::Figure8, 120.0, 10.0);
  std::vector<TrajectorySample> whole_seconds;
  for (std::size_t k = 0; k < traj.size(); k += 10) whole_seconds.push_back(traj[k]);
  const Worst w = preintegrationAgainstTrajectory(whole_seconds, trueImuReadings(traj, 200.0));
  EXPECT_LT(w.rotation_rad, 1e-9);
  EXPECT_LT(w.velocity_mps, 5e-5);
  EXPECT_LT(w.position_m, 5e-5);
}

/// Drift of the strapdown mechanization run alone on the true readings from the
/// trajectory's first sample: the position error at each whole second.
std::vector<double> mechanizationDrift_m(const std::vector<TrajectorySample>& traj, double imu_rate_hz) {
  const auto imu = trueImuReadings(traj, imu_rate_hz);
  EcefInsMechanization ins(trueNavState(traj.front()), ImuBias{});
  std::vector<double> drift{0.0};
  const auto per_second = static_cast<std::size_t>(std::lround(imu_rate_hz));
  for (std::size_t k = 0; k < imu.size(); ++k) {
    const double dt = k + 1 < imu.size() ? imu[k + 1].time - imu[k].time : 1.0 / imu_rate_hz;
    EXPECT_EQ(ins.propagate(imu[k], dt), InsStepStatus::Applied);
    if ((k + 1) % per_second == 0)
      drift.push_back((ins.state().position_world_m - traj[drift.size()].position_ecef_m).norm());
  }
  return drift;
}

// The strapdown mechanization alone (no GNSS) on the true readings, from the
// trajectory's first sample, follows every profile to its own second-order error:
// the readings are the body-axes means the mechanization expects. That error is of
// order T^2 dt^2 w^2 |a| / 12 (test_ins_mechanization); the highest w^2 |a| of the
// profiles is the survey's 50-m turns at 15 m/s (w = 0.3 rad/s, |a| = 4.5 m/s^2;
// the figure8's 90-m turns at 22 m/s: 0.24 rad/s, 5.4 m/s^2), and twice the term
// is the bound: 6.8e-4 m after 10 s and 2.4e-2 m after 60 s at 100 Hz (seen: at most
// 2.7e-4 and 3.1e-3 m, on the figure8). Second order: halving dt divides the
// figure8's drift by about 4. Readings in the axes at the interval's start drift
// by |w x f| dt / 2 = 6.6e-3 m/s^2 along the figure8's track at 100 Hz (0.28 m after
// 10 s, 1.4 m after 60 s) and only halve with dt.
TEST(SimulatedImu, MechanizationAloneFollowsEveryProfile) {
  const FlightProfile profiles[] = {FlightProfile::Loiter, FlightProfile::Survey, FlightProfile::Figure8,
                                    FlightProfile::Climb};
  const double max_w2a = 0.3 * 0.3 * 4.5;
  auto bound_m = [&](double duration_s, double rate_hz) {
    return duration_s * duration_s / (rate_hz * rate_hz) * max_w2a / 6.0;
  };
  for (FlightProfile p : profiles) {
    const auto drift = mechanizationDrift_m(profile(p, 60.0), 100.0);
    std::printf("%s at 100 Hz: drift after 10 s %.2e m, after 60 s %.2e m\n", flightProfileName(p), drift[10],
                drift[60]);
    EXPECT_LT(drift[10], bound_m(10.0, 100.0)) << flightProfileName(p);
    EXPECT_LT(drift[60], bound_m(60.0, 100.0)) << flightProfileName(p);
  }
  const double figure8_100_m = mechanizationDrift_m(profile(FlightProfile::Figure8, 60.0), 100.0)[60];
  const double figure8_200_m = mechanizationDrift_m(profile(FlightProfile::Figure8, 60.0), 200.0)[60];
  std::printf("figure8 after 60 s: %.2e m at 100 Hz, %.2e m at 200 Hz\n", figure8_100_m, figure8_200_m);
  EXPECT_NEAR(figure8_100_m / figure8_200_m, 4.0, 0.8);
}

// At rest: |f| is normal gravity (NIMA TR8350.2 eq. 4-1 with the height term) and
// the gyro reads the Earth rate; in NED the Earth rate is (w cos(lat), 0, -w sin(lat))
// and the specific force (0, 0, -g) (gravity along the ellipsoid normal). A reading
// is the interval's mean in the turning body axes: the body's turn with the Earth
// (w dt = 3.6e-7 rad) leaves only rounding (1e-9; readings in the axes at the
// interval's start were off by g cos(lat) w dt / 2 = 1.2e-6 m/s^2 sideways).
// The navigation frame's rate is 7.2921151467e-5 rad/s (TR8350.2's value for a
// precessing frame), 1.5e-12 rad/s above the WGS 84 defining 7.292115e-5 (2e-12).
TEST(SimulatedImu, AtRestReadsNormalGravityAndEarthRate) {
  const double roll = 10.0 * kDegToRad, pitch = -5.0 * kDegToRad, yaw = 30.0 * kDegToRad;
  const auto imu = trueImuReadings(atRest(roll, pitch, yaw, 5.0), 200.0);
  ASSERT_EQ(imu.size(), 1000u);
  const Geodetic o = defaultSimulationOrigin();
  const double g = normalGravity_mps2(o.latitude_rad, o.height_m);
  const Eigen::Matrix3d body_from_ned = bodyFromNed(roll, pitch, yaw);
  const Eigen::Vector3d earth_rate_ned(kWgs84EarthRate_radps * std::cos(o.latitude_rad), 0.0,
                                       -kWgs84EarthRate_radps * std::sin(o.latitude_rad));
  const double frame_rate = ecefNavigationFrame(geodeticToEcef(o)).earth_rate_world_radps.norm();
  for (const ImuSample& s : imu) {
    EXPECT_NEAR(s.specific_force_mps2.norm(), g, 1e-9);
    EXPECT_LT((s.specific_force_mps2 - body_from_ned * Eigen::Vector3d(0.0, 0.0, -g)).norm(), 1e-9);
    EXPECT_NEAR(s.angular_rate_radps.norm(), frame_rate, 1e-14);  // Log of a 3.6e-7 rad turn: rounding
    EXPECT_NEAR(s.angular_rate_radps.norm(), kWgs84EarthRate_radps, 2e-12);
    EXPECT_LT((s.angular_rate_radps - body_from_ned * earth_rate_ned).norm(), 2e-12);
  }
}

double sampleSigma(const std::vector<double>& v) {
  double mean = 0.0, sq = 0.0;
  for (double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  for (double x : v) sq += (x - mean) * (x - mean);
  return std::sqrt(sq / static_cast<double>(v.size() - 1));
}

// White noise: the readings minus the true readings and the true bias, 3 x 24,000
// values per sensor; the sample sigma's relative standard error is 1/sqrt(2N) =
// 0.26 %: 1.5 % is beyond 5 of them. Bias walk increments: same count, same bound.
TEST(SimulatedImu, NoiseAndBiasWalkHaveTheGradesSigmas) {
  const auto traj = atRest(0.0, 0.0, 0.0, 120.0);
  SimulatedImuOptions o;
  o.noise = imuNoisePreset(ImuGrade::ConsumerMems);
  const SimulatedImu imu = simulateImu(traj, o, 42);
  const auto truth = trueImuReadings(traj, o.rate_hz);
  ASSERT_EQ(imu.samples.size(), truth.size());
  std::vector<double> accel, gyro, accel_walk, gyro_walk;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    const Eigen::Vector3d a = imu.samples[k].specific_force_mps2 - truth[k].specific_force_mps2 - imu.biases[k].accel_mps2;
    const Eigen::Vector3d w = imu.samples[k].angular_rate_radps - truth[k].angular_rate_radps - imu.biases[k].gyro_radps;
    for (int i = 0; i < 3; ++i) accel.push_back(a(i)), gyro.push_back(w(i));
    if (k == 0) continue;
    const ImuBias& b = imu.biases[k];
    const ImuBias& p = imu.biases[k - 1];
    for (int i = 0; i < 3; ++i)
      accel_walk.push_back(b.accel_mps2(i) - p.accel_mps2(i)), gyro_walk.push_back(b.gyro_radps(i) - p.gyro_radps(i));
  }
  const double dt = 1.0 / o.rate_hz;
  EXPECT_NEAR(sampleSigma(accel) / (o.noise.accel_noise_density_mps2_per_sqrthz / std::sqrt(dt)), 1.0, 0.015);
  EXPECT_NEAR(sampleSigma(gyro) / (o.noise.gyro_noise_density_radps_per_sqrthz / std::sqrt(dt)), 1.0, 0.015);
  EXPECT_NEAR(sampleSigma(accel_walk) / (o.noise.accel_bias_random_walk_mps3_per_sqrthz * std::sqrt(dt)), 1.0, 0.015);
  EXPECT_NEAR(sampleSigma(gyro_walk) / (o.noise.gyro_bias_random_walk_radps2_per_sqrthz * std::sqrt(dt)), 1.0, 0.015);
}

// Turn-on bias ~ N(0, instability^2) per axis: 400 seeds x 3 axes, relative
// standard error of the sigma 1/sqrt(2400) = 2 %: 10 % is 5 of them.
TEST(SimulatedImu, TurnOnBiasHasTheInstabilitySigma) {
  const auto traj = atRest(0.0, 0.0, 0.0, 1.0);
  SimulatedImuOptions o;
  o.noise = imuNoisePreset(ImuGrade::IndustrialMems);
  std::vector<double> accel, gyro;
  for (std::uint64_t seed = 1; seed <= 400; ++seed) {
    const SimulatedImu imu = simulateImu(traj, o, seed);
    for (int i = 0; i < 3; ++i) accel.push_back(imu.biases[0].accel_mps2(i)), gyro.push_back(imu.biases[0].gyro_radps(i));
  }
  EXPECT_NEAR(sampleSigma(accel) / o.noise.accel_bias_instability_mps2, 1.0, 0.10);
  EXPECT_NEAR(sampleSigma(gyro) / o.noise.gyro_bias_instability_radps, 1.0, 0.10);
}

TEST(SimulatedImu, CsvReadsBackThroughThePlainImuReader) {
  SimulatedImuOptions o;
  o.noise = imuNoisePreset(ImuGrade::ConsumerMems);
  const SimulatedImu imu = simulateImu(profile(FlightProfile::Figure8, 20.0), o, 7);
  const auto path = test::tempDir("simulated_imu") / "imu.csv";
  {
    std::ofstream out(path);
    writeImuCsv(out, imu.samples);
  }
  const ImuCsvRead read = readImuCsv(path.string());
  EXPECT_TRUE(read.report.clean()) << read.report.summary();
  ASSERT_EQ(read.samples.size(), imu.samples.size());
  for (std::size_t k = 0; k < imu.samples.size(); ++k) {
    EXPECT_NEAR(read.samples[k].time - imu.samples[k].time, 0.0, 1e-9) << k;
    EXPECT_EQ(read.samples[k].specific_force_mps2, imu.samples[k].specific_force_mps2) << k;
    EXPECT_EQ(read.samples[k].angular_rate_radps, imu.samples[k].angular_rate_radps) << k;
  }
  EXPECT_FALSE(read.units_look_like_g);
}

bool sameReadings(const SimulatedImu& a, const SimulatedImu& b) {
  if (a.samples.size() != b.samples.size()) return false;
  for (std::size_t k = 0; k < a.samples.size(); ++k)
    if (a.samples[k].specific_force_mps2 != b.samples[k].specific_force_mps2 ||
        a.samples[k].angular_rate_radps != b.samples[k].angular_rate_radps)
      return false;
  return true;
}

TEST(SimulatedImu, SameSeedSameReadingsOtherSeedOtherReadings) {
  const auto traj = profile(FlightProfile::Loiter, 10.0);
  const SimulatedImuOptions o;
  EXPECT_TRUE(sameReadings(simulateImu(traj, o, 5), simulateImu(traj, o, 5)));
  EXPECT_FALSE(sameReadings(simulateImu(traj, o, 5), simulateImu(traj, o, 6)));
  SimulatedImuOptions none = o;
  none.errors = false;
  const SimulatedImu clean = simulateImu(traj, none, 5);
  EXPECT_TRUE(sameReadings(clean, simulateImu(traj, none, 6)));
  EXPECT_EQ(clean.biases[0].accel_mps2, Eigen::Vector3d::Zero());
}

TEST(SimulatedImu, RejectsBadRateAndTrajectory) {
  EXPECT_THROW(trueImuReadings(profile(FlightProfile::Loiter, 5.0), 0.0), std::invalid_argument);
  EXPECT_THROW(trueImuReadings(atRest(0.0, 0.0, 0.0, 0.0), 200.0), std::invalid_argument);
  auto traj = profile(FlightProfile::Loiter, 5.0);
  traj[3].time = traj[2].time;
  EXPECT_THROW(trueImuReadings(traj, 200.0), std::invalid_argument);
}

// In the flight: off by default (nothing changes), on from the YAML; its own
// sub-stream leaves the observations as they were.
TEST(SimulatedImu, FlightOptionAddsReadingsWithoutChangingTheObservations) {
  SimulationConfig c;
  c.duration_s = 60.0;
  const SimulatedFlight off = simulateFlight(c, 3);
  EXPECT_TRUE(off.imu.samples.empty());
  const SimulationConfig on =
      parseSimulationConfig("imu: { enabled: true, grade: tactical, rate_hz: 100 }", "test.yaml", c);
  const SimulatedFlight with = simulateFlight(on, 3);
  EXPECT_EQ(with.imu.samples.size(), 6000u);
  EXPECT_EQ(with.imu.noise.name, imuNoisePreset(ImuGrade::Tactical).name);
  EXPECT_EQ(rinexObsText(with.header, with.epochs), rinexObsText(off.header, off.epochs));
  EXPECT_THROW(parseSimulationConfig("imu: { grade: navigation }", "test.yaml"), ConfigError);
  const auto dir = test::tempDir("simulated_imu_flight");
  const auto written = writeSimulatedFlight(with, dir.string());
  EXPECT_EQ(written.back(), (dir / "imu_bias.csv").string());
  EXPECT_EQ(readImuCsv((dir / "imu.csv").string()).samples.size(), 6000u);
}

}  // namespace
}  // namespace ppp
