#pragma once
// DopplerObservation: one satellite's Doppler of one epoch as a range rate, with
// the satellite's state at the transmission time from the ephemeris source, and
// the range-rate model that predicts it at a receiver position and velocity.
//
// Sign (RINEX 3.05 section 5.2.3; u-blox RXM-RAWX doMes): the Doppler is positive
// for an approaching satellite, so the observed range rate is -lambda D [m/s].
// The model (all ECEF, at the receiver's time t):
//   rho(t)  = |Rz(w tau) r_s(t - tau) - r_r(t)|,  tau = rho / c  (light time; the
//             Earth's rotation during it, the Sagnac effect, as a rotation of the
//             satellite's ECEF state by w tau, Rz(a) = [c s 0; -s c 0; 0 0 1]);
//   -lambda D = d rho / dt + c ddt_r - c (ddt_s + ddt_rel),
// with d rho/dt exact for that rho: e.(Rz v_s - v_r) / (1 - b), b the light-time
// term e.(w Rz' r_s - Rz v_s) / c (a few mm/s); ddt_r the receiver clock drift
// [m/s, per c]; ddt_s the satellite clock drift (the source's clock, without the
// relativistic term, differentiated over +-0.5 s) and ddt_rel the rate of the
// periodic relativistic term -2 r.v / c^2, -2 (v_i.v_i - mu / |r|) / c^2 with the
// inertial velocity v_i = v + w x r (relativity.h; Kepler acceleration). The
// ionosphere's and troposphere's rates (mm/s) are not modelled.
// References: Misra & Enge, "Global Positioning System", 2nd ed. 2006, ch. 6.2
// (velocity from Doppler); Groves 2013, 2nd ed., 9.4.2 (range-rate measurement,
// Sagnac rate); Kaplan & Hegarty, 3rd ed. 2017, ch. 11.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/ppp/model/dual_frequency_observation.h"
#include "ppp_bayes_tree/types/glonass_channels.h"
#include "ppp_bayes_tree/types/obs_epoch.h"

namespace ppp {

struct DopplerObservation {
  SatelliteId satellite;
  ObservationCode code;                 // the Doppler's code (the first frequency's, e.g. D1C)
  double range_rate_mps = 0.0;          // -lambda D
  double wavelength_m = 0.0;
  Eigen::Vector3d satellite_position_ecef_m = Eigen::Vector3d::Zero();  // at the transmission time
  Eigen::Vector3d satellite_velocity_ecef_mps = Eigen::Vector3d::Zero();
  double satellite_clock_rate_mps = 0.0;  // c (ddt_s + ddt_rel)
};

/// The modelled range rate and its derivative with respect to the receiver velocity.
struct RangeRatePrediction {
  double range_rate_mps = 0.0;       // d rho / dt (geometry only, no clocks)
  Eigen::Vector3d d_receiver_velocity = Eigen::Vector3d::Zero();  // d(range rate)/d v_r
  Eigen::Vector3d line_of_sight = Eigen::Vector3d::Zero();        // unit, receiver -> satellite
  double elevation_rad = 0.0;
};

/// d rho / dt of the model above for a satellite state at the transmission time
/// and a receiver at `receiver_ecef_m` moving at `receiver_velocity_ecef_mps`.
RangeRatePrediction predictRangeRate(const Eigen::Vector3d& satellite_position_ecef_m,
                                     const Eigen::Vector3d& satellite_velocity_ecef_mps,
                                     const Eigen::Vector3d& receiver_ecef_m,
                                     const Eigen::Vector3d& receiver_velocity_ecef_mps);

/// The rate of the periodic relativistic clock term, c d(-2 r.v / c^2)/dt [m/s].
double relativisticClockRate_mps(const Eigen::Vector3d& satellite_position_ecef_m,
                                 const Eigen::Vector3d& satellite_velocity_ecef_mps);

/// Why a selected satellite has no Doppler observation.
enum class DopplerSkipReason { NoDoppler, NoClock, NoOrbit };
const char* dopplerSkipReasonText(DopplerSkipReason reason);

struct DopplerEpoch {
  std::vector<DopplerObservation> observations;
  std::vector<std::pair<SatelliteId, DopplerSkipReason>> skipped;
};

/// The Doppler of each satellite of `systems` in `epoch`, with the satellite state
/// at the transmission time t - C / c - dt_s from `ephemeris`: for a satellite of
/// the dual-frequency selection `selected`, its first phase signal's (same band and
/// attribute, e.g. L1C -> D1C); for any other (a single-frequency satellite: the
/// Doppler needs no pair), the first Doppler of the header's order with a
/// pseudorange of the same signal (GLONASS: its channel from `channels`).
DopplerEpoch dopplerObservations(const ObsEpoch& epoch, const std::vector<DualFrequencyObservation>& selected,
                                 const std::vector<GnssSystem>& systems, const GlonassChannels& channels,
                                 const EphemerisSource& ephemeris);

}  // namespace ppp
