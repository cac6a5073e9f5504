#pragma once
// The simulated turn the GNSS/INS estimators' tests run on (test_ppp_ins_ekf,
// test_ppp_ins_smoother): the synthetic GNSS code and phase of ppp_simulator.h
// (with its noise) at 1 Hz, of an antenna 0.5, 0.2, -1.0 m (body axes) from the
// IMU on an analytic turn (analytic_trajectory.h), and the turn's noise-free IMU
// readings at 100 Hz, each the value at its interval's middle stamped at the
// interval's start. The estimator options start near the truth (industrial
// MEMS noise; attitude 1.9 deg off with a sigma of 0.05 rad; velocity 0.24 m/s
// off). And the epochs the refusal tests of both estimators run: a new
// estimator's first epoch, and the epoch after the readings stop.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

#include "analytic_trajectory.h"
#include "core/ppp/estimators/ppp_simulator.h"
#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_options.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_estimator.h"

namespace ppp::test {

constexpr double kTurnImuRate_hz = 100.0;

struct TurnRunSetup {
  double duration_s = 120.0;
  double outage_from_s = -1.0;  // GNSS outage [from, from + outage_s)
  double outage_s = 0.0;
  double speed_mps = 10.0;
  double rate_radps = 0.1;
  int readings_before_start = 0;  // IMU readings before the first epoch (e.g. to level from)
  /// An error the IMU's noise does not model: added to each specific force reading
  /// (body axes) from accel_error_from_s on [m/s^2].
  Eigen::Vector3d accel_error_mps2 = Eigen::Vector3d::Zero();
  double accel_error_from_s = 0.0;
};

/// The turn of 60 s whose readings carry, from 30 s on, an accelerometer error of 0.05 m/s^2
/// along body x that an industrial grade's noise and bias instability do not allow for: each
/// 1-s prediction is then off by centimetres (the adaptive process noise's tests).
constexpr double kUnmodelledAccelErrorFrom_s = 30.0;
inline void addUnmodelledAccelError(TurnRunSetup& setup) {
  setup.duration_s = 60.0;
  setup.accel_error_mps2 = Eigen::Vector3d(0.05, 0.0, 0.0);
  setup.accel_error_from_s = kUnmodelledAccelErrorFrom_s;
}

/// The bound of the drift of the position error over a GNSS outage of `outage_s` on the
/// turn (noise-free readings of an industrial MEMS IMU), from the velocity and attitude
/// errors at its start: dv0 T + (g dtheta0 + 3 sigma_ba) T^2 / 2 + g 3 sigma_bg T^3 / 6 [m].
inline double turnOutageDriftBound_m(double outage_s, double velocity_error_mps, double attitude_error_rad) {
  const double T = outage_s;
  const ImuNoise grade = imuNoisePreset(ImuGrade::IndustrialMems);
  return velocity_error_mps * T +
         0.5 * (9.81 * attitude_error_rad + 3.0 * grade.accel_bias_instability_mps2) * T * T +
         9.81 * 3.0 * grade.gyro_bias_instability_radps * T * T * T / 6.0;
}

/// One epoch of the turn: what the estimators get, and the truth.
struct TurnEpoch {
  double t_s = 0.0;
  bool gnss = true;  // false in the outage (no satellites)
  NavState truth;    // the IMU's
  Eigen::Vector3d antenna_truth_m = Eigen::Vector3d::Zero();
  EstimatorEpochInput input;  // time, the GNSS measurements, the readings since the last epoch
};

class TurnRun {
 public:
  explicit TurnRun(const TurnRunSetup& setup) : setup_(setup) {
    sim_.noise = true;
    turn_ = AnalyticTurn::at(sim_.position, setup.speed_mps, setup.rate_radps);
    t0_ = sim_.time();
  }

  const AnalyticTurn& turn() const { return turn_; }
  static Eigen::Vector3d leverArm_m() { return Eigen::Vector3d(0.5, 0.2, -1.0); }

  /// The GNSS/INS options of the start near the truth.
  EstimatorOptions insOptions() const {
    EstimatorOptions options;
    options.ins.noise = imuNoisePreset(ImuGrade::IndustrialMems);
    options.ins.lever_arm_body_m = leverArm_m();
    options.ins.initial_rotation_ecef_body =
        turn_.state(0.0).rotation_world_body * so3::expMap(Eigen::Vector3d(0.01, -0.01, 0.03));
    options.ins.initial_velocity_ecef_mps = turn_.state(0.0).velocity_world_mps + Eigen::Vector3d(0.2, -0.1, 0.1);
    options.ins.initial_attitude_sigma_rad = 0.05;
    return options;
  }

  /// The epochs at 0, 1, ..., duration_s s in turn, each handed to `on_epoch(const TurnEpoch&)`.
  template <class OnEpoch>
  void forEachEpoch(OnEpoch on_epoch) {
    const double dt = 1.0 / kTurnImuRate_hz;
    int k = -setup_.readings_before_start;  // next IMU reading
    for (int e = 0; e <= static_cast<int>(setup_.duration_s); ++e) {
      const double t = e;
      std::vector<ImuSample> readings;
      for (; k * dt <= t + 1e-9; ++k) {
        ImuSample reading = turn_.reading((k + 0.5) * dt, t0_ + k * dt);
        if (k * dt >= setup_.accel_error_from_s) reading.specific_force_mps2 += setup_.accel_error_mps2;
        readings.push_back(reading);
      }
      TurnEpoch epoch;
      epoch.t_s = t;
      epoch.truth = turn_.state(t);
      sim_.t_s = t;
      sim_.position = epoch.truth.position_world_m + epoch.truth.rotation_world_body * leverArm_m();
      epoch.antenna_truth_m = sim_.position;
      epoch.gnss = !(t >= setup_.outage_from_s && t < setup_.outage_from_s + setup_.outage_s);
      const std::vector<sim::SimObs> obs = epoch.gnss ? sim_.epoch() : std::vector<sim::SimObs>{};
      const MeasurementFunction evaluate = sim::modelOf(obs);
      epoch.input.time = sim_.time();
      epoch.input.evaluate = &evaluate;
      epoch.input.imu = &readings;
      on_epoch(static_cast<const TurnEpoch&>(epoch));
    }
  }

 private:
  TurnRunSetup setup_;
  sim::Simulator sim_;
  AnalyticTurn turn_;
  GnssTime t0_;
};

/// The first epoch, at `sim`'s, of a new estimator `name` made with `options`, given `readings`.
inline EstimatorEpochResult firstEpoch(const std::string& name, const EstimatorOptions& options, sim::Simulator& sim,
                                       const std::vector<ImuSample>& readings) {
  std::string why;
  const auto estimator = makeEstimator(name, options, &why);
  EXPECT_TRUE(estimator) << why;
  if (!estimator) return {};
  const MeasurementFunction evaluate = sim::modelOf(sim.epoch());
  EstimatorEpochInput input;
  input.time = sim.time();
  input.evaluate = &evaluate;
  input.imu = &readings;
  return estimator->processEpoch(input);
}

/// A GNSS/INS estimator started at `sim`'s epoch with the readings `first`, then
/// 1 s later given none: the result of that second epoch (a gap in the readings).
inline EstimatorEpochResult epochAfterTheReadingsStop(PppEstimator& estimator, sim::Simulator& sim,
                                                      const std::vector<ImuSample>& first) {
  const MeasurementFunction evaluate = sim::modelOf(sim.epoch());
  EstimatorEpochInput input;
  input.time = sim.time();
  input.evaluate = &evaluate;
  input.imu = &first;
  EXPECT_EQ(estimator.processEpoch(input).status, EpochStatus::Ok);
  sim.t_s += 1.0;
  const MeasurementFunction later = sim::modelOf(sim.epoch());
  const std::vector<ImuSample> none;
  input.time = sim.time();
  input.evaluate = &later;
  input.imu = &none;
  return estimator.processEpoch(input);
}

/// The refusals of a GNSS/INS estimator `name`, each a NoSolution with its reason: without
/// an attitude (given `readings`); with one but without a reading at or before the start;
/// started with `readings`, then 1 s later without any (a gap; no GNSS-only solution).
inline void expectInsRefusals(const std::string& name, sim::Simulator& sim, const std::vector<ImuSample>& readings) {
  const EstimatorEpochResult a = firstEpoch(name, EstimatorOptions{}, sim, readings);
  EXPECT_EQ(a.status, EpochStatus::NoSolution);
  EXPECT_EQ(a.no_solution_reason, NoSolutionReason::NoInitialAttitude) << a.reason;
  EXPECT_NE(a.reason.find("no initial attitude"), std::string::npos) << a.reason;

  EstimatorOptions options;
  options.ins.initial_rotation_ecef_body = Eigen::Matrix3d::Identity();
  const EstimatorEpochResult b = firstEpoch(name, options, sim, {});
  EXPECT_EQ(b.status, EpochStatus::NoSolution);
  EXPECT_EQ(b.no_solution_reason, NoSolutionReason::NoImuReadings) << b.reason;
  EXPECT_NE(b.reason.find("no IMU reading at or before the start"), std::string::npos) << b.reason;

  std::string why;
  const auto gap = makeEstimator(name, options, &why);
  ASSERT_TRUE(gap) << why;
  const EstimatorEpochResult c = epochAfterTheReadingsStop(*gap, sim, readings);
  EXPECT_EQ(c.status, EpochStatus::NoSolution);
  EXPECT_EQ(c.no_solution_reason, NoSolutionReason::NoImuReadings);
  EXPECT_NE(c.reason.find("gap of"), std::string::npos) << c.reason;
}

}  // namespace ppp::test
