#pragma once
// The IMU's own share of a coasting error on a simulated flight: the strapdown
// mechanization (ecefInsStep) run alone through the flight's readings from the
// true state (position, velocity, attitude) and the true bias at one time to
// another, each reading held from its time to the next one's and the last to the
// end (the convention of the GNSS/INS EKF's propagation, ppp_ins_ekf.h), the bias
// held at its start value. The error against the truth at the end is what the
// readings' errors within the interval cause (white noise, and the bias's walk
// after the start): an estimator that started the coast from the error-free
// state and bias would end there; its own error at the start adds to it. With the
// true readings (SimulatedImuOptions::errors off) it is the mechanization's error
// against the simulator's motion (millimetres over 30 s: simulated_imu.h).
#include <Eigen/Core>
#include <optional>

#include "ppp_bayes_tree/simulation/flight_trajectory.h"
#include "ppp_bayes_tree/simulation/simulated_imu.h"

namespace ppp {

/// The coast's position error at `to` (coast minus truth) in the local East-North-Up
/// frame of the truth [m]; nullopt when the readings do not cover [from, to] (none at
/// or before from.time, or a hold longer than max_hold_s) or `to` is not after `from`.
std::optional<Eigen::Vector3d> insCoastErrorFromTruth_enu_m(const SimulatedImu& imu, const TrajectorySample& from,
                                                            const TrajectorySample& to, double max_hold_s = 0.1);

}  // namespace ppp
