// Dual-frequency combinations on synthetic observations built from their definitions.
#include <gtest/gtest.h>

#include <cmath>

#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "ppp_bayes_tree/types/constants.h"

using namespace ppp;

namespace {
const double kF1 = *carrierFrequency_hz(GnssSystem::GPS, '1');  // 1575.42 MHz (IS-GPS-200)
const double kF2 = *carrierFrequency_hz(GnssSystem::GPS, '2');  // 1227.60 MHz
}  // namespace

TEST(IonosphereFree, GpsL1L2Coefficients) {
  // 1575.42^2 / (1575.42^2 - 1227.60^2) = 2.54573, -1227.60^2 / (...) = -1.54573
  // (e.g. Kouba & Heroux 2001, "Precise Point Positioning using IGS orbit and clock products").
  const IonosphereFreeCoefficients k = ionosphereFreeCoefficients(kF1, kF2);
  EXPECT_NEAR(k.alpha, 2.5457, 1e-4);
  EXPECT_NEAR(k.beta, -1.5457, 1e-4);
  EXPECT_NEAR(k.alpha + k.beta, 1.0, 1e-14);
  EXPECT_NEAR(ionosphereFreeNoiseFactor(k), 2.978, 1e-3);
  EXPECT_NEAR(wideLaneWavelength_m(kF1, kF2), 0.8619, 1e-4);   // 86.2 cm
  EXPECT_NEAR(narrowLaneWavelength_m(kF1, kF2), 0.1070, 1e-4);  // 10.7 cm
}

struct Synthetic {
  double p1, p2, l1, l2;
};
// P_i = rho + I_i, L_i = rho - I_i + lambda_i N_i, I_2 = (f1/f2)^2 I_1.
Synthetic synthesise(double rho, double iono1, double n1, double n2) {
  const double g = (kF1 / kF2) * (kF1 / kF2);
  const double lam1 = kSpeedOfLight_mps / kF1, lam2 = kSpeedOfLight_mps / kF2;
  return {rho + iono1, rho + g * iono1, rho - iono1 + lam1 * n1, rho - g * iono1 + lam2 * n2};
}

TEST(IonosphereFree, RemovesFirstOrderIonosphere) {
  const Synthetic o = synthesise(22345678.9, 7.3, 0, 0);
  const IonosphereFreeCoefficients k = ionosphereFreeCoefficients(kF1, kF2);
  EXPECT_NEAR(ionosphereFree(o.p1, o.p2, k), 22345678.9, 1e-6);
  EXPECT_NEAR(ionosphereFree(o.l1, o.l2, k), 22345678.9, 1e-6);
}

TEST(IonosphereFree, AmbiguityDecomposition) {
  const IonosphereFreeCoefficients k = ionosphereFreeCoefficients(kF1, kF2);
  const double lam1 = kSpeedOfLight_mps / kF1, lam2 = kSpeedOfLight_mps / kF2;
  const double n1 = 123456, n2 = 96183;
  EXPECT_NEAR(ionosphereFreeAmbiguity_m(kF1, kF2, n1, n1 - n2), k.alpha * lam1 * n1 + k.beta * lam2 * n2, 1e-6);
  // c f2 / (f1^2 - f2^2) = 3.68025e17 / 9.74946e17 = 0.3775 m per wide-lane cycle (GPS),
  // i.e. lambda_wl f2 / (f1 + f2) = 0.8619 * 0.4380.
  EXPECT_NEAR(ionosphereFreeAmbiguity_m(kF1, kF2, 0, 1), 0.3775, 1e-4);
}

TEST(MelbourneWuebbena, GivesWideLaneAmbiguity) {
  const Synthetic o = synthesise(21000000.0, 12.5, 1000017, 999990);
  EXPECT_NEAR(melbourneWuebbena_cycles(o.l1, o.l2, o.p1, o.p2, kF1, kF2), 27.0, 1e-6);
  EXPECT_NEAR(melbourneWuebbena_m(o.l1, o.l2, o.p1, o.p2, kF1, kF2), 27.0 * wideLaneWavelength_m(kF1, kF2), 1e-6);
}

TEST(GeometryFree, KeepsIonosphereAndAmbiguity) {
  const double g = (kF1 / kF2) * (kF1 / kF2);
  const Synthetic o = synthesise(21000000.0, 4.0, 10, 7);
  EXPECT_NEAR(geometryFreeCode_m(o.p1, o.p2), (g - 1) * 4.0, 1e-6);
  const double lam1 = kSpeedOfLight_mps / kF1, lam2 = kSpeedOfLight_mps / kF2;
  EXPECT_NEAR(geometryFreePhase_m(o.l1, o.l2), (g - 1) * 4.0 + lam1 * 10 - lam2 * 7, 1e-6);
}

TEST(IonosphereFree, OffsetCombination) {
  // IF PCO: alpha pco1 + beta pco2; equal offsets stay unchanged.
  const IonosphereFreeCoefficients k = ionosphereFreeCoefficients(kF1, kF2);
  const Eigen::Vector3d a(0.001, -0.002, 0.090), b(0.0015, -0.001, 0.120);
  EXPECT_LT((ionosphereFreeOffset(a, a, k) - a).norm(), 1e-15);
  EXPECT_NEAR(ionosphereFreeOffset(a, b, k).z(), 2.5457 * 0.090 - 1.5457 * 0.120, 1e-5);
}

// GLONASS FDMA (GLONASS ICD 5.1, sec. 3.3.1.4): G1 = 1602 + 0.5625 k MHz, G2 = 1246 +
// 0.4375 k MHz, so f1 / f2 = 9 / 7 on every channel: the IF coefficients are
// 81/32 and -49/32 for all k, while the wavelengths, and with them the IF phase of
// given cycles and the IF ambiguity's wavelength c / (f1 + f2), are per channel.
TEST(IonosphereFree, GlonassCoefficientsPerChannel) {
  EXPECT_DOUBLE_EQ(*carrierFrequency_hz(GnssSystem::GLONASS, '1', 1), 1602.5625e6);
  EXPECT_DOUBLE_EQ(*carrierFrequency_hz(GnssSystem::GLONASS, '2', 1), 1246.4375e6);
  EXPECT_FALSE(carrierFrequency_hz(GnssSystem::GLONASS, '1').has_value());  // no channel: no frequency
  double previous_wavelength_m = 0.0;
  for (int k = -7; k <= 6; ++k) {
    const double f1 = *carrierFrequency_hz(GnssSystem::GLONASS, '1', k);
    const double f2 = *carrierFrequency_hz(GnssSystem::GLONASS, '2', k);
    const IonosphereFreeCoefficients c = ionosphereFreeCoefficients(f1, f2);
    EXPECT_NEAR(c.alpha, 81.0 / 32.0, 1e-12) << k;
    EXPECT_NEAR(c.beta, -49.0 / 32.0, 1e-12) << k;
    // The same cycles give a different IF phase in metres on each channel.
    const double if_m = ionosphereFree(1.0e8 * kSpeedOfLight_mps / f1, 0.8e8 * kSpeedOfLight_mps / f2, c);
    const double wavelength_m = kSpeedOfLight_mps / (f1 + f2);
    EXPECT_NEAR(if_m, (81.0 * 1.0e8 / f1 - 49.0 * 0.8e8 / f2) / 32.0 * kSpeedOfLight_mps, 1e-6) << k;
    if (k > -7) EXPECT_LT(wavelength_m, previous_wavelength_m) << k;  // higher channel, shorter wavelength
    previous_wavelength_m = wavelength_m;
  }
  // k = 0: c / (1602 + 1246 MHz) = 0.105262 m (c = 299792458 m/s).
  EXPECT_NEAR(kSpeedOfLight_mps / (1602.0e6 + 1246.0e6), 0.105264, 1e-5);
}
