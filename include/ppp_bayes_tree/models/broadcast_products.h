#pragma once
// Broadcast products for a PPP run (ppp_solve --nav FILE... [--ssr FILE]):
//  - without SSR: the broadcast records alone (BroadcastEphemerisStore), metre
//    level, and the run notes say so;
//  - with SSR: BroadcastSsrEphemeris over the decoded stream (falling back to
//    the broadcast records where its corrections are too old), its reference
//    point declared (or taken from the stream name: SSRA = antenna phase centre,
//    SSRC = centre of mass; otherwise centre of mass), and the stream's code and
//    phase biases as an SsrBiasProvider (null when the stream has none).
// A navigation file may also be an RTCM 3 or UBX stream recording (detected by
// content): its ephemerides are used, each from its reception time on (the
// causal rule of BroadcastEphemerisStore, the same as the live input), so that
// `ppp_solve --rtcm X --nav X` is broadcast-only PPP from one recording;
// `stream_reference_time` places MSM times without a week (--ref-date).
// Decoding and consistency problems (byte offset, frame index) become problems
// of the run; SSR epochs are placed in time next to the navigation records.
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ppp_bayes_tree/models/bias_provider.h"
#include "ppp_bayes_tree/models/broadcast_fallback.h"
#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/models/ssr_correction_store.h"
#include "ppp_bayes_tree/types/glonass_channels.h"

namespace ppp {

class BroadcastSsrEphemeris;

struct BroadcastProducts {
  std::shared_ptr<const EphemerisSource> ephemeris;
  /// With SSR: the SSR-corrected broadcast ephemeris inside `ephemeris` (which
  /// falls back to the broadcast records where its corrections are too old); null without SSR.
  std::shared_ptr<const BroadcastSsrEphemeris> corrected;
  std::shared_ptr<const BiasProvider> ssr_biases;  // null without SSR code biases
  bool ssr_phase_biases = false;                   // the SSR stream carries phase biases
  /// GLONASS frequency channels of the navigation records (RINEX header or
  /// records, stream records), for the signal selection of GLONASS.
  GlonassChannels glonass_channels;
  /// The satellites with decoded navigation records (files and stream recordings).
  std::set<SatelliteId> record_satellites;
  /// With SSR: the satellites the stream corrects (orbit and clock corrections).
  std::set<SatelliteId> corrected_satellites;
  std::vector<std::string> notes;
  std::vector<std::string> problems;
};

/// The first and last observation epoch of a run.
struct ObservationSpan {
  GnssTime first, last;
};

/// Throws FileOpenError / ParseError on unreadable files. With SSR, the
/// ephemeris falls back to the broadcast records where the corrections are too
/// old (models/ssr_broadcast_fallback.h, by `fallback`); with `observation_span`, a note says
/// when that is so at its first or last epoch, and how old the corrections are.
BroadcastProducts loadBroadcastProducts(const std::vector<std::string>& nav, const std::optional<std::string>& ssr,
                                        std::optional<EphemerisReference> ssr_reference = std::nullopt,
                                        SsrAgeLimits limits = {},
                                        BroadcastFallbackOptions fallback = {},
                                        std::optional<GnssTime> stream_reference_time = std::nullopt,
                                        std::optional<ObservationSpan> observation_span = std::nullopt);

}  // namespace ppp
