#pragma once
// MSM7 encoder (RTCM 10403.3 3.5.16, the inverse of Rtcm3Decoder's MSM part):
// one system's satellites of an epoch become one or more MSM7 payloads (more
// when satellites x signals exceed the 64-cell limit; all but the last carry the
// multiple-message bit). Used for generated streams (benchmark) and round trips
// in tests: decoded -> encoded -> decoded gives the same observations to the
// MSM7 resolution.
//
// Rough range: the middle of the satellite's pseudoranges on the 2^-10 ms grid; fine pseudorange 2^-29 ms, fine
// phase range 2^-31 ms, rough rate 1 m/s, fine rate 0.0001 m/s, CNR 1/16 dB-Hz;
// lock time to the largest DF407 indicator not above it; LLI bit 1 -> DF420.
// A value outside its field's range is left invalid (the decoder reads it absent).
#include <cstdint>
#include <vector>

#include "ppp_bayes_tree/io/rtcm/rtcm3_decoder.h"

namespace ppp {

struct MsmEncodeOptions {
  int station_id = 0;
  /// Set the multiple-message bit on the last payload too (more systems follow).
  bool more_messages_follow = false;
  GlonassChannels glonass_channels;  // for GLONASS wavelengths and the extended info
};

/// Payloads (without framing) of MSM7 messages for the satellites of `system` in
/// `epoch`. Empty when the epoch has none of that system.
std::vector<std::vector<std::uint8_t>> encodeMsm7(const StreamEpoch& epoch, GnssSystem system,
                                                  const MsmEncodeOptions& options);

/// Inverse of msmLockTimeDf407_ms: the largest indicator whose lock time is <= lock_ms.
unsigned msmLockIndicatorDf407(std::uint32_t lock_ms);

}  // namespace ppp
