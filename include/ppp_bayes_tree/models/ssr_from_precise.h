#pragma once
// SSR from precise products: what an analysis centre sends to correct the
// broadcast ephemeris towards its precise orbits and clocks (ppp_ssr_encode),
// so that broadcast + SSR reproduces the precise products up to the SSR
// quantisation (0.1 mm radial, 0.4 mm along/cross, 0.1 mm clock).
//
// At every epoch t0 on the interval grid, for every satellite with a precise
// orbit and clock and a broadcast record a user would select at t0
// (BroadcastEphemerisStore: healthy, valid, nearest toe among the records already
// transmitted at t0 by their RINEX transmission time; Galileo I/NAV):
//   dX(t)   = X_brdc(t) - X_precise(t)     (so that X = X_brdc - dX, RTCM sign)
//   dr, da, dc = dX . (e_r, e_a, e_c)     (RAC axes of the broadcast r, v at t)
//   rates   = (RAC(t0 + U) - RAC(t0)) / U (forward difference over the interval U,
//             so that the linear model is exact at both ends; the last epoch
//             uses the velocity difference)
//   C0      = c (dt_precise(t0) - dt_brdc_polynomial(t0)),  C1 likewise, C2 = 0
//   code bias = -OSB (SSR biases are added to the measurement)
//   phase bias = -OSB of the phase-bias provider (e.g. the wide-lane biases of
//             integer-recovery clocks, ClockWideLaneBiasProvider: L1/L2, E1/E5a
//             biases with a zero ionosphere-free combination and the header's
//             wide lane), one per RTCM signal id the provider answers, with the
//             integer, wide-lane integer (2: with every other signal) indicators
//             set and discontinuity counter 0 (the biases are constant); yaw
//             and yaw rate 0 (not sent: the user applies its attitude model);
//             DF486/DF487 set (the biases keep the dispersive and the MW
//             combination consistent). Messages 1265 (GPS), 1267 (Galileo).
// X_precise is the SP3 centre of mass, or with reference = AntennaPhaseCentre
// the centre of mass moved by the satellite's ionosphere-free PCO (L1/L2,
// E1/E5a; nominal yaw attitude): the point the measurement model expects when
// it is told the orbit is at the antenna phase centre; with AntennaPhaseCentreL1
// (as the IGS SSRA streams) moved by the L1 (E1) PCO
// (models/satellite_reference_point.h).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/models/antenna_calibration_provider.h"
#include "ppp_bayes_tree/models/bias_provider.h"
#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/types/ssr_corrections.h"

namespace ppp {

struct NavData;

struct SsrFromPreciseOptions {
  double interval_s = 5.0;  // SSR update interval and epoch spacing (a DF391 value)
  EphemerisReference reference = EphemerisReference::CentreOfMass;
  std::vector<GnssSystem> systems{GnssSystem::GPS, GnssSystem::Galileo, GnssSystem::GLONASS};
  /// Combined orbit+clock messages (1060/1066/1243); false: orbit and clock
  /// messages (1057+1058, ...).
  bool combined = true;
  int provider_id = 0, solution_id = 0, iod_ssr = 0;
  /// Satellites per message (messages are split, multiple-message bit set).
  int satellites_per_message = 20;
};

struct SsrFromPreciseResult {
  std::vector<SsrMessage> messages;  // in epoch order
  std::size_t epochs = 0;
  std::size_t satellite_epochs = 0;
  std::vector<std::string> notes;    // satellites left out and why (counted)
};

/// Builds the messages for [first, last] (whole seconds; first rounded up to the
/// interval grid). `antennas` is needed for reference = AntennaPhaseCentre;
/// `biases` (may be null) gives the code biases, `phase_biases` (may be null) the
/// integer phase biases (phase-bias messages, same epochs). Throws std::invalid_argument on
/// an interval that is not an SSR update interval, or APC without antennas.
SsrFromPreciseResult ssrFromPrecise(const std::vector<NavData>& navigation, const EphemerisSource& precise,
                                    const AntennaCalibrationProvider* antennas, const BiasProvider* biases,
                                    const GnssTime& first, const GnssTime& last, const SsrFromPreciseOptions& options,
                                    const BiasProvider* phase_biases = nullptr);

}  // namespace ppp
