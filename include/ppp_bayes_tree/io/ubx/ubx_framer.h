#pragma once
// UbxFramer: cuts a u-blox UBX byte stream, fed in chunks of any size, into
// frames (u-blox F9 HPG interface description UBX-18010854, section 3.2 "UBX
// frame structure"; 3.4 "UBX checksum").
//
//   0xB5 0x62 | class | id | length (U2, little-endian) | payload | CK_A CK_B
//
// The checksum is the 8-bit Fletcher algorithm (RFC 1145) over class, id,
// length and payload. Bytes outside frames are skipped (io/skipped_bytes.h):
// NMEA text interleaved by the receiver is counted, not a problem; anything
// else is garbage, one problem per run. A frame
// whose checksum fails is counted as a checksum error and the search for the
// next sync pair restarts at the byte after the false 0xB5, so a frame hidden
// behind a false sync is still found. A length above kMaxPayloadBytes is
// counted as BadLength (the largest message we read, RXM-RAWX with 255
// measurements, has 16 + 32*255 = 8176 bytes) and the search restarts the same
// way. finish() reports a frame the stream ended inside.
//
// Frames are counted per message type class<<8 | id (RXM-RAWX = 0x0215). The
// search itself is io/framer_base.h; this file holds the UBX rules.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/framer_base.h"

namespace ppp {

struct UbxFrame {
  std::uint8_t message_class = 0;
  std::uint8_t message_id = 0;
  std::vector<std::uint8_t> payload;  // without header and checksum
  std::uint64_t byte_offset = 0;      // of the 0xB5, from the first byte fed
  std::uint64_t frame_index = 0;      // 0-based count of good frames

  /// class<<8 | id, the key of StreamCounters::frames_by_type.
  int messageType() const { return (static_cast<int>(message_class) << 8) | message_id; }
};

/// The two Fletcher checksum bytes (CK_A, CK_B) over `size` bytes.
struct UbxChecksum {
  std::uint8_t a = 0, b = 0;
};
UbxChecksum ubxChecksum(const std::uint8_t* data, std::size_t size);

/// A message type class<<8 | id as problem texts name it: "0x02 0x15".
std::string ubxTypeText(int type);

/// A complete UBX frame around `payload` (at most 65535 bytes; throws
/// std::length_error otherwise).
std::vector<std::uint8_t> encodeUbxFrame(std::uint8_t message_class, std::uint8_t message_id,
                                         const std::vector<std::uint8_t>& payload);

class UbxFramer : public FramerBase {
 public:
  static constexpr std::size_t kMaxPayloadBytes = 8192;
  using FrameHandler = std::function<void(const UbxFrame&)>;

  UbxFramer() : FramerBase("UBX") {}

  /// Feeds bytes; calls `on_frame` for every complete frame with a good checksum.
  void feed(const std::uint8_t* data, std::size_t size, const FrameHandler& on_frame);

 private:
  FrameCandidate examine(const std::uint8_t* data, std::size_t available) const override;
  std::optional<FrameFault> truncatedFrame(const std::uint8_t* data, std::size_t available) const override;
};

}  // namespace ppp
