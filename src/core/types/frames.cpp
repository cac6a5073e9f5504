#include "ppp_bayes_tree/types/frames.h"

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <cmath>

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

Geodetic ecefToGeodetic(const Eigen::Vector3d& p) {
  const auto& earth = GeographicLib::Geocentric::WGS84();
  double lat_deg = 0, lon_deg = 0, h = 0;
  earth.Reverse(p.x(), p.y(), p.z(), lat_deg, lon_deg, h);
  return {lat_deg * kDegToRad, lon_deg * kDegToRad, h};
}

Eigen::Vector3d geodeticToEcef(const Geodetic& g) {
  const auto& earth = GeographicLib::Geocentric::WGS84();
  Eigen::Vector3d p;
  earth.Forward(g.latitude_rad * kRadToDeg, g.longitude_rad * kRadToDeg, g.height_m, p.x(), p.y(),
                p.z());
  return p;
}

Eigen::Matrix3d rotationEnuFromEcef(double lat, double lon) {
  const double sl = std::sin(lat), cl = std::cos(lat), so = std::sin(lon), co = std::cos(lon);
  Eigen::Matrix3d R_enu_ecef;
  R_enu_ecef << -so, co, 0.0,
                -sl * co, -sl * so, cl,
                cl * co, cl * so, sl;
  return R_enu_ecef;
}

Eigen::Vector3d ecefToEnu(const Eigen::Vector3d& point_ecef_m, const Eigen::Vector3d& origin_ecef_m) {
  const Geodetic g = ecefToGeodetic(origin_ecef_m);
  return rotationEnuFromEcef(g.latitude_rad, g.longitude_rad) * (point_ecef_m - origin_ecef_m);
}

Eigen::Vector3d enuToEcef(const Eigen::Vector3d& enu_m, const Eigen::Vector3d& origin_ecef_m) {
  const Geodetic g = ecefToGeodetic(origin_ecef_m);
  return origin_ecef_m + rotationEnuFromEcef(g.latitude_rad, g.longitude_rad).transpose() * enu_m;
}

AzimuthElevation azimuthElevation(const Eigen::Vector3d& receiver_ecef_m,
                                  const Eigen::Vector3d& target_ecef_m) {
  const Eigen::Vector3d enu = ecefToEnu(target_ecef_m, receiver_ecef_m);
  AzimuthElevation ae;
  ae.azimuth_rad = std::atan2(enu.x(), enu.y());
  if (ae.azimuth_rad < 0) ae.azimuth_rad += 2 * kPi;
  ae.elevation_rad = std::atan2(enu.z(), std::hypot(enu.x(), enu.y()));
  return ae;
}

}  // namespace ppp
