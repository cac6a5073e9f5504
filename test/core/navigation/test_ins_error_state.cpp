// The 15-state INS error model: F against numerical differentiation of the
// mechanization, the gravity gradient against the gravity model, the propagated
// covariance against a Monte Carlo of noisy static runs, the closed-loop reset, and the
// antenna position at a lever arm: its Jacobian against numerical differences and its
// covariance against sampled errors.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <random>

#include "ppp_bayes_tree/navigation/ins_error_state.h"
#include "ppp_bayes_tree/navigation/ins_mechanization.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp {
namespace {

const Eigen::Vector3d kEarthRate(0.0, 0.0, kEarthRotationRate_radps);

Eigen::Vector3d stationOrigin() { return geodeticToEcef(Geodetic{47.4 * kDegToRad, 8.5 * kDegToRad, 500.0}); }

Eigen::Matrix3d rotationEcefEnu(const Eigen::Vector3d& origin_ecef_m) {
  const Geodetic g = ecefToGeodetic(origin_ecef_m);
  return rotationEnuFromEcef(g.latitude_rad, g.longitude_rad).transpose();
}

/// The estimate (state, bias) moved by an error dx: what the truth is.
struct InsPoint {
  NavState state;
  ImuBias bias;
};

InsPoint moved(const InsPoint& x, const Vector15d& dx) {
  InsPoint out = x;
  applyInsErrorCorrection(dx, &out.state, &out.bias);
  return out;
}

Vector15d difference(const InsPoint& from, const InsPoint& to) {
  Vector15d d;
  d << from.state.localCoordinates(to.state), to.bias.vector() - from.bias.vector();
  return d;
}

/// One mechanization step with raw readings corrected by the point's own bias.
InsPoint step(const InsPoint& x, const Eigen::Vector3d& raw_force, const Eigen::Vector3d& raw_rate, double dt) {
  return {ecefInsStep(x.state, raw_force - x.bias.accel_mps2, raw_rate - x.bias.gyro_radps, dt), x.bias};
}

TEST(InsErrorState, GravityGradientMatchesCentralDifferencesOfTheGravityModel) {
  const Eigen::Vector3d p = stationOrigin();
  const Eigen::Matrix3d model = ecefGravityGradient(p);
  Eigen::Matrix3d numeric;
  const double h = 10.0;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(j);
    numeric.col(j) = (ecefNavigationFrame(p + e).gravity_world_mps2 - ecefNavigationFrame(p - e).gravity_world_mps2) /
                     (2.0 * h);
  }
  // The vertical gradient is 3.1e-6 /s^2, the horizontal ones -1.5e-6 /s^2; the model
  // leaves out the ellipsoid's flattening terms (~0.5 %).
  EXPECT_LT((model - numeric).norm(), 0.01 * numeric.norm()) << model << "\n" << numeric;
}

TEST(InsErrorState, FMatchesNumericalDifferentiationOfTheMechanization) {
  // A moving, turning, tilted state with biases: every block of F is exercised.
  InsPoint x;
  x.state.position_world_m = stationOrigin();
  x.state.rotation_world_body = rotationEcefEnu(x.state.position_world_m) * so3::expMap(Eigen::Vector3d(0.1, -0.2, 0.7));
  x.state.velocity_world_mps = Eigen::Vector3d(8.0, -5.0, 2.0);
  x.bias.accel_mps2 = Eigen::Vector3d(0.05, -0.02, 0.03);
  x.bias.gyro_radps = Eigen::Vector3d(1e-3, -2e-3, 5e-4);
  const Eigen::Vector3d raw_force(1.0, -0.5, 9.5), raw_rate(0.2, -0.1, 0.3);
  const double dt = 0.01;
  // Perturbation sizes per block: large enough that ECEF rounding (1e-9 m) is small
  // against the response, small enough that central differences stay linear.
  const double eps[5] = {1e-3, 1e-2, 10.0, 1e-2, 1e-2};
  const InsPoint next = step(x, raw_force, raw_rate, dt);
  Matrix15d phi_numeric;
  for (int j = 0; j < kInsErrorStateSize; ++j) {
    const Vector15d e = eps[j / 3] * Vector15d::Unit(j);
    const Vector15d plus = difference(next, step(moved(x, e), raw_force, raw_rate, dt));
    const Vector15d minus = difference(next, step(moved(x, -e), raw_force, raw_rate, dt));
    phi_numeric.col(j) = (plus - minus) / (2.0 * eps[j / 3]);
  }
  const Matrix15d f = insErrorStateF(x.state, raw_force - x.bias.accel_mps2, raw_rate - x.bias.gyro_radps);
  const Matrix15d first = Matrix15d::Identity() + f * dt;
  // First order: Phi - I - F dt is O(dt^2). Its size per element: |F|^2 dt^2 (the
  // square of F), |w| |F block| dt^2 (F turns with the attitude during the step) and
  // |F|^3 dt^3 / 3 (e.g. position against gyro bias, zero in F and F^2). Also allowed:
  // 1 % of F dt (the gravity-gradient model leaves out the flattening, ~0.5 %) and the
  // rounding of the differences (1e-9 m in ECEF positions, 1e-14 elsewhere, over the
  // perturbation).
  const Matrix15d f_abs = f.cwiseAbs();
  const Matrix15d f2_abs = f_abs * f_abs;
  const Matrix15d f3_abs = f2_abs * f_abs;
  const double rate = (raw_rate - x.bias.gyro_radps).norm();
  for (int i = 0; i < kInsErrorStateSize; ++i) {
    for (int j = 0; j < kInsErrorStateSize; ++j) {
      const double rounding = (i / 3 == 2 ? 1e-9 : 1e-14) / eps[j / 3];
      const double block_max = f_abs.block<3, 3>(3 * (i / 3), 3 * (j / 3)).maxCoeff();
      const double tol = 1e-2 * f_abs(i, j) * dt + (f2_abs(i, j) + rate * block_max) * dt * dt +
                         f3_abs(i, j) * dt * dt * dt / 3.0 + rounding;
      EXPECT_NEAR(phi_numeric(i, j), first(i, j), tol) << "row " << i << " column " << j;
    }
  }
  // Where F is not zero, Phi - I matches F dt to this relative accuracy.
  double worst_relative = 0.0;
  for (int i = 0; i < kInsErrorStateSize; ++i) {
    for (int j = 0; j < kInsErrorStateSize; ++j) {
      if (i == j || f(i, j) == 0.0) continue;
      worst_relative = std::max(worst_relative, std::abs(phi_numeric(i, j) - first(i, j)) / std::abs(f(i, j) * dt));
    }
  }
  std::printf("Phi - I against F dt (dt 0.01 s): worst relative difference %.2e over the non-zero entries\n",
              worst_relative);
  EXPECT_LT(worst_relative, 0.05);
}

// ---- Covariance against a Monte Carlo of noisy static runs -------------------------

struct MonteCarloSetup {
  ImuNoise noise = imuNoisePreset(ImuGrade::ConsumerMems);
  double rate_hz = 200.0;
  double duration_s = 10.0;
  int runs = 200;
  Vector15d initial_sigma;
  InsPoint truth;
  Eigen::Vector3d true_force, true_rate;

  MonteCarloSetup() {
    initial_sigma << Eigen::Vector3d::Constant(1e-3), Eigen::Vector3d::Constant(0.01), Eigen::Vector3d::Constant(0.1),
        Eigen::Vector3d::Constant(noise.accel_bias_instability_mps2),
        Eigen::Vector3d::Constant(noise.gyro_bias_instability_radps);
    truth.state.position_world_m = stationOrigin();
    truth.state.rotation_world_body =
        rotationEcefEnu(truth.state.position_world_m) * so3::expMap(Eigen::Vector3d(0.05, -0.03, 0.4));
    const Eigen::Matrix3d& r = truth.state.rotation_world_body;
    true_force = -r.transpose() * ecefNavigationFrame(truth.state.position_world_m).gravity_world_mps2;
    true_rate = r.transpose() * kEarthRate;
  }
};

Vector15d normalVector(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Vector15d v;
  for (int i = 0; i < kInsErrorStateSize; ++i) v[i] = normal(rng);
  return v;
}

/// One run: the truth sits still with a walking bias; the estimate starts off by a
/// drawn error and integrates the noisy readings. Returns truth minus estimate.
Vector15d staticRunError(const MonteCarloSetup& s, std::mt19937& rng) {
  const double dt = 1.0 / s.rate_hz;
  const Vector15d initial_error = s.initial_sigma.cwiseProduct(normalVector(rng));
  InsPoint truth = s.truth;
  truth.bias = ImuBias::fromVector(initial_error.tail<6>());
  InsPoint estimate;  // truth = estimate moved by the initial error
  estimate.state.rotation_world_body = truth.state.rotation_world_body * so3::expMap(-initial_error.head<3>());
  estimate.state.velocity_world_mps = truth.state.velocity_world_mps - initial_error.segment<3>(3);
  estimate.state.position_world_m = truth.state.position_world_m - initial_error.segment<3>(6);
  const double white_scale = 1.0 / std::sqrt(dt), walk_scale = std::sqrt(dt);
  const int n = static_cast<int>(std::lround(s.duration_s * s.rate_hz));
  for (int k = 0; k < n; ++k) {
    const Vector15d z = normalVector(rng);
    const Eigen::Vector3d force = s.true_force + truth.bias.accel_mps2 +
                                  s.noise.accel_noise_density_mps2_per_sqrthz * white_scale * z.segment<3>(0);
    const Eigen::Vector3d rate = s.true_rate + truth.bias.gyro_radps +
                                 s.noise.gyro_noise_density_radps_per_sqrthz * white_scale * z.segment<3>(3);
    estimate = step(estimate, force, rate, dt);
    truth.bias.accel_mps2 += s.noise.accel_bias_random_walk_mps3_per_sqrthz * walk_scale * z.segment<3>(6);
    truth.bias.gyro_radps += s.noise.gyro_bias_random_walk_radps2_per_sqrthz * walk_scale * z.segment<3>(9);
  }
  return difference(estimate, truth);
}

Matrix15d propagatedCovariance(const MonteCarloSetup& s) {
  const double dt = 1.0 / s.rate_hz;
  Matrix15d p = s.initial_sigma.array().square().matrix().asDiagonal();
  const InsDiscreteModel model =
      discretizeInsErrorModel(insErrorStateF(s.truth.state, s.true_force, s.true_rate), insErrorStateG(s.truth.state),
                              insNoiseSpectralDensity(s.noise), dt);
  const int n = static_cast<int>(std::lround(s.duration_s * s.rate_hz));
  for (int k = 0; k < n; ++k) p = propagateInsCovariance(p, model);
  return p;
}

TEST(InsErrorState, PropagatedCovarianceMatchesAMonteCarloOfNoisyStaticRuns) {
  const MonteCarloSetup setup;  // BMI088 noise, 200 runs of 10 s at 200 Hz
  std::mt19937 rng(20261206);
  Matrix15d sample = Matrix15d::Zero();
  for (int run = 0; run < setup.runs; ++run) {
    const Vector15d e = staticRunError(setup, rng);
    sample += e * e.transpose();
  }
  sample /= setup.runs;
  const Matrix15d model = propagatedCovariance(setup);
  // Each sample variance of 200 zero-mean draws is sigma^2 chi2(200)/200: standard
  // deviation 10 %; [0.68, 1.36] is its two-sided 99.9 % interval.
  for (int i = 0; i < 9; ++i) {
    const double ratio = sample(i, i) / model(i, i);
    std::printf("component %d: model sigma %.3e, sample sigma %.3e, variance ratio %.2f\n", i, std::sqrt(model(i, i)),
                std::sqrt(sample(i, i)), ratio);
    EXPECT_GT(ratio, 0.68) << "component " << i;
    EXPECT_LT(ratio, 1.36) << "component " << i;
  }
  // Tilt and horizontal velocity are coupled through gravity (-R [f]x): the model's
  // correlation between them must show in the sample too.
  const double model_corr = model(0, 4) / std::sqrt(model(0, 0) * model(4, 4));
  const double sample_corr = sample(0, 4) / std::sqrt(sample(0, 0) * sample(4, 4));
  std::printf("correlation tilt x / velocity y: model %.2f, sample %.2f\n", model_corr, sample_corr);
  EXPECT_NEAR(sample_corr, model_corr, 0.25);
}

TEST(InsErrorState, GaussMarkovBiasesReachTheirInstability) {
  const ImuNoise noise = imuNoisePreset(ImuGrade::IndustrialMems);
  InsBiasModel gauss_markov;
  gauss_markov.accel_correlation_time_s = 50.0;
  gauss_markov.gyro_correlation_time_s = 200.0;
  const Matrix12d density = insNoiseSpectralDensity(noise, gauss_markov);
  // Steady state of db' = -db / tau + n: q tau / 2 = instability^2.
  EXPECT_NEAR(density(6, 6) * 50.0 / 2.0, std::pow(noise.accel_bias_instability_mps2, 2), 1e-20);
  EXPECT_NEAR(density(9, 9) * 200.0 / 2.0, std::pow(noise.gyro_bias_instability_radps, 2), 1e-24);
  const Matrix12d walk = insNoiseSpectralDensity(noise);
  EXPECT_DOUBLE_EQ(walk(6, 6), std::pow(noise.accel_bias_random_walk_mps3_per_sqrthz, 2));
  const Matrix15d f = insErrorStateF(NavState{}, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), gauss_markov);
  EXPECT_DOUBLE_EQ(f(9, 9), -1.0 / 50.0);
  EXPECT_DOUBLE_EQ(f(12, 12), -1.0 / 200.0);
}

TEST(InsErrorState, CorrectionMovesTheEstimateOntoTheTruthAndResetJacobianMatches) {
  InsPoint estimate;
  estimate.state.position_world_m = stationOrigin();
  estimate.state.rotation_world_body = so3::expMap(Eigen::Vector3d(0.3, -1.0, 2.0));
  Vector15d error;
  error << 0.01, -0.02, 0.015, 0.1, 0.2, -0.3, 1.0, -2.0, 0.5, 1e-3, 2e-3, -1e-3, 1e-4, -2e-4, 3e-4;
  const InsPoint truth = moved(estimate, error);
  EXPECT_LT(difference(truth, moved(estimate, error)).norm(), 1e-12);
  EXPECT_LT((difference(estimate, truth) - error).norm(), 1e-9);
  // After the reset the remaining error of a nearby truth, e' = Log(Exp(dtheta)^T Exp(theta)),
  // changes with the pre-reset error theta by Jr(dtheta) = I - [dtheta/2]x + O(dtheta^2).
  InsPoint corrected = estimate;
  applyInsErrorCorrection(error, &corrected.state, &corrected.bias);
  const Matrix15d jacobian = insErrorResetJacobian(error);
  const double h = 1e-6;
  for (int j = 0; j < 3; ++j) {
    const Vector15d e = h * Vector15d::Unit(j);
    const Vector15d column =
        (difference(corrected, moved(estimate, error + e)) - difference(corrected, moved(estimate, error - e))) / (2 * h);
    EXPECT_LT((column - jacobian.col(j)).norm(), 1e-8) << "column " << j;
    const Eigen::Vector3d first_order = Eigen::Vector3d::Unit(j) - 0.5 * error.head<3>().cross(Eigen::Vector3d::Unit(j));
    EXPECT_LT((column.head<3>() - first_order).norm(), error.head<3>().squaredNorm() / 6.0) << "column " << j;
  }
}

TEST(InsErrorState, AntennaPositionJacobianMatchesNumericalDifferencesOfEveryErrorComponent) {
  // Near the origin, with a range to a point 50 m away, so that the central
  // differences are not lost in the rounding of ECEF coordinates (the mapping
  // does not depend on where the nominal is).
  NavState nominal;
  nominal.position_world_m = Eigen::Vector3d(3.0, -2.0, 1.0);
  nominal.rotation_world_body = so3::expMap(Eigen::Vector3d(0.3, -1.1, 2.0));
  nominal.velocity_world_mps = Eigen::Vector3d(3.0, -4.0, 1.0);
  const Eigen::Vector3d lever(0.8, -0.3, 1.5);
  const Eigen::Vector3d satellite(20.0, 30.0, 30.0);
  for (const double size : {0.0, 0.02}) {  // at the nominal and at an error already estimated
    Vector15d at = Vector15d::Zero();
    if (size > 0.0) at << size, -size, 2 * size, 0.1, 0.2, -0.1, 0.3, -0.2, 0.5, 0.01, 0.0, 0.0, 1e-4, 0.0, 0.0;
    const Eigen::Matrix<double, 3, 15> J = insAntennaPositionJacobian(nominal, lever, at);
    const Eigen::Vector3d p0 = insAntennaPosition(nominal, lever, at);
    const Eigen::RowVector3d u = -(satellite - p0).normalized().transpose();  // d range / d antenna
    const double h = 1e-6;
    for (int i = 0; i < 15; ++i) {
      SCOPED_TRACE("component " + std::to_string(i) + ", at size " + std::to_string(size));
      Vector15d plus = at, minus = at;
      plus(i) += h;
      minus(i) -= h;
      const Eigen::Vector3d numeric = (insAntennaPosition(nominal, lever, plus) -
                                       insAntennaPosition(nominal, lever, minus)) / (2 * h);
      EXPECT_LT((numeric - J.col(i)).norm(), 1e-7) << numeric.transpose() << " vs " << J.col(i).transpose();
      // The range model through the chain rule.
      const double range_numeric = ((satellite - insAntennaPosition(nominal, lever, plus)).norm() -
                                    (satellite - insAntennaPosition(nominal, lever, minus)).norm()) /
                                   (2 * h);
      EXPECT_NEAR(range_numeric, u * J.col(i), 1e-7);
    }
    // The sign convention of ins_error_state.h: truth = nominal moved by the error.
    if (size == 0.0) {
      EXPECT_TRUE((J.block<3, 3>(0, 6).isIdentity(0.0)));
      EXPECT_TRUE((J.block<3, 3>(0, 3).isZero(0.0)));
      EXPECT_TRUE((J.rightCols<6>().isZero(0.0)));
      EXPECT_LT(((J.block<3, 3>(0, 0)) + nominal.rotation_world_body * so3::hat(lever)).norm(), 1e-12);
    }
  }
}

TEST(InsErrorState, AntennaPositionCovarianceMatchesTheSpreadOfSampledErrors) {
  // J P J^T against the sample covariance of the antenna positions at errors drawn
  // from P: attitude errors of 0.5 deg turn a 1.5-m lever arm by about 1.3 cm.
  NavState nominal;
  nominal.position_world_m = Eigen::Vector3d(4331297.0, 567555.0, 4633133.0);
  nominal.rotation_world_body = so3::expMap(Eigen::Vector3d(0.3, -1.1, 2.0));
  const Eigen::Vector3d lever(0.8, -0.3, 1.5);
  Vector15d sigma = Vector15d::Constant(1e-3);
  sigma.segment<3>(InsErrorIndex::kAttitude) = Eigen::Vector3d(0.5, 0.3, 0.8) * kDegToRad;
  sigma.segment<3>(InsErrorIndex::kPosition) = Eigen::Vector3d(0.01, 0.02, 0.005);
  const Matrix15d P = sigma.cwiseAbs2().asDiagonal();
  const Eigen::Matrix3d predicted = insAntennaPositionCovariance(nominal, lever, P);
  std::mt19937 rng(11);
  std::normal_distribution<double> n01;
  const int samples = 20000;
  const Eigen::Vector3d p0 = insAntennaPosition(nominal, lever);
  Eigen::Matrix3d sampled = Eigen::Matrix3d::Zero();
  for (int k = 0; k < samples; ++k) {
    Vector15d e;
    for (int i = 0; i < kInsErrorStateSize; ++i) e(i) = sigma(i) * n01(rng);
    const Eigen::Vector3d d = insAntennaPosition(nominal, lever, e) - p0;
    sampled += d * d.transpose() / samples;
  }
  // 20000 samples: a variance within about 3 % (4 sigma), a covariance within 3 % of the diagonal.
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double scale = std::sqrt(predicted(i, i) * predicted(j, j));
      EXPECT_NEAR(sampled(i, j), predicted(i, j), 0.04 * scale) << i << "," << j;
    }
  // Without the lever arm only the position error is left.
  EXPECT_TRUE(insAntennaPositionCovariance(nominal, Eigen::Vector3d::Zero(), P)
                  .isApprox(P.block<3, 3>(InsErrorIndex::kPosition, InsErrorIndex::kPosition), 1e-12));
}

}  // namespace
}  // namespace ppp
