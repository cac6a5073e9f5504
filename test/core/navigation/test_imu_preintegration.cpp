// IMU preintegration and the IMU factor: against fine numerical integration,
// numerical Jacobians, re-integration with a new bias, a Monte Carlo of noisy
// readings, and a static IMU on the rotating Earth.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <random>

#include "ppp_bayes_tree/navigation/imu_factor.h"
#include "ppp_bayes_tree/navigation/imu_preintegration.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp {
namespace {

// ---- A known motion: a coning body rate and a sinusoidal specific force -------------

Eigen::Vector3d bodyRate_radps(double t) {
  // Coning: a rate of 0.3 rad/s turning at 2 rad/s about z, plus a spin of 0.2 rad/s.
  return Eigen::Vector3d(0.3 * std::cos(2.0 * t), 0.3 * std::sin(2.0 * t), 0.2);
}

Eigen::Vector3d specificForce_mps2(double t) {
  return Eigen::Vector3d(2.0 * std::sin(1.3 * t), 1.5 * std::cos(0.7 * t), 9.8 + 0.5 * std::sin(2.0 * t));
}

/// Reference deltas: RK4 of dR/dt = R [w]x, dv/dt = R f, dp/dt = v with `substeps`
/// steps per reading interval.
PreintegratedDeltas rk4Deltas(double duration_s, double step_s) {
  struct State {
    Eigen::Matrix3d r;
    Eigen::Vector3d v, p;
  };
  auto derivative = [](const State& s, double t) {
    return State{s.r * so3::hat(bodyRate_radps(t)), s.r * specificForce_mps2(t), s.v};
  };
  auto add = [](const State& s, const State& d, double h) { return State{s.r + h * d.r, s.v + h * d.v, s.p + h * d.p}; };
  State s{Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  const int n = static_cast<int>(std::lround(duration_s / step_s));
  for (int k = 0; k < n; ++k) {
    const double t = k * step_s;
    const State k1 = derivative(s, t);
    const State k2 = derivative(add(s, k1, step_s / 2), t + step_s / 2);
    const State k3 = derivative(add(s, k2, step_s / 2), t + step_s / 2);
    const State k4 = derivative(add(s, k3, step_s), t + step_s);
    s = State{s.r + step_s / 6 * (k1.r + 2 * k2.r + 2 * k3.r + k4.r), s.v + step_s / 6 * (k1.v + 2 * k2.v + 2 * k3.v + k4.v),
              s.p + step_s / 6 * (k1.p + 2 * k2.p + 2 * k3.p + k4.p)};
    s.r = so3::normalized(s.r);
  }
  return PreintegratedDeltas{s.r, s.v, s.p};
}

/// Readings at `rate_hz`, each the value at the middle of its interval (what an
/// IMU that averages over its output interval reports, to second order).
ImuPreintegration preintegrateMotion(double duration_s, double rate_hz, const ImuNoise& noise,
                                     const ImuBias& bias_estimate = {}, const ImuBias& true_bias = {},
                                     std::mt19937* rng = nullptr) {
  ImuPreintegration pim(noise, bias_estimate);
  const double dt = 1.0 / rate_hz;
  const int n = static_cast<int>(std::lround(duration_s * rate_hz));
  std::normal_distribution<double> normal;
  for (int k = 0; k < n; ++k) {
    const double t = (k + 0.5) * dt;
    Eigen::Vector3d f = specificForce_mps2(t) + true_bias.accel_mps2;
    Eigen::Vector3d w = bodyRate_radps(t) + true_bias.gyro_radps;
    if (rng) {
      for (int i = 0; i < 3; ++i) {
        f[i] += normal(*rng) * noise.accel_noise_density_mps2_per_sqrthz / std::sqrt(dt);
        w[i] += normal(*rng) * noise.gyro_noise_density_radps_per_sqrthz / std::sqrt(dt);
      }
    }
    pim.integrate(f, w, dt);
  }
  return pim;
}

struct DeltaErrors {
  double rotation_rad, velocity_mps, position_m;
};

DeltaErrors deltaErrors(const PreintegratedDeltas& a, const PreintegratedDeltas& b) {
  return {so3::logMap(a.rotation.transpose() * b.rotation).norm(), (a.velocity_mps - b.velocity_mps).norm(),
          (a.position_m - b.position_m).norm()};
}

TEST(ImuPreintegration, MatchesRk4OfAConingMotionToSecondOrder) {
  // Each reading is applied at its interval's mid attitude dR_k Exp(phi/2), so
  // the velocity and position sums are second order in dt, as the rotation
  // product with mid-interval rates. Holding the axes at the interval's start
  // would leave the first-order error dt/2 * T * |w| |f| = 9.3 mm/s in dv (seen:
  // 5.2 mm/s, halving at 400 Hz). Seen now: 1.2e-5 m/s and 1.4e-5 m at 200 Hz,
  // a quarter of that at 400 Hz; bounds 2e-5.
  const double duration_s = 1.0;
  const PreintegratedDeltas reference = rk4Deltas(duration_s, 1.0 / 2000.0);  // RK4 at 10x the 200 Hz rate
  const ImuNoise quiet;
  const DeltaErrors e200 = deltaErrors(preintegrateMotion(duration_s, 200.0, quiet).deltas(), reference);
  const DeltaErrors e400 = deltaErrors(preintegrateMotion(duration_s, 400.0, quiet).deltas(), reference);
  const double w_max = std::hypot(0.3, 0.2), f_max = std::hypot(std::hypot(2.0, 1.5), 10.3);
  const double first_order_velocity_mps = 0.5 / 200.0 * duration_s * w_max * f_max;  // 9.3 mm/s
  EXPECT_LT(e200.rotation_rad, 1e-5);
  EXPECT_LT(e200.velocity_mps, 2e-5);
  EXPECT_LT(e200.position_m, 2e-5);
  EXPECT_LT(e200.velocity_mps, 1e-2 * first_order_velocity_mps);
  // Second order: halving the step quarters the errors.
  EXPECT_LT(e400.velocity_mps, 0.3 * e200.velocity_mps);
  EXPECT_LT(e400.position_m, 0.3 * e200.position_m);
  EXPECT_LT(e400.rotation_rad, 0.3 * e200.rotation_rad);
  std::printf("RK4 agreement at 200 Hz over 1 s: rotation %.2e rad, velocity %.2e m/s, position %.2e m\n",
              e200.rotation_rad, e200.velocity_mps, e200.position_m);
  std::printf("RK4 agreement at 400 Hz over 1 s: rotation %.2e rad, velocity %.2e m/s, position %.2e m\n",
              e400.rotation_rad, e400.velocity_mps, e400.position_m);
}

TEST(ImuPreintegration, IntegrateBetweenHoldsEachSampleUntilTheNext) {
  std::vector<ImuSample> samples;
  const GnssTime t0 = GnssTime::fromGpsWeek(2381, 1000.0);
  for (int k = 0; k < 10; ++k) {
    ImuSample s;
    s.time = t0 + 0.1 * k;
    s.specific_force_mps2 = Eigen::Vector3d(k, 0, 0);
    samples.push_back(s);
  }
  ImuPreintegration pim(ImuNoise{}, ImuBias{});
  // [t0 + 0.15, t0 + 0.42]: sample 1 for 0.05 s, 2 and 3 for 0.1 s each, 4 for 0.02 s.
  EXPECT_EQ(pim.integrateBetween(samples, t0 + 0.15, t0 + 0.42), 4u);
  EXPECT_NEAR(pim.deltaTime_s(), 0.27, 1e-9);
  EXPECT_NEAR(pim.deltas().velocity_mps.x(), 1 * 0.05 + 2 * 0.1 + 3 * 0.1 + 4 * 0.02, 1e-9);
  ImuPreintegration early(ImuNoise{}, ImuBias{});
  EXPECT_EQ(early.integrateBetween(samples, t0 - 1.0, t0 + 0.5), 0u);  // nothing covers the start
}

TEST(ImuPreintegration, FirstOrderBiasCorrectionMatchesReintegration) {
  const ImuNoise quiet;
  const ImuPreintegration nominal = preintegrateMotion(1.0, 200.0, quiet);
  auto correctionError = [&](double scale) {
    ImuBias changed;
    changed.accel_mps2 = scale * Eigen::Vector3d(0.02, -0.03, 0.01);
    changed.gyro_radps = scale * Eigen::Vector3d(1e-3, 2e-3, -1.5e-3);
    const ImuPreintegration again = preintegrateMotion(1.0, 200.0, quiet, changed);
    return deltaErrors(nominal.correctedDeltas(changed), again.deltas());
  };
  const DeltaErrors big = correctionError(1.0), small = correctionError(0.5);
  // The bias moves the deltas by ~3 mrad, ~3 cm/s, ~1.5 cm; the first-order update leaves second-order residue.
  EXPECT_LT(big.rotation_rad, 1e-6);
  EXPECT_LT(big.velocity_mps, 1e-4);
  EXPECT_LT(big.position_m, 5e-5);
  EXPECT_NEAR(big.rotation_rad / small.rotation_rad, 4.0, 0.5);  // quadratic in the bias change
  EXPECT_NEAR(big.velocity_mps / small.velocity_mps, 4.0, 0.5);
  EXPECT_NEAR(big.position_m / small.position_m, 4.0, 0.5);
  std::printf("bias update vs re-integration: rotation %.2e rad, velocity %.2e m/s, position %.2e m\n",
              big.rotation_rad, big.velocity_mps, big.position_m);
}

TEST(ImuPreintegration, CovarianceMatchesMonteCarloOfNoisyReadings) {
  const ImuNoise noise = imuNoisePreset(ImuGrade::ConsumerMems);
  const ImuPreintegration clean = preintegrateMotion(1.0, 200.0, noise);
  std::mt19937 rng(7);
  const int runs = 2000;
  Matrix9d sample_cov = Matrix9d::Zero();
  for (int run = 0; run < runs; ++run) {
    const ImuPreintegration noisy = preintegrateMotion(1.0, 200.0, noise, {}, {}, &rng);
    Vector9d e;
    e << so3::logMap(clean.deltas().rotation.transpose() * noisy.deltas().rotation),
        noisy.deltas().velocity_mps - clean.deltas().velocity_mps, noisy.deltas().position_m - clean.deltas().position_m;
    sample_cov += e * e.transpose() / runs;
  }
  std::printf("Monte Carlo / propagated variance (2000 runs):");
  for (int i = 0; i < 9; ++i) {
    const double ratio = sample_cov(i, i) / clean.covariance()(i, i);
    std::printf(" %.3f", ratio);
    EXPECT_NEAR(ratio, 1.0, 0.12) << "component " << i;
  }
  std::printf("\n");
  // The cross terms between velocity and position (strongly correlated) agree too.
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(sample_cov(3 + i, 6 + i) / clean.covariance()(3 + i, 6 + i), 1.0, 0.12);
}

// ---- The factor -------------------------------------------------------------------

NavState exampleState(const Eigen::Vector3d& rotation_vector, const Eigen::Vector3d& v, const Eigen::Vector3d& p) {
  NavState s;
  s.rotation_world_body = so3::expMap(rotation_vector);
  s.velocity_world_mps = v;
  s.position_world_m = p;
  return s;
}

/// Central differences of `f` over the 9 tangent directions of `state`.
Matrix9d numericalStateJacobian(const std::function<Vector9d(const NavState&)>& f, const NavState& state) {
  Matrix9d j;
  for (int k = 0; k < 9; ++k) {
    // The residual is linear in velocity and position: a large step keeps ECEF's
    // 6e6 m coordinates from swamping the difference with round-off.
    const double h = k < 3 ? 1e-6 : 1e-2;
    Vector9d d = Vector9d::Zero();
    d[k] = h;
    j.col(k) = (f(state.retract(d)) - f(state.retract(-d))) / (2 * h);
  }
  return j;
}

Matrix96d numericalBiasJacobian(const std::function<Vector9d(const ImuBias&)>& f, const ImuBias& bias) {
  Matrix96d j;
  for (int k = 0; k < 6; ++k) {
    Vector6d d = Vector6d::Zero();
    d[k] = 1e-6;
    j.col(k) = (f(ImuBias::fromVector(bias.vector() + d)) - f(ImuBias::fromVector(bias.vector() - d))) / 2e-6;
  }
  return j;
}

void expectFactorJacobiansMatchNumerical(const NavigationFrame& frame, const Eigen::Vector3d& position_i) {
  ImuBias estimate;
  estimate.gyro_radps = Eigen::Vector3d(1e-3, -2e-3, 5e-4);
  const ImuPreintegration pim = preintegrateMotion(1.0, 100.0, imuNoisePreset(ImuGrade::IndustrialMems), estimate);
  const NavState si = exampleState(Eigen::Vector3d(0.3, -0.5, 1.1), Eigen::Vector3d(3, -2, 1), position_i);
  NavState sj = predictNavState(pim, si, estimate, frame);
  sj = sj.retract((Vector9d() << 0.02, -0.01, 0.03, 0.1, 0.2, -0.1, 0.5, -0.3, 0.2).finished());  // not at zero
  ImuBias bi = estimate;
  bi.accel_mps2 += Eigen::Vector3d(0.01, -0.02, 0.03);
  bi.gyro_radps += Eigen::Vector3d(2e-3, 1e-3, -3e-3);
  ImuFactorJacobians jac;
  const Vector9d r = imuFactorError(pim, si, bi, sj, frame, &jac);
  ASSERT_GT(r.norm(), 1e-3);
  const Matrix9d num_i = numericalStateJacobian(
      [&](const NavState& s) { return imuFactorError(pim, s, bi, sj, frame); }, si);
  const Matrix9d num_j = numericalStateJacobian(
      [&](const NavState& s) { return imuFactorError(pim, si, bi, s, frame); }, sj);
  const Matrix96d num_b =
      numericalBiasJacobian([&](const ImuBias& b) { return imuFactorError(pim, si, b, sj, frame); }, bi);
  EXPECT_LT((jac.d_state_i - num_i).cwiseAbs().maxCoeff(), 1e-6) << "analytic\n" << jac.d_state_i << "\nnumeric\n" << num_i;
  EXPECT_LT((jac.d_state_j - num_j).cwiseAbs().maxCoeff(), 1e-6) << "analytic\n" << jac.d_state_j << "\nnumeric\n" << num_j;
  EXPECT_LT((jac.d_bias_i - num_b).cwiseAbs().maxCoeff(), 1e-6) << "analytic\n" << jac.d_bias_i << "\nnumeric\n" << num_b;
}

TEST(ImuFactor, JacobiansMatchCentralDifferencesInALocalLevelFrame) {
  expectFactorJacobiansMatchNumerical(localLevelNavigationFrame(9.80), Eigen::Vector3d(10, -20, 5));
}

TEST(ImuFactor, JacobiansMatchCentralDifferencesInEcefWithEarthRotation) {
  const Eigen::Vector3d p = geodeticToEcef(Geodetic{40.0967 * kDegToRad, -105.1472 * kDegToRad, 1601.4});
  expectFactorJacobiansMatchNumerical(ecefNavigationFrame(p), p);
}

TEST(ImuFactor, ResidualIsZeroAtThePredictedState) {
  const Eigen::Vector3d p = geodeticToEcef(Geodetic{40.0967 * kDegToRad, -105.1472 * kDegToRad, 1601.4});
  const NavigationFrame frame = ecefNavigationFrame(p);
  ImuBias bias;
  bias.accel_mps2 = Eigen::Vector3d(0.01, 0.0, -0.02);
  const ImuPreintegration pim = preintegrateMotion(1.0, 100.0, ImuNoise{});
  const NavState si = exampleState(Eigen::Vector3d(0.1, 0.2, -0.3), Eigen::Vector3d(5, 1, 0), p);
  const NavState sj = predictNavState(pim, si, bias, frame);
  EXPECT_LT(imuFactorError(pim, si, bias, sj, frame).norm(), 1e-7);  // round-off of ECEF coordinates
}

TEST(ImuFactor, BiasRandomWalkErrorAndCovariance) {
  ImuBias a, b;
  b.accel_mps2 = Eigen::Vector3d(1, 2, 3);
  b.gyro_radps = Eigen::Vector3d(4, 5, 6);
  EXPECT_EQ(biasRandomWalkError(a, b), b.vector());
  const ImuNoise n = imuNoisePreset(ImuGrade::IndustrialMems);
  const Matrix6d c = biasRandomWalkCovariance(n, 4.0);
  EXPECT_NEAR(c(0, 0), 4.0 * std::pow(n.accel_bias_random_walk_mps3_per_sqrthz, 2), 1e-20);
  EXPECT_NEAR(c(5, 5), 4.0 * std::pow(n.gyro_bias_random_walk_radps2_per_sqrthz, 2), 1e-24);
}

// ---- A static IMU on the rotating Earth --------------------------------------------

struct StaticSetup {
  NavState state;
  NavigationFrame frame;
  Eigen::Vector3d specific_force_mps2, angular_rate_radps;
};

/// At rest in ECEF at the walk's site: the IMU senses -g and the Earth's rate, in its own axes.
StaticSetup staticSetup() {
  StaticSetup s;
  const Geodetic site{40.0967 * kDegToRad, -105.1472 * kDegToRad, 1601.4};
  s.state.position_world_m = geodeticToEcef(site);
  s.state.rotation_world_body = rotationEnuFromEcef(site.latitude_rad, site.longitude_rad).transpose() *
                                so3::expMap(Eigen::Vector3d(0.02, -0.01, 0.7));  // levelled, heading ~40 deg
  s.frame = ecefNavigationFrame(s.state.position_world_m);
  const Eigen::Matrix3d rt = s.state.rotation_world_body.transpose();
  s.specific_force_mps2 = -rt * s.frame.gravity_world_mps2;
  s.angular_rate_radps = rt * s.frame.earth_rate_world_radps;
  return s;
}

ImuPreintegration preintegrateStatic(const StaticSetup& s, const ImuNoise& noise, double duration_s, double rate_hz,
                                     std::mt19937* rng) {
  ImuPreintegration pim(noise, ImuBias{});
  const double dt = 1.0 / rate_hz;
  std::normal_distribution<double> normal;
  for (int k = 0; k < static_cast<int>(std::lround(duration_s * rate_hz)); ++k) {
    Eigen::Vector3d f = s.specific_force_mps2, w = s.angular_rate_radps;
    for (int i = 0; rng && i < 3; ++i) {
      f[i] += normal(*rng) * noise.accel_noise_density_mps2_per_sqrthz / std::sqrt(dt);
      w[i] += normal(*rng) * noise.gyro_noise_density_radps_per_sqrthz / std::sqrt(dt);
    }
    pim.integrate(f, w, dt);
  }
  return pim;
}

TEST(ImuStatic, NoiseFreePredictionOverSixtySecondsStaysPutWithEarthRotation) {
  const StaticSetup s = staticSetup();
  const ImuPreintegration pim = preintegrateStatic(s, ImuNoise{}, 60.0, 100.0, nullptr);
  const NavState predicted = predictNavState(pim, s.state, ImuBias{}, s.frame);
  const Vector9d e = s.state.localCoordinates(predicted);
  // The readings are applied at each interval's mid attitude, so the sensed gravity
  // turning at the Earth rate leaves no first-order term (with the axes at the
  // interval's start: dt/2 T w g = 2.1e-4 m/s and T/2 that = 6.4 mm). Seen:
  // 1.6e-10 m/s, 2.7e-7 m.
  EXPECT_LT(e.head<3>().norm(), 1e-9);
  EXPECT_LT(e.segment<3>(3).norm(), 1e-6);  // m/s
  EXPECT_LT(e.tail<3>().norm(), 1e-5);      // m
  // Without the Earth's rotation in the model the same readings drift by metres:
  // the gyros sense 15 deg/h that the frame does not turn by.
  NavigationFrame non_rotating = s.frame;
  non_rotating.earth_rate_world_radps.setZero();
  const Vector9d drift = s.state.localCoordinates(predictNavState(pim, s.state, ImuBias{}, non_rotating));
  EXPECT_GT(drift.tail<3>().norm(), 1.0);
  std::printf("static 60 s, noise-free: with Earth rate %.2e m/s, %.2e m; without %.2f m\n",
              e.segment<3>(3).norm(), e.tail<3>().norm(), drift.tail<3>().norm());
}

TEST(ImuStatic, NoisyStaticDriftStaysWithinThePropagatedCovariance) {
  // 60 s at 100 Hz with the noise of each grade: the truth's residual r (state
  // unchanged) is N(0, Sigma). Its mean NEES over 100 runs is 9 (sd 0.42), and no
  // component leaves 3 sigma more often than chance (0.27 %, i.e. ~2.4 of 900).
  for (const ImuGrade grade : {ImuGrade::ConsumerMems, ImuGrade::IndustrialMems, ImuGrade::Tactical}) {
    const ImuNoise noise = imuNoisePreset(grade);
    const StaticSetup s = staticSetup();
    std::mt19937 rng(11);
    double nees_sum = 0.0;
    int beyond_3_sigma = 0;
    const int runs = 100;
    Vector9d sigma;
    for (int run = 0; run < runs; ++run) {
      const ImuPreintegration pim = preintegrateStatic(s, noise, 60.0, 100.0, &rng);
      const Vector9d r = imuFactorError(pim, s.state, ImuBias{}, s.state, s.frame);
      nees_sum += r.dot(pim.covariance().ldlt().solve(r));
      sigma = pim.covariance().diagonal().cwiseSqrt();
      for (int i = 0; i < 9; ++i) beyond_3_sigma += std::abs(r[i]) > 3.0 * sigma[i];
    }
    const double nees = nees_sum / runs;
    std::printf("%s static 60 s: mean NEES %.2f (9 expected), beyond 3 sigma %d of %d, 3-sigma horizontal position "
                "%.2f m, 3-sigma tilt %.3f deg\n",
                imuGradeText(grade).c_str(), nees, beyond_3_sigma, runs * 9, 3 * std::hypot(sigma[6], sigma[7]),
                3 * std::hypot(sigma[0], sigma[1]) * kRadToDeg);
    EXPECT_NEAR(nees, 9.0, 1.5) << imuGradeText(grade);
    EXPECT_LE(beyond_3_sigma, 9) << imuGradeText(grade);
  }
}

}  // namespace
}  // namespace ppp
