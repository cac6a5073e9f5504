#pragma once
// Signal geometry: light-time iteration, Earth rotation during the signal
// flight (Sagnac effect), geometric range and line of sight.
//
// Frames: the satellite position at transmission is wanted in the ECEF frame
// of the RECEPTION epoch (where the receiver position lives). An ECEF position
// of epoch t - tau is expressed in the frame of epoch t by rotating it about z
// by -omega_e tau, i.e. applying R3(omega_e tau) (IS-GPS-200 20.3.3.4.3.4;
// Kaplan & Hegarty, "Understanding GPS" 2nd ed., sec. 2.5.2 / 7.2.1).
#include <cmath>
#include <optional>
#include <type_traits>
#include <utility>

#include <Eigen/Core>

#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

/// R3(omega_e tau) applied to an ECEF position of the transmission epoch: the same
/// point expressed in the ECEF axes of the reception epoch tau seconds later.
inline Eigen::Vector3d rotateForEarthRotation(const Eigen::Vector3d& position_ecef_m, double flight_time_s) {
  const double angle = kEarthRotationRate_radps * flight_time_s;
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * position_ecef_m.x() + s * position_ecef_m.y(), -s * position_ecef_m.x() + c * position_ecef_m.y(),
          position_ecef_m.z()};
}

/// Closed-form Sagnac range correction [m]: omega_e (x_s y_r - y_s x_r) / c, to
/// ADD to the range computed with the unrotated satellite position
/// (first-order equivalent of rotateForEarthRotation; IERS/RTKLIB geodist form).
inline double sagnacCorrection_m(const Eigen::Vector3d& satellite_ecef_m, const Eigen::Vector3d& receiver_ecef_m) {
  return kEarthRotationRate_radps *
         (satellite_ecef_m.x() * receiver_ecef_m.y() - satellite_ecef_m.y() * receiver_ecef_m.x()) /
         kSpeedOfLight_mps;
}

/// Euclidean distance [m].
inline double geometricRange_m(const Eigen::Vector3d& satellite_ecef_m, const Eigen::Vector3d& receiver_ecef_m) {
  return (satellite_ecef_m - receiver_ecef_m).norm();
}

/// Unit vector from the receiver towards the satellite.
inline Eigen::Vector3d lineOfSight(const Eigen::Vector3d& receiver_ecef_m, const Eigen::Vector3d& satellite_ecef_m) {
  return (satellite_ecef_m - receiver_ecef_m).normalized();
}

/// d range / d receiver position = -line of sight (row of the design matrix).
inline Eigen::Vector3d rangeJacobianWrtReceiver(const Eigen::Vector3d& receiver_ecef_m,
                                                const Eigen::Vector3d& satellite_ecef_m) {
  return -lineOfSight(receiver_ecef_m, satellite_ecef_m);
}

struct LightTimeSolution {
  GnssTime transmission_time;               ///< reception time - flight time (same time scale)
  Eigen::Vector3d satellite_ecef_m;         ///< at transmission, in the ECEF axes of reception
  Eigen::Vector3d satellite_ecef_at_transmission_m;  ///< as returned by the callable (unrotated)
  double flight_time_s = 0.0;
  double range_m = 0.0;                     ///< |satellite_ecef_m - receiver|
  int iterations = 0;
};

/// Solve tau = |R3(omega tau) x_s(t_r - tau) - x_r| / c by fixed-point iteration.
/// `satellite_position_at(GnssTime)` returns the ECEF position [m] of the satellite
/// antenna (or centre of mass, as the caller wishes) at a time, either as an
/// Eigen::Vector3d or as std::optional<Eigen::Vector3d> (nullopt: not available,
/// then the solve returns nullopt). The reception time must be the true time of
/// reception (receiver clock already removed). Returns nullopt when the position
/// is unavailable or the iteration does not converge to `tolerance_s` within
/// `max_iterations` (it converges in 2-3 iterations for GNSS orbits).
template <class SatellitePositionFn>
std::optional<LightTimeSolution> solveLightTime(const Eigen::Vector3d& receiver_ecef_m,
                                                const GnssTime& reception_time,
                                                SatellitePositionFn&& satellite_position_at,
                                                double tolerance_s = 1e-12, int max_iterations = 10) {
  LightTimeSolution sol;
  double tau = 0.075;  // typical MEO flight time [s]
  for (int i = 1; i <= max_iterations; ++i) {
    const GnssTime t_tx = reception_time - tau;
    Eigen::Vector3d position;
    using Result = std::decay_t<decltype(satellite_position_at(t_tx))>;
    if constexpr (std::is_same_v<Result, std::optional<Eigen::Vector3d>>) {
      const auto p = satellite_position_at(t_tx);
      if (!p) return std::nullopt;
      position = *p;
    } else {
      position = satellite_position_at(t_tx);
    }
    const Eigen::Vector3d rotated = rotateForEarthRotation(position, tau);
    const double range = (rotated - receiver_ecef_m).norm();
    const double tau_new = range / kSpeedOfLight_mps;
    sol.transmission_time = t_tx;
    sol.satellite_ecef_m = rotated;
    sol.satellite_ecef_at_transmission_m = position;
    sol.flight_time_s = tau;
    sol.range_m = range;
    sol.iterations = i;
    if (!std::isfinite(tau_new)) return std::nullopt;
    if (std::abs(tau_new - tau) < tolerance_s) return sol;
    tau = tau_new;
  }
  return std::nullopt;
}

}  // namespace ppp
