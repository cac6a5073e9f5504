#pragma once
// Rtcm3Framer: cuts an RTCM 3 byte stream, fed in chunks of any size, into
// frames (RTCM 10403.3, section 4: transport layer).
//
//   preamble 0xD3 | 6 reserved bits | 10-bit length N | N payload bytes | CRC-24Q
//
// The CRC-24Q (polynomial 0x1864CFB, Qualcomm) covers preamble, length and
// payload. On a CRC mismatch the framer counts a checksum error and searches
// for the next preamble from the byte after the false one, so that a frame hidden
// behind garbage or a false preamble is still found. Bytes skipped while
// searching are counted by io/skipped_bytes.h: NMEA text, or garbage (one
// problem per run of bytes). finish()
// reports a frame the stream ended inside. The search itself is
// io/framer_base.h; this file holds the RTCM 3 rules.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "ppp_bayes_tree/io/crc24q.h"
#include "ppp_bayes_tree/io/framer_base.h"

namespace ppp {

struct Rtcm3Frame {
  std::vector<std::uint8_t> payload;  // message bytes, without header and CRC
  int message_type = 0;               // DF002, the first 12 payload bits (0 when N < 2)
  std::uint64_t byte_offset = 0;      // of the preamble, from the first byte fed
  std::uint64_t frame_index = 0;      // 0-based count of good frames
};

/// A complete frame (preamble, length, payload, CRC) around `payload`
/// (at most 1023 bytes; throws std::length_error otherwise).
std::vector<std::uint8_t> encodeRtcm3Frame(const std::vector<std::uint8_t>& payload);

class Rtcm3Framer : public FramerBase {
 public:
  using FrameHandler = std::function<void(const Rtcm3Frame&)>;

  Rtcm3Framer() : FramerBase("RTCM 3") {}

  /// Feeds bytes; calls `on_frame` for every complete frame with a good CRC.
  void feed(const std::uint8_t* data, std::size_t size, const FrameHandler& on_frame);

 private:
  FrameCandidate examine(const std::uint8_t* data, std::size_t available) const override;
  std::optional<FrameFault> truncatedFrame(const std::uint8_t* data, std::size_t available) const override;
};

}  // namespace ppp
