#pragma once
// Earth-fixed frames: ECEF (WGS 84 ellipsoid, which matches GRS80/ITRF to 0.1 mm
// in geodetic conversion), geodetic latitude/longitude/height, and local
// East-North-Up. Conversions go through GeographicLib (Karney 2011), not a
// hand-written iteration.
#include <Eigen/Core>

namespace ppp {

struct Geodetic {
  double latitude_rad = 0.0;
  double longitude_rad = 0.0;
  double height_m = 0.0;  // ellipsoidal height
};

Geodetic ecefToGeodetic(const Eigen::Vector3d& position_ecef_m);
Eigen::Vector3d geodeticToEcef(const Geodetic& geodetic);

/// Rotation taking an ECEF vector into the local ENU frame at (lat, lon).
Eigen::Matrix3d rotationEnuFromEcef(double latitude_rad, double longitude_rad);
/// ENU coordinates of `point_ecef_m` relative to `origin_ecef_m` (axes at the origin).
Eigen::Vector3d ecefToEnu(const Eigen::Vector3d& point_ecef_m, const Eigen::Vector3d& origin_ecef_m);
Eigen::Vector3d enuToEcef(const Eigen::Vector3d& enu_m, const Eigen::Vector3d& origin_ecef_m);

struct AzimuthElevation {
  double azimuth_rad = 0.0;    // from north, clockwise, [0, 2 pi)
  double elevation_rad = 0.0;  // above the ellipsoid tangent plane
};
/// Azimuth and elevation of `target_ecef_m` seen from `receiver_ecef_m`.
AzimuthElevation azimuthElevation(const Eigen::Vector3d& receiver_ecef_m,
                                  const Eigen::Vector3d& target_ecef_m);

}  // namespace ppp
