#include "ppp_bayes_tree/io/ubx/ubx_framer.h"

#include <stdexcept>
#include <string>

#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

constexpr std::uint8_t kSync1 = 0xB5;
constexpr std::uint8_t kSync2 = 0x62;
constexpr std::size_t kHeaderBytes = 6;
constexpr std::size_t kChecksumBytes = 2;

}  // namespace

std::string ubxTypeText(int type) { return format("0x%02X 0x%02X", (type >> 8) & 0xFF, type & 0xFF); }

UbxChecksum ubxChecksum(const std::uint8_t* data, std::size_t size) {
  UbxChecksum ck;
  for (std::size_t i = 0; i < size; ++i) {
    ck.a = static_cast<std::uint8_t>(ck.a + data[i]);
    ck.b = static_cast<std::uint8_t>(ck.b + ck.a);
  }
  return ck;
}

std::vector<std::uint8_t> encodeUbxFrame(std::uint8_t message_class, std::uint8_t message_id,
                                         const std::vector<std::uint8_t>& payload) {
  if (payload.size() > 0xFFFF) {
    throw std::length_error("UBX payload of " + std::to_string(payload.size()) + " bytes (at most 65535)");
  }
  std::vector<std::uint8_t> frame;
  frame.reserve(payload.size() + kHeaderBytes + kChecksumBytes);
  frame.push_back(kSync1);
  frame.push_back(kSync2);
  frame.push_back(message_class);
  frame.push_back(message_id);
  frame.push_back(static_cast<std::uint8_t>(payload.size() & 0xFFu));
  frame.push_back(static_cast<std::uint8_t>((payload.size() >> 8) & 0xFFu));
  frame.insert(frame.end(), payload.begin(), payload.end());
  const UbxChecksum ck = ubxChecksum(frame.data() + 2, frame.size() - 2);
  frame.push_back(ck.a);
  frame.push_back(ck.b);
  return frame;
}

void UbxFramer::feed(const std::uint8_t* data, std::size_t size, const FrameHandler& on_frame) {
  feedBytes(data, size, [&on_frame](const FrameBytes& bytes) {
    UbxFrame out;
    out.message_class = bytes.data[2];
    out.message_id = bytes.data[3];
    out.payload.assign(bytes.data + kHeaderBytes, bytes.data + bytes.size - kChecksumBytes);
    out.byte_offset = bytes.byte_offset;
    out.frame_index = bytes.frame_index;
    on_frame(out);
  });
}

FrameCandidate UbxFramer::examine(const std::uint8_t* data, std::size_t available) const {
  if (data[0] != kSync1) return FrameCandidate::notAFrame();
  if (available < 2) return FrameCandidate::needMoreBytes();  // wait for the second sync byte
  if (data[1] != kSync2) return FrameCandidate::notAFrame();
  if (available < kHeaderBytes) return FrameCandidate::needMoreBytes();  // wait for class, id, length
  const int type = (static_cast<int>(data[2]) << 8) | data[3];
  const std::size_t length = static_cast<std::size_t>(data[4]) | (static_cast<std::size_t>(data[5]) << 8);
  if (length > kMaxPayloadBytes) {
    return FrameCandidate::rejected({StreamProblemKind::BadLength, type,
                                     "UBX " + ubxTypeText(type) + " length " + std::to_string(length) + " above " +
                                         std::to_string(kMaxPayloadBytes) + " bytes; searching for the next sync"});
  }
  const std::size_t frame_bytes = kHeaderBytes + length + kChecksumBytes;
  if (available < frame_bytes) return FrameCandidate::needMoreBytes();  // wait for the rest
  const UbxChecksum ck = ubxChecksum(data + 2, kHeaderBytes - 2 + length);
  if (ck.a != data[kHeaderBytes + length] || ck.b != data[kHeaderBytes + length + 1]) {
    return FrameCandidate::rejected({StreamProblemKind::ChecksumError, type,
                                     "UBX " + ubxTypeText(type) + " Fletcher checksum mismatch over a " +
                                         std::to_string(length) + "-byte payload; searching for the next sync"});
  }
  return FrameCandidate::good(frame_bytes, type);
}

std::optional<FrameFault> UbxFramer::truncatedFrame(const std::uint8_t* data, std::size_t available) const {
  const bool frame_start = data[0] == kSync1 && (available < 2 || data[1] == kSync2);
  if (!frame_start) return std::nullopt;
  return FrameFault{StreamProblemKind::TruncatedFrame,
                    available >= 4 ? ((static_cast<int>(data[2]) << 8) | data[3]) : 0,
                    "the stream ended " + std::to_string(available) + " byte(s) into a UBX frame"};
}

}  // namespace ppp
