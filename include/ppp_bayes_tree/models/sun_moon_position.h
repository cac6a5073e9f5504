#pragma once
// Low-precision Sun and Moon positions in ECEF, for solid-Earth tides, phase
// wind-up, satellite attitude and eclipses (accuracy ~0.01 deg Sun, ~0.1 deg
// Moon, ample for those uses).
//
// Method: the analytical series of Montenbruck & Gill, "Satellite Orbits"
// (2000), sec. 3.3.2 (eqs. 3.43-3.49), written in the mean ecliptic and
// equinox OF DATE (Sun: perihelion longitude of date; Moon: M&G's mean
// longitude without their -1.3972 deg/century precession term), rotated to the mean equator of date by the obliquity of date and then
// to ECEF by Greenwich mean sidereal time (IAU 1982). Nutation (<= 17") and
// polar motion (< 1") are neglected.
#include <Eigen/Core>

#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

/// Julian centuries of Terrestrial Time since J2000.0 (2000-01-01 12:00 TT),
/// with TT = TAI + 32.184 s (IERS Conventions 2010, ch. 10).
double julianCenturiesTtSinceJ2000(const GnssTime& t);

/// Greenwich mean sidereal time [rad, in [0, 2 pi)] at the UT1 instant given as a
/// Modified Julian Date (IAU 1982 expression, Aoki et al. 1982; Vallado,
/// "Fundamentals of Astrodynamics", eq. 3-47):
/// GMST = 67310.54841 s + (876600 h + 8640184.812866 s) T + 0.093104 s T^2 - 6.2e-6 s T^3.
double greenwichMeanSiderealTime_rad(double mjd_ut1);

/// Sun position in the mean equator and equinox of date [m], TT centuries since J2000.
Eigen::Vector3d sunPositionMeanOfDate_m(double tt_centuries_since_j2000);
/// Moon position in the mean equator and equinox of date [m], TT centuries since J2000.
Eigen::Vector3d moonPositionMeanOfDate_m(double tt_centuries_since_j2000);

struct SunMoonPositions {
  Eigen::Vector3d sun_ecef_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d moon_ecef_m = Eigen::Vector3d::Zero();
};

/// Sun and Moon in ECEF at the GPST instant `t`. `ut1_minus_utc_s` is UT1-UTC
/// (IERS Bulletin A, |value| < 0.9 s); taking UT1 = UTC costs at most
/// 0.9 s * 15"/s = 0.004 deg of Earth rotation.
SunMoonPositions sunMoonPositionsEcef(const GnssTime& t, double ut1_minus_utc_s = 0.0);
Eigen::Vector3d sunPositionEcef_m(const GnssTime& t, double ut1_minus_utc_s = 0.0);
Eigen::Vector3d moonPositionEcef_m(const GnssTime& t, double ut1_minus_utc_s = 0.0);

}  // namespace ppp
