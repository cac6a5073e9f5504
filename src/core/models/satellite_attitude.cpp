#include "ppp_bayes_tree/models/satellite_attitude.h"

#include <cmath>

#include <Eigen/Geometry>

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

struct OrbitFrame {
  Eigen::Vector3d radial, along_track, normal;
};

OrbitFrame orbitFrame(const Eigen::Vector3d& r, const Eigen::Vector3d& v_ecef) {
  OrbitFrame f;
  f.radial = r.normalized();
  f.normal = r.cross(inertialVelocity_mps(r, v_ecef)).normalized();
  f.along_track = f.normal.cross(f.radial);
  return f;
}

}  // namespace

Eigen::Vector3d inertialVelocity_mps(const Eigen::Vector3d& r, const Eigen::Vector3d& v) {
  return v + Eigen::Vector3d(0.0, 0.0, kEarthRotationRate_radps).cross(r);
}

OrbitSunAngles orbitSunAngles(const Eigen::Vector3d& r, const Eigen::Vector3d& v, const Eigen::Vector3d& sun) {
  const OrbitFrame f = orbitFrame(r, v);
  const Eigen::Vector3d e_sun = (sun - r).normalized();
  OrbitSunAngles a;
  a.beta_rad = std::asin(std::max(-1.0, std::min(1.0, e_sun.dot(f.normal))));
  // Orbit midnight: in-plane direction opposite to the Sun. mu is the angle from
  // it to the radial direction, positive along the motion (about the normal).
  const Eigen::Vector3d midnight = -(e_sun - e_sun.dot(f.normal) * f.normal);
  a.mu_rad = std::atan2(midnight.cross(f.radial).dot(f.normal), midnight.dot(f.radial));
  return a;
}

double nominalYawAngle_rad(const OrbitSunAngles& a) { return std::atan2(-std::tan(a.beta_rad), std::sin(a.mu_rad)); }

SatelliteBodyAxes satelliteAxesFromYaw(const Eigen::Vector3d& r, const Eigen::Vector3d& v, double yaw_rad) {
  const OrbitFrame f = orbitFrame(r, v);
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  SatelliteBodyAxes axes;
  axes.z_ecef = -f.radial;
  axes.x_ecef = c * f.along_track - s * f.normal;
  axes.y_ecef = -c * f.normal - s * f.along_track;
  return axes;
}

SatelliteBodyAxes nominalSatelliteAxes(const Eigen::Vector3d& r, const Eigen::Vector3d& v,
                                       const Eigen::Vector3d& sun) {
  const Eigen::Vector3d ez = -r.normalized();
  const Eigen::Vector3d e_sun = (sun - r).normalized();
  const Eigen::Vector3d y = ez.cross(e_sun);
  const double norm = y.norm();
  if (norm < 1e-9) return satelliteAxesFromYaw(r, v, nominalYawAngle_rad(orbitSunAngles(r, v, sun)));
  SatelliteBodyAxes axes;
  axes.z_ecef = ez;
  axes.y_ecef = y / norm;
  axes.x_ecef = axes.y_ecef.cross(ez);
  return axes;
}

}  // namespace ppp
