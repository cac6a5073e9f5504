#pragma once
// The simulated flights the GNSS/INS tests and the real-time benchmark
// (ppp_bench_ins_realtime) share: GPS + Galileo with phase biases
// (the Monte Carlo configuration "gps_galileo_ar"), white code noise (no multipath,
// no time correlation in the code or the wide lane), so that PPP-AR fixes within
// minutes, and an industrial MEMS IMU at 100 Hz; seed 7, GNSS at 1 Hz (the
// benchmark sets its own seed and rates).
#include <vector>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/navigation/imu_noise.h"

namespace ppp {

inline MonteCarloOptions insArFlightOptions(std::vector<FlightProfile> profiles, double duration_s) {
  MonteCarloOptions o;
  o.seed = 7;
  o.duration_s = duration_s;
  o.profiles = std::move(profiles);
  o.simulation.errors.multipath.enabled = false;
  o.ppp.stochastic.code_correlation_time_s = 0.0;
  o.ppp.ambiguity_resolution.wide_lane.correlation_time_s = 0.0;
  o = withConfiguration(o, *findMonteCarloConfiguration("gps_galileo_ar"));
  o.simulation.imu.enabled = true;
  o.simulation.imu.grade = ImuGrade::IndustrialMems;
  o.simulation.imu.rate_hz = 100.0;
  return o;
}

}  // namespace ppp
