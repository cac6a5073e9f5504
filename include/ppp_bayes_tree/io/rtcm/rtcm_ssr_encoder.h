#pragma once
// RTCM SSR encoder: the inverse of RtcmSsrDecoder, for SSR streams made from
// precise products (ppp_ssr_encode), generated streams (benchmarks) and tests.
// The bit layout is shared with the decoder (src/core/io/rtcm/rtcm_ssr_layout.h).
// Values are rounded to the fields' resolution (e.g. 0.1 mm radial, 0.4 mm
// along/cross, 0.1 mm C0, 0.01 m code bias).
#include <cstdint>
#include <vector>

#include "ppp_bayes_tree/types/ssr_corrections.h"

namespace ppp {

/// The message payload (without RTCM framing) of `message`: an RTCM SSR message
/// when header.igs_subtype == 0, else IGS-SSR 4076 with that sub-type. The
/// message type is derived from header.system and header.kind (header.message_type
/// is ignored). Throws std::out_of_range when a value does not fit its field
/// (e.g. a radial correction beyond +-209.7 m) and std::invalid_argument when
/// the message cannot be written (more than 63 satellites, a kind the system has no
/// message for, a combined message with unequal orbit and clock lists).
std::vector<std::uint8_t> encodeSsrPayload(const SsrMessage& message);

/// The same, framed (preamble, length, CRC-24Q); throws std::length_error when
/// the payload exceeds 1023 bytes.
std::vector<std::uint8_t> encodeSsrFrame(const SsrMessage& message);

}  // namespace ppp
