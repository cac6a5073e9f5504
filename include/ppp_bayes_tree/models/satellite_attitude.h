#pragma once
// Nominal GNSS satellite attitude (yaw steering): body axes in ECEF.
//
// IGS convention (Kouba 2009, "A simplified yaw-attitude model for eclipsing
// GPS satellites", GPS Solutions 13:1-12; Montenbruck et al. 2015, "GNSS
// satellite geometry and attitude models", Adv. Space Res. 56:1015-1029):
//   e_z = -r/|r|                       (antenna boresight, towards the Earth centre)
//   e_y = e_z x e_sun / |e_z x e_sun|  (solar panel axis, e_sun: satellite -> Sun)
//   e_x = e_y x e_z                    (completes the right-handed triad; points
//                                       into the Sun-lit hemisphere)
// Equivalently, with the orbit frame e_r = r/|r|, n = r x v_inertial normalised,
// e_t = n x e_r and the yaw angle psi = atan2(-tan beta, sin mu) (beta: Sun
// elevation above the orbit plane, mu: orbit angle from orbit midnight):
//   e_x = cos(psi) e_t - sin(psi) n,  e_y = -cos(psi) n - sin(psi) e_t.
// The yaw form lets eclipse/noon-turn yaw models (later) supply their own psi.
#include <Eigen/Core>

namespace ppp {

struct SatelliteBodyAxes {
  Eigen::Vector3d x_ecef = Eigen::Vector3d::UnitX();
  Eigen::Vector3d y_ecef = Eigen::Vector3d::UnitY();
  Eigen::Vector3d z_ecef = Eigen::Vector3d::UnitZ();
};

struct OrbitSunAngles {
  double beta_rad = 0.0;  ///< Sun elevation above the orbit plane (positive on the orbit-normal side)
  double mu_rad = 0.0;    ///< orbit angle of the satellite from orbit midnight, along the motion, [-pi, pi]
};

/// Inertial-axes velocity of an ECEF state: v + omega_e x r (the ECEF velocity
/// misses the Earth rotation; the orbit normal needs the inertial one).
Eigen::Vector3d inertialVelocity_mps(const Eigen::Vector3d& position_ecef_m, const Eigen::Vector3d& velocity_ecef_mps);

/// beta and mu from the ECEF satellite state and the Sun position.
OrbitSunAngles orbitSunAngles(const Eigen::Vector3d& position_ecef_m, const Eigen::Vector3d& velocity_ecef_mps,
                              const Eigen::Vector3d& sun_ecef_m);

/// Nominal yaw angle psi = atan2(-tan beta, sin mu) [rad] (Kouba 2009 eq. 1 form).
double nominalYawAngle_rad(const OrbitSunAngles& angles);

/// Body axes for a given yaw angle (orbit-frame form above).
SatelliteBodyAxes satelliteAxesFromYaw(const Eigen::Vector3d& position_ecef_m,
                                       const Eigen::Vector3d& velocity_ecef_mps, double yaw_rad);

/// Nominal yaw-steering axes from the Sun direction; when the Sun is (numerically)
/// on the e_z line (|e_z x e_sun| < 1e-9: orbit noon/midnight with beta = 0) the
/// yaw form with psi = atan2(-tan beta, sin mu) is used instead.
SatelliteBodyAxes nominalSatelliteAxes(const Eigen::Vector3d& position_ecef_m,
                                       const Eigen::Vector3d& velocity_ecef_mps, const Eigen::Vector3d& sun_ecef_m);

}  // namespace ppp
