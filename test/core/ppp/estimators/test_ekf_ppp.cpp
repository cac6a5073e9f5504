// PppEkf and codeLeastSquares on a small synthetic measurement generator (the
// real measurement model is separate): GPS-like circular orbits (radius
// 26 560 km, inclination 55 deg, 6 planes x 5 satellites, no Earth rotation),
// a receiver near ZIM2 (47 N, 7.5 E, spherical Earth), IF code and phase =
// range + clock + ZWD / sin(el) (+ arc bias for phase), noise-free or with
// Gaussian noise of the sigmas given to the filter (0.9 m and 9 mm at zenith,
// / sin(el)). The filter runs with the method's table (methodTableStochasticModel).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include "ppp_bayes_tree/ppp/estimators/code_least_squares.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_ekf.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_simulator.h"

using namespace ppp;
using namespace ppp::sim;

namespace {

double positionError(const EstimatorEpochResult& r, const Simulator& sim) {
  return (r.solution->state.position_ecef_m - sim.position).norm();
}

/// Runs `epochs` epochs every `dt` seconds (each Ok); returns the last result.
EstimatorEpochResult run(PppEkf& ekf, Simulator& sim, int epochs, double dt = 30.0) {
  return runEpochs(ekf, sim, epochs, dt).back();
}

const SatelliteId& firstUsed(const EstimatorEpochResult& r) { return r.used.front(); }

}  // namespace

TEST(CodeLeastSquares, FromTheEarthCentreRecoversTheTruth) {
  Simulator sim;
  ReceiverState start;
  start.zwd_m = sim.zwd_m;  // ZWD is held, not estimated
  const auto r = codeLeastSquares(modelOf(sim.epoch()), start);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_LT((r.state.position_ecef_m - sim.position).norm(), 1e-6);
  EXPECT_NEAR(r.state.clock_m(GnssSystem::GPS), sim.clock_m, 1e-6);
  EXPECT_GE(r.used.size(), 5u);
  EXPECT_LT(r.iterations, 15);
}

TEST(CodeLeastSquares, RejectsACodeOutlierAndReportsTooFewSatellites) {
  Simulator sim;
  auto obs = sim.epoch();
  ASSERT_GE(obs.size(), 6u);
  obs[2].code_m += 100.0;
  ReceiverState start;
  start.position_ecef_m = sim.position + Eigen::Vector3d(3e3, -2e3, 1e3);
  start.zwd_m = sim.zwd_m;
  const auto r = codeLeastSquares(modelOf(obs), start);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_LT((r.state.position_ecef_m - sim.position).norm(), 1e-6);
  ASSERT_EQ(r.rejected.size(), 1u);
  EXPECT_EQ(r.rejected[0].satellite, obs[2].sat);
  EXPECT_NE(r.rejected[0].detail.find("code least-squares residual"), std::string::npos) << r.rejected[0].detail;

  obs.resize(3);
  const auto few = codeLeastSquares(modelOf(obs), start);
  EXPECT_FALSE(few.ok);
  EXPECT_NE(few.reason.find("3 satellites"), std::string::npos) << few.reason;
}

TEST(PppEkf, NoiseFreeRecoversTheTruePositionBelowOneMillimetre) {
  Simulator sim;
  PppEkf ekf(methodTableStochasticModel());
  sim.zwd_m = 0.15;  // 5 cm off the a priori 0.1 m: converges through the geometry change
  const auto first = ekf.processEpoch(sim.time(), modelOf(sim.epoch()));
  ASSERT_EQ(first.status, EpochStatus::Ok) << first.reason;
  EXPECT_EQ(first.dt_s, 0.0);
  EXPECT_EQ(first.active_biases, static_cast<int>(first.used.size()));
  EXPECT_GT(first.iterations, 2);  // the code least-squares evaluations, then 2 updates
  double worst_late = 0.0;
  for (int i = 1; i < 120; ++i) {  // one hour at 30 s
    sim.t_s += 30.0;
    const auto r = ekf.processEpoch(sim.time(), modelOf(sim.epoch()));
    ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
    EXPECT_EQ(r.iterations, 2);  // default iterations_per_epoch: 2 evaluations of the model
    if (i >= 60) worst_late = std::max(worst_late, positionError(r, sim));
  }
  EXPECT_LT(worst_late, 1e-3);
  EXPECT_NEAR(ekf.receiverState().zwd_m, sim.zwd_m, 1e-3);
}

TEST(PppEkf, PositionNeesIsWithinChiSquareBounds) {
  // 40 independent runs with a random-walk truth (the filter's own process
  // model, q = 5 m/sqrt(s)) and Gaussian noise; at a fixed epoch the sum of the
  // 40 position NEES values is chi-square with 120 degrees of freedom.
  // The start is the code least squares of the first epoch, whose error (~2 m
  // here) the method's 1 m a priori does not cover, and which reuses that
  // epoch's code: a consistency test needs an uninformative position prior.
  StochasticModel model = methodTableStochasticModel();
  model.position.initial_sigma_m = 100.0;
  const int runs = 40;
  const std::vector<int> check_epochs{10, 40};
  std::map<int, double> nees_sum =
      positionNeesSums([&model] { return PppEkf(model); }, runs, 1000, check_epochs);
  ASSERT_FALSE(nees_sum.empty());
  const double dof = 3.0 * runs;
  const double lower = chiSquareQuantile(dof, -2.5758), upper = chiSquareQuantile(dof, 2.5758);  // 99 %
  for (int c : check_epochs) {
    EXPECT_GT(nees_sum[c], lower) << "epoch " << c << ": filter too pessimistic";
    EXPECT_LT(nees_sum[c], upper) << "epoch " << c << ": filter too optimistic";
  }
}

TEST(PppEkf, JosephFormKeepsTheCovarianceSymmetricPositiveDefinite) {
  Simulator sim;
  sim.noise = true;
  PppEkf ekf(methodTableStochasticModel());
  for (int i = 0; i < 200; ++i) {  // 200 epochs at 30 s: satellites set and rise, arcs come and go
    if (i > 0) sim.t_s += 30.0;
    const auto r = ekf.processEpoch(sim.time(), modelOf(sim.epoch()));
    ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
    const Eigen::MatrixXd& P = ekf.covarianceMatrix();
    ASSERT_EQ(P.rows(), 5 + ekf.activeBiasCount());
    EXPECT_EQ((P - P.transpose()).cwiseAbs().maxCoeff(), 0.0);
    const double min_eigen = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(P).eigenvalues().minCoeff();
    EXPECT_GT(min_eigen, 0.0) << "epoch " << i;
  }
}

TEST(PppEkf, ArcEventsAddReplaceAndRemoveBiases) {
  Simulator sim;
  PppEkf ekf(methodTableStochasticModel());
  auto r = run(ekf, sim, 10);
  const int n_biases = ekf.activeBiasCount();
  EXPECT_EQ(n_biases, static_cast<int>(r.used.size()));
  for (ArcId arc : ekf.activeArcs()) EXPECT_NEAR(*ekf.biasEstimate_m(arc), sim.bias_m[arc], 1e-3);

  // A slip: the arc tracker starts a new arc; its bias replaces the old one.
  const SatelliteId sat = firstUsed(r);
  const ArcId old_arc = sim.arcOf(sat);
  const ArcId new_arc = sim.slip(sat, 7.3);
  sim.t_s += 30.0;
  r = ekf.processEpoch(sim.time(), modelOf(sim.epoch()));
  ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
  EXPECT_FALSE(ekf.biasEstimate_m(old_arc).has_value());
  ASSERT_TRUE(ekf.biasEstimate_m(new_arc).has_value());
  EXPECT_NEAR(*ekf.biasSigma_m(new_arc), 0.9, 0.9);  // re-initialised: code-level, not converged
  EXPECT_EQ(ekf.activeBiasCount(), n_biases);
  const auto it = std::find_if(r.residuals.begin(), r.residuals.end(),
                               [&](const MeasurementResidual& m) { return m.satellite == sat; });
  ASSERT_NE(it, r.residuals.end());
  EXPECT_TRUE(it->new_arc);
  EXPECT_LT(positionError(r, sim), 1e-3);
  r = run(ekf, sim, 5);
  EXPECT_NEAR(*ekf.biasEstimate_m(new_arc), sim.bias_m[new_arc], 1e-3);  // 7.3 m jump recovered

  // A satellite that stays away: its bias is kept up to stale_arc_timeout_s (300 s), then removed.
  const SatelliteId gone = r.used.back();
  const ArcId gone_arc = sim.arcOf(gone);
  sim.hidden.insert(gone);
  run(ekf, sim, 10);  // 300 s unused: not more than the timeout
  EXPECT_TRUE(ekf.biasEstimate_m(gone_arc).has_value());
  run(ekf, sim, 1);  // 330 s
  EXPECT_FALSE(ekf.biasEstimate_m(gone_arc).has_value());

  // Explicit end of an arc.
  const ArcId ended = ekf.activeArcs().front();
  const int before = ekf.activeBiasCount();
  ekf.removeArc(ended);
  EXPECT_EQ(ekf.activeBiasCount(), before - 1);
  EXPECT_EQ(ekf.covarianceMatrix().rows(), 5 + before - 1);
  EXPECT_FALSE(ekf.biasEstimate_m(ended).has_value());
}

TEST(PppEkf, TooFewSatellitesIsNoSolutionWithoutStateChange) {
  Simulator sim;
  PppEkf ekf(methodTableStochasticModel());
  run(ekf, sim, 10);
  const Eigen::VectorXd x = ekf.stateVector();
  const Eigen::MatrixXd P = ekf.covarianceMatrix();
  const GnssTime last = *ekf.lastTime();

  sim.t_s += 30.0;
  auto obs = sim.epoch();
  obs.resize(4);
  const auto r = ekf.processEpoch(sim.time(), modelOf(obs));
  EXPECT_EQ(r.status, EpochStatus::NoSolution);
  EXPECT_FALSE(r.solution.has_value());
  EXPECT_NE(r.reason.find("4 satellites usable after screening, at least 5 needed"), std::string::npos) << r.reason;
  EXPECT_EQ(ekf.stateVector(), x);
  EXPECT_EQ(ekf.covarianceMatrix(), P);
  EXPECT_EQ(*ekf.lastTime(), last);

  // The next epoch predicts over the real elapsed time (60 s).
  sim.t_s += 30.0;
  const auto next = ekf.processEpoch(sim.time(), modelOf(sim.epoch()));
  ASSERT_EQ(next.status, EpochStatus::Ok) << next.reason;
  EXPECT_DOUBLE_EQ(next.dt_s, 60.0);
  EXPECT_LT(positionError(next, sim), 1e-3);

  // No satellites at all before the start: no solution, not initialised.
  PppEkf fresh(methodTableStochasticModel());
  const auto none = fresh.processEpoch(sim.time(), modelOf({}));
  EXPECT_EQ(none.status, EpochStatus::NoSolution);
  EXPECT_NE(none.reason.find("no initial position"), std::string::npos) << none.reason;
  EXPECT_FALSE(fresh.initialised());
}

TEST(PppEkf, ProcessNoiseScalesWithTheElapsedTime) {
  Simulator sim;
  PppEkf ekf(methodTableStochasticModel());
  run(ekf, sim, 10);
  const Eigen::MatrixXd P = ekf.covarianceMatrix();
  const StochasticModel m = methodTableStochasticModel();
  for (double dt : {30.0, 600.0}) {
    const Eigen::MatrixXd Pp = ekf.predictedCovariance(dt);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(Pp(a, a) - P(a, a), 25.0 * dt, 1e-9 * dt);  // q^2 dt, q = 5 m/sqrt(s)
    EXPECT_NEAR(Pp(3, 3) - P(3, 3), 9e-10 * dt, 1e-15);                                // q = 3e-5 m/sqrt(s)
    EXPECT_DOUBLE_EQ(Pp(4, 4), 4e6 * dt);                                             // white clock: reset to q^2 dt
    EXPECT_EQ(Pp.row(4).head(4).norm() + Pp.row(4).tail(Pp.cols() - 5).norm(), 0.0);  // no clock memory
    EXPECT_EQ(Pp.bottomRightCorner(P.rows() - 5, P.cols() - 5), P.bottomRightCorner(P.rows() - 5, P.cols() - 5));
  }
  // A 10-minute data gap is processed with dt = 600 s and still solves.
  sim.t_s += 600.0;
  const auto r = ekf.processEpoch(sim.time(), modelOf(sim.epoch()));
  ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
  EXPECT_DOUBLE_EQ(r.dt_s, 600.0);
  EXPECT_LT(positionError(r, sim), 1e-3);
}

/// The variance of a solution's height [m^2] (its position covariance along the local up).
double heightVariance_m2(const EstimatorEpochResult& r) {
  const Geodetic g = ecefToGeodetic(r.solution->state.position_ecef_m);
  const Eigen::Vector3d up = rotationEnuFromEcef(g.latitude_rad, g.longitude_rad).row(2).transpose();
  return up.dot(r.solution->positionCovariance_m2() * up);
}

TEST(PppEkf, WetDelayProcessNoiseFollowsTheHeightRate) {
  // A receiver climbing 1 m/s (30 m per 30-s epoch), noise-free: with the height-driven
  // term q_h the predicted ZWD variance grows by q^2 dt + q_h^2 |dh|, dh = 1 m/s x dt at the
  // vertical rate of the last two solutions (30 s apart: further than the 10-s window);
  // without it (q_h = 0) by q^2 dt only. With the noise threshold (k = 3, the default)
  // the rate counts only the change beyond 3 sigmas of the two heights' difference.
  for (const double k : {0.0, 3.0}) {
    for (const double q_h : {0.0, 1.0e-3}) {
      Simulator sim;
      StochasticModel m = methodTableStochasticModel();
      m.zwd_per_sqrt_height_m_per_sqrt_m = q_h;
      m.zwd_height_change_threshold_sigmas = k;
      PppEkf ekf(m);
      const Eigen::Vector3d up = sim.position.normalized();  // the simulator's Earth is a sphere
      std::vector<double> height_variances_m2;
      for (int i = 0; i < 10; ++i) {
        if (ekf.initialised()) {
          sim.t_s += 30.0;
          sim.position += 30.0 * up;
        }
        const auto r = ekf.processEpoch(sim.time(), modelOf(sim.epoch()));
        ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
        height_variances_m2.push_back(heightVariance_m2(r));
      }
      const double sigma_dh_m = std::sqrt(height_variances_m2[8] + height_variances_m2[9]);
      ASSERT_LT(3.0 * sigma_dh_m, 10.0);  // the climb stands out of the noise
      const double counted_mps = (30.0 - k * sigma_dh_m) / 30.0;
      const Eigen::MatrixXd P = ekf.covarianceMatrix();
      for (double dt : {30.0, 600.0}) {
        const double added = ekf.predictedCovariance(dt)(3, 3) - P(3, 3);
        // The geodetic up differs from the radial one by < 0.2 deg (1e-5 of dh); the solved heights by < 1 mm.
        EXPECT_NEAR(added, 9e-10 * dt + q_h * q_h * counted_mps * dt, 1e-12 + 1e-4 * q_h * q_h * dt)
            << "q_h " << q_h << " k " << k;
      }
    }
  }
  // A level receiver gets the time term only.
  Simulator sim;
  StochasticModel m = methodTableStochasticModel();
  m.zwd_per_sqrt_height_m_per_sqrt_m = 1.0e-3;
  PppEkf ekf(m);
  run(ekf, sim, 10);
  EXPECT_NEAR(ekf.predictedCovariance(30.0)(3, 3) - ekf.covarianceMatrix()(3, 3), 9e-10 * 30.0, 1e-12);
}

TEST(PppEkf, WetDelayProcessNoiseIgnoresTheFloatsOwnHeightNoise) {
  // A level receiver with measurement noise (0.9 m code, 9 mm phase at zenith): its solved
  // heights differ from epoch to epoch by their own noise. Counting every change (k = 0)
  // drives the height-driven wet-delay noise at every epoch; beyond 3 sigmas of the
  // heights' difference (k = 3, the default) it drives none, and the prediction adds the
  // random walk in time only (q^2 dt, q = 3e-5 m/sqrt(s): 2.7e-8 m^2 over 30 s).
  for (const double k : {0.0, 3.0}) {
    Simulator sim;
    sim.noise = true;
    StochasticModel m = methodTableStochasticModel();
    m.zwd_per_sqrt_height_m_per_sqrt_m = 3.2e-3;
    m.zwd_height_change_threshold_sigmas = k;
    PppEkf ekf(m);
    int driven = 0, epochs = 0;
    for (int i = 0; i < 120; ++i) {  // one hour at 30 s
      if (i > 0) sim.t_s += 30.0;
      const auto r = ekf.processEpoch(sim.time(), modelOf(sim.epoch()));
      ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
      if (i == 0) continue;
      ++epochs;
      const double added = ekf.predictedCovariance(30.0)(3, 3) - ekf.covarianceMatrix()(3, 3);
      // 1 mm of counted height change adds 1e-8 m^2.
      if (added > 9e-10 * 30.0 + 1e-12) ++driven;
    }
    if (k == 0.0)
      EXPECT_EQ(driven, epochs);
    else
      EXPECT_EQ(driven, 0);
  }
}

TEST(PppEkf, PrefitScreeningRejectsA50mCodeOutlierAndAPhaseJump) {
  Simulator sim;
  PppEkf ekf(methodTableStochasticModel());
  run(ekf, sim, 10);
  sim.t_s += 30.0;
  auto obs = sim.epoch();
  obs[1].code_m += 50.0;
  obs[3].phase_m += 20.0;  // an undetected slip (same arc)
  const auto r = ekf.processEpoch(sim.time(), modelOf(obs));
  ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
  EXPECT_EQ(r.prefit_rejections, 2);
  EXPECT_EQ(r.postfit_rejections, 0);
  ASSERT_EQ(r.rejected.size(), 2u);
  EXPECT_EQ(r.rejected[0].satellite, obs[1].sat);
  EXPECT_NE(r.rejected[0].detail.find("prefit code residual"), std::string::npos) << r.rejected[0].detail;
  EXPECT_NE(r.rejected[0].detail.find("> 30.000 m"), std::string::npos) << r.rejected[0].detail;
  EXPECT_EQ(r.rejected[1].satellite, obs[3].sat);
  EXPECT_NE(r.rejected[1].detail.find("prefit phase-minus-code innovation 20.0"), std::string::npos)
      << r.rejected[1].detail;
  EXPECT_EQ(r.used.size(), obs.size() - 2);
  EXPECT_LT(positionError(r, sim), 1e-3);  // the outliers did not reach the estimate
}

TEST(PppEkf, PostfitCheckRejectsAModerateCodeOutlierOnANewArc) {
  // On a new arc the phase-minus-code prefit test cannot see a code outlier
  // (the new bias starts from phase minus code): the postfit check must.
  for (const bool check : {true, false}) {
    Simulator sim;
    EkfOptions options;
    options.screening.postfit_check = check;
    PppEkf ekf(methodTableStochasticModel(), options);
    const auto last = run(ekf, sim, 10);
    const SatelliteId sat = firstUsed(last);
    sim.slip(sat, 0.0);
    sim.t_s += 30.0;
    auto obs = sim.epoch();
    const auto it = std::find_if(obs.begin(), obs.end(), [&](const SimObs& o) { return o.sat == sat; });
    ASSERT_NE(it, obs.end());
    it->code_m += 15.0;  // below the 30 m prefit threshold, but > 10 sigma
    const auto r = ekf.processEpoch(sim.time(), modelOf(obs));
    ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
    EXPECT_EQ(r.prefit_rejections, 0);
    if (check) {
      EXPECT_EQ(r.postfit_rejections, 1);
      ASSERT_EQ(r.rejected.size(), 1u);
      EXPECT_EQ(r.rejected[0].satellite, sat);
      EXPECT_NE(r.rejected[0].detail.find("postfit code residual"), std::string::npos) << r.rejected[0].detail;
      EXPECT_FALSE(ekf.biasEstimate_m(sim.arcOf(sat)).has_value());  // its new bias was not kept
      EXPECT_LT(positionError(r, sim), 1e-3);
    } else {
      EXPECT_EQ(r.postfit_rejections, 0);
      const auto res = std::find_if(r.residuals.begin(), r.residuals.end(),
                                    [&](const MeasurementResidual& m) { return m.satellite == sat; });
      ASSERT_NE(res, r.residuals.end());
      EXPECT_GT(std::abs(res->code_postfit_m), 5.0 * res->code_sigma_m);  // what the check would have caught
    }
  }
}

TEST(PppEkf, ReceiverClockJumpOfOneMillisecondIsAbsorbed) {
  Simulator sim;
  PppEkf ekf(methodTableStochasticModel());
  run(ekf, sim, 10);
  sim.clock_m += 299792.458;  // 1 ms clock steering jump
  sim.t_s += 30.0;
  const auto r = ekf.processEpoch(sim.time(), modelOf(sim.epoch()));
  ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
  EXPECT_TRUE(r.rejected.empty());
  EXPECT_LT(positionError(r, sim), 1e-3);
  EXPECT_NEAR(r.solution->state.clock_m(GnssSystem::GPS), sim.clock_m, 1e-3);
  for (const auto& res : r.residuals) EXPECT_LT(std::abs(res.code_prefit_m), 1.0);  // clock shifted by the median
}

TEST(PppEkf, NonFiniteMeasurementsAreRejectedWithAReasonNeverPropagated) {
  Simulator sim;
  PppEkf ekf(methodTableStochasticModel());
  run(ekf, sim, 5);
  sim.t_s += 30.0;
  auto obs = sim.epoch();
  obs[0].code_m = std::numeric_limits<double>::quiet_NaN();
  obs[2].phase_m = std::numeric_limits<double>::infinity();
  obs[4].code_sigma_m = std::numeric_limits<double>::quiet_NaN();
  const auto r = ekf.processEpoch(sim.time(), modelOf(obs));
  ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
  ASSERT_EQ(r.rejected.size(), 3u);
  EXPECT_EQ(r.rejected[0].detail, "non-finite observed code");
  EXPECT_EQ(r.rejected[1].detail, "non-finite observed phase");
  EXPECT_NE(r.rejected[2].detail.find("invalid code sigma"), std::string::npos);
  EXPECT_TRUE(ekf.stateVector().allFinite());
  EXPECT_TRUE(ekf.covarianceMatrix().allFinite());
  EXPECT_LT(positionError(r, sim), 1e-3);

  // A model that turns non-finite at re-linearisation: the satellite is dropped with the reason.
  sim.t_s += 30.0;
  const auto good = modelOf(sim.epoch());
  int calls = 0;
  const MeasurementFunction flaky = [&](const ReceiverState& s) {
    auto e = good(s);
    if (++calls > 1) e.used[0].jacobian(0) = std::numeric_limits<double>::quiet_NaN();
    return e;
  };
  const auto r2 = ekf.processEpoch(sim.time(), flaky);
  ASSERT_EQ(r2.status, EpochStatus::Ok) << r2.reason;
  ASSERT_EQ(r2.rejected.size(), 1u);
  EXPECT_EQ(r2.rejected[0].detail, "non-finite Jacobian");
  EXPECT_TRUE(ekf.stateVector().allFinite());
}

TEST(PppEkf, TimeGoingBackwardsFailsAndRollsBack) {
  Simulator sim;
  PppEkf ekf(methodTableStochasticModel());
  run(ekf, sim, 5);
  const Eigen::VectorXd x = ekf.stateVector();
  const auto r = ekf.processEpoch(sim.time() - 30.0, modelOf(sim.epoch()));
  EXPECT_EQ(r.status, EpochStatus::Failed);
  EXPECT_NE(r.reason.find("is not after the last solved epoch"), std::string::npos) << r.reason;
  EXPECT_FALSE(r.solution.has_value());
  EXPECT_EQ(ekf.stateVector(), x);
}
