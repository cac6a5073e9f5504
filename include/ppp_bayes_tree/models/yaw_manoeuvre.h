#pragma once
// Noon and midnight yaw manoeuvres: when a satellite's attitude departs from
// nominal yaw steering (satellite_attitude.h).
//
// Near orbit noon (mu = +-pi) and midnight (mu = 0) with a small Sun elevation
// beta above the orbit plane, nominal yaw steering would turn the satellite at
//   |dpsi/dt| = mu_dot |tan beta| |cos x| / (sin^2 x + tan^2 beta),
// x the orbit angle from the turn point: up to mu_dot / |tan beta| at x = 0,
// 0.4 deg/s at |beta| = 1.2 deg. A GPS satellite turns at most at its hardware
// yaw rate R (Block IIF 0.11 deg/s: Dilssner 2010, "GPS IIF-1 satellite antenna
// phase center and attitude modeling", Inside GNSS 5(6); Block IIR 0.2 deg/s:
// Kouba 2009, "A simplified yaw-attitude model for eclipsing GPS satellites",
// GPS Solutions 13:1-12), so its yaw lags the nominal one from the point where
// the nominal rate reaches R, x_s = -asin(sqrt(mu_dot |tan beta| / R - tan^2
// beta)) (Kouba 2009, eq. 6 without the small-angle form), until it has caught
// up, at most the time of a half turn pi / R later (27 min for a Block IIF).
// In that window the wind-up (up to half an ionosphere-free narrow-lane
// wavelength, 5 cm) and the horizontal phase centre offset follow a yaw the
// model does not know. Galileo satellites replace the Sun direction by a
// smoothed one when |beta| is small near noon and midnight (European GNSS
// Service Centre 2017, "Galileo IOV and FOC satellite metadata": FOC |beta| <
// 4.1 deg within 10 deg of the turn point, IOV |beta| < 2 deg within 15 deg).
// Both are limits per system below (the slowest block of each). Inside its
// window a GPS satellite takes the rate-limited yaw (rateLimitedYaw_rad); the
// measurement model leaves a satellite without such a model (Galileo) out of
// the epoch, like one in the Earth's shadow (MeasurementModelOptions::
// yaw_manoeuvre). Midnight turns happen mostly in the Earth's shadow, whose
// satellites are rejected anyway; after the shadow exit the same rate-limited
// form stands in for the blocks' eclipse behaviour (Kouba 2009 models the IIA
// and IIR ones; a Block IIF turns at 0.06 deg/s in the shadow, Dilssner 2010).
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
