#include "ppp_bayes_tree/models/satellite_eclipse.h"

#include <algorithm>
#include <cmath>

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

bool inCylindricalShadow(const Eigen::Vector3d& sat, const Eigen::Vector3d& sun) {
  const Eigen::Vector3d e_sun = sun.normalized();
  const double along = sat.dot(e_sun);
  return along < 0.0 && (sat - along * e_sun).norm() < kWgs84SemiMajorAxis_m;
}

double sunlightFraction(const Eigen::Vector3d& sat, const Eigen::Vector3d& sun) {
  const Eigen::Vector3d to_sun = sun - sat;
  const double d_sun = to_sun.norm(), d_earth = sat.norm();
  if (d_earth <= kWgs84SemiMajorAxis_m) return 0.0;  // inside the Earth: no light
  const double a = std::asin(std::min(1.0, kSunRadius_m / d_sun));           // apparent Sun radius
  const double b = std::asin(kWgs84SemiMajorAxis_m / d_earth);               // apparent Earth radius
  const double cos_c = std::clamp(-sat.dot(to_sun) / (d_earth * d_sun), -1.0, 1.0);
  const double c = std::acos(cos_c);                                         // apparent separation
  if (c >= a + b) return 1.0;                   // no overlap
  if (c <= b - a) return 0.0;                   // Sun disc fully behind the Earth (umbra)
  if (c <= a - b) return 1.0 - (b * b) / (a * a);  // Earth disc inside the Sun disc (annular)
  // Partial overlap of two discs (M&G eq. 3.87).
  const double x = (c * c + a * a - b * b) / (2.0 * c);
  const double y = std::sqrt(std::max(0.0, a * a - x * x));
  const double area = a * a * std::acos(std::clamp(x / a, -1.0, 1.0)) +
                      b * b * std::acos(std::clamp((c - x) / b, -1.0, 1.0)) - c * y;
  return std::clamp(1.0 - area / (kPi * a * a), 0.0, 1.0);
}

EclipseState eclipseState(const Eigen::Vector3d& sat, const Eigen::Vector3d& sun) {
  const double f = sunlightFraction(sat, sun);
  if (f <= 0.0) return EclipseState::Umbra;
  if (f >= 1.0) return EclipseState::Sunlit;
  return EclipseState::Penumbra;
}

}  // namespace ppp
