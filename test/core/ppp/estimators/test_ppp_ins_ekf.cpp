// PppInsEkf, the tightly coupled GNSS/INS filter: the error-state mapping of the
// antenna velocity against numerical differences; a simulated run (noise-free
// IMU of an analytic turn, test/support/analytic_trajectory.h; GNSS code and
// phase of the synthetic generator ppp_simulator.h with its noise, the same data
// for the GNSS EKF) where its position error is at most the EKF's and its attitude
// converges; a 10 s GNSS outage the INS bridges; the registry's "ekf_ins"; and
// the refusals without an attitude or IMU readings.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "ins_turn_run.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/estimators/ins_process_noise_adaptation.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_ins_ekf.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_ins_smoother.h"

namespace ppp {
namespace {

using Vector15 = Eigen::Matrix<double, 15, 1>;

NavState someNominal() {
  NavState s;
  s.position_world_m = Eigen::Vector3d(4331297.0, 567555.0, 4633133.0);
  s.rotation_world_body = so3::expMap(Eigen::Vector3d(0.3, -1.1, 2.0));
  s.velocity_world_mps = Eigen::Vector3d(3.0, -4.0, 1.0);
  return s;
}

// ---- (a) The error-state mapping of the antenna velocity ----------------------------

TEST(PppInsEkf, AntennaVelocityJacobianMatchesNumericalDifferences) {
  // The Doppler velocity update's model: v + R Exp(dtheta) (w_eb x lever), w_eb the
  // gyro reading less the gyro bias error and the Earth's rate.
  const NavState nominal = someNominal();
  const Eigen::Vector3d lever(0.8, -0.3, 1.5);
  const Eigen::Vector3d gyro(0.3, -0.5, 1.2);
  for (const double size : {0.0, 0.02}) {
    Vector15 at = Vector15::Zero();
    if (size > 0.0) at << size, -size, 2 * size, 0.1, 0.2, -0.1, 0.3, -0.2, 0.5, 0.01, 0.0, 0.0, 1e-2, 0.0, -1e-2;
    const Eigen::Matrix<double, 3, 15> J = PppInsEkf::antennaVelocityJacobian(nominal, lever, gyro, at);
    const double h = 1e-6;
    for (int i = 0; i < 15; ++i) {
      SCOPED_TRACE("component " + std::to_string(i) + ", at size " + std::to_string(size));
      Vector15 plus = at, minus = at;
      plus(i) += h;
      minus(i) -= h;
      const Eigen::Vector3d numeric = (PppInsEkf::antennaVelocityAt(nominal, lever, gyro, plus) -
                                       PppInsEkf::antennaVelocityAt(nominal, lever, gyro, minus)) / (2 * h);
      // The Earth rate's attitude term is left out of J (7.3e-5 rad/s x 1.7 m here).
      EXPECT_LT((numeric - J.col(i)).norm(), 2e-4) << numeric.transpose() << " vs " << J.col(i).transpose();
    }
  }
}

TEST(PppInsEkf, AntennaVelocityOfAPlatformTurningInPlace) {
  // At rest, turning about the body z axis at 1 rad/s with the antenna 0.5 m along
  // body x: the antenna moves at 0.5 m/s along body y (w x l), plus the Earth's rate.
  NavState nominal = someNominal();
  nominal.velocity_world_mps.setZero();
  const Eigen::Vector3d lever(0.5, 0.0, 0.0);
  const Eigen::Vector3d earth_in_body =
      nominal.rotation_world_body.transpose() * Eigen::Vector3d(0.0, 0.0, 7.2921151467e-5);
  const Eigen::Vector3d gyro = Eigen::Vector3d(0.0, 0.0, 1.0) + earth_in_body;
  const Eigen::Vector3d v = PppInsEkf::antennaVelocityAt(nominal, lever, gyro, Vector15::Zero());
  EXPECT_LT((nominal.rotation_world_body.transpose() * v - Eigen::Vector3d(0.0, 0.5, 0.0)).norm(), 1e-12);
}

// ---- The simulated run ---------------------------------------------------------------

/// The turn (ins_turn_run.h) and how the INS EKF starts on it.
struct RunSetup : test::TurnRunSetup {
  /// No attitude, heading or velocity given: levelled from 2 s of readings before the
  /// start, the heading aligned in motion (InsEkfOptions::heading_alignment).
  bool unknown_heading = false;
  /// InsEkfOptions::process_noise_adaptation.enabled.
  bool adaptive_process_noise = true;
};

struct EpochErrors {
  double t_s = 0.0;
  bool gnss = true;
  EstimatorEpochResult ins, ekf;
  double ins_position_m = 0.0;   // |antenna (nominal) - truth|
  Eigen::Vector3d ins_error_m = Eigen::Vector3d::Zero();  // antenna (nominal) - truth
  double ins_velocity_mps = 0.0;
  double ins_attitude_rad = 0.0;
  double ekf_position_m = -1.0;  // -1: no solution
  double ins_heading_error_rad = 0.0;  // wrapped to (-pi, pi]
  std::optional<InsAttitudeQuality> attitude;
  ProcessNoiseScale noise_scale;  // the INS EKF's test of its prediction
};

/// Both filters on the same synthetic GNSS data (1 Hz) along an analytic turn
/// (ins_turn_run.h); the INS EKF also gets the noise-free IMU readings (100 Hz).
std::vector<EpochErrors> runBoth(const RunSetup& setup) {
  test::TurnRunSetup turn_setup = setup;
  turn_setup.readings_before_start = setup.unknown_heading ? 200 : 0;
  test::TurnRun turn(turn_setup);
  EstimatorOptions options = turn.insOptions();
  if (setup.unknown_heading) {
    options.ins.initial_rotation_ecef_body.reset();
    options.ins.initial_velocity_ecef_mps.setZero();
    options.ins.initial_velocity_sigma_mps = 1.0;
  }
  options.ins.process_noise_adaptation.enabled = setup.adaptive_process_noise;
  std::string why;
  auto ins = makeEstimatorAs<PppInsEkf>("ekf_ins", options, &why);
  auto ekf = makeEstimator("ekf", options, &why);
  EXPECT_TRUE(ins && ekf) << why;
  if (!ins || !ekf) return {};

  std::vector<EpochErrors> out;
  turn.forEachEpoch([&](const test::TurnEpoch& epoch) {
    EpochErrors r;
    r.t_s = epoch.t_s;
    r.gnss = epoch.gnss;
    EstimatorEpochInput input = epoch.input;
    r.ins = ins->processEpoch(input);
    input.imu = nullptr;
    r.ekf = ekf->processEpoch(input);
    const NavState& truth = epoch.truth;
    r.ins_error_m = ins->antennaPosition() - epoch.antenna_truth_m;
    r.ins_position_m = r.ins_error_m.norm();
    r.ins_velocity_mps = (ins->navState().velocity_world_mps - truth.velocity_world_mps).norm();
    r.ins_attitude_rad =
        so3::logMap(truth.rotation_world_body.transpose() * ins->navState().rotation_world_body).norm();
    if (r.ekf.solution) r.ekf_position_m = (r.ekf.solution->state.position_ecef_m - epoch.antenna_truth_m).norm();
    const Eigen::Matrix3d ecef_ned = rotationEcefNed(truth.position_world_m);
    const double heading_error_rad = eulerAngles(ecef_ned.transpose() * ins->navState().rotation_world_body).yaw_rad -
                                     eulerAngles(ecef_ned.transpose() * truth.rotation_world_body).yaw_rad;
    r.ins_heading_error_rad = std::remainder(heading_error_rad, 2.0 * M_PI);
    r.attitude = r.ins.attitude;
    r.noise_scale = ins->processNoiseAdaptation();
    out.push_back(std::move(r));
  });
  return out;
}

double meanOver(const std::vector<EpochErrors>& run, double from_s, double EpochErrors::*field) {
  double sum = 0.0;
  int n = 0;
  for (const auto& r : run)
    if (r.t_s >= from_s) sum += r.*field, ++n;
  return n ? sum / n : -1.0;
}

TEST(PppInsEkf, PositionAtMostTheGnssEkfsAndAttitudeConvergesOnATurn) {
  const std::vector<EpochErrors> run = runBoth(RunSetup{});
  ASSERT_EQ(run.size(), 121u);
  for (const auto& r : run) {
    ASSERT_EQ(r.ins.status, EpochStatus::Ok) << r.t_s << " s: " << r.ins.reason;
    ASSERT_EQ(r.ekf.status, EpochStatus::Ok) << r.t_s << " s: " << r.ekf.reason;
    // The solution is the antenna's (as the EKF's): the nominal's antenna position.
    EXPECT_LT((r.ins.solution->state.position_ecef_m - r.ekf.solution->state.position_ecef_m).norm(), 50.0);
  }
  const double ins_m = meanOver(run, 60.0, &EpochErrors::ins_position_m);
  const double ekf_m = meanOver(run, 60.0, &EpochErrors::ekf_position_m);
  const double attitude_rad = run.back().ins_attitude_rad;
  std::printf("last minute mean 3D error: INS EKF %.3f m, GNSS EKF %.3f m; final attitude error %.2e rad, "
              "velocity %.2e m/s\n",
              ins_m, ekf_m, attitude_rad, run.back().ins_velocity_mps);
  EXPECT_LE(ins_m, ekf_m + 0.02);
  EXPECT_LT(run.front().ins_attitude_rad, 0.035);  // the start: 1.9 deg given
  EXPECT_LT(attitude_rad, 5e-3);                   // converged below 0.3 deg
  EXPECT_LT(run.back().ins_velocity_mps, 0.05);
}

TEST(PppInsEkf, CarriesThePositionThroughATenSecondGnssOutage) {
  RunSetup setup;
  setup.duration_s = 100.0;
  setup.outage_from_s = 80.0;
  setup.outage_s = 10.0;
  const std::vector<EpochErrors> run = runBoth(setup);
  ASSERT_EQ(run.size(), 101u);
  const EpochErrors& before = run[79];
  ASSERT_TRUE(before.gnss);
  ASSERT_EQ(before.ins.status, EpochStatus::Ok);
  // The drift of the error over the outage, bounded from the state at its start
  // and the IMU grade: over T, dv0 T + (g dtheta0 + 3 sigma_ba) T^2 / 2 +
  // g 3 sigma_bg T^3 / 6 (the noise-free readings add nothing else). The error at
  // the start (dp0) is the GNSS solution's, code-dominated after 80 s of float PPP.
  const double dp0 = before.ins_position_m, dv0 = before.ins_velocity_mps, dtheta0 = before.ins_attitude_rad;
  EXPECT_LT(dp0, 1.0);
  EXPECT_LT(dv0, 0.05);
  EXPECT_LT(dtheta0, 5e-3);
  const double bound_m = test::turnOutageDriftBound_m(10.0, dv0, dtheta0);
  double worst_m = 0.0;
  for (const auto& r : run) {
    if (r.gnss) continue;
    EXPECT_EQ(r.ekf.status, EpochStatus::NoSolution);
    EXPECT_FALSE(r.ekf.solution.has_value());
    EXPECT_EQ(r.ins.status, EpochStatus::NoSolution);
    EXPECT_EQ(r.ins.no_solution_reason, NoSolutionReason::TooFewSatellites);
    worst_m = std::max(worst_m, (r.ins_error_m - before.ins_error_m).norm());
  }
  std::printf("outage of 10 s: INS position drift at most %.3f m (bound %.3f m; at the start %.3f m, "
              "%.3f m/s, %.2e rad)\n",
              worst_m, bound_m, dp0, dv0, dtheta0);
  EXPECT_LT(worst_m, bound_m);
  // After the outage both solve again; the INS EKF's error stays small.
  EXPECT_EQ(run.back().ins.status, EpochStatus::Ok) << run.back().ins.reason;
  EXPECT_LT(run.back().ins_position_m, 1.0);
}

TEST(PppInsEkf, ScalesItsProcessNoiseWhenThePhasesDisagreeWithItsPrediction) {
  // From 30 s on the readings carry an accelerometer error of 0.05 m/s^2 along body x that
  // the industrial grade's noise and bias instability do not allow for: each 1-s
  // prediction is then off by centimetres, many of the phases' sigmas. Without the
  // adaptive process noise the postfit test rejects phases of satellites that are right
  // (10 when written) and the error grows to 3.49 m; with it, the prediction's noise is
  // scaled where the phases disagree (9 epochs when written), no phase is rejected and
  // the error stays at the GNSS EKF's (2.71 m, the EKF 2.75 m).
  for (const bool adaptive : {true, false}) {
    RunSetup setup;
    test::addUnmodelledAccelError(setup);
    setup.adaptive_process_noise = adaptive;
    const std::vector<EpochErrors> run = runBoth(setup);
    ASSERT_EQ(run.size(), 61u);
    int rejections = 0, inflated = 0, inflated_before = 0;
    double worst_m = 0.0, worst_ekf_m = 0.0;
    for (const auto& r : run) {
      ASSERT_EQ(r.ins.status, EpochStatus::Ok) << r.t_s << " s: " << r.ins.reason;
      if (r.t_s < test::kUnmodelledAccelErrorFrom_s) {
        inflated_before += r.noise_scale.inflated();
        continue;
      }
      rejections += r.ins.postfit_rejections;
      inflated += r.noise_scale.inflated();
      worst_m = std::max(worst_m, r.ins_position_m);
      worst_ekf_m = std::max(worst_ekf_m, r.ekf_position_m);
    }
    std::printf("adaptive process noise %s: from 30 s %d postfit rejections, %d epochs scaled (before: %d); "
                "worst 3D error %.3f m (GNSS EKF %.3f m)\n",
                adaptive ? "on" : "off", rejections, inflated, inflated_before, worst_m, worst_ekf_m);
    EXPECT_EQ(inflated_before, 0);  // a prediction consistent with the phases keeps its noise
    if (adaptive) {
      EXPECT_GE(inflated, 1);
      EXPECT_EQ(rejections, 0);
      EXPECT_LT(worst_m, worst_ekf_m + 0.1);
    } else {
      EXPECT_GT(rejections, 0);  // the case the adaptation is for
    }
  }
}

TEST(PppInsEkf, ProcessNoiseScaleOfPhaseInnovations) {
  // ins_process_noise_adaptation.h on six rows (three GPS, three Galileo), phase sigma 1 cm,
  // relative antenna error 1 mm per axis, of it 0.7 mm the process noise.
  const std::vector<Eigen::Vector3d> los = {{0.3, 0.2, 0.93}, {-0.6, 0.1, 0.79}, {0.1, -0.7, 0.7},
                                            {0.8, 0.3, 0.52}, {-0.2, -0.4, 0.89}, {-0.5, 0.6, 0.62}};
  const auto rows = [&](const Eigen::Vector3d& error_m, std::optional<int> outlier = std::nullopt) {
    std::vector<PhaseInnovationRow> out;
    for (std::size_t k = 0; k < los.size(); ++k) {
      PhaseInnovationRow row;
      row.satellite = SatelliteId{k < 3 ? GnssSystem::GPS : GnssSystem::Galileo, static_cast<int>(k) + 1};
      row.clock_system = row.satellite.system;
      row.d_antenna_m = -los[k].normalized();
      row.innovation_m = row.d_antenna_m.dot(error_m) + (k < 3 ? 0.5 : -0.3);  // clocks jumped
      if (outlier && *outlier == static_cast<int>(k)) row.innovation_m += 0.2;
      row.variance_m2 = 1e-4;
      out.push_back(row);
    }
    return out;
  };
  const Eigen::Matrix3d relative = 1e-6 * Eigen::Matrix3d::Identity(), process = 0.5e-6 * Eigen::Matrix3d::Identity();
  const ProcessNoiseAdaptationOptions options;
  const ChiSquareUpperQuantile quantile(options.false_alarm);
  // Only the clocks moved: consistent, the noise kept; 6 rows - 2 clocks - 1 left out.
  const ProcessNoiseScale still = processNoiseScale(rows(Eigen::Vector3d::Zero()), relative, process, options, quantile);
  EXPECT_EQ(still.scale, 1.0) << still.text();
  EXPECT_EQ(still.dof, 3);
  EXPECT_LT(still.statistic, 1e-9);
  // One phase 20 cm off: left out, not a reason to scale.
  const ProcessNoiseScale slip = processNoiseScale(rows(Eigen::Vector3d::Zero(), 4), relative, process, options, quantile);
  EXPECT_EQ(slip.scale, 1.0) << slip.text();
  ASSERT_TRUE(slip.left_out);
  EXPECT_EQ(slip.left_out->toString(), "E05");
  // The prediction 23 cm off: scaled; twice the error, about four times the scale (T is
  // quadratic in the error, and the scaled process noise dominates its covariance).
  const Eigen::Vector3d off(0.1, -0.2, 0.05);
  const ProcessNoiseScale once = processNoiseScale(rows(off), relative, process, options, quantile);
  const ProcessNoiseScale twice = processNoiseScale(rows(2.0 * off), relative, process, options, quantile);
  std::printf("%s\n%s\n", once.text().c_str(), twice.text().c_str());
  EXPECT_GT(once.statistic, once.quantile);
  EXPECT_GT(once.scale, 10.0);
  EXPECT_NEAR(twice.scale / once.scale, 4.0, 0.4);
  // At that scale the innovations are consistent: T is its expectation, the degrees of
  // freedom (the rows without the satellite left out, which may be another one now: at most).
  const ProcessNoiseScale rescaled =
      processNoiseScale(rows(off), relative + (once.scale - 1.0) * process, process, options, quantile);
  std::printf("%s\n", rescaled.text().c_str());
  EXPECT_EQ(rescaled.scale, 1.0);
  EXPECT_LT(rescaled.statistic, once.dof * 1.01);
  EXPECT_GT(rescaled.statistic, once.dof * 0.8);
}

// ---- (d) The registry and the refusals -----------------------------------------------

TEST(PppInsEkf, RegisteredAsEkfInsAndNotRunByBoth) {
  const EstimatorEntry* entry = findEstimator("ekf_ins");
  ASSERT_NE(entry, nullptr);
  EXPECT_EQ(entry->state, EstimatedState::GnssInertial);
  EXPECT_FALSE(entry->monte_carlo_study);
  std::string why;
  const auto made = makeEstimatorAs<PppInsEkf>("ekf_ins", EstimatorOptions{}, &why);
  ASSERT_TRUE(made) << why;
  EXPECT_EQ(made->name(), "ekf_ins");
  const auto selected = selectEstimators("ekf_ins");
  ASSERT_TRUE(selected && selected->size() == 1u);
  EXPECT_EQ(selected->front(), entry);
  const auto all = selectEstimators(kAllEstimators);
  ASSERT_TRUE(all);
  for (const EstimatorEntry* e : *all) EXPECT_NE(e->name, "ekf_ins");
}

TEST(PppInsEkf, SaysWhyWithoutAnAttitudeOrWithoutImuReadings) {
  // Without an attitude (one reading: too few to level); without a reading at the start;
  // started with a reading, then 1 s later without any: a gap, said so, no GNSS-only solution.
  sim::Simulator sim;
  ImuSample still;
  still.time = sim.time();
  still.specific_force_mps2 = Eigen::Vector3d(0.0, 0.0, 9.8);
  test::expectInsRefusals("ekf_ins", sim, {still});
}

TEST(PppInsEkf, AReadingHeldFromBeforeTheEpochCountsWholeAsTheSmootherCountsIt) {
  // Held from 0.06 s before the first epoch to 0.05 s after it: 0.11 s, over the 0.1 s
  // allowed, though only 0.05 s of it is after the epoch (imu_coverage.h). Both GNSS/INS
  // estimators refuse the next epoch with the same reason.
  for (const char* name : {"ekf_ins", "smoother_ins"}) {
    SCOPED_TRACE(name);
    sim::Simulator sim;
    EstimatorOptions options;
    options.ins.initial_rotation_ecef_body = Eigen::Matrix3d::Identity();
    std::string why;
    const auto estimator = makeEstimator(name, options, &why);
    ASSERT_TRUE(estimator) << why;
    const GnssTime t0 = sim.time();
    const std::vector<ImuSample> first{ImuSample{t0 - 0.06, Eigen::Vector3d(0, 0, 9.8), Eigen::Vector3d::Zero()}};
    std::vector<ImuSample> next;
    for (int k = 1; k <= 20; ++k) next.push_back(ImuSample{t0 + 0.05 * k, Eigen::Vector3d(0, 0, 9.8), Eigen::Vector3d::Zero()});
    const MeasurementFunction evaluate = sim::modelOf(sim.epoch());
    EstimatorEpochInput input;
    input.time = t0;
    input.evaluate = &evaluate;
    input.imu = &first;
    ASSERT_EQ(estimator->processEpoch(input).status, EpochStatus::Ok);
    sim.t_s = 1.0;
    const MeasurementFunction later = sim::modelOf(sim.epoch());
    input.time = sim.time();
    input.evaluate = &later;
    input.imu = &next;
    const EstimatorEpochResult r = estimator->processEpoch(input);
    EXPECT_EQ(r.no_solution_reason, NoSolutionReason::NoImuReadings) << r.reason;
    EXPECT_EQ(r.reason, "IMU readings do not cover the interval to " + sim.time().toString() +
                            ": gap of 0.110000 s after the reading at " + (t0 - 0.06).toString() +
                            " (at most 0.100000 s)");
  }
}

TEST(PppInsEkf, InertialStateIsTheNominalWithItsQualityAndCovarianceAndNoneForGnssOnly) {
  test::TurnRunSetup setup;
  setup.duration_s = 3.0;
  test::TurnRun turn(setup);
  std::string why;
  const auto ins = makeEstimatorAs<PppInsEkf>("ekf_ins", turn.insOptions(), &why);
  const auto smoother = makeEstimatorAs<PppInsSmoother>("smoother_ins", turn.insOptions(), &why);
  const auto gnss = makeEstimator("ekf", turn.insOptions(), &why);
  ASSERT_TRUE(ins && smoother && gnss) << why;
  EXPECT_FALSE(ins->inertialState().has_value());  // before the start
  turn.forEachEpoch([&](const test::TurnEpoch& epoch) {
    ins->processEpoch(epoch.input);
    smoother->processEpoch(epoch.input);
    gnss->processEpoch(epoch.input);
  });
  EXPECT_FALSE(gnss->inertialState().has_value());
  const std::optional<InertialState> s = ins->inertialState();
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->time - *ins->navTime(), 0.0);
  EXPECT_EQ(s->nav.position_world_m, ins->navState().position_world_m);
  EXPECT_EQ(s->nav.rotation_world_body, ins->navState().rotation_world_body);
  EXPECT_EQ(s->bias.gyro_radps, ins->imuBias().gyro_radps);
  EXPECT_EQ(s->antenna_ecef_m, ins->antennaPosition());
  ASSERT_TRUE(s->attitude_quality && s->error_covariance);
  EXPECT_EQ(s->attitude_quality->heading_sigma_rad, ins->attitudeQuality().heading_sigma_rad);
  EXPECT_EQ(*s->error_covariance, (ins->covarianceMatrix().topLeftCorner<15, 15>()));
  // The smoother's: its navState() at navTime(), with its covariance and attitude quality.
  const std::optional<InertialState> m = smoother->inertialState();
  ASSERT_TRUE(m.has_value());
  EXPECT_EQ(m->time - *smoother->navTime(), 0.0);
  EXPECT_EQ(m->nav.position_world_m, smoother->navState()->position_world_m);
  EXPECT_EQ(m->antenna_ecef_m, *smoother->antennaPosition());
  ASSERT_TRUE(m->attitude_quality && m->error_covariance);
  EXPECT_EQ(*m->error_covariance, *smoother->errorCovariance());
}

// Neither attitude nor heading nor velocity given, a walker's pace on a slow turn:
// levelled from the readings before the start (the centripetal 0.06 m/s^2 tilts it
// by 0.35 deg), the heading unknown (1 rad sigma, 90 deg off) until the antenna
// track reaches 0.5 m/s over 1 s; then the course is the heading. Measured: aligned
// at 1 s with -2.9 deg, at most 4.9 deg off after 10 s, 3.9 deg at 60 s (sigma
// 1.4 deg; at 1.5 m/s the turn makes the heading only weakly observable).
TEST(PppInsEkf, AlignsAnUnknownHeadingFromTheCourseInMotion) {
  RunSetup setup;
  setup.duration_s = 60.0;
  setup.rate_radps = 0.04;  // 2.3 deg/s: below the levelling gyro threshold
  setup.speed_mps = 1.5;
  setup.unknown_heading = true;
  const std::vector<EpochErrors> run = runBoth(setup);
  ASSERT_EQ(run.size(), 61u);
  ASSERT_EQ(run[0].ins.status, EpochStatus::Ok) << run[0].ins.reason;
  ASSERT_TRUE(run[0].attitude);
  EXPECT_EQ(run[0].attitude->state, AlignmentState::LevelOnly);
  EXPECT_FALSE(run[0].attitude->publishable);
  EXPECT_NEAR(std::abs(run[0].ins_heading_error_rad), M_PI / 2, 0.01);  // north given, east true
  double aligned_at_s = -1.0, worst_after_10s_rad = 0.0;
  for (const auto& r : run) {
    ASSERT_EQ(r.ins.status, EpochStatus::Ok) << r.t_s << " s: " << r.ins.reason;
    if (aligned_at_s < 0.0 && r.attitude->state == AlignmentState::Aligned) aligned_at_s = r.t_s;
    if (r.t_s >= 10.0) worst_after_10s_rad = std::max(worst_after_10s_rad, std::abs(r.ins_heading_error_rad));
  }
  const EpochErrors& last = run.back();
  std::printf("heading aligned at %.0f s (error then %.2f deg, sigma %.2f deg); worst error after 10 s %.2f deg; "
              "final %.3f deg, sigma %.2f deg, publishable %d\n",
              aligned_at_s, run[static_cast<std::size_t>(aligned_at_s)].ins_heading_error_rad * kRadToDeg,
              run[static_cast<std::size_t>(aligned_at_s)].attitude->heading_sigma_rad * kRadToDeg,
              worst_after_10s_rad * kRadToDeg, last.ins_heading_error_rad * kRadToDeg,
              last.attitude->heading_sigma_rad * kRadToDeg, last.attitude->publishable);
  EXPECT_GE(aligned_at_s, 1.0);
  EXPECT_LE(aligned_at_s, 3.0);
  EXPECT_LT(worst_after_10s_rad, 6.0 * kDegToRad);
  EXPECT_LT(std::abs(last.ins_heading_error_rad), 6.0 * kDegToRad);
  EXPECT_TRUE(last.attitude->publishable);
}

// An attitude and a velocity given in the local NED frame of the start (a node
// knows them before the position): the start equals the one given in ECEF at
// the start position (the code solution's, metres from the simulator's: the NED
// frame turns by 1.6e-7 rad per metre).
TEST(PppInsEkf, StartsFromAnAttitudeAndVelocityGivenInTheLocalNedFrame) {
  sim::Simulator sim;
  const MeasurementFunction evaluate = sim::modelOf(sim.epoch());
  ImuSample reading;
  reading.time = sim.time();
  reading.specific_force_mps2 = Eigen::Vector3d(0.0, 0.0, -9.8);
  const std::vector<ImuSample> one{reading};
  EstimatorEpochInput input;
  input.time = sim.time();
  input.evaluate = &evaluate;
  input.imu = &one;
  const Eigen::Matrix3d ned_body = rotationNedBody(0.1, -0.05, 2.0);
  const Eigen::Vector3d velocity_ned(12.0, -3.0, 0.5);
  EstimatorOptions local, ecef;
  local.ins.initial_rotation_ned_body = ned_body;
  local.ins.initial_velocity_ned_mps = velocity_ned;
  ecef.ins.initial_rotation_ecef_body = rotationEcefNed(sim.position) * ned_body;
  ecef.ins.initial_velocity_ecef_mps = rotationEcefNed(sim.position) * velocity_ned;
  std::string why;
  auto a = makeEstimatorAs<PppInsEkf>("ekf_ins", local, &why);
  auto b = makeEstimatorAs<PppInsEkf>("ekf_ins", ecef, &why);
  ASSERT_TRUE(a && b) << why;
  ASSERT_EQ(a->processEpoch(input).status, EpochStatus::Ok);
  ASSERT_EQ(b->processEpoch(input).status, EpochStatus::Ok);
  const double attitude_rad =
      so3::logMap(b->navState().rotation_world_body.transpose() * a->navState().rotation_world_body).norm();
  const double velocity_mps = (a->navState().velocity_world_mps - b->navState().velocity_world_mps).norm();
  std::printf("NED start against ECEF start: %.2e rad, %.2e m/s\n", attitude_rad, velocity_mps);
  EXPECT_LT(attitude_rad, 1e-4);
  EXPECT_LT(velocity_mps, 1e-3);
  local.ins.initial_velocity_ned_mps = Eigen::Vector3d(std::nan(""), 0.0, 0.0);
  EXPECT_EQ(local.ins.validate(), "initial NED velocity not finite");
}

// Without a given attitude: roll and pitch from levelling the readings up to the
// first epoch (at rest), the heading given; too few readings are refused, said so.
TEST(PppInsEkf, StartsFromLevellingWithAGivenHeading) {
  sim::Simulator sim;
  const Eigen::Matrix3d truth = rotationEcefNed(sim.position) * rotationNedBody(0.02, -0.03, 0.7);
  ImuSample at_rest;  // gravity and the Earth rate in the body axes, noise-free
  at_rest.specific_force_mps2 = -truth.transpose() * ecefNavigationFrame(sim.position).gravity_world_mps2;
  at_rest.angular_rate_radps = truth.transpose() * Eigen::Vector3d(0.0, 0.0, 7.2921151467e-5);
  std::vector<ImuSample> readings;
  for (int k = 200; k >= 0; --k) {
    at_rest.time = sim.time() - 0.01 * k;
    readings.push_back(at_rest);
  }
  const MeasurementFunction evaluate = sim::modelOf(sim.epoch());
  EstimatorEpochInput input;
  input.time = sim.time();
  input.evaluate = &evaluate;
  input.imu = &readings;
  EstimatorOptions options;
  options.ins.initial_heading_rad = 0.7;
  std::string why;
  auto ins = makeEstimatorAs<PppInsEkf>("ekf_ins", options, &why);
  ASSERT_TRUE(ins) << why;
  const EstimatorEpochResult r = ins->processEpoch(input);
  ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
  const double error_rad = so3::logMap(truth.transpose() * ins->navState().rotation_world_body).norm();
  std::printf("levelled start: attitude error %.2e rad\n", error_rad);
  EXPECT_LT(error_rad, 1e-9);  // noise-free readings at rest: roll and pitch to rounding

  auto few = makeEstimatorAs<PppInsEkf>("ekf_ins", options, &why);
  const std::vector<ImuSample> ten(readings.end() - 10, readings.end());
  input.imu = &ten;
  const EstimatorEpochResult f = few->processEpoch(input);
  EXPECT_EQ(f.no_solution_reason, NoSolutionReason::NoInitialAttitude);
  EXPECT_NE(f.reason.find("levelling the 10 readings up to the start refused: too few samples"), std::string::npos)
      << f.reason;
}

}  // namespace
}  // namespace ppp
