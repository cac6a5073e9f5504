#include "ppp_bayes_tree/ppp/model/time_correlated_noise.h"

#include <cmath>

namespace ppp {

double gaussMarkovCorrelation(double interval_s, double correlation_time_s) {
  if (!(correlation_time_s > 0.0) || !(interval_s > 0.0) || !std::isfinite(interval_s) ||
      !std::isfinite(correlation_time_s))
    return 0.0;
  return std::exp(-interval_s / correlation_time_s);
}

double gaussMarkovVarianceFactor(double interval_s, double correlation_time_s) {
  const double rho = gaussMarkovCorrelation(interval_s, correlation_time_s);
  return (1.0 + rho) / (1.0 - rho);
}

double gaussMarkovEffectiveSamples(int samples, double interval_s, double correlation_time_s) {
  if (samples <= 0) return 0.0;
  const double rho = gaussMarkovCorrelation(interval_s, correlation_time_s);
  if (rho <= 0.0 || samples == 1) return static_cast<double>(samples);
  const double n = static_cast<double>(samples);
  const double one_minus = 1.0 - rho;
  const double bracket =
      (1.0 + rho) / one_minus - 2.0 * rho * (1.0 - std::pow(rho, n)) / (n * one_minus * one_minus);
  return n / bracket;
}

}  // namespace ppp
