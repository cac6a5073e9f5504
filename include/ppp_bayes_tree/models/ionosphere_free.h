#pragma once
// Dual-frequency linear combinations (Hofmann-Wellenhof et al., "GNSS" 2008,
// sec. 5.1.3 / 7.2; Teunissen & Montenbruck (eds.), Springer Handbook of GNSS
// 2017, sec. 20.2). Observations in metres unless the name says cycles.
//
// First-order ionospheric delay on frequency f is I_f = 40.3 TEC / f^2, so
// code P_i = rho + I_i and phase L_i = rho - I_i + lambda_i N_i.
#include <Eigen/Core>

namespace ppp {

/// Ionosphere-free weights: alpha = f1^2/(f1^2 - f2^2), beta = -f2^2/(f1^2 - f2^2);
/// alpha + beta = 1 (geometry kept), alpha/f1^2 + beta/f2^2 = 0 (first-order
/// ionosphere removed). GPS L1/L2: 2.5457, -1.5457.
struct IonosphereFreeCoefficients {
  double alpha = 0.0;
  double beta = 0.0;
};
IonosphereFreeCoefficients ionosphereFreeCoefficients(double f1_hz, double f2_hz);

/// alpha x1 + beta x2 (codes, phases in metres, PCV values, any quantity in metres).
inline double ionosphereFree(double x1, double x2, const IonosphereFreeCoefficients& k) {
  return k.alpha * x1 + k.beta * x2;
}
/// Ionosphere-free combination of two antenna phase-centre offsets [m] (any frame).
inline Eigen::Vector3d ionosphereFreeOffset(const Eigen::Vector3d& offset1_m, const Eigen::Vector3d& offset2_m,
                                            const IonosphereFreeCoefficients& k) {
  return k.alpha * offset1_m + k.beta * offset2_m;
}
/// Noise amplification sqrt(alpha^2 + beta^2) for equal, independent noise (2.98 for GPS L1/L2).
double ionosphereFreeNoiseFactor(const IonosphereFreeCoefficients& k);

/// Wide-lane wavelength c / (f1 - f2) [m] (86.2 cm for GPS L1/L2).
double wideLaneWavelength_m(double f1_hz, double f2_hz);
/// Narrow-lane wavelength c / (f1 + f2) [m] (10.7 cm for GPS L1/L2).
double narrowLaneWavelength_m(double f1_hz, double f2_hz);

/// Ionosphere-free ambiguity term alpha lambda1 N1 + beta lambda2 N2 [m] written as
/// c f2 / (f1^2 - f2^2) N_wl + lambda_nl N1 with N_wl = N1 - N2.
double ionosphereFreeAmbiguity_m(double f1_hz, double f2_hz, double n1_cycles, double n_wide_lane_cycles);

/// Melbourne-Wuebbena combination [m] (Melbourne 1985, Wuebbena 1985):
/// (f1 L1 - f2 L2)/(f1 - f2) - (f1 P1 + f2 P2)/(f1 + f2) = lambda_wl (N1 - N2) + biases.
double melbourneWuebbena_m(double l1_m, double l2_m, double p1_m, double p2_m, double f1_hz, double f2_hz);
/// Same in wide-lane cycles.
double melbourneWuebbena_cycles(double l1_m, double l2_m, double p1_m, double p2_m, double f1_hz, double f2_hz);

/// Geometry-free phase L1 - L2 [m] = (gamma - 1) I_1 + lambda1 N1 - lambda2 N2, gamma = f1^2/f2^2.
inline double geometryFreePhase_m(double l1_m, double l2_m) { return l1_m - l2_m; }
/// Geometry-free code P2 - P1 [m] = (gamma - 1) I_1 (+ biases).
inline double geometryFreeCode_m(double p1_m, double p2_m) { return p2_m - p1_m; }

}  // namespace ppp
