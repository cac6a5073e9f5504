#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"

#include <array>
#include <stdexcept>
#include <string>

namespace ppp {
namespace {

constexpr std::uint8_t kPreamble = 0xD3;
constexpr std::size_t kHeaderBytes = 3;
constexpr std::size_t kCrcBytes = 3;

}  // namespace

std::vector<std::uint8_t> encodeRtcm3Frame(const std::vector<std::uint8_t>& payload) {
  if (payload.size() > 1023) {
    throw std::length_error("RTCM 3 payload of " + std::to_string(payload.size()) + " bytes (at most 1023)");
  }
  std::vector<std::uint8_t> frame;
  frame.reserve(payload.size() + kHeaderBytes + kCrcBytes);
  frame.push_back(kPreamble);
  frame.push_back(static_cast<std::uint8_t>((payload.size() >> 8) & 0x03u));
  frame.push_back(static_cast<std::uint8_t>(payload.size() & 0xFFu));
  frame.insert(frame.end(), payload.begin(), payload.end());
  const std::uint32_t crc = crc24q(frame.data(), frame.size());
  frame.push_back(static_cast<std::uint8_t>((crc >> 16) & 0xFFu));
  frame.push_back(static_cast<std::uint8_t>((crc >> 8) & 0xFFu));
  frame.push_back(static_cast<std::uint8_t>(crc & 0xFFu));
  return frame;
}

void Rtcm3Framer::feed(const std::uint8_t* data, std::size_t size, const FrameHandler& on_frame) {
  feedBytes(data, size, [&on_frame](const FrameBytes& bytes) {
    Rtcm3Frame out;
    out.payload.assign(bytes.data + kHeaderBytes, bytes.data + bytes.size - kCrcBytes);
    out.message_type = bytes.message_type;
    out.byte_offset = bytes.byte_offset;
    out.frame_index = bytes.frame_index;
    on_frame(out);
  });
}

FrameCandidate Rtcm3Framer::examine(const std::uint8_t* data, std::size_t available) const {
  if (data[0] != kPreamble) return FrameCandidate::notAFrame();
  if (available < kHeaderBytes) return FrameCandidate::needMoreBytes();  // wait for the length
  // Reserved bits set: not a frame start (RTCM 10403.3 requires them zero).
  if ((data[1] & 0xFCu) != 0) return FrameCandidate::notAFrame();
  const std::size_t length = (static_cast<std::size_t>(data[1] & 0x03u) << 8) | data[2];
  const std::size_t frame_bytes = kHeaderBytes + length + kCrcBytes;
  if (available < frame_bytes) return FrameCandidate::needMoreBytes();  // wait for the rest
  const int type = length >= 2 ? static_cast<int>((data[3] << 4) | (data[4] >> 4)) : 0;
  const std::uint32_t expected = (static_cast<std::uint32_t>(data[kHeaderBytes + length]) << 16) |
                                 (static_cast<std::uint32_t>(data[kHeaderBytes + length + 1]) << 8) |
                                 data[kHeaderBytes + length + 2];
  if (crc24q(data, kHeaderBytes + length) != expected) {
    return FrameCandidate::rejected({StreamProblemKind::ChecksumError, type,
                                     "CRC-24Q mismatch over a " + std::to_string(length) +
                                         "-byte frame; searching for the next preamble"});
  }
  return FrameCandidate::good(frame_bytes, type);
}

std::optional<FrameFault> Rtcm3Framer::truncatedFrame(const std::uint8_t* data, std::size_t available) const {
  if (data[0] != kPreamble) return std::nullopt;
  return FrameFault{StreamProblemKind::TruncatedFrame, 0,
                    "the stream ended " + std::to_string(available) + " byte(s) into a frame"};
}

}  // namespace ppp
