#include "ppp_bayes_tree/models/sun_moon_position.h"

#include <cmath>

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

constexpr double kArcsecToRad = kDegToRad / 3600.0;
constexpr double kTtMinusTai_s = 32.184;   // IERS Conventions 2010, ch. 10
constexpr double kMjdJ2000 = 51544.5;      // 2000-01-01 12:00

/// Mean obliquity of the ecliptic of date [rad] (IAU 1976, Lieske et al. 1977,
/// truncated after the linear term: 23 26' 21.448" - 46.8150" T).
double meanObliquity_rad(double t) { return (23.43929111 - 0.0130041667 * t) * kDegToRad; }

/// Ecliptic (longitude, latitude, distance) of date -> mean equator of date.
Eigen::Vector3d eclipticToEquatorial(double lon_rad, double lat_rad, double r_m, double t) {
  const double eps = meanObliquity_rad(t);
  const double cb = std::cos(lat_rad), sb = std::sin(lat_rad);
  const double cl = std::cos(lon_rad), sl = std::sin(lon_rad);
  const double ce = std::cos(eps), se = std::sin(eps);
  return {r_m * cb * cl, r_m * (cb * sl * ce - sb * se), r_m * (cb * sl * se + sb * ce)};
}

/// Rotation about z by GMST: mean-of-date equatorial -> ECEF (R3(GMST)).
Eigen::Vector3d rotateByGmst(const Eigen::Vector3d& v, double gmst_rad) {
  const double c = std::cos(gmst_rad), s = std::sin(gmst_rad);
  return {c * v.x() + s * v.y(), -s * v.x() + c * v.y(), v.z()};
}

}  // namespace

double julianCenturiesTtSinceJ2000(const GnssTime& t) {
  const double mjd_tt = t.mjd(TimeSystem::TAI) + kTtMinusTai_s / 86400.0;
  return (mjd_tt - kMjdJ2000) / 36525.0;
}

double greenwichMeanSiderealTime_rad(double mjd_ut1) {
  // The 876600 h T term is 86400 s per day elapsed, so it contributes only the
  // fraction of the day: keep it separate to preserve precision.
  const double days = mjd_ut1 - kMjdJ2000;
  const double t = days / 36525.0;
  const double day_fraction = days - std::floor(days);
  double gmst_s = 67310.54841 + 8640184.812866 * t + 0.093104 * t * t - 6.2e-6 * t * t * t +
                  86400.0 * day_fraction;
  gmst_s = std::fmod(gmst_s, 86400.0);
  if (gmst_s < 0) gmst_s += 86400.0;
  return gmst_s * (2.0 * kPi / 86400.0);
}

Eigen::Vector3d sunPositionMeanOfDate_m(double t) {
  // Montenbruck & Gill (2000) eqs. 3.43-3.46. M&G hold the longitude of
  // perihelion (Omega + omega = 282.94 deg) fixed in the J2000 frame; of date it
  // moves by 1.71946 deg/century (Meeus, Astronomical Algorithms, ch. 31, Earth's
  // perihelion + 180 deg), which also refers the longitude to the equinox of date
  // (without it the error reaches 0.06 deg in 2020).
  const double m = (357.5256 + 35999.049 * t) * kDegToRad;  // mean anomaly
  const double lon = (282.9400 + 1.71946 * t) * kDegToRad + m +
                     (6892.0 * std::sin(m) + 72.0 * std::sin(2 * m)) * kArcsecToRad;
  const double r = (149.619 - 2.499 * std::cos(m) - 0.021 * std::cos(2 * m)) * 1e9;
  return eclipticToEquatorial(lon, 0.0, r, t);
}

Eigen::Vector3d moonPositionMeanOfDate_m(double t) {
  // Montenbruck & Gill (2000) eqs. 3.47-3.49 (Brown's theory, main terms); mean
  // longitude L0 of date (M&G's -1.3972 deg T precession term left out).
  const double L0 = (218.31617 + 481267.88088 * t) * kDegToRad;
  const double l = (134.96292 + 477198.86753 * t) * kDegToRad;   // Moon mean anomaly
  const double lp = (357.52543 + 35999.04944 * t) * kDegToRad;   // Sun mean anomaly
  const double F = (93.27283 + 483202.01873 * t) * kDegToRad;    // mean argument of latitude
  const double D = (297.85027 + 445267.11135 * t) * kDegToRad;   // mean elongation
  const double dlon_arcsec =
      22640 * std::sin(l) + 769 * std::sin(2 * l) - 4586 * std::sin(l - 2 * D) + 2370 * std::sin(2 * D) -
      668 * std::sin(lp) - 412 * std::sin(2 * F) - 212 * std::sin(2 * l - 2 * D) -
      206 * std::sin(l + lp - 2 * D) + 192 * std::sin(l + 2 * D) - 165 * std::sin(lp - 2 * D) +
      148 * std::sin(l - lp) - 125 * std::sin(D) - 110 * std::sin(l + lp) - 55 * std::sin(2 * F - 2 * D);
  const double lon = L0 + dlon_arcsec * kArcsecToRad;
  const double s = F + (dlon_arcsec + 412 * std::sin(2 * F) + 541 * std::sin(lp)) * kArcsecToRad;
  const double h = F - 2 * D;
  const double lat_arcsec = 18520 * std::sin(s) - 526 * std::sin(h) + 44 * std::sin(l + h) -
                            31 * std::sin(-l + h) - 23 * std::sin(lp + h) + 11 * std::sin(-lp + h) -
                            25 * std::sin(-2 * l + F) + 21 * std::sin(-l + F);
  const double r_km = 385000 - 20905 * std::cos(l) - 3699 * std::cos(2 * D - l) - 2956 * std::cos(2 * D) -
                      570 * std::cos(2 * l) + 246 * std::cos(2 * l - 2 * D) - 205 * std::cos(lp - 2 * D) -
                      171 * std::cos(l + 2 * D) - 152 * std::cos(l + lp - 2 * D);
  return eclipticToEquatorial(lon, lat_arcsec * kArcsecToRad, r_km * 1e3, t);
}

SunMoonPositions sunMoonPositionsEcef(const GnssTime& t, double ut1_minus_utc_s) {
  const double tt = julianCenturiesTtSinceJ2000(t);
  const double gmst = greenwichMeanSiderealTime_rad(t.mjd(TimeSystem::UTC) + ut1_minus_utc_s / 86400.0);
  return {rotateByGmst(sunPositionMeanOfDate_m(tt), gmst), rotateByGmst(moonPositionMeanOfDate_m(tt), gmst)};
}

Eigen::Vector3d sunPositionEcef_m(const GnssTime& t, double ut1_minus_utc_s) {
  const double gmst = greenwichMeanSiderealTime_rad(t.mjd(TimeSystem::UTC) + ut1_minus_utc_s / 86400.0);
  return rotateByGmst(sunPositionMeanOfDate_m(julianCenturiesTtSinceJ2000(t)), gmst);
}

Eigen::Vector3d moonPositionEcef_m(const GnssTime& t, double ut1_minus_utc_s) {
  const double gmst = greenwichMeanSiderealTime_rad(t.mjd(TimeSystem::UTC) + ut1_minus_utc_s / 86400.0);
  return rotateByGmst(moonPositionMeanOfDate_m(julianCenturiesTtSinceJ2000(t)), gmst);
}

}  // namespace ppp
