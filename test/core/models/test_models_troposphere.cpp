// Troposphere: standard atmosphere, Saastamoinen, modified Hopfield, mapping
// functions (Niell, GMF) against published values; the gradient mapping of
// Chen & Herring (1997) against values computed by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "ppp_bayes_tree/models/troposphere.h"
#include "ppp_bayes_tree/models/troposphere_gradient.h"
#include "ppp_bayes_tree/types/constants.h"

using namespace ppp;

TEST(StandardAtmosphere, SeaLevelValues) {
  // Berg (1948) standard atmosphere at h = 0: 1013.25 hPa, 15 deg C; with RH 50 %
  // the Magnus form gives e = 0.5 * 6.108 exp((17.15*288.15 - 4684)/(288.15 - 38.45))
  // = 8.574 hPa (computed by hand from the formula).
  const SurfaceMeteo m = standardAtmosphere(0.0);
  EXPECT_DOUBLE_EQ(m.pressure_hpa, 1013.25);
  EXPECT_DOUBLE_EQ(m.temperature_k, 288.15);
  EXPECT_NEAR(m.water_vapour_pressure_hpa, 8.574, 0.002);
}

TEST(StandardAtmosphere, At1000m) {
  // P = 1013.25 (1 - 2.2557e-5 * 1000)^5.2568 = 898.73 hPa; T = 15 - 6.5 = 8.5 deg C.
  const SurfaceMeteo m = standardAtmosphere(1000.0);
  EXPECT_NEAR(m.pressure_hpa, 898.73, 0.01);
  EXPECT_NEAR(m.temperature_k, 281.65, 1e-9);
}

TEST(Saastamoinen, ZenithHydrostaticAt45Degrees) {
  // 0.0022768 * 1013.25 / (1 - 0.00266 cos 90 deg - 0) = 2.30697 m (Davis et al. 1985).
  EXPECT_NEAR(saastamoinenZenithHydrostaticDelay_m(1013.25, 45.0 * kDegToRad, 0.0), 2.306967, 1e-6);
  // Equator: denominator 1 - 0.00266 = 0.99734 -> 2.31312 m; height 1 km: -0.00028.
  EXPECT_NEAR(saastamoinenZenithHydrostaticDelay_m(1013.25, 0.0, 0.0), 2.306967 / 0.99734, 1e-6);
  EXPECT_NEAR(saastamoinenZenithHydrostaticDelay_m(1013.25, 45.0 * kDegToRad, 1000.0),
              2.306967 / (1.0 - 0.00028), 1e-6);
}

TEST(Saastamoinen, ZenithWetStandardAtmosphere) {
  // 0.002277 (1255 / 288.15 + 0.05) 8.574 = 0.0860 m.
  EXPECT_NEAR(saastamoinenZenithWetDelay_m(standardAtmosphere(0.0)), 0.0860, 0.0005);
}

TEST(ModifiedHopfield, ZenithEqualsHopfieldClosedForm) {
  // At zenith the series reduces to Hopfield's 1e-6 N0 h / 5 (Hopfield 1969;
  // Hofmann-Wellenhof et al. 2008, sec. 5.3.2).
  const SurfaceMeteo m = standardAtmosphere(0.0);
  const TroposphereDelays z = modifiedHopfieldZenithDelays(m, 0.0);
  const double T = m.temperature_k, e = m.water_vapour_pressure_hpa;
  const double h_d = 40136.0 + 148.72 * (T - 273.16);
  EXPECT_NEAR(z.hydrostatic_m, 1e-6 * 77.64 * m.pressure_hpa / T * h_d / 5.0, 1e-9);
  EXPECT_NEAR(z.wet_m, 1e-6 * (-12.96 * e / T + 3.718e5 * e / (T * T)) * 11000.0 / 5.0, 1e-9);
  // And agrees with Saastamoinen within about a centimetre (both ~2.31 m / ~0.085 m).
  EXPECT_NEAR(z.hydrostatic_m, saastamoinenZenithHydrostaticDelay_m(m.pressure_hpa, 45 * kDegToRad, 0), 0.01);
  EXPECT_NEAR(z.wet_m, saastamoinenZenithWetDelay_m(m), 0.005);
}

TEST(ModifiedHopfield, SlantGrowsLikeCosecant) {
  const SurfaceMeteo m = standardAtmosphere(500.0);
  const TroposphereDelays z = modifiedHopfieldZenithDelays(m, 500.0);
  const TroposphereDelays s30 = modifiedHopfieldSlantDelays(m, 30 * kDegToRad, 500.0);
  const TroposphereDelays s5 = modifiedHopfieldSlantDelays(m, 5 * kDegToRad, 500.0);
  EXPECT_NEAR(s30.hydrostatic_m / z.hydrostatic_m, 2.0, 0.02);
  EXPECT_NEAR(s30.wet_m / z.wet_m, 2.0, 0.02);
  // At 5 deg the flat-Earth 1/sin = 11.47 overestimates; curved-Earth values ~10.
  EXPECT_GT(s5.hydrostatic_m / z.hydrostatic_m, 9.5);
  EXPECT_LT(s5.hydrostatic_m / z.hydrostatic_m, 11.0);
}

TEST(MappingFunctions, UnityAtZenithAndNearCosecantAt30) {
  const double zen = 0.5 * kPi, e30 = 30 * kDegToRad;
  EXPECT_NEAR(cosecantMapping(zen), 1.0, 1e-15);
  EXPECT_NEAR(blackEisnerMapping(zen), 1.0, 1e-12);  // 1.001 / sqrt(1.002001) = 1
  const MappingFunctions n = niellMapping(zen, 47 * kDegToRad, 0.0, 133.0);
  const MappingFunctions g = globalMappingFunction(zen, 47 * kDegToRad, 7.5 * kDegToRad, 0.0, 61173.0);
  EXPECT_NEAR(n.hydrostatic, 1.0, 1e-12);
  EXPECT_NEAR(n.wet, 1.0, 1e-12);
  EXPECT_NEAR(g.hydrostatic, 1.0, 1e-12);
  EXPECT_NEAR(g.wet, 1.0, 1e-12);
  for (double m : {blackEisnerMapping(e30), niellMapping(e30, 47 * kDegToRad, 900.0, 133.0).hydrostatic,
                   niellMapping(e30, 47 * kDegToRad, 900.0, 133.0).wet,
                   globalMappingFunction(e30, 47 * kDegToRad, 7.5 * kDegToRad, 900.0, 61173.0).hydrostatic,
                   globalMappingFunction(e30, 47 * kDegToRad, 7.5 * kDegToRad, 900.0, 61173.0).wet}) {
    EXPECT_NEAR(m, 2.0, 0.04);  // 1/sin 30 = 2, within 2 %
    EXPECT_LT(m, 2.0);          // Earth curvature makes every real mapping smaller
  }
}

TEST(MappingFunctions, MonotonicInElevation) {
  double last_h = 1e9, last_w = 1e9, last_g = 1e9, last_b = 1e9;
  for (double el_deg = 3.0; el_deg <= 90.0; el_deg += 1.0) {
    const double el = el_deg * kDegToRad;
    const MappingFunctions n = niellMapping(el, -33 * kDegToRad, 300.0, 200.0);
    const MappingFunctions g = globalMappingFunction(el, -33 * kDegToRad, 151 * kDegToRad, 300.0, 59000.0);
    EXPECT_LT(n.hydrostatic, last_h);
    EXPECT_LT(n.wet, last_w);
    EXPECT_LT(g.hydrostatic, last_g);
    EXPECT_LT(blackEisnerMapping(el), last_b);
    last_h = n.hydrostatic;
    last_w = n.wet;
    last_g = g.hydrostatic;
    last_b = blackEisnerMapping(el);
  }
}

TEST(NiellMapping, PublishedValueLeMans) {
  // Orekit NiellMappingFunctionModelTest (citing Mercier & Perosanz, "Mesures GNSS,
  // Resolution des ambiguites"): Le Mans, lat 48.0 deg, lon 0.2 deg, h 68 m,
  // 1994-01-01 0h UT, elevation 5 deg -> hydrostatic 10.16, wet 10.75.
  const MappingFunctions m = niellMapping(5.0 * kDegToRad, 48.0 * kDegToRad, 68.0, 1.0);
  EXPECT_NEAR(m.hydrostatic, 10.16, 0.01);
  EXPECT_NEAR(m.wet, 10.75, 0.01);
}

TEST(GlobalMappingFunction, IersConventionsTestCase) {
  // IERS Conventions 2010 software GMF.F, header test case: DMJD = 55055,
  // DLAT = 0.6708665767 rad, DLON = -1.393397187 rad (NRAO Green Bank), DHGT = 844.715 m,
  // ZD = 1.278564131 rad -> GMFH = 3.425245519339138678, GMFW = 3.449589116182419257.
  const double el = 0.5 * kPi - 1.278564131;
  const MappingFunctions m = globalMappingFunction(el, 0.6708665767, -1.393397187, 844.715, 55055.0);
  EXPECT_NEAR(m.hydrostatic, 3.425245519339138678, 1e-12);
  EXPECT_NEAR(m.wet, 3.449589116182419257, 1e-12);
}

TEST(GlobalMappingFunction, CloseToNiell) {
  // GMF was fitted to agree with NMF on average (Boehm et al. 2006): at 10 deg they
  // differ by well under 1 %.
  const double el = 10 * kDegToRad;
  const MappingFunctions n = niellMapping(el, 47 * kDegToRad, 950.0, 133.0);
  const MappingFunctions g = globalMappingFunction(el, 47 * kDegToRad, 7.5 * kDegToRad, 950.0, 61173.0);
  EXPECT_NEAR(g.hydrostatic / n.hydrostatic, 1.0, 0.01);
  EXPECT_NEAR(g.wet / n.wet, 1.0, 0.01);
}

TEST(SlantDelay, PartialWrtZwdIsWetMappingByCentralDifference) {
  const MappingFunctions m = niellMapping(12 * kDegToRad, 47 * kDegToRad, 950.0, 133.0);
  const double zhd = 2.1, zwd = 0.12, h = 1e-4;
  const double numeric = (slantTroposphereDelay_m(m, zhd, zwd + h) - slantTroposphereDelay_m(m, zhd, zwd - h)) /
                         (2 * h);
  EXPECT_NEAR(slantDelayPartialWrtZwd(m), numeric, 1e-9);
  EXPECT_GT(slantDelayPartialWrtZwd(m), 4.0);  // ~1/sin 12 = 4.8
}

// Chen & Herring (1997) gradient mapping m_g(e) = 1 / (sin e tan e + 0.0032),
// values by hand from the formula:
//   e = 90 deg: tan e -> infinity, m_g -> 0 (a zenith ray sees no horizontal gradient);
//   e = 45 deg: sin e tan e = sqrt(2)/2 = 0.7071068 -> 1 / 0.7103068 = 1.407842;
//   e = 30 deg: 0.5 / sqrt(3) = 0.2886751 -> 1 / 0.2918751 = 3.426123;
//   e = 10 deg: 0.1736482 x 0.1763270 = 0.0306189 -> 1 / 0.0338189 = 29.5693;
//   e = 0: 1 / 0.0032 = 312.5 (the constant keeps the horizon finite).
TEST(TroposphereGradient, ChenHerringMappingKnownValues) {
  EXPECT_NEAR(gradientMapping(90.0 * kDegToRad), 0.0, 1e-12);
  EXPECT_NEAR(gradientMapping(45.0 * kDegToRad), 1.407842, 1e-6);
  EXPECT_NEAR(gradientMapping(30.0 * kDegToRad), 3.426123, 1e-6);
  EXPECT_NEAR(gradientMapping(10.0 * kDegToRad), 29.5693, 1e-4);
  EXPECT_DOUBLE_EQ(gradientMapping(0.0), 312.5);
  // Monotonic towards the horizon.
  double previous = 0.0;
  for (int deg = 89; deg >= 1; --deg) {
    const double m = gradientMapping(deg * kDegToRad);
    EXPECT_GT(m, previous) << deg;
    previous = m;
  }
}

TEST(TroposphereGradient, PartialsFollowTheAzimuthAndTheDelayIsLinear) {
  const double e = 30.0 * kDegToRad, m_g = 3.426123;
  // Azimuth from north, clockwise: north sees G_N only, east G_E only, south-west both negatively.
  GradientPartials p = gradientPartials(e, 0.0);
  EXPECT_NEAR(p.north, m_g, 1e-6);
  EXPECT_NEAR(p.east, 0.0, 1e-12);
  p = gradientPartials(e, 90.0 * kDegToRad);
  EXPECT_NEAR(p.north, 0.0, 1e-12);
  EXPECT_NEAR(p.east, m_g, 1e-6);
  p = gradientPartials(e, 225.0 * kDegToRad);
  EXPECT_NEAR(p.north, -m_g / std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(p.east, -m_g / std::sqrt(2.0), 1e-6);
  // 1 mm north gradient seen from the north at 30 deg: 3.43 mm; from the south: -3.43 mm.
  EXPECT_NEAR(slantGradientDelay_m(e, 0.0, 0.001, 0.0), 3.426123e-3, 1e-9);
  EXPECT_NEAR(slantGradientDelay_m(e, kPi, 0.001, 0.0), -3.426123e-3, 1e-9);
  EXPECT_NEAR(slantGradientDelay_m(e, 1.0, 0.002, -0.003),
              2.0 * slantGradientDelay_m(e, 1.0, 0.001, 0.0) - 3.0 * slantGradientDelay_m(e, 1.0, 0.0, 0.001), 1e-15);
}
