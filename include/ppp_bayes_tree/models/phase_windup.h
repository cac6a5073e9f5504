#pragma once
// Carrier-phase wind-up (Wu, Wu, Hajj, Bertiger & Lichten 1993, "Effects of
// antenna orientation on GPS carrier phase", manuscripta geodaetica 18:91-98;
// Kouba 2009 "A guide to using IGS products" sec. 5.3.1).
//
// With k the unit vector satellite -> receiver, satellite body axes (x', y')
// and receiver antenna axes (x, y):
//   D' = x' - k (k.x') - k x y',   D = x - k (k.x) + k x y,
//   windup = sign(k . (D' x D)) acos(D'.D / |D'||D|) / (2 pi)  [cycles],
// made continuous by adding the integer number of cycles closest to the
// previous value. The value is the term CONTAINED in the phase observation
// (L = rho + ... + lambda * windup), so the modelled phase adds it.
//
// Sign convention (checked by a unit test): receiver axes x = north, y = west
// (z = up, right-handed). Turning the receiver antenna by +90 deg about the up
// axis (counter-clockwise seen from above) changes the wind-up by -0.25 cycle.
// Physical check: GPS signals are right-hand circularly polarised, whose field
// turns clockwise seen along the propagation (IEEE definition), i.e. seen from
// above for a signal from the zenith; an antenna turned counter-clockwise by
// psi therefore sees the carrier phase advanced by psi, and the carrier-phase
// observable (which grows with range) shrinks by psi / 2 pi.
#include <optional>

#include <Eigen/Core>

#include "ppp_bayes_tree/models/satellite_attitude.h"

namespace ppp {

/// Receiver antenna dipole axes in ECEF.
struct ReceiverAntennaAxes {
  Eigen::Vector3d x_ecef = Eigen::Vector3d::UnitX();
  Eigen::Vector3d y_ecef = Eigen::Vector3d::UnitY();
};

/// Conventional axes of a north-oriented antenna at (lat, lon): x = north, y = west.
ReceiverAntennaAxes northWestAntennaAxes(double latitude_rad, double longitude_rad);

/// Wind-up [cycles]. `previous_cycles` (the value of the previous epoch of the same
/// satellite-receiver arc) makes the result continuous; without it the value is in
/// [-0.5, 0.5]. nullopt when the geometry is degenerate (a dipole vector D or D'
/// vanishes).
std::optional<double> phaseWindup_cycles(const SatelliteBodyAxes& satellite_axes,
                                         const ReceiverAntennaAxes& receiver_axes,
                                         const Eigen::Vector3d& satellite_ecef_m,
                                         const Eigen::Vector3d& receiver_ecef_m,
                                         std::optional<double> previous_cycles = std::nullopt);

}  // namespace ppp
