#include "ppp_bayes_tree/navigation/navigation_frame.h"

#include <Eigen/Geometry>
#include <cmath>

#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp {
namespace {

// WGS 84 normal gravity constants (NIMA TR8350.2, 3rd ed., tables 3.4 and 3.5).
constexpr double kGravityEquator_mps2 = 9.7803253359;
constexpr double kSomiglianaK = 0.00193185265241;
constexpr double kFirstEccentricitySquared = 0.00669437999013;
constexpr double kGravityRatioM = 0.00344978650684;  // omega^2 a^2 b / GM

}  // namespace

double normalGravity_mps2(double latitude_rad, double height_m) {
  const double s2 = std::sin(latitude_rad) * std::sin(latitude_rad);
  const double on_ellipsoid =
      kGravityEquator_mps2 * (1.0 + kSomiglianaK * s2) / std::sqrt(1.0 - kFirstEccentricitySquared * s2);
  const double a = kWgs84SemiMajorAxis_m;
  const double f = kWgs84Flattening;
  const double height_factor =
      1.0 - 2.0 / a * (1.0 + f + kGravityRatioM - 2.0 * f * s2) * height_m + 3.0 * height_m * height_m / (a * a);
  return on_ellipsoid * height_factor;
}

NavigationFrame ecefNavigationFrame(const Eigen::Vector3d& position_ecef_m) {
  const Geodetic geo = ecefToGeodetic(position_ecef_m);
  const double cl = std::cos(geo.latitude_rad);
  const Eigen::Vector3d up(cl * std::cos(geo.longitude_rad), cl * std::sin(geo.longitude_rad),
                           std::sin(geo.latitude_rad));
  NavigationFrame frame;
  frame.gravity_world_mps2 = -normalGravity_mps2(geo.latitude_rad, geo.height_m) * up;
  frame.earth_rate_world_radps = Eigen::Vector3d(0.0, 0.0, kEarthRotationRate_radps);
  return frame;
}

NavigationFrame localLevelNavigationFrame(double gravity_mps2) {
  NavigationFrame frame;
  frame.gravity_world_mps2 = Eigen::Vector3d(0.0, 0.0, -gravity_mps2);
  return frame;
}

}  // namespace ppp

#include "ppp_bayes_tree/navigation/so3.h"

namespace ppp {

namespace {

/// sum_n dt^(n + order) / (n + order)! [w]x^n for order 1 (the integral of Exp([w]x t)
/// over [0, dt]) and order 2 (its double integral); the terms fall by |w| dt / n, so
/// eight of them reach double precision for any interval shorter than hours.
Eigen::Matrix3d rotationIntegral(const Eigen::Matrix3d& w_hat, double dt_s, int order) {
  constexpr int kTerms = 8;
  double coefficient = 1.0;
  for (int k = 1; k <= order; ++k) coefficient *= dt_s / k;
  Eigen::Matrix3d power = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d sum = coefficient * power;
  for (int n = 1; n < kTerms; ++n) {
    coefficient *= dt_s / (n + order);
    power = power * w_hat;
    sum += coefficient * power;
  }
  return sum;
}

}  // namespace

FrameIntegrals frameIntegrals(const NavigationFrame& frame, const Eigen::Vector3d& position_i_world_m,
                              double dt_s) {
  const Eigen::Vector3d& w = frame.earth_rate_world_radps;
  const Eigen::Matrix3d w_hat = so3::hat(w);
  const Eigen::Vector3d gamma = frame.gravity_world_mps2 + w.cross(w.cross(position_i_world_m));
  const Eigen::Matrix3d d_gamma_d_p = w_hat * w_hat;
  const Eigen::Matrix3d velocity_map = rotationIntegral(w_hat, dt_s, 1);
  const Eigen::Matrix3d position_map = rotationIntegral(w_hat, dt_s, 2);
  FrameIntegrals out;
  out.frame_rotation = so3::expMap(w * dt_s);
  out.velocity_mps = velocity_map * gamma;
  out.position_m = position_map * gamma;
  out.d_velocity_d_position = velocity_map * d_gamma_d_p;
  out.d_position_d_position = position_map * d_gamma_d_p;
  return out;
}

}  // namespace ppp
