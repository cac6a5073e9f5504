// The smoother's IMU factors: analytic Jacobians against central differences on the
// manifold (NavState retraction), a static IMU chain (readings at rest with a grade's
// white noise, no GNSS) whose smoothed position stays within its propagated noise, and
// iSAM2 one epoch at a time equal to the batch solver on that chain.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "ppp_bayes_tree/navigation/imu_smoother_factor.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/smoother/batch_solver.h"
#include "ppp_bayes_tree/smoother/isam2.h"
#include "ppp_bayes_tree/smoother/numerical_jacobian.h"
#include "ppp_bayes_tree/smoother/prior_factor.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp {
namespace {

using smoother::Key;
using smoother::symbolKey;

/// At rest in ECEF (Boulder, levelled, heading ~40 deg): the IMU senses -g and the Earth's rate.
struct StaticSite {
  NavState state;
  NavigationFrame frame;
  Eigen::Vector3d specific_force_mps2, angular_rate_radps;
};

StaticSite staticSite() {
  StaticSite s;
  const Geodetic site{40.0967 * kDegToRad, -105.1472 * kDegToRad, 1601.4};
  s.state.position_world_m = geodeticToEcef(site);
  s.state.rotation_world_body = rotationEnuFromEcef(site.latitude_rad, site.longitude_rad).transpose() *
                                so3::expMap(Eigen::Vector3d(0.02, -0.01, 0.7));
  s.frame = ecefNavigationFrame(s.state.position_world_m);
  const Eigen::Matrix3d rt = s.state.rotation_world_body.transpose();
  s.specific_force_mps2 = -rt * s.frame.gravity_world_mps2;
  s.angular_rate_radps = rt * s.frame.earth_rate_world_radps;
  return s;
}

/// One second of readings at 100 Hz with the noise's white noise (rng null: noise-free),
/// or a motion (constant body rate and force offset) for the Jacobian checks.
ImuPreintegration preintegrate(const StaticSite& s, const ImuNoise& noise, std::mt19937* rng,
                               const Eigen::Vector3d& extra_rate = Eigen::Vector3d::Zero(),
                               const Eigen::Vector3d& extra_force = Eigen::Vector3d::Zero()) {
  ImuPreintegration pim(noise, ImuBias{});
  const double dt = 0.01;
  std::normal_distribution<double> normal;
  for (int k = 0; k < 100; ++k) {
    Eigen::Vector3d f = s.specific_force_mps2 + extra_force, w = s.angular_rate_radps + extra_rate;
    for (int i = 0; rng && i < 3; ++i) {
      f[i] += normal(*rng) * noise.accel_noise_density_mps2_per_sqrthz / std::sqrt(dt);
      w[i] += normal(*rng) * noise.gyro_noise_density_radps_per_sqrthz / std::sqrt(dt);
    }
    pim.integrate(f, w, dt);
  }
  return pim;
}

void expectJacobiansMatch(const NavigationFrame& frame, const NavState& si, double step, double tolerance) {
  const ImuNoise noise = imuNoisePreset(ImuGrade::IndustrialMems);
  StaticSite s = staticSite();
  s.frame = frame;
  const ImuPreintegration pim = preintegrate(s, noise, nullptr, Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(1, 2, -1));
  NavState sj = predictNavState(pim, si, ImuBias{}, frame);
  sj = sj.retract((Eigen::Matrix<double, 9, 1>() << 0.02, -0.01, 0.03, 0.1, 0.2, -0.1, 0.5, -0.3, 0.2).finished());
  smoother::Values x;
  insertNavState(x, symbolKey('x', 0), si);
  insertNavState(x, symbolKey('x', 1), sj);
  x.insert(symbolKey('b', 0), (Eigen::Matrix<double, 6, 1>() << 0.01, -0.02, 0.03, 2e-3, 1e-3, -3e-3).finished());
  const ImuSmootherFactor f(symbolKey('x', 0), symbolKey('b', 0), symbolKey('x', 1), pim, frame);
  ASSERT_GT(f.unwhitenedError(x, nullptr).norm(), 1e-3);
  const smoother::JacobianCheck c = smoother::checkJacobians(f, x, tolerance, step);
  EXPECT_TRUE(c.ok) << c.report;
}

TEST(ImuSmootherFactor, JacobiansMatchCentralDifferencesOnTheManifoldInALocalLevelFrame) {
  NavState si;
  si.rotation_world_body = so3::expMap(Eigen::Vector3d(0.3, -0.5, 1.1));
  si.velocity_world_mps = Eigen::Vector3d(3, -2, 1);
  si.position_world_m = Eigen::Vector3d(10, -20, 5);
  expectJacobiansMatch(localLevelNavigationFrame(9.80), si, 1e-6, 1e-6);
}

TEST(ImuSmootherFactor, JacobiansMatchCentralDifferencesOnTheManifoldInEcef) {
  StaticSite s = staticSite();
  s.state.velocity_world_mps = Eigen::Vector3d(3, -2, 1);
  // ECEF coordinates of 6e6 m: a step of 1e-4 keeps the round-off of the differences
  // (1e-16 * 6e6 / 1e-4 ~ 6e-6) below the tolerance.
  expectJacobiansMatch(s.frame, s.state, 1e-4, 2e-5);
}

TEST(ImuSmootherFactor, BiasRandomWalkFactorJacobiansAndRejections) {
  const ImuNoise noise = imuNoisePreset(ImuGrade::IndustrialMems);
  const BiasRandomWalkFactor f(symbolKey('b', 0), symbolKey('b', 1), noise, 1.0);
  smoother::Values x;
  x.insert(symbolKey('b', 0), smoother::Vector::Constant(6, 0.1));
  x.insert(symbolKey('b', 1), smoother::Vector::Constant(6, -0.3));
  const smoother::JacobianCheck c = smoother::checkJacobians(f, x);
  EXPECT_TRUE(c.ok) << c.report;
  EXPECT_THROW(BiasRandomWalkFactor(symbolKey('b', 0), symbolKey('b', 1), noise, 0.0), std::invalid_argument);
  EXPECT_THROW(BiasRandomWalkFactor(symbolKey('b', 0), symbolKey('b', 1), ImuNoise{}, 1.0), std::invalid_argument);
  const ImuPreintegration empty(noise, ImuBias{});
  EXPECT_THROW(ImuSmootherFactor(symbolKey('x', 0), symbolKey('b', 0), symbolKey('x', 1), empty, staticSite().frame),
               std::invalid_argument);
}

/// The chain: a prior on the first state and bias, then per second an IMU factor and a
/// bias random-walk factor; every state starts at the truth moved by 0.5 m / 0.01 rad.
struct StaticChain {
  smoother::NonlinearFactorGraph graph;
  smoother::Values initial;
};

void addEpoch(StaticChain& chain, const StaticSite& s, const ImuNoise& noise, int k, std::mt19937& rng,
              smoother::NonlinearFactorGraph& f, smoother::Values& v) {
  const Eigen::Matrix<double, 9, 1> off =
      (Eigen::Matrix<double, 9, 1>() << 0.01, -0.01, 0.01, 0.1, -0.1, 0.1, 0.5, -0.5, 0.5).finished();
  insertNavState(v, symbolKey('x', k), s.state.retract(off));
  v.insert(symbolKey('b', k), smoother::Vector::Zero(6));
  if (k == 0) {
    Eigen::Matrix<double, 9, 1> sig;
    sig << 0.001, 0.001, 0.001, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01;
    f.push_back(std::make_shared<NavStatePriorFactor>(symbolKey('x', 0), s.state, smoother::NoiseModel::sigmas(sig)));
    Eigen::Matrix<double, 6, 1> bsig;
    bsig << smoother::Vector::Constant(3, noise.accel_bias_instability_mps2),
        smoother::Vector::Constant(3, noise.gyro_bias_instability_radps);
    f.push_back(std::make_shared<smoother::PriorFactor>(symbolKey('b', 0), smoother::Vector::Zero(6),
                                                        smoother::NoiseModel::sigmas(bsig)));
  } else {
    f.push_back(std::make_shared<ImuSmootherFactor>(symbolKey('x', k - 1), symbolKey('b', k - 1), symbolKey('x', k),
                                                    preintegrate(s, noise, &rng), s.frame));
    f.push_back(std::make_shared<BiasRandomWalkFactor>(symbolKey('b', k - 1), symbolKey('b', k), noise, 1.0));
  }
  chain.graph.insert(chain.graph.end(), f.begin(), f.end());
  for (Key key : v.keys()) chain.initial.insertFrom(v, key);
}

TEST(ImuSmootherFactor, StaticChainStaysWithinItsNoiseAndIncrementalEqualsBatch) {
  const StaticSite s = staticSite();
  const ImuNoise noise = imuNoisePreset(ImuGrade::IndustrialMems);
  std::mt19937 rng(5);
  smoother::ISAM2Params p;
  p.relinearize_threshold = 1e-5;
  p.relinearize_skip = 1;
  smoother::ISAM2 isam(p);
  StaticChain chain;
  const int n = 61;  // 60 s
  for (int k = 0; k < n; ++k) {
    smoother::NonlinearFactorGraph f;
    smoother::Values v;
    addEpoch(chain, s, noise, k, rng, f, v);
    isam.update(f, v);
  }
  for (int i = 0; i < 5; ++i) isam.update();
  // ECEF coordinates of 6e6 m: Gauss-Newton stops at round-off, above the default 1e-12.
  smoother::BatchParams bp;
  bp.absolute_delta_tolerance = 1e-9;
  bp.relative_error_tolerance = 1e-10;
  const smoother::BatchResult batch = smoother::optimizeBatch(chain.graph, chain.initial, bp);
  ASSERT_TRUE(batch.converged);
  const smoother::Values inc = isam.calculateBestEstimate();
  double worst = 0.0;
  for (int k = 0; k < n; ++k) {
    const Key key = symbolKey('x', k);
    worst = std::max(worst, navStateAt(inc, key).localCoordinates(navStateAt(batch.values, key)).norm());
  }
  EXPECT_LT(worst, 1e-6);
  // The last state: its position error within 3 sigma of its marginal covariance
  // (the drift the grade's white noise allows over 60 s), per axis.
  const Key last = symbolKey('x', n - 1);
  const Eigen::Vector3d err = navStateAt(inc, last).position_world_m - s.state.position_world_m;
  const smoother::Matrix cov = isam.marginalCovariance(last);
  const Eigen::Vector3d sigma = cov.diagonal().tail<3>().cwiseSqrt();
  std::printf("static 60 s industrial MEMS: last position error %.3f m, 1-sigma %.3f %.3f %.3f m\n", err.norm(),
              sigma[0], sigma[1], sigma[2]);
  for (int i = 0; i < 3; ++i) EXPECT_LT(std::abs(err[i]), 3.0 * sigma[i]) << "axis " << i;
  // What the priors and the grade allow over T = 60 s: tilt 1 mrad -> g tilt T^2 / 2 =
  // 17.7 m; gyro bias 2 deg/h -> g bg T^3 / 6 = 3.4 m; accel bias 3.6 ug -> 0.06 m; white
  // noise well below 1 m. The smoother's sigma is no larger than their sum.
  const double t = 60.0, g = 9.80;
  const double bound = 0.5 * g * 0.001 * t * t + g * noise.gyro_bias_instability_radps * t * t * t / 6.0 +
                       0.5 * noise.accel_bias_instability_mps2 * t * t + 1.0;
  EXPECT_LT(sigma.maxCoeff(), bound);
}

}  // namespace
}  // namespace ppp
