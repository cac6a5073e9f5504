#include "ppp_bayes_tree/models/solid_earth_tide.h"

#include "ppp_bayes_tree/models/sun_moon_position.h"

namespace ppp {

Eigen::Vector3d bodyTideDisplacementEcef_m(const Eigen::Vector3d& station_ecef_m,
                                           const Eigen::Vector3d& body_ecef_m, double gm_ratio) {
  const double r_station = station_ecef_m.norm();
  const double r_body = body_ecef_m.norm();
  if (r_station <= 0.0 || r_body <= 0.0 || gm_ratio == 0.0) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d r_hat = station_ecef_m / r_station;
  const Eigen::Vector3d body_hat = body_ecef_m / r_body;
  const double c = body_hat.dot(r_hat);               // cosine of the body's zenith angle
  const Eigen::Vector3d horizontal = body_hat - c * r_hat;  // tangential direction to the body

  // IERS 2010 eq. 7.2: latitude dependence, sin(phi) geocentric.
  const double sin_lat = r_hat.z();
  const double p2_lat = 0.5 * (3.0 * sin_lat * sin_lat - 1.0);
  const double h2 = 0.6078 - 0.0006 * p2_lat;
  const double l2 = 0.0847 + 0.0002 * p2_lat;
  constexpr double h3 = 0.292, l3 = 0.015;

  const double ratio = kIersEarthRadius_m / r_body;
  const double scale2 = gm_ratio * kIersEarthRadius_m * ratio * ratio * ratio;  // GM_j/GM_E R^4/R_j^3
  const double scale3 = scale2 * ratio;                                          // GM_j/GM_E R^5/R_j^4
  // Degree 2 (eq. 7.5) and degree 3 (eq. 7.6).
  const Eigen::Vector3d d2 = scale2 * (h2 * (1.5 * c * c - 0.5) * r_hat + 3.0 * l2 * c * horizontal);
  const Eigen::Vector3d d3 =
      scale3 * (h3 * (2.5 * c * c * c - 1.5 * c) * r_hat + l3 * (7.5 * c * c - 1.5) * horizontal);
  return d2 + d3;
}

Eigen::Vector3d solidEarthTideDisplacementEcef_m(const Eigen::Vector3d& station_ecef_m,
                                                 const Eigen::Vector3d& sun_ecef_m,
                                                 const Eigen::Vector3d& moon_ecef_m) {
  return bodyTideDisplacementEcef_m(station_ecef_m, sun_ecef_m, kSunEarthGmRatio) +
         bodyTideDisplacementEcef_m(station_ecef_m, moon_ecef_m, kMoonEarthMassRatio);
}

Eigen::Vector3d solidEarthTideDisplacementEcef_m(const Eigen::Vector3d& station_ecef_m, const GnssTime& t,
                                                 double ut1_minus_utc_s) {
  const SunMoonPositions sm = sunMoonPositionsEcef(t, ut1_minus_utc_s);
  return solidEarthTideDisplacementEcef_m(station_ecef_m, sm.sun_ecef_m, sm.moon_ecef_m);
}

}  // namespace ppp
