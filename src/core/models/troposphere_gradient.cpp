#include "ppp_bayes_tree/models/troposphere_gradient.h"

#include <cmath>

namespace ppp {

double gradientMapping(double elevation_rad) {
  return 1.0 / (std::sin(elevation_rad) * std::tan(elevation_rad) + kChenHerringGradientConstant);
}

GradientPartials gradientPartials(double elevation_rad, double azimuth_rad) {
  const double m_g = gradientMapping(elevation_rad);
  return {m_g * std::cos(azimuth_rad), m_g * std::sin(azimuth_rad)};
}

double slantGradientDelay_m(double elevation_rad, double azimuth_rad, double gradient_north_m,
                            double gradient_east_m) {
  const GradientPartials p = gradientPartials(elevation_rad, azimuth_rad);
  return p.north * gradient_north_m + p.east * gradient_east_m;
}

}  // namespace ppp
