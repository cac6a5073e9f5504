// PPP-AR of the GNSS/INS filter (ekf_ins) on simulated flights with an
// industrial-MEMS IMU (simulated_imu.h) and simulated satellite phase biases
// (the gps_galileo_ar configuration of the Monte Carlo study, white code noise as
// test_monte_carlo_ambiguity): ekf_ins runs the EKF's resolver over its own state
// (the INS error in place of the position) and must fix every flight, hold only
// the simulator's integers (HeldIntegerCheck), and its fixed antenna positions
// must agree with the EKF's fixed ones on the same data; its fixed navigation
// state (the nominal moved by the fixed INS error) carries the fixed position.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "ppp_bayes_tree/evaluation/ins_ar_flights.h"
#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_ins_ekf.h"
#include "ppp_bayes_tree/simulation/simulated_imu.h"

namespace ppp {
namespace {

MonteCarloOptions insArStudy() {
  return insArFlightOptions({FlightProfile::Survey, FlightProfile::Loiter}, 900.0);
}

/// The GNSS/INS filter's start: the true attitude and velocity of the first epoch
/// moved by a small error (0.3 deg, 0.1 m/s per axis), the grade's noise.
PppConfig insConfig(PppConfig c, const SimulatedFlight& f) {
  const TrajectorySample& first = f.truth.front().trajectory;
  c.ins.noise = f.imu.noise;
  c.ins.initial_rotation_ecef_body = ecefFromBody(first) * so3::expMap(Eigen::Vector3d(0.005, -0.005, 0.005));
  c.ins.initial_velocity_ecef_mps = first.velocity_ecef_mps + Eigen::Vector3d(0.1, -0.1, 0.1);
  return c;
}

struct FlightComparison {
  FlightEstimatorTrack ekf, ins;
  std::size_t ins_fixed_nav_epochs = 0;     // fixed epochs with a fixed navigation state
  double ins_fixed_nav_vs_solution_m = 0.0;  // max |antenna of the fixed nav state - fixed solution|
  double ins_float_error_after_300s_m = 0.0;  // max |float antenna position - truth| from 300 s on
  double ins_accel_bias_error_mps2 = 0.0;     // max over epochs and axes |bias estimate - true bias|
};

/// The float filter against the truth at epoch k: its antenna position (from 300 s
/// on) and its accelerometer bias against the simulated one of the epoch's reading.
void compareFloatWithTruth(const SimulatedFlight& f, std::size_t k, const PppInsEkf& ins, FlightComparison& c) {
  const TrajectorySample& truth = f.truth[k].trajectory;
  if (truth.time - f.truth.front().trajectory.time >= 300.0)
    c.ins_float_error_after_300s_m =
        std::max(c.ins_float_error_after_300s_m, (ins.antennaPosition() - truth.position_ecef_m).norm());
  const auto reading = std::lower_bound(f.imu.samples.begin(), f.imu.samples.end(), truth.time,
                                        [](const ImuSample& s, const GnssTime& t) { return s.time < t; });
  if (reading == f.imu.samples.end()) return;
  const ImuBias& true_bias = f.imu.biases[static_cast<std::size_t>(reading - f.imu.samples.begin())];
  c.ins_accel_bias_error_mps2 = std::max(c.ins_accel_bias_error_mps2,
                                         (ins.imuBias().accel_mps2 - true_bias.accel_mps2).cwiseAbs().maxCoeff());
}

FlightComparison runFlight(const MonteCarloOptions& o, int index) {
  const MonteCarloFlightSetup setup = monteCarloFlightSetup(o, index);
  const SimulatedFlight f = simulateFlight(monteCarloSimulationConfig(o, setup), setup.seed);
  const PppConfig config = flightPppConfig(o.ppp, f);
  FlightComparison c;
  c.ekf = trackEstimatorOnFlight(f, config, "ekf");
  c.ins = trackEstimatorOnFlight(
      f, insConfig(config, f), "ekf_ins", [&](std::size_t k, const PppEpochRecord& rec, const PppEstimator& e) {
        const auto& ins = dynamic_cast<const PppInsEkf&>(e);
        compareFloatWithTruth(f, k, ins, c);
        if (rec.solution.status != SolutionStatus::PppFixed || !ins.fixedNavState()) return;
        ++c.ins_fixed_nav_epochs;
        const NavState& s = *ins.fixedNavState();
        const Eigen::Vector3d antenna =
            s.position_world_m + s.rotation_world_body * ins.insOptions().lever_arm_body_m;
        c.ins_fixed_nav_vs_solution_m =
            std::max(c.ins_fixed_nav_vs_solution_m, (antenna - *rec.solution.position_ecef_m).norm());
      });
  return c;
}

/// The flights: flights 0 and 1 of the study (survey, loiter) and flight 1 of the
/// profiles survey, figure8 (a figure8 with 0.24 rad/s turns and bank reversals).
std::vector<std::pair<MonteCarloOptions, int>> insArFlights() {
  MonteCarloOptions figure8 = insArStudy();
  figure8.profiles = {FlightProfile::Survey, FlightProfile::Figure8};
  return {{insArStudy(), 0}, {insArStudy(), 1}, {figure8, 1}};
}

// Besides the fixes: the float filter follows the truth. From 300 s on its antenna
// position stays within 0.3 m (seen: at most 0.19 m, on the figure8), and its
// accelerometer bias within 5e-4 m/s^2 of the simulated one per axis (seen: 2e-4 on
// the figure8's weakly observed y axis; the simulated bias walks by 1.5e-4 over the
// flight). Readings that were the mean in the body axes at the interval's start
// put |w x f| dt / 2 = 6.6e-3 m/s^2 along the figure8's track: the x bias estimate
// went to -3.3e-3 m/s^2, the float stayed 0.6-0.9 m off and never fixed.
TEST(InsAmbiguityResolution, EkfInsFixesHoldsTheTrueIntegersAndAgreesWithTheEkf) {
  const auto flights = insArFlights();
  for (int index = 0; index < static_cast<int>(flights.size()); ++index) {
    SCOPED_TRACE("flight " + std::to_string(index));
    const auto& [o, flight] = flights[static_cast<std::size_t>(index)];
    const FlightComparison c = runFlight(o, flight);
    std::size_t ins_fixed = 0, ekf_fixed = 0, both = 0;
    std::size_t first_ins = c.ins.fixed.size(), first_ekf = c.ekf.fixed.size();
    std::vector<double> differences_m;
    for (std::size_t k = 0; k < c.ins.fixed.size(); ++k) {
      if (c.ins.fixed[k]) ins_fixed++, first_ins = std::min(first_ins, k);
      if (c.ekf.fixed[k]) ekf_fixed++, first_ekf = std::min(first_ekf, k);
      if (c.ins.fixed[k] && c.ekf.fixed[k]) {
        ++both;
        differences_m.push_back((*c.ins.position_ecef_m[k] - *c.ekf.position_ecef_m[k]).norm());
      }
    }
    std::sort(differences_m.begin(), differences_m.end());
    const double median_m = differences_m.empty() ? -1.0 : differences_m[differences_m.size() / 2];
    const double max_m = differences_m.empty() ? -1.0 : differences_m.back();
    std::printf("flight %d: fixed epochs ekf_ins %zu (first at %zu s), ekf %zu (first at %zu s), both %zu; "
                "|ekf_ins - ekf| fixed median %.4f m, max %.4f m; holds ekf_ins %zu (wrong %zu), ekf %zu (wrong %zu); "
                "fixed nav state vs solution max %.2e m; float error from 300 s max %.3f m, accel bias error max %.2e m/s^2\n",
                index, ins_fixed, first_ins, ekf_fixed, first_ekf, both, median_m, max_m, c.ins.held_check.held,
                c.ins.held_check.wrong, c.ekf.held_check.held, c.ekf.held_check.wrong, c.ins_fixed_nav_vs_solution_m,
                c.ins_float_error_after_300s_m, c.ins_accel_bias_error_mps2);
    EXPECT_LT(c.ins_float_error_after_300s_m, 0.3);
    EXPECT_LT(c.ins_accel_bias_error_mps2, 5e-4);
    EXPECT_GT(ins_fixed, 0u);
    EXPECT_GE(c.ins.held_check.held, 4u);
    EXPECT_EQ(c.ins.held_check.wrong, 0u);
    EXPECT_EQ(c.ins.held_check.fixed_epochs_with_wrong_hold, 0u);
    EXPECT_EQ(c.ekf.held_check.wrong, 0u);
    ASSERT_GT(both, 0u);
    EXPECT_LT(median_m, 0.02);
    EXPECT_LT(max_m, 0.10);
    EXPECT_EQ(c.ins_fixed_nav_epochs, ins_fixed);
    EXPECT_LT(c.ins_fixed_nav_vs_solution_m, 1e-6);
  }
}

}  // namespace
}  // namespace ppp

