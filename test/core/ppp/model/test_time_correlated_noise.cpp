// Time-correlated (first-order Gauss-Markov) measurement noise: the variance
// inflation of a white-noise update and the effective number of independent
// samples of a mean (time_correlated_noise.h), the code weighting of the
// shared stochastic model and the Melbourne-Wuebbena averaging length as a time.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "ppp_bayes_tree/ppp/ambiguity/wide_lane_ambiguity.h"
#include "ppp_bayes_tree/ppp/model/stochastic_model.h"
#include "ppp_bayes_tree/ppp/model/time_correlated_noise.h"

namespace ppp {
namespace {

/// Bartlett's sum for the variance of the mean of n AR(1) samples, term by term:
/// Var(mean) n / sigma^2 = 1 + 2 sum_{k=1}^{n-1} (1 - k/n) rho^k.
double bartlettSum(int n, double rho) {
  double s = 1.0;
  for (int k = 1; k < n; ++k) s += 2.0 * (1.0 - static_cast<double>(k) / n) * std::pow(rho, k);
  return s;
}

TEST(TimeCorrelatedNoise, CorrelationAndVarianceFactorKnownValues) {
  // rho = exp(-dt/tau): 1 s at tau 15 s -> exp(-1/15) = 0.9355069850;
  // (1 + rho) / (1 - rho) = 1.9355069850 / 0.0644930150 = 30.0111103.
  EXPECT_NEAR(gaussMarkovCorrelation(1.0, 15.0), 0.9355069850316178, 1e-12);
  EXPECT_NEAR(gaussMarkovVarianceFactor(1.0, 15.0), 30.01111028815295, 1e-9);
  // 30 s at tau 15 s: rho = exp(-2) = 0.1353352832, factor 1.1353352832 / 0.8646647168 = 1.3130352855.
  EXPECT_NEAR(gaussMarkovVarianceFactor(30.0, 15.0), 1.3130352854993315, 1e-12);
  // dt << tau: factor ~ 2 tau / dt (10 Hz, tau 15 s: 300.0).
  EXPECT_NEAR(gaussMarkovVarianceFactor(0.1, 15.0), 2.0 * 15.0 / 0.1, 0.01);
  // White noise, a first epoch (dt 0), a gap far longer than tau: no inflation.
  EXPECT_EQ(gaussMarkovVarianceFactor(1.0, 0.0), 1.0);
  EXPECT_EQ(gaussMarkovVarianceFactor(0.0, 15.0), 1.0);
  EXPECT_NEAR(gaussMarkovVarianceFactor(3600.0, 15.0), 1.0, 1e-12);
  EXPECT_EQ(gaussMarkovVarianceFactor(std::nan(""), 15.0), 1.0);
}

TEST(TimeCorrelatedNoise, EffectiveSamplesAreBartlettsVarianceOfTheMean) {
  const double rho = std::exp(-1.0 / 15.0);
  // n = 1: one sample is one sample. n = 2: Var(mean) = sigma^2 (1 + rho) / 2, n_eff = 2 / (1 + rho).
  EXPECT_DOUBLE_EQ(gaussMarkovEffectiveSamples(1, 1.0, 15.0), 1.0);
  EXPECT_NEAR(gaussMarkovEffectiveSamples(2, 1.0, 15.0), 2.0 / (1.0 + rho), 1e-12);
  // The closed form equals the term-by-term sum (100 samples at 1 Hz, tau 15 s: 3.9187).
  for (const int n : {3, 10, 100, 1000})
    EXPECT_NEAR(gaussMarkovEffectiveSamples(n, 1.0, 15.0), n / bartlettSum(n, rho), 1e-9 * n) << n;
  EXPECT_NEAR(gaussMarkovEffectiveSamples(100, 1.0, 15.0), 3.918725428329181, 1e-9);
  // Many samples: n (1 - rho) / (1 + rho), i.e. n / the variance factor.
  EXPECT_NEAR(gaussMarkovEffectiveSamples(100000, 1.0, 15.0) / (100000.0 / gaussMarkovVarianceFactor(1.0, 15.0)),
              1.0, 1e-3);
  // White: every sample counts; none: zero.
  EXPECT_DOUBLE_EQ(gaussMarkovEffectiveSamples(50, 1.0, 0.0), 50.0);
  EXPECT_DOUBLE_EQ(gaussMarkovEffectiveSamples(0, 1.0, 15.0), 0.0);
}

TEST(TimeCorrelatedNoise, EffectiveSamplesMatchASimulatedGaussMarkovError) {
  // The simulator's code multipath process (simulation_config.h): x_k = rho x_{k-1}
  // + sqrt(1 - rho^2) sigma w_k from the stationary start. The empirical variance
  // of 200-sample means over 4000 series is sigma^2 / n_eff within its sampling
  // error (relative sigma sqrt(2/4000) = 2.2 %; 8 % is 3.6 of them).
  const double dt = 1.0, tau = 15.0, sigma = 0.4;
  const int n = 200, series = 4000;
  const double rho = gaussMarkovCorrelation(dt, tau);
  std::mt19937 rng(11);
  std::normal_distribution<double> w(0.0, 1.0);
  double sum_sq = 0.0;
  for (int s = 0; s < series; ++s) {
    double x = sigma * w(rng), mean = 0.0;
    for (int k = 0; k < n; ++k) {
      if (k > 0) x = rho * x + std::sqrt(1.0 - rho * rho) * sigma * w(rng);
      mean += x / n;
    }
    sum_sq += mean * mean;
  }
  const double empirical = sum_sq / series;
  const double predicted = sigma * sigma / gaussMarkovEffectiveSamples(n, dt, tau);
  EXPECT_NEAR(empirical / predicted, 1.0, 0.08) << empirical << " vs " << predicted;
  // White weighting would claim a variance 24x too small here.
  EXPECT_GT(predicted / (sigma * sigma / n), 20.0);
}

TEST(TimeCorrelatedNoise, StochasticModelInflatesTheCodeVarianceOverTheInterval) {
  StochasticModel m;
  EXPECT_EQ(m.code_correlation_time_s, 15.0);  // config/ppp.yaml default
  EXPECT_NEAR(m.codeVarianceFactor(1.0), 30.01111028815295, 1e-9);
  EXPECT_NEAR(m.codeVarianceFactor(30.0), 1.3130352854993315, 1e-12);
  EXPECT_EQ(m.codeVarianceFactor(0.0), 1.0);  // the first epoch
  m.code_correlation_time_s = 0.0;
  EXPECT_EQ(m.codeVarianceFactor(1.0), 1.0);  // white
  EXPECT_TRUE(m.validate().empty());
  m.code_correlation_time_s = -1.0;
  EXPECT_NE(m.validate().find("code_correlation_time_s"), std::string::npos);
}

/// sigmaOfMean of one arc fed with alternating +-0.3 cycle around 5 (sample sigma
/// ~0.3) every `interval_s` for `duration_s`.
double wideLaneSigmaAfter(double interval_s, double duration_s, const WideLaneOptions& options) {
  WideLaneResolver r(options);
  const GnssTime t0 = GnssTime::fromGpsSeconds(1300000000);
  const int n = static_cast<int>(std::lround(duration_s / interval_s));
  for (int k = 0; k < n; ++k) r.addValue(1, SatelliteId{GnssSystem::GPS, 1}, 5.0 + (k % 2 ? 0.3 : -0.3), t0 + k * interval_s);
  return r.arcs().at(1).sigmaOfMean_cycles(options);
}

TEST(TimeCorrelatedNoise, WideLaneAveragingLengthIsATimeNotASampleCount) {
  WideLaneOptions o;
  EXPECT_EQ(o.correlation_time_s, 15.0);  // config/ppp.yaml default
  o.correlation_time_s = 60.0;
  // After 10 min, 1 Hz and 30 s data have the same sigma of the MW mean within 4 %
  // (tau 60 s: n_eff 5.555 of 600 samples vs 5.418 of 20, both ~ duration / (2 tau) = 5;
  // the sample standard deviations of the +-0.3 values differ by sqrt(600/599 * 19/20)).
  const double at_1hz = wideLaneSigmaAfter(1.0, 600.0, o), at_30s = wideLaneSigmaAfter(30.0, 600.0, o);
  EXPECT_NEAR(at_1hz / at_30s,
              std::sqrt(600.0 / 599.0 * 19.0 / 20.0) * std::sqrt(5.418239101467254 / 5.555370359806269), 1e-6);
  EXPECT_NEAR(at_1hz / at_30s, 1.0, 0.04);
  // A sample count would make 1 Hz data look far more independent: white MW at
  // 1 Hz reaches a 10x smaller sigma than the time-correlated model.
  WideLaneOptions white = o;
  white.correlation_time_s = 0.0;
  EXPECT_GT(at_1hz / wideLaneSigmaAfter(1.0, 600.0, white), 10.0);
  // The default 15 s: about 30 epochs per independent sample at 1 Hz (1800 samples:
  // n_eff 60.48, 1800 / 30.01 = 59.98 plus the finite-n term), 1.3 at 30 s (60 samples: 45.91).
  EXPECT_NEAR(gaussMarkovEffectiveSamples(1800, 1.0, 15.0), 60.481426, 1e-3);
  EXPECT_NEAR(gaussMarkovEffectiveSamples(60, 30.0, 15.0), 45.906606, 1e-3);
}

}  // namespace
}  // namespace ppp
