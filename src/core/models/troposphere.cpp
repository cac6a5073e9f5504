#include "ppp_bayes_tree/models/troposphere.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

/// Linear interpolation in the Niell latitude grid 15, 30, 45, 60, 75 deg,
/// constant beyond its ends (Niell 1996, sec. 4).
double interpolateNiell(const std::array<double, 5>& values, double abs_latitude_deg) {
  if (abs_latitude_deg <= 15.0) return values[0];
  if (abs_latitude_deg >= 75.0) return values[4];
  const double x = (abs_latitude_deg - 15.0) / 15.0;
  const int i = std::min(3, static_cast<int>(x));
  const double f = x - i;
  return values[i] * (1.0 - f) + values[i + 1] * f;
}

/// Hopfield-type layer integral along the ray (Goad & Goodman 1974): delay
/// 1e-6 N0 sum_k alpha_k r^k / k for the quartic profile of top height h.
double hopfieldLayerDelay_m(double n0, double layer_height_m, double elevation_rad, double radius_m) {
  const double se = std::sin(elevation_rad), ce = std::cos(elevation_rad);
  const double R = radius_m, h = layer_height_m;
  const double r = std::sqrt((R + h) * (R + h) - R * R * ce * ce) - R * se;
  const double a = -se / h, b = -ce * ce / (2.0 * h * R);
  const double a2 = a * a, b2 = b * b;
  const double alpha[9] = {1.0,
                           4.0 * a,
                           6.0 * a2 + 4.0 * b,
                           4.0 * a * (a2 + 3.0 * b),
                           a2 * a2 + 12.0 * a2 * b + 6.0 * b2,
                           4.0 * a * b * (a2 + 3.0 * b),
                           b2 * (6.0 * a2 + 4.0 * b),
                           4.0 * a * b2 * b,
                           b2 * b2};
  double sum = 0.0, rk = 1.0;
  for (int k = 1; k <= 9; ++k) {
    rk *= r;
    sum += alpha[k - 1] * rk / k;
  }
  return 1e-6 * n0 * sum;
}

}  // namespace

SurfaceMeteo standardAtmosphere(double height_m, double relative_humidity_sea_level) {
  const double h = std::clamp(height_m, -500.0, 11000.0);
  SurfaceMeteo m;
  m.pressure_hpa = 1013.25 * std::pow(1.0 - 2.2557e-5 * h, 5.2568);
  m.temperature_k = 15.0 - 6.5e-3 * h + 273.15;
  const double rh = relative_humidity_sea_level * std::exp(-6.396e-4 * h);
  const double T = m.temperature_k;
  m.water_vapour_pressure_hpa = 6.108 * rh * std::exp((17.15 * T - 4684.0) / (T - 38.45));
  return m;
}

double saastamoinenZenithHydrostaticDelay_m(double pressure_hpa, double latitude_rad, double height_m) {
  return 0.0022768 * pressure_hpa /
         (1.0 - 0.00266 * std::cos(2.0 * latitude_rad) - 0.00028 * height_m * 1e-3);
}

double saastamoinenZenithWetDelay_m(const SurfaceMeteo& meteo) {
  return 0.002277 * (1255.0 / meteo.temperature_k + 0.05) * meteo.water_vapour_pressure_hpa;
}

TroposphereDelays modifiedHopfieldSlantDelays(const SurfaceMeteo& meteo, double elevation_rad,
                                              double height_m) {
  const double T = meteo.temperature_k, e = meteo.water_vapour_pressure_hpa;
  const double n_dry = 77.64 * meteo.pressure_hpa / T;
  const double n_wet = -12.96 * e / T + 3.718e5 * e / (T * T);
  const double h_dry = 40136.0 + 148.72 * (T - 273.16);
  const double h_wet = 11000.0;
  const double radius = kWgs84SemiMajorAxis_m + height_m;
  return {hopfieldLayerDelay_m(n_dry, h_dry, elevation_rad, radius),
          hopfieldLayerDelay_m(n_wet, h_wet, elevation_rad, radius)};
}

TroposphereDelays modifiedHopfieldZenithDelays(const SurfaceMeteo& meteo, double height_m) {
  return modifiedHopfieldSlantDelays(meteo, 0.5 * kPi, height_m);
}

double standardWetDelayHeightRatio(double height_m) {
  return modifiedHopfieldZenithDelays(standardAtmosphere(height_m), height_m).wet_m /
         modifiedHopfieldZenithDelays(standardAtmosphere(0.0), 0.0).wet_m;
}

double cosecantMapping(double elevation_rad) { return 1.0 / std::sin(elevation_rad); }

double blackEisnerMapping(double elevation_rad) {
  const double s = std::sin(elevation_rad);
  return 1.001 / std::sqrt(0.002001 + s * s);
}

double mariniMapping(double elevation_rad, double a, double b, double c) {
  const double s = std::sin(elevation_rad);
  return (1.0 + a / (1.0 + b / (1.0 + c))) / (s + a / (s + b / (s + c)));
}

MappingFunctions niellMapping(double elevation_rad, double latitude_rad, double height_m,
                              double day_of_year) {
  // Niell (1996) Table 3 (hydrostatic average / amplitude) and Table 4 (wet).
  static constexpr std::array<double, 5> kAvgA = {1.2769934e-3, 1.2683230e-3, 1.2465397e-3, 1.2196049e-3,
                                                  1.2045996e-3};
  static constexpr std::array<double, 5> kAvgB = {2.9153695e-3, 2.9152299e-3, 2.9288445e-3, 2.9022565e-3,
                                                  2.9024912e-3};
  static constexpr std::array<double, 5> kAvgC = {62.610505e-3, 62.837393e-3, 63.721774e-3, 63.824265e-3,
                                                  64.258455e-3};
  static constexpr std::array<double, 5> kAmpA = {0.0, 1.2709626e-5, 2.6523662e-5, 3.4000452e-5,
                                                  4.1202191e-5};
  static constexpr std::array<double, 5> kAmpB = {0.0, 2.1414979e-5, 3.0160779e-5, 7.2562722e-5,
                                                  11.723375e-5};
  static constexpr std::array<double, 5> kAmpC = {0.0, 9.0128400e-5, 4.3497037e-5, 84.795348e-5,
                                                  170.37206e-5};
  static constexpr std::array<double, 5> kWetA = {5.8021897e-4, 5.6794847e-4, 5.8118017e-4, 5.9727542e-4,
                                                  6.1641693e-4};
  static constexpr std::array<double, 5> kWetB = {1.4275268e-3, 1.5138625e-3, 1.4572752e-3, 1.5007428e-3,
                                                  1.7599082e-3};
  static constexpr std::array<double, 5> kWetC = {4.3472961e-2, 4.6729510e-2, 4.3908931e-2, 4.4626982e-2,
                                                  5.4736038e-2};
  // Height correction coefficients (Niell 1996, eq. 6).
  constexpr double kHtA = 2.53e-5, kHtB = 5.49e-3, kHtC = 1.14e-3;

  const double lat_deg = std::abs(latitude_rad) * kRadToDeg;
  const double phase = 2.0 * kPi * (day_of_year - 28.0) / 365.25 + (latitude_rad < 0.0 ? kPi : 0.0);
  const double season = std::cos(phase);
  const double ah = interpolateNiell(kAvgA, lat_deg) - interpolateNiell(kAmpA, lat_deg) * season;
  const double bh = interpolateNiell(kAvgB, lat_deg) - interpolateNiell(kAmpB, lat_deg) * season;
  const double ch = interpolateNiell(kAvgC, lat_deg) - interpolateNiell(kAmpC, lat_deg) * season;
  const double height_correction =
      (1.0 / std::sin(elevation_rad) - mariniMapping(elevation_rad, kHtA, kHtB, kHtC)) * height_m * 1e-3;
  MappingFunctions m;
  m.hydrostatic = mariniMapping(elevation_rad, ah, bh, ch) + height_correction;
  m.wet = mariniMapping(elevation_rad, interpolateNiell(kWetA, lat_deg), interpolateNiell(kWetB, lat_deg),
                        interpolateNiell(kWetC, lat_deg));
  return m;
}

}  // namespace ppp
