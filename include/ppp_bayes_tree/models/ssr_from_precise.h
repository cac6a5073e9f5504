#pragma once
// SSR from precise products: what an analysis centre sends to correct the
// broadcast ephemeris towards its precise orbits and clocks (ppp_ssr_encode), so
// that broadcast + SSR reproduces the precise products up to the SSR
// quantisation (0.1 mm radial, 0.4 mm along/cross, 0.1 mm clock). At every epoch
// of the interval grid and for every satellite with a precise orbit and clock and
// a broadcast record a user would select: orbit corrections in radial, along and
// cross-track with rates, clock polynomial C0/C1, code biases and (from a
// phase-bias provider such as integer-recovery clocks) phase biases, RTCM signs.
// The formulas, the reference point and the phase-bias fields:
// doc/offline_tools.md, "How ppp_ssr_encode makes SSR from precise products".
// Reference: RTCM 10403.3 (SSR messages, 1265/1267 phase biases).
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
