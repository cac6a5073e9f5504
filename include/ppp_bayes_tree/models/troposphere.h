#pragma once
// Tropospheric delay: standard atmosphere, zenith delays (Saastamoinen,
// modified Hopfield) and elevation mapping functions (cosecant, Black & Eisner,
// Niell 1996, GMF). All delays in metres, elevations in radians.
//
// Slant delay model used by the estimators:
//   T = m_h(el) * ZHD + m_w(el) * ZWD,   d T / d ZWD = m_w(el).
#include <Eigen/Core>

namespace ppp {

/// Surface meteorological values at the receiver.
struct SurfaceMeteo {
  double pressure_hpa = 0.0;                ///< total pressure
  double temperature_k = 0.0;               ///< air temperature
  double water_vapour_pressure_hpa = 0.0;   ///< partial pressure of water vapour
};

/// Standard atmosphere at ellipsoidal height `height_m` (Berg 1948, as used by
/// RTKLIB and the GPS literature): P = 1013.25 (1 - 2.2557e-5 h)^5.2568 hPa,
/// T = 15 - 6.5e-3 h deg C, relative humidity RH0 exp(-6.396e-4 h); water vapour
/// pressure from the Magnus form e = RH 6.108 exp((17.15 T - 4684)/(T - 38.45)) hPa
/// (T in K). Heights are clamped to [-500, 11000] m (the troposphere).
SurfaceMeteo standardAtmosphere(double height_m, double relative_humidity_sea_level = 0.5);

/// Zenith hydrostatic delay [m] (Saastamoinen 1972 in the form of Davis et al. 1985):
/// ZHD = 0.0022768 P / (1 - 0.00266 cos 2 phi - 0.00028 H_km).
double saastamoinenZenithHydrostaticDelay_m(double pressure_hpa, double latitude_rad, double height_m);

/// Zenith wet delay [m] (Saastamoinen 1972): ZWD = 0.002277 (1255 / T + 0.05) e.
double saastamoinenZenithWetDelay_m(const SurfaceMeteo& meteo);

struct TroposphereDelays {
  double hydrostatic_m = 0.0;  ///< dry part
  double wet_m = 0.0;
};

/// Modified Hopfield slant delays (Goad & Goodman 1974; Hofmann-Wellenhof,
/// Lichtenegger & Wasle, "GNSS" 2008, sec. 5.3.2): quartic refractivity profiles
/// N_d0 = 77.64 P/T up to h_d = 40136 + 148.72 (T - 273.16) m and
/// N_w0 = -12.96 e/T + 3.718e5 e/T^2 up to h_w = 11000 m, integrated along the
/// straight ray with the 9-term series in r_i = sqrt((R+h_i)^2 - R^2 cos^2 E) - R sin E,
/// R being the receiver's geocentric radius (a + height_m). At E = 90 deg it
/// reduces to Hopfield's zenith delay 1e-6 N_0 h / 5.
TroposphereDelays modifiedHopfieldSlantDelays(const SurfaceMeteo& meteo, double elevation_rad,
                                              double height_m);
/// Zenith form of the modified Hopfield model.
TroposphereDelays modifiedHopfieldZenithDelays(const SurfaceMeteo& meteo, double height_m);

/// The modified Hopfield wet zenith delay of the standard atmosphere at height_m
/// over the one at the ellipsoid, w(h) / w(0): the factor that carries a zenith
/// wet delay from height 0 to the receiver (MeasurementModelOptions::zwd_at_ellipsoid).
double standardWetDelayHeightRatio(double height_m);

/// Simple mapping 1 / sin(el).
double cosecantMapping(double elevation_rad);
/// Black & Eisner (1984) mapping 1.001 / sqrt(0.002001 + sin^2 el), finite at the horizon.
double blackEisnerMapping(double elevation_rad);

struct MappingFunctions {
  double hydrostatic = 1.0;
  double wet = 1.0;
};

/// Marini (1972) continued fraction normalised to 1 at zenith (Herring 1992 form):
/// m = (1 + a/(1 + b/(1 + c))) / (sin e + a/(sin e + b/(sin e + c))).
double mariniMapping(double elevation_rad, double a, double b, double c);

/// Niell (1996) mapping functions ("Global mapping functions for the atmosphere
/// delay at radio wavelengths", JGR 101(B2), Tables 3 and 4): latitude-interpolated
/// average and seasonal (phase DOY 28, half a year later in the south)
/// coefficients plus the hydrostatic height correction. `day_of_year` is
/// fractional (1.0 = 1 January 0 h), `height_m` above sea level.
MappingFunctions niellMapping(double elevation_rad, double latitude_rad, double height_m,
                              double day_of_year);

/// Global Mapping Function (Boehm, Niell, Tregoning & Schuh 2006, GRL 33 L07304;
/// IERS Conventions 2010 sec. 9.2): a coefficients from a degree/order 9
/// spherical-harmonic expansion (mean + annual), b and c as in the paper,
/// Niell's height correction. `mjd` is the Modified Julian Date, `height_m`
/// above mean sea level.
MappingFunctions globalMappingFunction(double elevation_rad, double latitude_rad, double longitude_rad,
                                       double height_m, double mjd);

/// Slant tropospheric delay m_h ZHD + m_w ZWD [m].
inline double slantTroposphereDelay_m(const MappingFunctions& m, double zhd_m, double zwd_m) {
  return m.hydrostatic * zhd_m + m.wet * zwd_m;
}
/// Partial derivative of the slant delay with respect to the zenith wet delay (= m_w).
inline double slantDelayPartialWrtZwd(const MappingFunctions& m) { return m.wet; }

}  // namespace ppp
