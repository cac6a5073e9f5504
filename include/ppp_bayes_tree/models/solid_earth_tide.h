#pragma once
// Solid Earth tide station displacement, IERS Conventions 2010 (TN 36),
// sec. 7.1.1, step 1: in-phase degree-2 (eq. 7.5) and degree-3 (eq. 7.6)
// displacement due to the Moon and the Sun, with the latitude dependence of
// h2 and l2 (eq. 7.2): h2 = 0.6078 - 0.0006 (3 sin^2 phi - 1)/2,
// l2 = 0.0847 + 0.0002 (3 sin^2 phi - 1)/2, h3 = 0.292, l3 = 0.015.
// Step-1 out-of-phase terms, the step-2 frequency-dependent corrections (< ~13 mm
// radial, mostly K1) and pole tide are not modelled.
//
// Permanent tide: the displacement includes the permanent (zero-frequency)
// part, so applied to a "conventional tide free" ITRF coordinate it gives the
// instantaneous position, which is the IERS convention (sec. 7.1.1 "permanent
// tide"); do NOT remove it when working with ITRF/IGS products.
#include <Eigen/Core>

#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

/// GM_Sun / GM_Earth and M_Moon / M_Earth (IERS Conventions 2010 Table 1.1 values, as
/// used by the IERS DEHANTTIDEINEL software).
constexpr double kSunEarthGmRatio = 332946.0482;
constexpr double kMoonEarthMassRatio = 0.0123000371;
/// Equatorial radius of the Earth used by the tide formulas [m] (IERS 2010, Table 1.1).
constexpr double kIersEarthRadius_m = 6378136.6;

/// Displacement [m, ECEF] of the station at `station_ecef_m` caused by one body
/// at `body_ecef_m` whose GM is `gm_ratio` times the Earth's (eqs. 7.5 and 7.6).
Eigen::Vector3d bodyTideDisplacementEcef_m(const Eigen::Vector3d& station_ecef_m,
                                           const Eigen::Vector3d& body_ecef_m, double gm_ratio);

/// Sum of the Sun and Moon contributions [m, ECEF] for given body positions.
Eigen::Vector3d solidEarthTideDisplacementEcef_m(const Eigen::Vector3d& station_ecef_m,
                                                 const Eigen::Vector3d& sun_ecef_m,
                                                 const Eigen::Vector3d& moon_ecef_m);

/// Same, with the Sun and Moon from sunMoonPositionsEcef(t, ut1_minus_utc_s).
Eigen::Vector3d solidEarthTideDisplacementEcef_m(const Eigen::Vector3d& station_ecef_m, const GnssTime& t,
                                                 double ut1_minus_utc_s = 0.0);

}  // namespace ppp
