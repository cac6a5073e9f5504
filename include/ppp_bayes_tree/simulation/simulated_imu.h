#pragma once
// Simulated IMU: the readings a strapdown IMU fixed to the airframe (body axes of
// the trajectory: x forward, y right, z down) gives along a simulated flight:
// the angular rate of the body with respect to inertial space (the Earth's
// rotation included) and the specific force (the acceleration with respect to
// inertial space minus the gravitation: at rest it points up with the magnitude
// of WGS 84 normal gravity), each plus the grade's errors.
//
// Method (doc/gnss_ins.md, "Simulated IMU"):
// - Between the trajectory's samples the motion is interpolated: ECEF position
//   and velocity by cubic Hermite interpolation of the samples' positions and
//   velocities (the velocity is the derivative of the position curve), the
//   attitude (ECEF <- body, from roll/pitch/yaw in the local NED frame) along the
//   geodesic between the samples' rotations (a constant body rate in between).
// - Reading k covers [t_k, t_k + dt] and is the mean over that interval of what
//   the sensors see in the body axes as they turn (what a strapdown IMU's
//   increments give), measured in the inertial frame that coincides with ECEF at
//   t_k (Q = Exp(w_e dt) takes ECEF at t_k + dt into it). With the body turning
//   by phi = Log(R_k^T Q R_k+1) at a constant rate and the inertial specific force
//   taken as its interval mean F, the body axes at t_k + s dt are Exp(s phi) from
//   those at t_k, and the mean of Exp(-s phi) over s in [0, 1] is the right
//   Jacobian J_r(phi) = I - (1 - cos|phi|)/|phi|^2 [phi]x + (|phi| - sin|phi|)/|phi|^3 [phi]x^2
//   (Groves, 2nd ed., ch. 5, "Precision Specific-Force Frame Transformation":
//   the specific force is an interval mean, so is the body-to-reference rotation):
//     gyro  = phi / dt,
//     force = J_r(phi) R_k^T F,  F = (Q (v_k+1 + w_e x p_k+1) - (v_k + w_e x p_k)) / dt - Exp(w_e dt/2) gamma(p_mid),
//   gamma = normal gravity + w_e x (w_e x p) (the gravitation), p_mid the position
//   at t_k + dt/2. A strapdown mechanization that applies a reading with the
//   interval's mean attitude (EcefInsMechanization) or mid attitude
//   (ImuPreintegration) gives back the interpolated trajectory to its
//   second-order error; one that applies it in the axes at the interval's start
//   leaves the first-order term (phi x force) dt / 2 in velocity per reading.
// - Errors per axis: white noise N(0, density^2 / dt), a turn-on bias
//   N(0, bias instability^2) and a bias random walk with increments
//   N(0, random-walk density^2 dt), each from its own sub-stream of the seed.
#include <cstdint>
#include <vector>

#include "ppp_bayes_tree/navigation/imu_bias.h"
#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/navigation/nav_state.h"
#include "ppp_bayes_tree/simulation/flight_trajectory.h"

namespace ppp {

struct SimulatedImuOptions {
  double rate_hz = 200.0;
  ImuNoise noise = imuNoisePreset(ImuGrade::IndustrialMems);
  bool errors = true;  ///< false: the true readings (no noise, no bias)
};

/// The readings of a flight with the truth of their errors.
struct SimulatedImu {
  ImuNoise noise;                  ///< the parameters the errors were drawn with
  std::vector<ImuSample> samples;  ///< at t_0 + k / rate, each held until the next
  std::vector<ImuBias> biases;     ///< the true bias of each reading (zero without errors)
};

/// The error-free readings at t_0 + k / rate_hz, k = 0 .. floor((t_last - t_0) rate_hz) - 1,
/// the last one ending at or before the trajectory's last sample. Throws
/// std::invalid_argument for a rate <= 0, fewer than two samples or times that
/// do not increase.
std::vector<ImuSample> trueImuReadings(const std::vector<TrajectorySample>& trajectory, double rate_hz);

/// The readings with the errors of options.noise drawn from `seed` (the same
/// seed gives the same readings).
SimulatedImu simulateImu(const std::vector<TrajectorySample>& trajectory, const SimulatedImuOptions& options,
                         std::uint64_t seed);

/// The rotation ECEF <- body of a trajectory sample (attitude in the local NED frame at its position).
Eigen::Matrix3d ecefFromBody(const TrajectorySample& sample);
/// The true navigation state (ECEF attitude, position, velocity) of a trajectory sample.
NavState trueNavState(const TrajectorySample& sample);

}  // namespace ppp
