#pragma once
// Ocean tide loading displacement from the 11 BLQ constituents (IERS
// Conventions 2010 sec. 7.1.2, simplified 11-wave form without the
// admittance-interpolated side lines of HARDISP; nodal modulation neglected,
// which is at the 1-2 mm level at most for the lunar waves).
//
// Astronomical arguments chi_k(t) follow Schwiderski's ARG routine used by the
// Onsala loading service that produces BLQ files (and by RTKLIB tide_oload):
//   chi_k = omega_k * (UT seconds of day) + a_k h0 + b_k s0 + c_k p0 + 2 pi d_k,
// with the mean longitudes of the Sun h0, Moon s0 and lunar perigee p0 at 0 h UT
// (Newcomb/Brown expressions in Julian centuries from 1900 Jan 0.5) and the
// Schwiderski phase offsets d_k (+-1/4 cycle for the diurnal waves).
#include <array>

#include <Eigen/Core>

#include "ppp_bayes_tree/types/ocean_loading_coefficients.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

/// Astronomical arguments chi_k [rad, in [0, 2 pi)] of the 11 constituents in BLQ order at `t`.
std::array<double, kOceanLoadingConstituents> oceanLoadingArguments_rad(const GnssTime& t);

/// Displacement (east, north, up) [m] at `t`: for each constituent
/// d = A cos(chi - phase); east = -west, north = -south.
Eigen::Vector3d oceanLoadingDisplacementEnu_m(const OceanLoadingCoefficients& coefficients,
                                              const GnssTime& t);

}  // namespace ppp
