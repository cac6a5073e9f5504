// PppSmoother and the PPP factors on the synthetic generator of ppp_simulator.h
// (the same as the EKF tests): Jacobians of the new factors, the exact-range
// re-evaluation, equality with the EKF on a linear model, NEES of the filtered
// position, smoothed = filtered at the last epoch, smoothed = batch optimum,
// gaps / no-solution epochs, fixed lag, screening and diagnostics. The
// estimators run with the method's table (methodTableStochasticModel).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <Eigen/Dense>
#include <map>
#include <random>

#include "ppp_bayes_tree/ppp/estimators/ppp_ekf.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/screening/postfit_screening.h"
#include "ppp_bayes_tree/ppp/model/ppp_factors.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"
#include "ppp_bayes_tree/smoother/batch_solver.h"
#include "ppp_bayes_tree/smoother/numerical_jacobian.h"
#include "ppp_simulator.h"

using namespace ppp;
using namespace ppp::sim;
namespace sm = ppp::smoother;

namespace {

/// A measurement as the real model gives it: predicted = range + clock + ZWD m_w +
/// dry(h), Jacobian = -e + g (g along up: the height term of the dry delay).
SatelliteMeasurement realisticMeasurement(const ReceiverState& x0, Eigen::Vector3d* satellite) {
  const Eigen::Vector3d rx = x0.position_ecef_m;
  *satellite = rx + 2.2e7 * Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const Eigen::Vector3d offset(0.01, -0.02, 0.1);
  const Eigen::Vector3d d = *satellite - rx - offset;
  SatelliteMeasurement m;
  m.satellite = SatelliteId{GnssSystem::GPS, 5};
  m.arc = 3;
  m.predicted_code_m = d.norm() + x0.clock_m(GnssSystem::GPS) + 2.3 * x0.zwd_m + 4.0;
  m.predicted_phase_m = m.predicted_code_m + 0.05;  // wind-up
  m.observed_code_m = m.predicted_code_m + 1.5;
  m.observed_phase_m = m.predicted_phase_m + 7.0;
  const Eigen::Vector3d up = rx.normalized();
  m.jacobian.resize(x0.layout.dim());  // GPS only: x, y, z, zwd, clock
  m.jacobian << (-d.normalized() + 3e-4 * 2.5 * up).transpose(), 2.3, 1.0;
  m.code_sigma_m = 0.9;
  m.phase_sigma_m = 0.009;
  m.satellite_apc_ecef_m = *satellite;
  m.receiver_apc_offset_ecef_m = offset;
  return m;
}

ReceiverState someState() {
  Simulator sim;
  ReceiverState s;
  s.position_ecef_m = sim.position;
  s.zwd_m = 0.12;
  s.setClock_m(GnssSystem::GPS, 1234.5);
  return s;
}

std::vector<EstimatorEpochResult> runSmoother(PppSmoother& smoother, Simulator& sim, int epochs,
                                             SimModelOptions model = {true}) {
  return runEpochs(smoother, sim, epochs, 30.0, model);
}

}  // namespace

TEST(PppFactors, KeysPrintAsStatesAndArcBiases) {
  EXPECT_EQ(sm::keyToString(stateKey(42)), "x42");
  EXPECT_EQ(sm::keyToString(biasKey(SatelliteId{GnssSystem::GPS, 5}, 3)), "b(G05,3)");
  EXPECT_NE(biasKey(SatelliteId{GnssSystem::GPS, 5}, 3), biasKey(SatelliteId{GnssSystem::GPS, 5}, 4));
}

TEST(PppFactors, JacobiansMatchCentralDifferences) {
  const ReceiverState x0 = someState();
  Eigen::Vector3d satellite;
  const SatelliteMeasurement m = realisticMeasurement(x0, &satellite);
  sm::Values v;
  // Away from x0 (the factor is evaluated after relinearization), metre-level move.
  Eigen::VectorXd x = x0.vector();
  x.segment<3>(x0.layout.position()) += Eigen::Vector3d(1.2, -0.7, 2.1);
  x(x0.layout.zwd()) += 0.03;
  x(x0.layout.clock(GnssSystem::GPS)) += 25.0;
  v.insert(stateKey(7), x);
  v.insert(stateKey(6), x0.vector());
  v.insert(biasKey(m.satellite, m.arc), Eigen::VectorXd::Constant(1, 6.5));
  for (bool exact : {true, false}) {
    const SatellitePrediction p(m, x0, exact);
    EXPECT_EQ(p.exactRange(), exact);
    const PppCodeFactor code(stateKey(7), p, sm::NoiseModel::isotropic(1, m.code_sigma_m));
    const PppPhaseFactor phase(stateKey(7), biasKey(m.satellite, m.arc), p, sm::NoiseModel::isotropic(1, m.phase_sigma_m));
    // Range of 2e7 m: a 0.1 m step keeps the rounding of the differences (eps 2e7 / 0.1 = 5e-8)
    // and the truncation (h^2 / rho^2) far below the tolerance.
    auto c = sm::checkJacobians(code, v, 1e-6, 0.1);
    EXPECT_TRUE(c.ok) << c.report;
    c = sm::checkJacobians(phase, v, 1e-6, 0.1);
    EXPECT_TRUE(c.ok) << c.report;
  }
  const ReceiverRandomWalkFactor walk(stateKey(6), stateKey(7), ReceiverStateLayout(), 0.5, 0.01);
  auto c = sm::checkJacobians(walk, v, 1e-6, 0.1);
  EXPECT_TRUE(c.ok) << c.report;
  const ClockPriorFactor clock(stateKey(7), ReceiverStateLayout().clock(GnssSystem::GPS), 1000.0, 300.0);
  c = sm::checkJacobians(clock, v, 1e-6, 0.1);
  EXPECT_TRUE(c.ok) << c.report;
}

TEST(PppFactors, JacobiansWithTheTroposphereGradientBlockMatchCentralDifferences) {
  // The GPS-only measurement extended by the gradient columns (m_g cos a, m_g sin a).
  const ReceiverState gps = someState();
  Eigen::Vector3d satellite;
  SatelliteMeasurement m = realisticMeasurement(gps, &satellite);
  ReceiverState x0(ReceiverStateLayout({GnssSystem::GPS}, true));
  x0.position_ecef_m = gps.position_ecef_m;
  x0.zwd_m = gps.zwd_m;
  x0.setClock_m(GnssSystem::GPS, gps.clock_m(GnssSystem::GPS));
  x0.gradient_north_m = 0.001;
  x0.gradient_east_m = -0.002;
  const double g_n = 1.7, g_e = -0.4;
  m.jacobian.conservativeResize(x0.layout.dim());
  m.jacobian(x0.layout.gradientNorth()) = g_n;
  m.jacobian(x0.layout.gradientEast()) = g_e;
  m.predicted_code_m += g_n * x0.gradient_north_m + g_e * x0.gradient_east_m;
  m.predicted_phase_m += g_n * x0.gradient_north_m + g_e * x0.gradient_east_m;

  sm::Values v;
  Eigen::VectorXd x = x0.vector();
  x.segment<3>(x0.layout.position()) += Eigen::Vector3d(1.2, -0.7, 2.1);
  x(x0.layout.zwd()) += 0.03;
  x(x0.layout.gradientNorth()) += 0.004;
  x(x0.layout.gradientEast()) -= 0.003;
  v.insert(stateKey(7), x);
  v.insert(stateKey(6), x0.vector());
  v.insert(biasKey(m.satellite, m.arc), Eigen::VectorXd::Constant(1, 6.5));
  for (bool exact : {true, false}) {
    const SatellitePrediction p(m, x0, exact);
    // The gradients enter linearly with the model's constant partials.
    Eigen::VectorXd x_gradient = x0.vector();
    x_gradient(x0.layout.gradientNorth()) += 0.004;
    x_gradient(x0.layout.gradientEast()) -= 0.003;
    // (to the rounding of a 2e7 m prediction, 4e-9 m)
    EXPECT_NEAR(p.code_m(x_gradient, nullptr) - m.predicted_code_m, g_n * 0.004 - g_e * 0.003, 1e-8);
    const PppCodeFactor code(stateKey(7), p, sm::NoiseModel::isotropic(1, m.code_sigma_m));
    const PppPhaseFactor phase(stateKey(7), biasKey(m.satellite, m.arc), p, sm::NoiseModel::isotropic(1, m.phase_sigma_m));
    EXPECT_TRUE(code.affineInComponent(stateKey(7), x0.layout.gradientNorth()));
    auto c = sm::checkJacobians(code, v, 1e-6, 0.1);
    EXPECT_TRUE(c.ok) << c.report;
    c = sm::checkJacobians(phase, v, 1e-6, 0.1);
    EXPECT_TRUE(c.ok) << c.report;
  }
  // The random walk carries the gradients with their own sigma.
  const ReceiverRandomWalkFactor walk(stateKey(6), stateKey(7), x0.layout, 0.5, 0.01, 0.0002);
  const auto c = sm::checkJacobians(walk, v, 1e-6, 0.1);
  EXPECT_TRUE(c.ok) << c.report;
  const sm::Vector e = walk.evaluateError(x0.vector(), x, nullptr, nullptr);
  ASSERT_EQ(e.size(), 6);
  EXPECT_NEAR(e(4), 0.004, 1e-15);
  EXPECT_NEAR(e(5), -0.003, 1e-15);
  // Whitened by the gradient sigma: 0.004 / 0.0002 = 20.
  EXPECT_NEAR(walk.noiseModel()->whiten(e)(4), 20.0, 1e-9);
  EXPECT_NEAR(walk.noiseModel()->whiten(e)(5), -15.0, 1e-9);
}

TEST(PppFactors, PredictionEqualsTheModelAtX0AndTheExactRangeElsewhere) {
  const ReceiverState x0 = someState();
  Eigen::Vector3d satellite;
  const SatelliteMeasurement m = realisticMeasurement(x0, &satellite);
  const SatellitePrediction p(m, x0, true);
  SatellitePrediction::Row j;
  // At x0: the model's prediction and Jacobian.
  EXPECT_NEAR(p.code_m(x0.vector(), &j), m.predicted_code_m, 1e-9);
  EXPECT_NEAR(p.phase_m(x0.vector(), nullptr), m.predicted_phase_m, 1e-9);
  EXPECT_LT((j - m.jacobian).norm(), 1e-12);
  // 300 m away across the line of sight: the range grows by 300^2 / (2 rho) = 2 mm,
  // which the linear prediction misses and the exact range has (to 1e-6 m).
  Eigen::VectorXd x = x0.vector();
  const Eigen::Vector3d e = (satellite - x0.position_ecef_m - m.receiver_apc_offset_ecef_m).normalized();
  const Eigen::Vector3d across = e.cross(Eigen::Vector3d::UnitZ()).normalized();
  x.head<3>() += 300.0 * across;
  const Eigen::Vector3d g = m.jacobian.head<3>().transpose() + e;
  const double exact = m.predicted_code_m +
                       (satellite - x.head<3>() - m.receiver_apc_offset_ecef_m).norm() -
                       (satellite - x0.position_ecef_m - m.receiver_apc_offset_ecef_m).norm() +
                       g.dot(x.head<3>() - x0.position_ecef_m);
  EXPECT_NEAR(p.code_m(x, nullptr), exact, 1e-6);
  const SatellitePrediction linear(m, x0, false);
  EXPECT_NEAR(linear.code_m(x, nullptr) - p.code_m(x, nullptr), -300.0 * 300.0 / (2 * 2.2e7), 1e-4);
}

TEST(PppFactors, ExactRangePredictionIsThePlainFormulaBitForBit) {
  // code_m reads x0 and the model's partials from copies held in the prediction; its
  // value and Jacobian must be the formula of the top of ppp_factors.h evaluated on the
  // measurement itself, term by term in the same order (EXPECT_EQ: bit for bit).
  for (const bool galileo : {false, true}) {
    ReceiverState x0 = someState();
    if (galileo) {
      ReceiverState two(ReceiverStateLayout({GnssSystem::GPS, GnssSystem::Galileo}));
      two.position_ecef_m = x0.position_ecef_m;
      two.zwd_m = x0.zwd_m;
      two.setClock_m(GnssSystem::GPS, 812.0);
      two.setClock_m(GnssSystem::Galileo, -37.5);
      x0 = two;
    }
    Eigen::Vector3d satellite;
    SatelliteMeasurement m = realisticMeasurement(someState(), &satellite);  // GPS-only row
    if (galileo) {  // the row in the two-clock layout: a nonzero partial in every column
      Eigen::RowVectorXd j = Eigen::RowVectorXd::Zero(x0.layout.dim());
      j.head(5) = m.jacobian;
      j(x0.layout.dim() - 1) = 0.75;
      m.jacobian = j;
    }
    const SatellitePrediction p(m, x0, true);
    Eigen::VectorXd x = x0.vector();
    x.head<3>() += Eigen::Vector3d(120.5, -33.25, 71.0);
    for (int i = 3; i < x.size(); ++i) x(i) += 0.37 * i - 1.1;
    const Eigen::Vector3d o = m.receiver_apc_offset_ecef_m;
    const Eigen::Vector3d d0 = satellite - (x0.position_ecef_m + o);
    const Eigen::Vector3d g = m.jacobian.head<3>().transpose() + d0 / d0.norm();
    const Eigen::Vector3d d = satellite - (x.head<3>() + o);
    const Eigen::Vector3d dpos = x.head<3>() - x0.position_ecef_m;
    double expected = m.predicted_code_m + (d.norm() - d0.norm()) + g.dot(dpos);
    double rest = 0.0;
    for (int i = 3; i < x.size(); ++i) rest += m.jacobian(i) * (x(i) - x0.vector()(i));
    expected += rest;
    SatellitePrediction::Row j;
    EXPECT_EQ(p.code_m(x, &j), expected);
    ASSERT_EQ(j.rows(), 1);
    ASSERT_EQ(j.cols(), x.size());
    const Eigen::Vector3d position_partial = -d / d.norm() + g;
    for (int i = 0; i < 3; ++i) EXPECT_EQ(j(0, i), position_partial(i));
    for (int i = 3; i < x.size(); ++i) EXPECT_EQ(j(0, i), m.jacobian(i));
    EXPECT_EQ(p.phase_m(x, nullptr), expected + (m.predicted_phase_m - m.predicted_code_m));
  }
}

// Consistency test (a): linear model (linearised once, the same for both),
// single iteration, same noise, same initialisation: the smoother's filtered
// estimate equals the EKF's epoch by epoch, through a cycle slip, a no-solution
// epoch and a data gap. Returns the largest position difference and the largest
// relative difference of the position sigmas.
std::pair<double, double> ekfVersusSmoother(const StochasticModel& model, bool noise,
                                            smoother::Factorization factorization, bool compare_smoothers = false) {
  Simulator sim;
  sim.noise = noise;
  sim.zwd_m = 0.15;
  ReceiverState about;
  about.position_ecef_m = sim.position + Eigen::Vector3d(3.0, -2.0, 4.0);  // not the truth
  about.zwd_m = 0.1;
  about.setClock_m(GnssSystem::GPS, sim.clock_m);
  const SimModelOptions linear{false, true, about};
  EkfOptions ekf_options;
  ekf_options.iterations_per_epoch = 1;
  ekf_options.screening.postfit_check = false;
  PppEkf ekf(model, ekf_options);
  PppSmootherOptions options;
  options.screening.postfit_check = false;  // as the EKF's
  options.exact_range = false;
  options.factorization = factorization;
  PppSmoother smoother(model, options);
  PppSmootherOptions qr_options = options;
  qr_options.factorization = smoother::Factorization::QR;
  PppSmoother reference(model, qr_options);
  double worst = 0.0, worst_sigma = 0.0;
  int solved = 0;
  SatelliteId last_seen;
  for (int i = 0; i < 80; ++i) {
    if (i > 0) sim.t_s += 30.0;
    if (i == 30) sim.slip(last_seen, 0.57);  // a new arc, as the arc tracker would report
    std::vector<SimObs> obs = sim.epoch();
    last_seen = obs.front().sat;
    if (i == 40) obs.resize(3);       // too few satellites: no solution in both
    if (i == 50 || i == 51) continue;  // data gap: the next step spans 90 s
    const auto b = smoother.processEpoch(sim.time(), modelOf(obs, linear));
    struct Other {
      EpochStatus status;
      std::string reason;
      std::size_t used;
      int active_biases;
      double dt_s;
      std::optional<EpochSolution> solution;
    } a;
    if (compare_smoothers) {
      const auto r = reference.processEpoch(sim.time(), modelOf(obs, linear));
      a = {r.status, r.reason, r.used.size(), r.active_biases, r.dt_s, r.solution};
    } else {
      const auto r = ekf.processEpoch(sim.time(), modelOf(obs, linear));
      a = {r.status, r.reason, r.used.size(), r.active_biases, r.dt_s, r.solution};
    }
    const auto& a_solution = a.solution;
    EXPECT_EQ(a.status, b.status) << "epoch " << i << ": " << a.reason << " / " << b.reason;
    EXPECT_EQ(a.used, b.used.size());
    EXPECT_EQ(a.active_biases, b.active_biases) << "epoch " << i;
    if (a.status != EpochStatus::Ok || b.status != EpochStatus::Ok) {
      EXPECT_EQ(i, 40);
      continue;
    }
    ++solved;
    EXPECT_DOUBLE_EQ(a.dt_s, b.dt_s);
    worst = std::max(worst, (a_solution->state.position_ecef_m - b.solution->state.position_ecef_m).norm());
    worst = std::max(worst, std::abs(a_solution->state.zwd_m - b.solution->state.zwd_m));
    const Eigen::Vector3d sa = a_solution->positionCovariance_m2().diagonal().cwiseSqrt();
    const Eigen::Vector3d sb = b.solution->positionCovariance_m2().diagonal().cwiseSqrt();
    worst_sigma = std::max(worst_sigma, ((sa - sb).array() / sa.array()).abs().maxCoeff());
  }
  EXPECT_EQ(solved, 77);
  return {worst, worst_sigma};
}

TEST(PppSmoother, FilteredEqualsTheEkfOnALinearModel) {
  // The method's clock a priori sigma is 3e6 m: at the first epoch the EKF's
  // innovation covariance mixes 9e12 m^2 with the phase's 1e-4 m^2 (condition
  // ~1e17), and the covariance-form EKF loses precision there: 1 mm at epoch 0 and,
  // through the corrupted covariance, 5 cm at epoch 4, decaying to 2 mm at epoch 79
  // (measured: 3e-5 m with a 1e5 m a priori clock sigma, 4e-7 m with 1e3 m, whatever
  // the clock process noise). The information-form smoother does not lose it: it
  // agrees with a QR-factorized smoother to 1e-7 m. The equality to 1e-6 m is
  // therefore shown with a clock a priori that keeps the EKF well conditioned
  // (1 km, which also caps the white clock's variance per step: min(q^2 dt, sigma0^2));
  // everything else is the default model.
  StochasticModel conditioned = methodTableStochasticModel();
  conditioned.clock.initial_sigma_m = 1e3;
  conditioned.clock.process_noise_m_per_sqrt_s = 100.0;
  for (bool noise : {false, true}) {
    const auto [d, s] = ekfVersusSmoother(conditioned, noise, smoother::Factorization::Cholesky);
    std::printf("noise %d: largest |EKF - smoother filtered| %.3g m, sigma relative %.3g\n", noise, d, s);
    EXPECT_LT(d, 1e-6);
    EXPECT_LT(s, 1e-6);
  }
  // Default model: the smoother against a QR-factorized smoother (1e-6 m) and
  // against the EKF (its rounding: millimetre level).
  const auto [dq, sq] = ekfVersusSmoother(methodTableStochasticModel(), true, smoother::Factorization::Cholesky, true);
  EXPECT_LT(dq, 1e-6);
  EXPECT_LT(sq, 1e-6);
  const auto [de, se] = ekfVersusSmoother(methodTableStochasticModel(), true, smoother::Factorization::Cholesky);
  std::printf("default clock model: smoother Cholesky vs QR %.3g m; EKF vs smoother %.3g m (sigma %.3g)\n", dq, de,
              se);
  EXPECT_LT(de, 0.1);
}

// Consistency test (b): NEES of the filtered position over many epochs, with the
// nonlinear model and exact-range factors. 40 independent runs with a random-walk
// truth (the process model, q = 5 m/sqrt(s)) and Gaussian noise of the sigmas
// given to the estimator; at a fixed epoch the sum of the 40 NEES values is
// chi-square with 120 degrees of freedom (as in the EKF test; uninformative
// position prior for the same reason: the start reuses the first epoch's code).
TEST(PppSmoother, FilteredPositionNeesIsWithinChiSquareBounds) {
  StochasticModel model = methodTableStochasticModel();
  model.position.initial_sigma_m = 100.0;
  const int runs = 40;
  const std::vector<int> check_epochs{10, 25, 40};
  std::map<int, double> nees_sum =
      positionNeesSums([&model] { return PppSmoother(model); }, runs, 2000, check_epochs, {true});
  ASSERT_FALSE(nees_sum.empty());
  const double dof = 3.0 * runs;
  const double lower = chiSquareQuantile(dof, -1.95996), upper = chiSquareQuantile(dof, 1.95996);  // 95 %
  for (int c : check_epochs) {
    std::printf("epoch %d: NEES sum %.1f, 95%% bounds [%.1f, %.1f]\n", c, nees_sum[c], lower, upper);
    EXPECT_GT(nees_sum[c], lower) << "epoch " << c << ": too pessimistic";
    EXPECT_LT(nees_sum[c], upper) << "epoch " << c << ": too optimistic";
  }
}

// Consistency test (c), and the smoothed trajectory is the full-data optimum.
TEST(PppSmoother, SmoothedLastEpochEqualsFilteredAndTheTrajectoryIsTheBatchOptimum) {
  Simulator sim;
  sim.noise = true;
  sim.zwd_m = 0.14;
  PppSmoother smoother(methodTableStochasticModel());
  const auto results = runSmoother(smoother, sim, 60);
  const auto smoothed = smoother.smoothedTrajectory(true);
  ASSERT_EQ(smoothed.size(), 60u);
  const auto& last = results.back();
  EXPECT_EQ(smoothed.back().time, last.time);
  EXPECT_LT((smoothed.back().state.vector() - last.solution->state.vector()).norm(), 1e-6);
  ASSERT_TRUE(smoothed.back().covariance.has_value());
  EXPECT_LT((*smoothed.back().covariance - last.solution->covariance).norm(), 1e-6 * last.solution->covariance.norm());

  // Batch Gauss-Newton on the same graph from the iSAM2 estimate.
  const sm::BatchResult batch =
      sm::optimizeBatch(smoother.isam2().nonlinearFactors(), smoother.isam2().calculateEstimate());
  double worst = 0.0;
  for (const auto& s : smoothed)
    worst = std::max(worst, (s.state.position_ecef_m - batch.values.at(stateKey(s.index)).head<3>()).norm());
  EXPECT_LT(worst, 1e-3);
  // Smoothing uses the later data: the first 10 epochs are much better than filtered.
  double filtered_early = 0.0, smoothed_early = 0.0;
  for (int i = 0; i < 10; ++i) {
    filtered_early += (results[i].solution->state.position_ecef_m - sim.position).norm() / 10;
    smoothed_early += (smoothed[i].state.position_ecef_m - sim.position).norm() / 10;
  }
  std::printf("first 10 epochs mean 3D: filtered %.3f m, smoothed %.3f m; iSAM2 vs batch %.2g m\n", filtered_early,
              smoothed_early, worst);
  EXPECT_LT(smoothed_early, 0.5 * filtered_early);
  EXPECT_LT((smoothed.front().covariance->diagonal() - results.front().solution->covariance.diagonal())
                .head<3>()
                .maxCoeff(),
            0.0);  // the smoothed first state is more certain than its filtered estimate
}

TEST(PppSmoother, GapsAndNoSolutionEpochsKeepTheChainOverTheRealElapsedTime) {
  Simulator sim;
  PppSmoother smoother(methodTableStochasticModel());
  runSmoother(smoother, sim, 5);
  sim.t_s += 30.0;
  auto obs = sim.epoch();
  obs.resize(4);
  const auto none = smoother.processEpoch(sim.time(), modelOf(obs, {true}));
  EXPECT_EQ(none.status, EpochStatus::NoSolution);
  EXPECT_FALSE(none.solution.has_value());
  EXPECT_NE(none.reason.find("4 satellites usable after screening, at least 5"), std::string::npos) << none.reason;
  EXPECT_EQ(smoother.smoothedTrajectory().size(), 5u);  // no state added
  sim.t_s += 90.0;  // and a gap
  const auto r = smoother.processEpoch(sim.time(), modelOf(sim.epoch(), {true}));
  ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
  EXPECT_DOUBLE_EQ(r.dt_s, 120.0);
  // The between factor x4 -> x5 spans 120 s: sigma^2 = q^2 dt = 25 * 120 m^2 (position),
  // 9e-10 * 120 (ZWD); the clock prior has q^2 dt = 4e6 * 120 m^2.
  int walks = 0, clocks = 0;
  for (sm::FactorIndex f : smoother.isam2().factorsOf(stateKey(5))) {
    const auto factor = smoother.isam2().factor(f);
    const Eigen::MatrixXd cov = factor->noiseModel()->covarianceMatrix();
    if (dynamic_cast<const ReceiverRandomWalkFactor*>(factor.get())) {
      ++walks;
      EXPECT_EQ(factor->keys(), (sm::KeyVector{stateKey(4), stateKey(5)}));
      EXPECT_NEAR(cov(0, 0), 25.0 * 120.0, 1e-9);
      EXPECT_NEAR(cov(3, 3), 9e-10 * 120.0, 1e-15);
    }
    if (dynamic_cast<const ClockPriorFactor*>(factor.get())) {
      ++clocks;
      EXPECT_NEAR(cov(0, 0), 4e6 * 120.0, 1e-3);
    }
  }
  EXPECT_EQ(walks, 1);
  EXPECT_EQ(clocks, 1);
  // No between factor on the clock: the clock is white (no factor links two clocks).
  EXPECT_LT((r.solution->state.position_ecef_m - sim.position).norm(), 0.05);
}

TEST(PppSmoother, NewestStateAndObservedBiasesAreInTheRootClique) {
  Simulator sim;
  PppSmoother smoother(methodTableStochasticModel());
  const auto results = runSmoother(smoother, sim, 12);
  const auto& roots = smoother.isam2().bayesTree().roots();
  ASSERT_EQ(roots.size(), 1u);
  const sm::KeyVector& root = roots.front()->frontals;
  auto inRoot = [&](sm::Key k) { return std::find(root.begin(), root.end(), k) != root.end(); };
  EXPECT_TRUE(inRoot(stateKey(11)));
  for (const auto& r : results.back().residuals) EXPECT_TRUE(inRoot(biasKey(r.satellite, r.arc)));
  EXPECT_FALSE(inRoot(stateKey(0)));
  // Diagnostics of the last update.
  const auto& d = results.back();
  ASSERT_TRUE(d.smoother && results.front().smoother);
  EXPECT_GT(d.smoother->variables_reeliminated, 0u);
  EXPECT_GT(d.smoother->update_time_s, 0.0);
  EXPECT_GE(d.epoch_time_s, d.smoother->update_time_s);
  EXPECT_EQ(d.active_biases, static_cast<int>(d.used.size()));
  EXPECT_EQ(results.front().smoother->new_biases, static_cast<int>(results.front().used.size()));
}

TEST(PppSmoother, RelinearizesFromAPoorStartAndRecoversTheTruthNoiseFree) {
  Simulator sim;
  sim.zwd_m = 0.15;
  PppSmoother smoother(methodTableStochasticModel());
  smoother.setApproximatePosition(sim.position + Eigen::Vector3d(5e3, -3e3, 2e3));
  const auto results = runSmoother(smoother, sim, 120);
  std::size_t relinearized = 0;
  for (const auto& r : results) relinearized += r.smoother->variables_relinearized;
  EXPECT_GT(relinearized, 0u);
  // Noise-free: the smoothed trajectory recovers the truth below 1 mm everywhere
  // (the filtered estimate needs the geometry change first).
  double worst = 0.0;
  for (const auto& s : smoother.smoothedTrajectory()) worst = std::max(worst, (s.state.position_ecef_m - sim.position).norm());
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT((results.back().solution->state.position_ecef_m - sim.position).norm(), 1e-3);
}

TEST(PppSmoother, FixedLagBoundsTheGraphAndKeepsTheFilteredSolution) {
  Simulator sim_a, sim_b;
  sim_a.noise = sim_b.noise = true;
  PppSmootherOptions lagged;
  lagged.exact_range = false;
  lagged.fixed_lag_s = 300.0;
  PppSmootherOptions full;
  full.exact_range = false;
  PppSmoother a(methodTableStochasticModel(), lagged), b(methodTableStochasticModel(), full);
  ReceiverState about;
  about.position_ecef_m = sim_a.position;
  about.zwd_m = 0.1;
  const SimModelOptions linear{false, true, about};
  const auto ra = runSmoother(a, sim_a, 80, linear);
  const auto rb = runSmoother(b, sim_b, 80, linear);
  double worst = 0.0;
  std::size_t marginalized = 0;
  for (std::size_t i = 0; i < ra.size(); ++i) {
    worst = std::max(worst, (ra[i].solution->state.position_ecef_m - rb[i].solution->state.position_ecef_m).norm());
    marginalized += ra[i].smoother->variables_marginalized;
  }
  // Marginalization is exact on a linear graph: the filtered solutions agree.
  EXPECT_LT(worst, 1e-6);
  EXPECT_GT(marginalized, 0u);
  std::size_t states_in_graph = 0;
  for (const auto& [key, value] : a.isam2().linearizationPoint())
    if (sm::keySymbol(key) == 'x') ++states_in_graph;
  EXPECT_LE(states_in_graph, 13u);  // lag 300 s = 10 epochs, buckets of a tenth of the lag
  EXPECT_EQ(a.smoothedTrajectory().size(), 80u);  // marginalized states keep their last estimate
}

TEST(PppSmoother, PrefitScreeningRejectsACodeOutlierAndAPhaseJumpWithReasons) {
  Simulator sim;
  PppSmoother smoother(methodTableStochasticModel());
  runSmoother(smoother, sim, 10);
  sim.t_s += 30.0;
  auto obs = sim.epoch();
  obs[1].code_m += 50.0;
  obs[2].phase_m += 20.0;  // an undetected slip (same arc), as in the EKF test
  const auto r = smoother.processEpoch(sim.time(), modelOf(obs, {true}));
  ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
  EXPECT_EQ(r.prefit_rejections, 2);
  ASSERT_EQ(r.rejected.size(), 2u);
  EXPECT_EQ(r.rejected[0].satellite, obs[1].sat);
  EXPECT_NE(r.rejected[0].detail.find("prefit code residual"), std::string::npos) << r.rejected[0].detail;
  EXPECT_EQ(r.rejected[1].satellite, obs[2].sat);
  EXPECT_NE(r.rejected[1].detail.find("phase-minus-code"), std::string::npos) << r.rejected[1].detail;
  EXPECT_LT((r.solution->state.position_ecef_m - sim.position).norm(), 0.05);
}

// As the EKF's test (test_ppp_ekf.cpp): on a new arc the phase-minus-code prefit
// test cannot see a moderate code outlier; the smoother's postfit check (it
// had none before) rejects it with the reason and removes its factors from the graph.
TEST(PppSmoother, PostfitCheckRemovesAModerateCodeOutlierOnANewArcFromTheGraph) {
  for (const bool check : {true, false}) {
    Simulator sim;
    PppSmootherOptions options;
    options.screening.postfit_check = check;
    PppSmoother smoother(methodTableStochasticModel(), options);
    runSmoother(smoother, sim, 10);
    auto obs0 = sim.epoch();
    const SatelliteId sat = obs0[0].sat;
    const ArcId arc = sim.slip(sat, 0.0);
    sim.t_s += 30.0;
    auto obs = sim.epoch();
    const auto it = std::find_if(obs.begin(), obs.end(), [&](const SimObs& o) { return o.sat == sat; });
    ASSERT_NE(it, obs.end());
    it->code_m += 15.0;  // below the 30 m prefit threshold, but > 10 sigma
    const auto r = smoother.processEpoch(sim.time(), modelOf(obs, {true}));
    ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
    EXPECT_EQ(r.prefit_rejections, 0);
    const std::size_t bias_factors = smoother.isam2().factorsOf(biasKey(sat, arc)).size();
    if (check) {
      EXPECT_EQ(r.postfit_rejections, 1);
      ASSERT_EQ(r.rejected.size(), 1u);
      EXPECT_EQ(r.rejected[0].satellite, sat);
      EXPECT_EQ(r.rejected[0].reason, RejectionReason::PostfitCode);
      EXPECT_NE(r.rejected[0].detail.find("postfit code residual"), std::string::npos) << r.rejected[0].detail;
      EXPECT_EQ(r.used.size(), obs.size() - 1);
      EXPECT_EQ(bias_factors, 1u);  // only its prior: the code and phase factors were removed
      const auto active = smoother.activeArcs();
      EXPECT_EQ(std::count(active.begin(), active.end(), arc), 0);  // the new arc did not become active
      EXPECT_LT((r.solution->state.position_ecef_m - sim.position).norm(), 1e-3);
      EXPECT_EQ(r.integrity, SolutionIntegrity::Consistent) << r.consistency;
      // The next epoch goes on, the satellite's arc starting afresh.
      sim.t_s += 30.0;
      const auto next = smoother.processEpoch(sim.time(), modelOf(sim.epoch(), {true}));
      ASSERT_EQ(next.status, EpochStatus::Ok) << next.reason;
      EXPECT_EQ(next.used.size(), obs.size());
      EXPECT_LT((next.solution->state.position_ecef_m - sim.position).norm(), 1e-3);
    } else {
      EXPECT_EQ(r.postfit_rejections, 0);
      EXPECT_EQ(bias_factors, 2u);  // prior and phase factor
      const auto res = std::find_if(r.residuals.begin(), r.residuals.end(),
                                    [&](const MeasurementResidual& m) { return m.satellite == sat; });
      ASSERT_NE(res, r.residuals.end());
      EXPECT_GT(std::abs(res->code_postfit_m), 5.0 * res->code_sigma_m);  // what the check would have caught
    }
  }
}

// The epoch consistency test (postfit_screening.h), same code in both estimators:
// a code error spread over every satellite that no single postfit residual shows
// above 5 sigma still makes the weighted postfit sum of squares contradict the
// covariance; the solution is flagged, its covariance inflated by T / m, or
// withheld.
TEST(PppSmoother, AnInconsistentEpochIsFlaggedAndInflatedOrWithheldInBothEstimators) {
  for (const ConsistencyAction action : {ConsistencyAction::Inflate, ConsistencyAction::Withhold}) {
    Simulator sim;
    ScreeningOptions screening;
    screening.postfit_check = false;
    screening.consistency_action = action;
    PppSmootherOptions options;
    options.screening = screening;
    EkfOptions ekf_options;
    ekf_options.screening = screening;
    PppSmoother smoother(methodTableStochasticModel(), options);
    PppEkf ekf(methodTableStochasticModel(), ekf_options);
    for (int i = 0; i < 10; ++i) {
      if (i > 0) sim.t_s += 30.0;
      const auto obs = sim.epoch();
      for (PppEstimator* e : {static_cast<PppEstimator*>(&smoother), static_cast<PppEstimator*>(&ekf)}) {
        const auto r = e->processEpoch(sim.time(), modelOf(obs, {true}));
        ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
        EXPECT_EQ(r.integrity, SolutionIntegrity::Consistent) << r.consistency;  // noise-free: T = 0
      }
    }
    sim.t_s += 30.0;
    auto obs = sim.epoch();
    // Code errors of alternating sign, 4.5 code sigmas each (phase errors would go
    // into the arcs' biases): the fit of position, clock and ZWD takes up only part
    // of them, and their postfit sum of squares exceeds the quantile.
    for (std::size_t k = 0; k < obs.size(); ++k) obs[k].code_m += (k % 2 ? 4.5 : -4.5) * obs[k].code_sigma_m;
    for (PppEstimator* e : {static_cast<PppEstimator*>(&smoother), static_cast<PppEstimator*>(&ekf)}) {
      const auto r = e->processEpoch(sim.time(), modelOf(obs, {true}));
      EXPECT_EQ(r.integrity, SolutionIntegrity::Inconsistent) << r.consistency;
      EXPECT_GT(r.consistency_statistic, chiSquareUpperQuantile(r.consistency_dof, 1e-6)) << r.consistency;
      EXPECT_NE(r.consistency.find("postfit chi-square"), std::string::npos) << r.consistency;
      if (action == ConsistencyAction::Inflate) {
        ASSERT_EQ(r.status, EpochStatus::Ok) << r.reason;
        EXPECT_GT(r.consistency_variance_factor, 1.0);
      } else {
        EXPECT_EQ(r.status, EpochStatus::NoSolution);
        EXPECT_EQ(r.no_solution_reason, NoSolutionReason::InconsistentSolution);
        EXPECT_FALSE(r.solution.has_value());
        EXPECT_NE(r.reason.find("withheld"), std::string::npos) << r.reason;
      }
    }
  }
}

TEST(PppSmoother, HuberKernelLimitsAModerateOutlier) {
  // A 20 m code error (below the 30 m prefit threshold) on one satellite for the
  // whole run: the Huber kernel down-weights it.
  std::map<bool, double> error;
  for (bool robust : {false, true}) {
    Simulator sim;
    PppSmootherOptions options;
    options.robust = robust;
    options.screening.postfit_check = false;  // the kernel alone (the postfit test would remove it)
    PppSmoother smoother(methodTableStochasticModel(), options);
    SatelliteId bad;
    for (int i = 0; i < 20; ++i) {
      if (i > 0) sim.t_s += 30.0;
      auto obs = sim.epoch();
      if (i == 0) bad = obs[2].sat;
      for (auto& o : obs)
        if (o.sat == bad) o.code_m += 20.0;
      const auto r = smoother.processEpoch(sim.time(), modelOf(obs, {true}));
      ASSERT_EQ(r.status, EpochStatus::Ok);
      error[robust] = (r.solution->state.position_ecef_m - sim.position).norm();
    }
  }
  // Measured 0.80 m against 1.01 m after 20 epochs (the weight is set at each
  // linearization point, which the outlier has already pulled).
  EXPECT_LT(error[true], 0.9 * error[false]) << error[true] << " vs " << error[false];
}

TEST(PppSmoother, InvalidOptionsThrowAndTimeBackwardsFails) {
  PppSmootherOptions bad;
  bad.relinearize_position_m = 0.0;
  EXPECT_THROW(PppSmoother(methodTableStochasticModel(), bad), std::invalid_argument);
  Simulator sim;
  PppSmoother smoother(methodTableStochasticModel());
  runSmoother(smoother, sim, 3);
  sim.t_s -= 30.0;
  const auto r = smoother.processEpoch(sim.time(), modelOf(sim.epoch(), {true}));
  EXPECT_EQ(r.status, EpochStatus::Failed);
  EXPECT_NE(r.reason.find("not after the last solved epoch"), std::string::npos);
  EXPECT_EQ(smoother.smoothedTrajectory().size(), 3u);
}

TEST(PppSmoother, ConfigSectionBindsTheOptionsAndSharesTheScreening) {
  // Values written in the YAML text below.
  const PppConfig c = parsePppConfig(
      "estimator:\n  min_satellites: 6\n  prefit_phase_sigmas: 4.0\n"
      "smoother:\n  robust: true\n  relinearize_position_m: 0.02\n  relinearize_clock_m: 2.5\n  fixed_lag_s: 600\n",
      "inline");
  EXPECT_TRUE(c.smoother.robust);
  EXPECT_DOUBLE_EQ(c.smoother.relinearize_position_m, 0.02);
  EXPECT_DOUBLE_EQ(c.smoother.relinearize_clock_m, 2.5);
  EXPECT_DOUBLE_EQ(c.smoother.relinearize_zwd_m, 0.001);  // default kept
  EXPECT_DOUBLE_EQ(c.smoother.fixed_lag_s, 600.0);
  EXPECT_EQ(c.smoother.screening.min_satellites, 6);                // from `estimator`
  EXPECT_DOUBLE_EQ(c.smoother.screening.prefit_phase_sigmas, 4.0);
  try {
    parsePppConfig("smoother:\n  relinearize_bias: 0.01\n", "inline");
    FAIL() << "unknown key accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.keyPath(), "smoother.relinearize_bias");
  }
  EXPECT_THROW(parsePppConfig("smoother:\n  relinearize_zwd_m: 0\n", "inline"), ConfigError);
  // The template parses (every key documented there).
  EXPECT_NO_THROW(loadPppConfig(std::string(PPP_REPO_DIR) + "/config/ppp.yaml"));
}

TEST(PppSmoother, PerComponentRelinearizationThresholds) {
  // The thresholds the smoother gives iSAM2: position 1 cm, ZWD 1 mm, clock 1 m, bias 1 cm.
  const PppSmoother smoother(methodTableStochasticModel());
  const sm::ISAM2Params& p = smoother.isam2().params();
  Eigen::VectorXd d = Eigen::VectorXd::Zero(5);
  d(4) = 0.9;  // clock moved 0.9 m: below 1 m
  d(0) = 0.009;
  EXPECT_FALSE(p.exceedsThreshold(stateKey(3), d));
  d(3) = 0.0011;  // ZWD moved 1.1 mm
  EXPECT_TRUE(p.exceedsThreshold(stateKey(3), d));
  d.setZero();
  d(4) = 1.1;
  EXPECT_TRUE(p.exceedsThreshold(stateKey(3), d));
  const SatelliteId g05{GnssSystem::GPS, 5};
  EXPECT_FALSE(p.exceedsThreshold(biasKey(g05, 1), Eigen::VectorXd::Constant(1, 0.009)));
  EXPECT_TRUE(p.exceedsThreshold(biasKey(g05, 1), Eigen::VectorXd::Constant(1, -0.011)));
}

TEST(PppSmoother, SmoothedEpochAtIsOneStateOfTheTrajectoryAndStopsAtTheLagBoundary) {
  Simulator sim;
  sim.noise = true;
  PppSmoother full(methodTableStochasticModel());
  const auto results = runSmoother(full, sim, 40);
  const auto trajectory = full.smoothedTrajectory(true);
  EXPECT_FALSE(full.smoothedEpochAt(results.front().time - 1.0).has_value());  // before the first state
  // The newest state: the filtered one (same information), covariance included.
  const auto newest = full.smoothedEpochAt(results.back().time, true);
  ASSERT_TRUE(newest && newest->covariance);
  EXPECT_EQ(newest->index, trajectory.back().index);
  EXPECT_LT((newest->state.vector() - results.back().solution->state.vector()).norm(), 1e-9);
  EXPECT_LT((*newest->covariance - results.back().solution->covariance).norm(),
            1e-6 * results.back().solution->covariance.norm());
  // Between epochs 20 and 21 (30 s apart): epoch 20, as the whole-trajectory read gives it.
  const auto mid = full.smoothedEpochAt(results[20].time + 10.0, true);
  ASSERT_TRUE(mid && mid->covariance);
  EXPECT_EQ(mid->time, results[20].time);
  EXPECT_EQ(mid->index, trajectory[20].index);
  EXPECT_LT((mid->state.vector() - trajectory[20].state.vector()).norm(), 1e-12);
  EXPECT_LT((*mid->covariance - *trajectory[20].covariance).norm(), 1e-9 * trajectory[20].covariance->norm());

  // Fixed lag 300 s (10 epochs): an epoch inside the window is itself; an older one
  // gives the oldest state still in the window (the lag boundary), with a covariance.
  Simulator sim_lag;
  sim_lag.noise = true;
  PppSmootherOptions lagged;
  lagged.fixed_lag_s = 300.0;
  PppSmoother lag(methodTableStochasticModel(), lagged);
  const auto r = runSmoother(lag, sim_lag, 60);
  const auto lag_trajectory = lag.smoothedTrajectory();
  const auto at_lag = lag.smoothedEpochAt(r.back().time - 300.0, true);
  ASSERT_TRUE(at_lag && at_lag->covariance);
  EXPECT_EQ(at_lag->time, r.back().time - 300.0);
  const auto boundary = lag.smoothedEpochAt(r.front().time, true);
  ASSERT_TRUE(boundary && boundary->covariance) << "the oldest state in the window has a marginal";
  EXPECT_GT(boundary->index, 40u);
  EXPECT_LE(boundary->index, at_lag->index);
  EXPECT_TRUE(lag.isam2().exists(stateKey(boundary->index)));
  EXPECT_FALSE(lag.isam2().exists(stateKey(boundary->index - 1)));
  EXPECT_LT((boundary->state.vector() - lag_trajectory[boundary->index].state.vector()).norm(), 1e-12);
}

// Horizontal tropospheric gradients (Chen & Herring 1997): the synthetic data carry
// G_N = 2 mm, G_E = -1 mm (m_g(10 deg) = 29.6: up to 6 cm of slant delay at the
// 10 deg cutoff), constant, noise-free, over 2 hours of the kinematic model. With the
// gradient block in the state (a loose 1 cm prior and a slow 1e-6 m/sqrt(s) random
// walk, so that neither pulls the constant truth), both estimators recover the
// gradients and the position; without it the unmodelled azimuthal delay leaks
// into the position.
TEST(TroposphereGradients, BothEstimatorsRecoverASimulatedGradient) {
  StochasticModel model = methodTableStochasticModel();
  model.troposphere_gradient.initial_sigma_m = 0.01;
  model.troposphere_gradient.process_noise_m_per_sqrt_s = 1.0e-6;
  const int epochs = 240;
  auto simulator = [] {
    Simulator sim;
    sim.gradient_north_m = 0.002;
    sim.gradient_east_m = -0.001;
    return sim;
  };
  auto lastError = [](const std::vector<EstimatorEpochResult>& results, const Simulator& sim) {
    return (results.back().solution->state.position_ecef_m - sim.position).norm();
  };
  const ReceiverStateLayout with({GnssSystem::GPS}, true);
  const ReceiverStateLayout without({GnssSystem::GPS});

  Simulator sim = simulator();
  PppEkf ekf(model, {}, {}, with);
  const auto ekf_results = runEpochs(ekf, sim, epochs, 30.0, {true});
  const ReceiverState ekf_state = ekf_results.back().solution->state;
  const double ekf_error = lastError(ekf_results, sim);

  sim = simulator();
  PppSmoother smoother(model, {}, {}, with);
  const auto smoother_results = runEpochs(smoother, sim, epochs, 30.0, {true});
  const ReceiverState filtered = smoother_results.back().solution->state;
  const auto smoothed = smoother.smoothedTrajectory();
  ASSERT_EQ(smoothed.size(), static_cast<std::size_t>(epochs));
  const double smoother_error = lastError(smoother_results, sim);

  sim = simulator();
  PppEkf blind(model, {}, {}, without);
  const double blind_error = lastError(runEpochs(blind, sim, epochs, 30.0, {true}), sim);

  std::printf("G_N / G_E [mm]: EKF %.3f / %.3f, smoother filtered %.3f / %.3f, smoothed first %.3f / %.3f; "
              "position error EKF %.2f mm, smoother %.2f mm, without gradients %.2f mm\n",
              ekf_state.gradient_north_m * 1e3, ekf_state.gradient_east_m * 1e3, filtered.gradient_north_m * 1e3,
              filtered.gradient_east_m * 1e3, smoothed.front().state.gradient_north_m * 1e3,
              smoothed.front().state.gradient_east_m * 1e3, ekf_error * 1e3, smoother_error * 1e3, blind_error * 1e3);
  // Measured: 1.998 / -0.999 mm in all three, 0.03 mm position error, 31 mm without gradients.
  for (const ReceiverState* s : {&ekf_state, &filtered, &smoothed.front().state}) {
    EXPECT_NEAR(s->gradient_north_m, 0.002, 2e-5);
    EXPECT_NEAR(s->gradient_east_m, -0.001, 2e-5);
  }
  EXPECT_LT(ekf_error, 5e-4);
  EXPECT_LT(smoother_error, 5e-4);
  EXPECT_GT(blind_error, 0.01);
  // The filtered smoother equals the EKF on the same data.
  EXPECT_NEAR(filtered.gradient_north_m, ekf_state.gradient_north_m, 1e-5);
  EXPECT_NEAR(filtered.gradient_east_m, ekf_state.gradient_east_m, 1e-5);
}
