#pragma once
// Fuzz entry for the u-blox UBX decoder: bytes -> UbxDecoder fed whole and in
// chunks whose sizes come from the data (framing across chunk boundaries), then
// every epoch through the RINEX-like layout (ubxObservationHeader, toObsEpoch)
// and every released record through the broadcast models at a few instants, and
// every problem through describe(). Nothing may throw: the decoder reports bad
// input as counted problems.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ppp_bayes_tree/io/ubx/ubx_decoder.h"
#include "ppp_bayes_tree/io/ubx/ubx_observation_source.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"

namespace ppp::fuzz {

inline void fuzzUbx(const std::uint8_t* data, std::size_t size) {
  volatile double sink = 0.0;
  for (int pass = 0; pass < 2; ++pass) {
    UbxDecoder decoder;
    std::vector<UbxObservationEpoch> epochs;
    BroadcastEphemerisStore store;
    UbxDecoder::Handlers handlers;
    handlers.on_epoch = [&](const UbxObservationEpoch& e) { epochs.push_back(e); };
    handlers.on_gps = [&](const GpsLnavEphemeris& e) {
      if (!checkKeplerOrbit(e.orbit)) {
        for (double dt : {-3600.0, 0.0, 900.0}) sink = sink + satelliteState(e, e.orbit.toe + dt).position_ecef_m.sum();
      }
      (void)store.add(e);
    };
    handlers.on_galileo = [&](const GalileoEphemeris& e) {
      if (!checkKeplerOrbit(e.orbit)) {
        for (double dt : {-3600.0, 0.0, 900.0}) sink = sink + satelliteState(e, e.orbit.toe + dt).clock_bias_s;
      }
      (void)store.add(e);
    };
    if (pass == 0) {
      decoder.feed(data, size, handlers);
    } else {
      std::size_t at = 0;
      while (at < size) {
        const std::size_t chunk = 1 + data[at] % 17;
        const std::size_t n = chunk < size - at ? chunk : size - at;
        decoder.feed(data + at, n, handlers);
        at += n;
      }
    }
    decoder.finish();
    const RinexObsHeader header = ubxObservationHeader(epochs, "fuzz.ubx");
    ObsEpoch out;
    for (const auto& e : epochs) {
      toObsEpoch(e, header, out);
      sink = sink + static_cast<double>(out.observations.size());
    }
    for (const auto& p : decoder.counters().problems) sink = sink + static_cast<double>(p.describe().size());
  }
}

}  // namespace ppp::fuzz
