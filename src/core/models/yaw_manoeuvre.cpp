#include "ppp_bayes_tree/models/yaw_manoeuvre.h"

#include <array>
#include <cmath>
#include <utility>

#include <Eigen/Geometry>

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

// Per-system limits (the header gives the sources).
const std::array<std::pair<GnssSystem, YawManoeuvreLimits>, 2> kYawManoeuvreLimits{{
    {GnssSystem::GPS, {0.11 * kDegToRad, 0.0, 0.0}},
    {GnssSystem::Galileo, {0.0, 4.1 * kDegToRad, 15.0 * kDegToRad}},
}};

/// [x_s, x_s + mu_dot pi / R] of a rate-limited turn, or none when the nominal
/// rate never reaches R.
std::optional<std::pair<double, double>> rateLimitedTurnWindow_rad(const OrbitSunAngles& a, double mu_dot_radps,
                                                                   double max_rate_radps) {
  const double tan_beta = std::abs(std::tan(a.beta_rad));
  const double sin2_start = mu_dot_radps * tan_beta / max_rate_radps - tan_beta * tan_beta;
  if (sin2_start < 0.0) return std::nullopt;
  const double x_start = -std::asin(std::min(1.0, std::sqrt(sin2_start)));
  return std::make_pair(x_start, x_start + mu_dot_radps * kPi / max_rate_radps);
}

bool inRateLimitedTurn(const OrbitSunAngles& a, double x_rad, double mu_dot_radps, double max_rate_radps) {
  const auto window = rateLimitedTurnWindow_rad(a, mu_dot_radps, max_rate_radps);
  return window && x_rad >= window->first && x_rad <= window->second;
}

double wrapAngle_rad(double a) { return std::atan2(std::sin(a), std::cos(a)); }

}  // namespace

std::optional<YawManoeuvreLimits> yawManoeuvreLimits(GnssSystem system) {
  for (const auto& [s, limits] : kYawManoeuvreLimits)
    if (s == system) return limits;
  return std::nullopt;
}

double angleFromTurnPoint_rad(const OrbitSunAngles& a) {
  if (std::abs(a.mu_rad) <= 0.5 * kPi) return a.mu_rad;
  return a.mu_rad > 0.0 ? a.mu_rad - kPi : a.mu_rad + kPi;
}

double orbitAngularRate_radps(const Eigen::Vector3d& r, const Eigen::Vector3d& v) {
  return r.cross(inertialVelocity_mps(r, v)).norm() / r.squaredNorm();
}

bool inYawManoeuvre(const OrbitSunAngles& a, double orbit_rate_radps, const YawManoeuvreLimits& limits) {
  const double x = angleFromTurnPoint_rad(a);
  if (limits.max_yaw_rate_radps > 0.0 && inRateLimitedTurn(a, x, orbit_rate_radps, limits.max_yaw_rate_radps))
    return true;
  return std::abs(a.beta_rad) < limits.smoothed_beta_limit_rad && std::abs(x) < limits.smoothed_window_rad;
}

std::optional<double> rateLimitedYaw_rad(const OrbitSunAngles& a, double orbit_rate_radps,
                                         const YawManoeuvreLimits& limits) {
  if (!(limits.max_yaw_rate_radps > 0.0)) return std::nullopt;
  const double x = angleFromTurnPoint_rad(a);
  const auto window = rateLimitedTurnWindow_rad(a, orbit_rate_radps, limits.max_yaw_rate_radps);
  if (!window || x < window->first || x > window->second) return std::nullopt;
  const bool noon = std::abs(a.mu_rad) > 0.5 * kPi;
  const double turn_point_rad = noon ? kPi : 0.0;
  OrbitSunAngles start = a;
  start.mu_rad = wrapAngle_rad(turn_point_rad + window->first);
  const double beta_sign = a.beta_rad < 0.0 ? -1.0 : 1.0;
  const double direction = noon ? -beta_sign : beta_sign;
  const double yaw = nominalYawAngle_rad(start) +
                     direction * limits.max_yaw_rate_radps * (x - window->first) / orbit_rate_radps;
  // Caught up: the nominal yaw is no longer ahead in the turn's direction.
  if (direction * wrapAngle_rad(nominalYawAngle_rad(a) - yaw) <= 0.0) return std::nullopt;
  return wrapAngle_rad(yaw);
}

bool inYawManoeuvre(GnssSystem system, const Eigen::Vector3d& r, const Eigen::Vector3d& v, const Eigen::Vector3d& sun) {
  const std::optional<YawManoeuvreLimits> limits = yawManoeuvreLimits(system);
  return limits && inYawManoeuvre(orbitSunAngles(r, v, sun), orbitAngularRate_radps(r, v), *limits);
}

}  // namespace ppp
