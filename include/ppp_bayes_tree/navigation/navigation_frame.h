#pragma once
// NavigationFrame: what the world frame W of a NavState contributes to the motion
// between two IMU epochs: the gravity vector (gravitation plus the centrifugal
// term of the Earth's rotation) and the Earth's rotation rate, both in W.
//
// Two uses:
// - ECEF (the estimators' frame): gravity from the WGS 84 normal gravity at the
//   position, earth rate (0, 0, 7.2921151467e-5) rad/s. The prediction then
//   accounts for the rotating frame (attitude transport, Coriolis, the rotation
//   of gravity during the interval; see imu_preintegration.h).
// - A local-level frame treated as non-rotating: gravity (0, 0, -g) in ENU and
//   earth rate zero. Only valid with a zero earth rate (positions there are not
//   geocentric); adequate for consumer MEMS over short spans.
#include <Eigen/Core>

namespace ppp {

struct NavigationFrame {
  Eigen::Vector3d gravity_world_mps2 = Eigen::Vector3d(0.0, 0.0, -9.80665);
  Eigen::Vector3d earth_rate_world_radps = Eigen::Vector3d::Zero();
};

/// Magnitude of WGS 84 normal gravity [m/s^2] at geodetic latitude and
/// ellipsoidal height: Somigliana's closed formula on the ellipsoid with the
/// second-order height correction (NIMA TR8350.2, 3rd ed., eqs. 4-1 and 4-3).
double normalGravity_mps2(double latitude_rad, double height_m);

/// The ECEF frame at `position_ecef_m`: normal gravity along the downward
/// ellipsoid normal (deflection of the vertical neglected, < ~1e-4 rad) and the
/// WGS 84 Earth rotation rate about z.
NavigationFrame ecefNavigationFrame(const Eigen::Vector3d& position_ecef_m);

/// A local-level (ENU) frame treated as non-rotating, with gravity (0, 0, -g).
NavigationFrame localLevelNavigationFrame(double gravity_mps2);

}  // namespace ppp

namespace ppp {

/// What gravity and the frame's rotation add over an interval dt starting at
/// position p_i, in the frame W frozen at the start of the interval (an inertial
/// frame when W rotates with the Earth, rate w):
///   frame_rotation  Q = Exp(w dt) (W at the end -> W frozen at the start),
///   gravitation     gamma = g + w x (w x p_i) (gravity without the centrifugal term),
///   velocity        int_0^dt Exp(w t) gamma dt       = gamma dt + dt^2/2 w x gamma + ...,
///   position        double integral of the same      = gamma dt^2/2 + dt^3/6 w x gamma + ...
/// (series summed to double precision; gravitation held at its value at p_i,
/// whose change with the position over an interval is below 1e-8 relative). With
/// w = 0 they are g dt and g dt^2/2.
struct FrameIntegrals {
  Eigen::Matrix3d frame_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  /// d velocity_mps / d p_i and d position_m / d p_i (through the centrifugal term).
  Eigen::Matrix3d d_velocity_d_position = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d d_position_d_position = Eigen::Matrix3d::Zero();
};

FrameIntegrals frameIntegrals(const NavigationFrame& frame, const Eigen::Vector3d& position_i_world_m,
                              double dt_s);

}  // namespace ppp
