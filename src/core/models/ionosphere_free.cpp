#include "ppp_bayes_tree/models/ionosphere_free.h"

#include <cmath>

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

IonosphereFreeCoefficients ionosphereFreeCoefficients(double f1_hz, double f2_hz) {
  const double f1s = f1_hz * f1_hz, f2s = f2_hz * f2_hz;
  return {f1s / (f1s - f2s), -f2s / (f1s - f2s)};
}

double ionosphereFreeNoiseFactor(const IonosphereFreeCoefficients& k) { return std::hypot(k.alpha, k.beta); }

double wideLaneWavelength_m(double f1_hz, double f2_hz) { return kSpeedOfLight_mps / (f1_hz - f2_hz); }

double narrowLaneWavelength_m(double f1_hz, double f2_hz) { return kSpeedOfLight_mps / (f1_hz + f2_hz); }

double ionosphereFreeAmbiguity_m(double f1_hz, double f2_hz, double n1_cycles, double n_wide_lane_cycles) {
  return kSpeedOfLight_mps * f2_hz / (f1_hz * f1_hz - f2_hz * f2_hz) * n_wide_lane_cycles +
         narrowLaneWavelength_m(f1_hz, f2_hz) * n1_cycles;
}

double melbourneWuebbena_m(double l1_m, double l2_m, double p1_m, double p2_m, double f1_hz, double f2_hz) {
  return (f1_hz * l1_m - f2_hz * l2_m) / (f1_hz - f2_hz) - (f1_hz * p1_m + f2_hz * p2_m) / (f1_hz + f2_hz);
}

double melbourneWuebbena_cycles(double l1_m, double l2_m, double p1_m, double p2_m, double f1_hz, double f2_hz) {
  return melbourneWuebbena_m(l1_m, l2_m, p1_m, p2_m, f1_hz, f2_hz) / wideLaneWavelength_m(f1_hz, f2_hz);
}

}  // namespace ppp
