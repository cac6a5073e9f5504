#pragma once
// A simulated flight with one GNSS outage, for the tests of what ekf_ins does
// across it (test_ins_gap_bridge, test_ins_slip_repair): the flight of the Monte
// Carlo options with the outage added, the GNSS/INS configuration started near
// the truth (0.005 rad per axis of attitude error, 0.1 m/s per axis of velocity
// error) and the first epoch after the outage.
#include <Eigen/Core>
#include <cstddef>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/navigation/so3.h"

namespace ppp::test {

/// Flight 0 of `o` with an outage of `duration_s` from `start_s` after its start.
inline SimulatedFlight simulateWithOutage(const MonteCarloOptions& o, double start_s, double duration_s,
                                          bool keeps_lock) {
  const MonteCarloFlightSetup setup = monteCarloFlightSetup(o, 0);
  SimulationConfig c = monteCarloSimulationConfig(o, setup);
  c.outages.push_back({start_s, duration_s, keeps_lock});
  return simulateFlight(c, setup.seed);
}

/// `c` with the flight's IMU noise and a start attitude and velocity near the truth.
inline PppConfig insConfigNearTruth(PppConfig c, const SimulatedFlight& f) {
  const TrajectorySample& first = f.truth.front().trajectory;
  c.ins.noise = f.imu.noise;
  c.ins.initial_rotation_ecef_body = ecefFromBody(first) * so3::expMap(Eigen::Vector3d(0.005, -0.005, 0.005));
  c.ins.initial_velocity_ecef_mps = first.velocity_ecef_mps + Eigen::Vector3d(0.1, -0.1, 0.1);
  return c;
}

/// Index of the first epoch at or after `end_s` from the flight's first epoch (the size: none).
inline std::size_t firstEpochFrom(const SimulatedFlight& f, double end_s) {
  for (std::size_t k = 0; k < f.epochs.size(); ++k)
    if (f.epochs[k].time - f.epochs.front().time >= end_s - 1e-6) return k;
  return f.epochs.size();
}

}  // namespace ppp::test
