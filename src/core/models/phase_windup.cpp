#include "ppp_bayes_tree/models/phase_windup.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp {

ReceiverAntennaAxes northWestAntennaAxes(double latitude_rad, double longitude_rad) {
  const Eigen::Matrix3d R = rotationEnuFromEcef(latitude_rad, longitude_rad);  // rows: E, N, U in ECEF
  ReceiverAntennaAxes axes;
  axes.x_ecef = R.row(1).transpose();
  axes.y_ecef = -R.row(0).transpose();
  return axes;
}

std::optional<double> phaseWindup_cycles(const SatelliteBodyAxes& sat, const ReceiverAntennaAxes& rcv,
                                         const Eigen::Vector3d& satellite_ecef_m,
                                         const Eigen::Vector3d& receiver_ecef_m,
                                         std::optional<double> previous_cycles) {
  const Eigen::Vector3d k = (receiver_ecef_m - satellite_ecef_m).normalized();
  const Eigen::Vector3d d_sat = sat.x_ecef - k * k.dot(sat.x_ecef) - k.cross(sat.y_ecef);
  const Eigen::Vector3d d_rcv = rcv.x_ecef - k * k.dot(rcv.x_ecef) + k.cross(rcv.y_ecef);
  const double n_sat = d_sat.norm(), n_rcv = d_rcv.norm();
  if (!(n_sat > 1e-12) || !(n_rcv > 1e-12)) return std::nullopt;
  const double cos_angle = std::clamp(d_sat.dot(d_rcv) / (n_sat * n_rcv), -1.0, 1.0);
  double windup = std::acos(cos_angle) / (2.0 * kPi);
  if (k.dot(d_sat.cross(d_rcv)) < 0.0) windup = -windup;
  if (previous_cycles) windup += std::round(*previous_cycles - windup);
  return windup;
}

}  // namespace ppp
