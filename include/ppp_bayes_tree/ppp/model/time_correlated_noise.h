#pragma once
// Time-correlated measurement noise: a first-order Gauss-Markov (AR(1))
// error e_k = rho e_{k-1} + w_k with stationary variance sigma^2 and, between
// samples dt apart, correlation rho = exp(-dt / tau) (tau: correlation time).
// Code multipath is of this kind (seconds to minutes); an estimator that weights
// it as white noise accumulates information at the sampling rate and its
// covariance becomes optimistic by about (1 + rho) / (1 - rho) (30 for
// tau = 15 s at 1 Hz, 1.31 at 30 s).
//
// Two consequences of the AR(1) model:
//  * The mean of n equally spaced samples has the variance (Bartlett 1946)
//        Var(mean) = sigma^2 / n * [1 + 2 sum_{k=1}^{n-1} (1 - k/n) rho^k]
//                  = sigma^2 / n * [(1 + rho) / (1 - rho) - 2 rho (1 - rho^n) / (n (1 - rho)^2)],
//    i.e. n_eff = n / [...] independent samples (1 for n = 1; for n -> inf,
//    n (1 - rho) / (1 + rho), about duration / (2 tau) when dt << tau). The
//    Melbourne-Wuebbena wide lane averages its arc with this n_eff.
//  * A sequential estimator that keeps the white-noise update (no noise state)
//    reaches the right steady-state variance of a constant it averages when
//    each sample's variance is inflated by (1 + rho) / (1 - rho), the limit
//    of the bracket above (El-Rabbany & Kleusberg 2003 scale the GPS
//    covariance the same way). Both estimators weight the code so
//    (StochasticModel::code_correlation_time_s).
// Neither changes a single epoch's residual test: the marginal variance of a
// sample is still sigma^2 (screening uses the white sigma).
//
// References: Bartlett M.S. (1946) On the theoretical specification and
// sampling properties of autocorrelated time-series. J R Stat Soc Suppl
// 8(1):27-41. El-Rabbany A., Kleusberg A. (2003) Effect of temporal physical
// correlation on accuracy estimation in GPS relative positioning. J Surv Eng
// 129(1):28-32. Gelb A. (1974) Applied Optimal Estimation, MIT Press, 3.8
// (the first-order Gauss-Markov process).

namespace ppp {

/// rho = exp(-dt / tau); 0 when tau <= 0 (white), dt <= 0 or not finite.
double gaussMarkovCorrelation(double interval_s, double correlation_time_s);

/// (1 + rho) / (1 - rho) >= 1: the variance inflation of one sample of a
/// white-noise update so that the information per unit time is the AR(1)
/// one (1 for white noise, a first epoch or a gap much longer than tau).
double gaussMarkovVarianceFactor(double interval_s, double correlation_time_s);

/// n / [(1 + rho) / (1 - rho) - 2 rho (1 - rho^n) / (n (1 - rho)^2)]: the
/// number of independent samples that give the variance of the mean of `samples`
/// AR(1) samples `interval_s` apart (= samples when white; 1 when samples = 1;
/// 0 when samples <= 0).
double gaussMarkovEffectiveSamples(int samples, double interval_s, double correlation_time_s);

}  // namespace ppp
