// The epoch front end shared by the EKF and the smoother (PppEstimator):
// several systems with one receiver clock each, a configured system without
// satellites, the same screened set for both estimators, and the smoother's
// restart from its last good state after a failed update.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "ppp_bayes_tree/ppp/estimators/code_least_squares.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_ekf.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"
#include "ppp_simulator.h"

namespace ppp {
namespace {

using sim::modelOf;
using sim::SimModelOptions;
using sim::SimObs;
using sim::Simulator;

const ReceiverStateLayout kGpsGalileo({GnssSystem::GPS, GnssSystem::Galileo});

int countSystem(const std::vector<SatelliteId>& used, GnssSystem system) {
  return static_cast<int>(std::count_if(used.begin(), used.end(), [&](const SatelliteId& s) { return s.system == system; }));
}

template <class Estimator>
void expectTwoClocksRecovered(Estimator& estimator) {
  Simulator sim;
  sim.addGalileo(35.0);  // the Galileo receiver clock is 35 m (117 ns) ahead of GPS's
  const auto results = sim::runEpochs(estimator, sim, 20);
  const EstimatorEpochResult& r = results.back();
  ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
  EXPECT_GE(countSystem(r.used, GnssSystem::Galileo), 3);
  EXPECT_GE(countSystem(r.used, GnssSystem::GPS), 4);
  EXPECT_TRUE(r.rejected.empty());
  ASSERT_EQ(r.solution->state.layout, kGpsGalileo);
  EXPECT_EQ(r.solution->covariance.rows(), 6);
  EXPECT_LT((r.solution->state.position_ecef_m - sim.position).norm(), 1e-3);
  EXPECT_NEAR(r.solution->state.clock_m(GnssSystem::GPS), sim.clock_m, 1e-3);
  EXPECT_NEAR(r.solution->state.clock_m(GnssSystem::Galileo), sim.clock_m + 35.0, 1e-3);
  for (const auto& res : r.residuals) EXPECT_LT(std::abs(res.code_postfit_m), 1e-3) << res.satellite.toString();
}

TEST(EstimatorFrontEnd, GpsAndGalileoWithOneClockEachThroughTheEkf) {
  PppEkf ekf({}, {}, {}, kGpsGalileo);
  expectTwoClocksRecovered(ekf);
}

TEST(EstimatorFrontEnd, GpsAndGalileoWithOneClockEachThroughTheSmoother) {
  PppSmoother smoother({}, {}, {}, kGpsGalileo);
  expectTwoClocksRecovered(smoother);
  EXPECT_EQ(smoother.smoothedTrajectory().back().state.layout, kGpsGalileo);
}

TEST(EstimatorFrontEnd, CodeLeastSquaresSolvesTheClocksOfTheSystemsPresentOnly) {
  Simulator sim;
  sim.addGalileo(-20.0);
  ReceiverState start(kGpsGalileo);
  start.zwd_m = sim.zwd_m;
  const CodeLeastSquaresResult both = codeLeastSquares(modelOf(sim.epoch()), start);
  ASSERT_TRUE(both.ok) << both.reason;
  EXPECT_EQ(both.covariance_components, (std::vector<int>{0, 1, 2, 4, 5}));
  EXPECT_NEAR(both.state.clock_m(GnssSystem::Galileo), sim.clock_m - 20.0, 1e-6);

  // GPS satellites only: the Galileo clock column is left out (not singular) and keeps its start value.
  Simulator gps_only;
  ReceiverState s(kGpsGalileo);
  s.zwd_m = gps_only.zwd_m;
  s.setClock_m(GnssSystem::Galileo, 7.0);
  const CodeLeastSquaresResult one = codeLeastSquares(modelOf(gps_only.epoch()), s);
  ASSERT_TRUE(one.ok) << one.reason;
  EXPECT_EQ(one.covariance_components, (std::vector<int>{0, 1, 2, 4}));
  EXPECT_EQ(one.state.clock_m(GnssSystem::Galileo), 7.0);
  EXPECT_LT((one.state.position_ecef_m - gps_only.position).norm(), 1e-6);

  // Four satellites of two systems: 3 + 2 unknowns, not enough.
  Simulator mixed;
  mixed.addGalileo(0.0);
  std::vector<SimObs> obs = mixed.epoch(), few;
  for (GnssSystem system : {GnssSystem::GPS, GnssSystem::Galileo}) {
    int n = 0;
    for (const auto& o : obs)
      if (o.sat.system == system && n < 2) few.push_back(o), ++n;
  }
  ASSERT_EQ(few.size(), 4u);
  const CodeLeastSquaresResult short_of_one = codeLeastSquares(modelOf(few), ReceiverState(kGpsGalileo));
  EXPECT_FALSE(short_of_one.ok);
  EXPECT_NE(short_of_one.reason.find("at least 5 needed"), std::string::npos) << short_of_one.reason;
}

TEST(EstimatorFrontEnd, AConfiguredSystemWithoutSatellitesKeepsItsClockAtThePrior) {
  Simulator sim_a, sim_b;  // GPS only
  PppEkf ekf({}, {}, {}, kGpsGalileo);
  PppSmoother smoother({}, {}, {}, kGpsGalileo);
  const auto ra = sim::runEpochs(ekf, sim_a, 10);
  const auto rb = sim::runEpochs(smoother, sim_b, 10);
  const StochasticModel model;
  for (const auto* r : {&ra.back(), &rb.back()}) {
    ASSERT_EQ(r->status, EpochStatus::Ok) << r->reason;
    EXPECT_LT((r->solution->state.position_ecef_m - sim_a.position).norm(), 1e-3);
    // White clock without observations: the prior of one step, nothing learnt.
    EXPECT_NEAR(r->solution->clockVariance_m2(GnssSystem::Galileo), model.clock.processVariance_m2(30.0),
                1e-6 * model.clock.processVariance_m2(30.0));
  }
}

TEST(EstimatorFrontEnd, EkfAndSmootherSeeTheSameScreenedSetAndAgreeInTheLinearCaseWithTwoClocks) {
  Simulator sim_a, sim_b;
  for (Simulator* s : {&sim_a, &sim_b}) {
    s->addGalileo(12.0);
    s->noise = true;
  }
  ReceiverState about(kGpsGalileo);
  about.position_ecef_m = sim_a.position + Eigen::Vector3d(2.0, -1.0, 3.0);
  about.zwd_m = 0.1;
  about.setClock_m(GnssSystem::GPS, sim_a.clock_m);
  about.setClock_m(GnssSystem::Galileo, sim_a.clock_m + 12.0);
  const SimModelOptions linear{false, true, about};
  // The clock a priori that keeps the EKF well conditioned (test_ppp_smoother's consistency test).
  StochasticModel conditioned;
  conditioned.clock.initial_sigma_m = 1e3;
  conditioned.clock.process_noise_m_per_sqrt_s = 100.0;
  EkfOptions ekf_options;
  ekf_options.iterations_per_epoch = 1;
  ekf_options.screening.postfit_check = false;
  PppEkf ekf(conditioned, ekf_options, {}, kGpsGalileo);
  PppSmootherOptions options;
  options.exact_range = false;
  PppSmoother smoother(conditioned, options, {}, kGpsGalileo);
  double worst = 0.0;
  std::vector<SatelliteId> previous;
  for (int i = 0; i < 40; ++i) {
    if (i > 0) sim_a.t_s += 30.0, sim_b.t_s += 30.0;
    std::vector<SimObs> obs_a = sim_a.epoch(), obs_b = sim_b.epoch();
    if (i == 20) obs_a[1].code_m += 80.0, obs_b[1].code_m += 80.0;  // a code outlier for the screening
    const EstimatorEpochResult a = ekf.processEpoch(sim_a.time(), modelOf(obs_a, linear));
    const EstimatorEpochResult b = smoother.processEpoch(sim_b.time(), modelOf(obs_b, linear));
    ASSERT_EQ(a.status, EpochStatus::Ok) << a.reason;
    ASSERT_EQ(b.status, EpochStatus::Ok) << b.reason;
    EXPECT_EQ(a.used, b.used) << "epoch " << i;
    ASSERT_EQ(a.rejected.size(), b.rejected.size()) << "epoch " << i;
    for (std::size_t k = 0; k < a.rejected.size(); ++k) {
      EXPECT_EQ(a.rejected[k].satellite, b.rejected[k].satellite);
      EXPECT_EQ(a.rejected[k].reason, b.rejected[k].reason);
    }
    if (i == 20) {
      ASSERT_FALSE(a.rejected.empty());
      EXPECT_EQ(a.rejected[0].reason, RejectionReason::PrefitCode);
      EXPECT_EQ(a.rejected[0].satellite, obs_a[1].sat);
    }
    EXPECT_EQ(a.active_biases, b.active_biases);
    for (std::size_t k = 0; k < a.residuals.size(); ++k) {
      EXPECT_EQ(a.residuals[k].new_arc, b.residuals[k].new_arc);
      EXPECT_NEAR(a.residuals[k].code_prefit_m, b.residuals[k].code_prefit_m, 1e-6);
      // The bias prior: the EKF's current estimate, the smoother's filtered value of
      // the arc's last update; they coincide when the arc was used in the last epoch.
      const bool continued = std::count(previous.begin(), previous.end(), a.residuals[k].satellite) > 0;
      if (continued || a.residuals[k].new_arc)
        EXPECT_NEAR(a.residuals[k].phase_prefit_m, b.residuals[k].phase_prefit_m, 1e-6)
            << "epoch " << i << " " << a.residuals[k].satellite.toString();
    }
    previous = a.used;
    worst = std::max(worst, (a.solution->state.position_ecef_m - b.solution->state.position_ecef_m).norm());
    for (GnssSystem system : {GnssSystem::GPS, GnssSystem::Galileo})
      worst = std::max(worst, std::abs(a.solution->state.clock_m(system) - b.solution->state.clock_m(system)));
  }
  EXPECT_LT(worst, 1e-6);
}

/// A model whose sigmas are so small that the whitened system overflows: an
/// indeterminate update for the smoother (the values are finite, so the front
/// end accepts them).
MeasurementFunction overflowing(MeasurementFunction good) {
  return [good](const ReceiverState& s) {
    EpochMeasurements e = good(s);
    for (auto& m : e.used) m.code_sigma_m = m.phase_sigma_m = 1e-300;
    return e;
  };
}

TEST(EstimatorFrontEnd, TheSmootherRestartsFromItsLastGoodStateAfterAFailedUpdate) {
  Simulator sim;
  PppSmoother smoother;
  sim::runEpochs(smoother, sim, 10);
  const int biases_before = smoother.activeBiasCount();
  ASSERT_GT(biases_before, 0);
  sim.t_s += 30.0;
  const EstimatorEpochResult failed = smoother.processEpoch(sim.time(), overflowing(modelOf(sim.epoch())));
  ASSERT_EQ(failed.status, EpochStatus::Failed) << failed.reason;
  EXPECT_EQ(failed.no_solution_reason, NoSolutionReason::SmootherUpdateFailed);
  EXPECT_TRUE(failed.estimator_reset);
  EXPECT_NE(failed.reason.find("restarted from the last filtered state"), std::string::npos) << failed.reason;
  EXPECT_EQ(smoother.resets(), 1);
  EXPECT_EQ(smoother.activeBiasCount(), biases_before);  // the active arcs go on with their filtered biases

  // The next epochs are solved again, the arcs continue (no new biases) and the
  // noise-free truth is held.
  for (int i = 0; i < 10; ++i) {
    sim.t_s += 30.0;
    const EstimatorEpochResult r = smoother.processEpoch(sim.time(), modelOf(sim.epoch()));
    ASSERT_EQ(r.status, EpochStatus::Ok) << "epoch " << i << ": " << r.reason;
    EXPECT_FALSE(r.estimator_reset);
    if (i == 0) {
      ASSERT_TRUE(r.smoother);
      EXPECT_EQ(r.smoother->new_biases, 0);
      EXPECT_NEAR(r.dt_s, 60.0, 1e-9);  // from the last solved epoch, across the failed one
    }
    EXPECT_LT((r.solution->state.position_ecef_m - sim.position).norm(), 1e-3);
  }
  EXPECT_EQ(smoother.resets(), 1);
  const auto trajectory = smoother.smoothedTrajectory();
  ASSERT_EQ(trajectory.size(), 20u);  // the states before the restart are kept
  for (const auto& s : trajectory) EXPECT_LT((s.state.position_ecef_m - sim.position).norm(), 1e-3);
  const auto old = smoother.smoothedEpochAt(trajectory[3].time);  // before the restart: its last estimate
  ASSERT_TRUE(old);
  EXPECT_EQ(old->index, trajectory[3].index);

  // Through the pipeline's estimator interface the restart is reported the same way.
  PppEkf ekf;
  Simulator sim_e;
  sim::runEpochs(ekf, sim_e, 5);
  sim_e.t_s += 30.0;
  const EstimatorEpochResult e = ekf.processEpoch(sim_e.time(), overflowing(modelOf(sim_e.epoch())));
  EXPECT_FALSE(e.estimator_reset);  // the EKF never changed its state: nothing to restart
  EXPECT_EQ(ekf.resets(), 0);
  sim_e.t_s += 30.0;
  EXPECT_EQ(ekf.processEpoch(sim_e.time(), modelOf(sim_e.epoch())).status, EpochStatus::Ok);
}

}  // namespace
}  // namespace ppp
