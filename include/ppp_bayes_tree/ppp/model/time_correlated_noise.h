#pragma once
// Time-correlated measurement noise: a first-order Gauss-Markov (AR(1)) error
// with correlation rho = exp(-dt / tau) between samples dt apart. Code multipath
// is of this kind; weighted as white noise it makes the covariance optimistic by
// about (1 + rho) / (1 - rho). Here: rho, that variance factor (both estimators
// inflate each code variance by it) and Bartlett's effective number of samples of
// a mean (the Melbourne-Wuebbena wide lane averages its arc with it).
// The derivation: doc/estimators.md, "Time-correlated noise".
// References: Bartlett M.S. (1946) J R Stat Soc Suppl 8(1):27-41; El-Rabbany A.,
// Kleusberg A. (2003) J Surv Eng 129(1):28-32; Gelb A. (1974) Applied Optimal
// Estimation, MIT Press, 3.8.

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
