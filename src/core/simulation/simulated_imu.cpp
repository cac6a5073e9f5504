#include "ppp_bayes_tree/simulation/simulated_imu.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/simulation/random_stream.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp {
namespace {

/// Sub-stream tags of the IMU seed, one per error term.
enum ImuStreamTag : std::uint64_t { kTagTurnOnBias = 1, kTagBiasWalk, kTagAccelNoise, kTagGyroNoise };

/// Position, velocity (ECEF) and attitude (ECEF <- body) at one time.
struct KinematicState {
  Eigen::Vector3d position_ecef_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ecef_mps = Eigen::Vector3d::Zero();
  Eigen::Matrix3d ecef_from_body = Eigen::Matrix3d::Identity();
};

/// The trajectory between its samples: cubic Hermite position and velocity,
/// geodesic attitude (see simulated_imu.h).
class TrajectoryInterpolant {
 public:
  explicit TrajectoryInterpolant(const std::vector<TrajectorySample>& trajectory) : samples_(trajectory) {
    rotations_.reserve(trajectory.size());
    for (const auto& s : trajectory) rotations_.push_back(ecefFromBody(s));
  }

  KinematicState at(const GnssTime& t) const {
    const std::size_t a = segmentOf(t);
    const TrajectorySample &sa = samples_[a], &sb = samples_[a + 1];
    const double h = sb.time - sa.time;
    const double s = (t - sa.time) / h;
    // Hermite basis (h00 = 1 - h01) and its derivatives d/ds.
    const double h01 = s * s * (3.0 - 2.0 * s), h10 = s * (s - 1.0) * (s - 1.0), h11 = s * s * (s - 1.0);
    const double d01 = 6.0 * s * (1.0 - s), d10 = (3.0 * s - 1.0) * (s - 1.0), d11 = s * (3.0 * s - 2.0);
    const Eigen::Vector3d dp = sb.position_ecef_m - sa.position_ecef_m;
    KinematicState k;
    k.position_ecef_m = sa.position_ecef_m + h01 * dp + h * (h10 * sa.velocity_ecef_mps + h11 * sb.velocity_ecef_mps);
    k.velocity_ecef_mps = d01 * dp / h + d10 * sa.velocity_ecef_mps + d11 * sb.velocity_ecef_mps;
    const Eigen::Matrix3d& ra = rotations_[a];
    k.ecef_from_body = ra * so3::expMap(s * so3::logMap(ra.transpose() * rotations_[a + 1]));
    return k;
  }

 private:
  /// Index a of the segment [a, a + 1] holding t (the first or last one outside).
  std::size_t segmentOf(const GnssTime& t) const {
    std::size_t lo = 0, hi = samples_.size() - 1;  // samples_[lo].time <= t < samples_[hi].time
    while (hi - lo > 1) {
      const std::size_t mid = (lo + hi) / 2;
      (samples_[mid].time <= t ? lo : hi) = mid;
    }
    return lo;
  }

  const std::vector<TrajectorySample>& samples_;
  std::vector<Eigen::Matrix3d> rotations_;
};

/// The true reading over [a, b] (dt_s long) with the state at its middle.
ImuSample trueReading(const GnssTime& t, const KinematicState& a, const KinematicState& mid, const KinematicState& b,
                      double dt_s) {
  const NavigationFrame frame = ecefNavigationFrame(mid.position_ecef_m);
  const Eigen::Vector3d& w = frame.earth_rate_world_radps;
  const Eigen::Matrix3d q = so3::expMap(w * dt_s);  // ECEF at the end -> ECEF frozen at t
  const Eigen::Vector3d inertial_a = a.velocity_ecef_mps + w.cross(a.position_ecef_m);
  const Eigen::Vector3d inertial_b = q * (b.velocity_ecef_mps + w.cross(b.position_ecef_m));
  const Eigen::Vector3d gravitation =
      frame.gravity_world_mps2 + w.cross(w.cross(mid.position_ecef_m));
  const Eigen::Vector3d mean_gravitation = so3::expMap(w * (0.5 * dt_s)) * gravitation;
  const Eigen::Vector3d turn_rad = so3::logMap(a.ecef_from_body.transpose() * q * b.ecef_from_body);
  // The body turns by turn_rad at a constant rate over the interval: the mean of
  // Exp(-s turn_rad) over s in [0, 1] (the right Jacobian) takes a vector from the
  // axes at the start into the turning axes, averaged over the interval.
  const Eigen::Matrix3d mean_body_from_start_axes = so3::rightJacobian(turn_rad);
  ImuSample s;
  s.time = t;
  s.angular_rate_radps = turn_rad / dt_s;
  s.specific_force_mps2 = mean_body_from_start_axes * a.ecef_from_body.transpose() *
                          ((inertial_b - inertial_a) / dt_s - mean_gravitation);
  return s;
}

void checkTrajectory(const std::vector<TrajectorySample>& trajectory, double rate_hz) {
  if (!(rate_hz > 0.0)) throw std::invalid_argument("simulated IMU: the rate must be positive");
  if (trajectory.size() < 2) throw std::invalid_argument("simulated IMU: the trajectory has fewer than two samples");
  for (std::size_t i = 1; i < trajectory.size(); ++i)
    if (!(trajectory[i - 1].time < trajectory[i].time))
      throw std::invalid_argument("simulated IMU: trajectory sample " + std::to_string(i) +
                                  " is not later than the one before");
}

/// Three independent N(0, sigma^2) draws, x then y then z (one draw per statement).
Eigen::Vector3d normalVector(RandomStream& rng, double sigma) {
  const double x = rng.normal(sigma);
  const double y = rng.normal(sigma);
  const double z = rng.normal(sigma);
  return Eigen::Vector3d(x, y, z);
}

}  // namespace

Eigen::Matrix3d ecefFromBody(const TrajectorySample& sample) {
  const Geodetic geo = ecefToGeodetic(sample.position_ecef_m);
  Eigen::Matrix3d ned_from_enu;
  ned_from_enu << 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0;
  const Eigen::Matrix3d ned_from_ecef = ned_from_enu * rotationEnuFromEcef(geo.latitude_rad, geo.longitude_rad);
  return ned_from_ecef.transpose() * bodyFromNed(sample.roll_rad, sample.pitch_rad, sample.yaw_rad).transpose();
}

NavState trueNavState(const TrajectorySample& sample) {
  NavState s;
  s.rotation_world_body = ecefFromBody(sample);
  s.position_world_m = sample.position_ecef_m;
  s.velocity_world_mps = sample.velocity_ecef_mps;
  return s;
}

std::vector<ImuSample> trueImuReadings(const std::vector<TrajectorySample>& trajectory, double rate_hz) {
  checkTrajectory(trajectory, rate_hz);
  const TrajectoryInterpolant path(trajectory);
  const GnssTime t0 = trajectory.front().time;
  const auto count = static_cast<std::size_t>(std::floor((trajectory.back().time - t0) * rate_hz + 1e-9));
  std::vector<ImuSample> out;
  out.reserve(count);
  KinematicState start = path.at(t0);
  for (std::size_t k = 0; k < count; ++k) {
    const GnssTime ta = t0 + static_cast<double>(k) / rate_hz;
    const GnssTime tb = t0 + static_cast<double>(k + 1) / rate_hz;
    const double dt_s = tb - ta;
    const KinematicState end = path.at(tb);
    out.push_back(trueReading(ta, start, path.at(ta + 0.5 * dt_s), end, dt_s));
    start = end;
  }
  return out;
}

SimulatedImu simulateImu(const std::vector<TrajectorySample>& trajectory, const SimulatedImuOptions& options,
                         std::uint64_t seed) {
  SimulatedImu imu;
  imu.noise = options.noise;
  imu.samples = trueImuReadings(trajectory, options.rate_hz);
  imu.biases.assign(imu.samples.size(), ImuBias{});
  if (!options.errors) return imu;
  const ImuNoise& n = options.noise;
  const RandomStream root(seed);
  RandomStream turn_on = root.derive(kTagTurnOnBias), walk = root.derive(kTagBiasWalk);
  RandomStream accel_noise = root.derive(kTagAccelNoise), gyro_noise = root.derive(kTagGyroNoise);
  ImuBias bias;
  bias.accel_mps2 = normalVector(turn_on, n.accel_bias_instability_mps2);
  bias.gyro_radps = normalVector(turn_on, n.gyro_bias_instability_radps);
  for (std::size_t k = 0; k < imu.samples.size(); ++k) {
    ImuSample& s = imu.samples[k];
    const double dt_s = k + 1 < imu.samples.size() ? imu.samples[k + 1].time - s.time : 1.0 / options.rate_hz;
    imu.biases[k] = bias;
    s.specific_force_mps2 += bias.accel_mps2 + normalVector(accel_noise, n.accel_noise_density_mps2_per_sqrthz /
                                                                             std::sqrt(dt_s));
    s.angular_rate_radps += bias.gyro_radps + normalVector(gyro_noise, n.gyro_noise_density_radps_per_sqrthz /
                                                                         std::sqrt(dt_s));
    bias.accel_mps2 += normalVector(walk, n.accel_bias_random_walk_mps3_per_sqrthz * std::sqrt(dt_s));
    bias.gyro_radps += normalVector(walk, n.gyro_bias_random_walk_radps2_per_sqrthz * std::sqrt(dt_s));
  }
  return imu;
}

}  // namespace ppp
