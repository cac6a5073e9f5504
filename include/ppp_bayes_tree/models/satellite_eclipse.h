#pragma once
// Satellite eclipse by the Earth: cylindrical and conical shadow models
// (Montenbruck & Gill, "Satellite Orbits" 2000, sec. 3.4.2, eqs. 3.79-3.87).
// Earth taken as a sphere of the WGS 84 equatorial radius.
#include <Eigen/Core>

namespace ppp {

/// Mean solar radius [m] (IAU 2015 Resolution B3 nominal value).
constexpr double kSunRadius_m = 6.957e8;

enum class EclipseState { Sunlit, Penumbra, Umbra };

/// Cylindrical shadow (M&G eq. 3.79): in shadow when the satellite is on the
/// night side (r . e_sun < 0) and less than one Earth radius from the Earth-Sun line.
bool inCylindricalShadow(const Eigen::Vector3d& satellite_ecef_m, const Eigen::Vector3d& sun_ecef_m);

/// Fraction of the solar disc visible from the satellite, in [0, 1] (conical
/// model, M&G eqs. 3.85-3.87: overlap of the apparent Sun and Earth discs).
double sunlightFraction(const Eigen::Vector3d& satellite_ecef_m, const Eigen::Vector3d& sun_ecef_m);

/// Umbra (fraction 0), penumbra (0 < fraction < 1) or sunlit (1).
EclipseState eclipseState(const Eigen::Vector3d& satellite_ecef_m, const Eigen::Vector3d& sun_ecef_m);

}  // namespace ppp
