#pragma once
// Fuzz entry for the RTCM SSR decoder: bytes -> Rtcm3Framer -> RtcmSsrDecoder
// (with a reference time, so epochs are placed), then the corrections go into
// an SsrCorrectionStore and a BroadcastSsrEphemeris without navigation records
// is queried at the decoded epochs, and every decoded message is encoded again
// and decoded once more. Only the documented exceptions are caught: the encoder's
// std::out_of_range (a decoded BeiDou RTKLIB-layout IODCRC does not fit the IGS
// layout's 8-bit IOD) and std::length_error (a frame over 1023 bytes).
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_encoder.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/models/broadcast_ssr_ephemeris.h"
#include "ppp_bayes_tree/models/ssr_bias_provider.h"

namespace ppp::fuzz {

inline void fuzzRtcmSsr(const std::uint8_t* data, std::size_t size) {
  const GnssTime reference = GnssTime::fromGpsWeek(2400, 300000.0);
  const SsrStreamFile f = decodeSsrStream(data, size, reference);
  (void)f.summary.format();
  for (const auto& p : f.counters.problems) (void)p.describe();
  auto store = std::make_shared<SsrCorrectionStore>();
  for (const auto& m : f.messages) store->add(m);
  const BroadcastSsrEphemeris eph(std::vector<NavData>{}, store, {});
  const SsrBiasProvider biases(store, "fuzz");
  const ObservationCode c1c = *ObservationCode::parse("C1C");
  for (const auto& m : f.messages) {
    if (m.header.epoch) {
      for (const auto& o : m.orbits) {
        (void)eph.satelliteOrbit(o.satellite, *m.header.epoch + 1.0);
        (void)eph.satelliteClock(o.satellite, *m.header.epoch + 1.0);
      }
      for (const auto& b : m.code_biases) (void)biases.codeBias(b.satellite, c1c, *m.header.epoch);
    }
    try {
      const auto frame = encodeSsrFrame(m);
      const SsrStreamFile again = decodeSsrStream(frame.data(), frame.size(), reference);
      (void)again;
    } catch (const std::out_of_range&) {
    } catch (const std::length_error&) {
    }
  }
}

}  // namespace ppp::fuzz
