#pragma once
// Relativistic corrections of GNSS observations.
#include <Eigen/Core>

namespace ppp {

/// GM of the Earth used for the Shapiro delay [m^3/s^2] (IERS Conventions 2010, Table 1.1).
constexpr double kGmEarthIers_m3ps2 = 3.986004418e14;

/// Periodic relativistic satellite clock correction [s], -2 r.v / c^2 (IS-GPS-200
/// 20.3.3.3.3.1, equal to F e sqrt(A) sin E for a Kepler orbit; IERS Conventions
/// 2010 eq. 10.19). ADD it to the broadcast/precise satellite clock offset.
/// r.v is the same in ECEF and inertial axes (r . (omega x r) = 0), so an ECEF
/// position and velocity may be used directly.
double relativisticClockCorrection_s(const Eigen::Vector3d& satellite_position_m,
                                     const Eigen::Vector3d& satellite_velocity_mps);

/// Shapiro (gravitational) signal delay [m] (IERS Conventions 2010 eq. 11.17):
/// 2 GM / c^2 ln((r_s + r_r + rho) / (r_s + r_r - rho)); add it to the modelled
/// range. Up to ~19 mm for GPS at the horizon, ~13 mm at zenith.
double shapiroDelay_m(const Eigen::Vector3d& satellite_ecef_m, const Eigen::Vector3d& receiver_ecef_m,
                      double gm_m3ps2 = kGmEarthIers_m3ps2);

}  // namespace ppp
