#include "ppp_bayes_tree/models/relativity.h"

#include <cmath>

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

double relativisticClockCorrection_s(const Eigen::Vector3d& r, const Eigen::Vector3d& v) {
  return -2.0 * r.dot(v) / (kSpeedOfLight_mps * kSpeedOfLight_mps);
}

double shapiroDelay_m(const Eigen::Vector3d& satellite_ecef_m, const Eigen::Vector3d& receiver_ecef_m,
                      double gm_m3ps2) {
  const double rs = satellite_ecef_m.norm();
  const double rr = receiver_ecef_m.norm();
  const double rho = (satellite_ecef_m - receiver_ecef_m).norm();
  return 2.0 * gm_m3ps2 / (kSpeedOfLight_mps * kSpeedOfLight_mps) * std::log((rs + rr + rho) / (rs + rr - rho));
}

}  // namespace ppp
