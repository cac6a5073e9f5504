#pragma once
// Noon and midnight yaw manoeuvres: when a satellite's attitude departs from
// nominal yaw steering (satellite_attitude.h). Near the turn points with a small
// Sun elevation beta above the orbit plane, the nominal yaw rate exceeds what the
// satellite can turn: a GPS satellite then lags at its hardware rate until it has
// caught up (rateLimitedYaw_rad); Galileo steers by a smoothed Sun direction. The
// windows per system and the rate-limited yaw are here; the measurement model
// uses them (MeasurementModelOptions::yaw_manoeuvre). The geometry:
// doc/measurement_model.md, "Noon and midnight yaw turns".
// References: Kouba J. (2009) GPS Solutions 13:1-12; Dilssner F. (2010) Inside
// GNSS 5(6); European GNSS Service Centre (2017) Galileo IOV and FOC satellite
// metadata.
#include <optional>

#include <Eigen/Core>

#include "ppp_bayes_tree/models/satellite_attitude.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// How a system's satellites leave nominal yaw steering near noon and midnight.
struct YawManoeuvreLimits {
  /// Hardware yaw rate limit [rad/s] (> 0: rate-limited turn, Kouba 2009); 0 = none.
  double max_yaw_rate_radps = 0.0;
  /// Smoothed yaw steering (Galileo): |beta| below this [rad] ...
  double smoothed_beta_limit_rad = 0.0;
  /// ... and |x| (orbit angle from noon or midnight) below this [rad].
  double smoothed_window_rad = 0.0;
};

/// The limits of a system (GPS: Block IIF's 0.11 deg/s, the slowest flying block,
/// so Block IIR turns are covered conservatively; Galileo: the union of the FOC
/// and IOV smoothed-yaw windows, |beta| < 4.1 deg within 15 deg), or none
/// (BeiDou, QZSS, ...: not modelled, the nominal attitude is used).
std::optional<YawManoeuvreLimits> yawManoeuvreLimits(GnssSystem system);

/// Orbit angle from the nearer turn point [rad], negative before it (along the
/// motion): mu near 0 (midnight) or +-pi (noon), in [-pi/2, pi/2].
double angleFromTurnPoint_rad(const OrbitSunAngles& angles);

/// Orbit angular rate |r x v_inertial| / |r|^2 [rad/s] of an ECEF state.
double orbitAngularRate_radps(const Eigen::Vector3d& position_ecef_m, const Eigen::Vector3d& velocity_ecef_mps);

/// Whether the attitude departs from nominal yaw steering: a rate-limited turn
/// (x in [x_s, x_s + mu_dot pi / R]) or a smoothed-yaw window (both above).
bool inYawManoeuvre(const OrbitSunAngles& angles, double orbit_rate_radps, const YawManoeuvreLimits& limits);

/// Yaw angle [rad] of a rate-limited turn (Kouba 2009): inside the window the
/// yaw leaves the nominal one at the turn's start x_s and turns at the maximum
/// rate R, in the nominal turn's direction (noon: -sign(beta), midnight:
/// +sign(beta)), psi = psi_nominal(x_s) + direction R (x - x_s) / mu_dot, until it
/// has caught up with the nominal yaw. std::nullopt where the attitude is the
/// nominal one (outside the window, caught up, or no rate limit).
std::optional<double> rateLimitedYaw_rad(const OrbitSunAngles& angles, double orbit_rate_radps,
                                         const YawManoeuvreLimits& limits);

/// The same from the ECEF satellite state and the Sun, with the system's limits
/// (false for a system without limits).
bool inYawManoeuvre(GnssSystem system, const Eigen::Vector3d& position_ecef_m, const Eigen::Vector3d& velocity_ecef_mps,
                    const Eigen::Vector3d& sun_ecef_m);

}  // namespace ppp
