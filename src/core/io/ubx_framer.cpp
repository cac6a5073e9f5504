#include "ppp_bayes_tree/io/ubx_framer.h"

#include <cstdio>
#include <stdexcept>
#include <string>

namespace ppp {
namespace {

constexpr std::uint8_t kSync1 = 0xB5;
constexpr std::uint8_t kSync2 = 0x62;
constexpr std::size_t kHeaderBytes = 6;
constexpr std::size_t kChecksumBytes = 2;

std::string hexType(int type) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%02X 0x%02X", (type >> 8) & 0xFF, type & 0xFF);
  return text;
}

}  // namespace

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
  counters_.bytes += size;
  buffer_.insert(buffer_.end(), data, data + size);
  scan(on_frame);
}

void UbxFramer::scan(const FrameHandler& on_frame) {
  std::size_t pos = 0;
  auto skipByte = [&]() {
    skipped_.skip(buffer_offset_ + pos, buffer_[pos]);
    ++pos;
  };
  while (pos < buffer_.size()) {
    if (buffer_[pos] != kSync1) {
      skipByte();
      continue;
    }
    if (buffer_.size() - pos < 2) break;  // wait for the second sync byte
    if (buffer_[pos + 1] != kSync2) {
      skipByte();
      continue;
    }
    if (buffer_.size() - pos < kHeaderBytes) break;  // wait for class, id, length
    const std::uint8_t* frame = buffer_.data() + pos;
    const int type = (static_cast<int>(frame[2]) << 8) | frame[3];
    const std::size_t length = static_cast<std::size_t>(frame[4]) | (static_cast<std::size_t>(frame[5]) << 8);
    if (length > kMaxPayloadBytes) {
      skipped_.flush(counters_);
      counters_.add(StreamProblem{StreamProblemKind::BadLength, buffer_offset_ + pos, counters_.frames, type,
                                  "UBX " + hexType(type) + " length " + std::to_string(length) + " above " +
                                      std::to_string(kMaxPayloadBytes) + " bytes; searching for the next sync"});
      skipByte();
      continue;
    }
    const std::size_t frame_bytes = kHeaderBytes + length + kChecksumBytes;
    if (buffer_.size() - pos < frame_bytes) break;  // wait for the rest
    const UbxChecksum ck = ubxChecksum(frame + 2, kHeaderBytes - 2 + length);
    if (ck.a != frame[kHeaderBytes + length] || ck.b != frame[kHeaderBytes + length + 1]) {
      skipped_.flush(counters_);
      counters_.add(StreamProblem{StreamProblemKind::ChecksumError, buffer_offset_ + pos, counters_.frames, type,
                                  "UBX " + hexType(type) + " Fletcher checksum mismatch over a " +
                                      std::to_string(length) + "-byte payload; searching for the next sync"});
      skipByte();
      continue;
    }
    skipped_.flush(counters_);
    UbxFrame out;
    out.message_class = frame[2];
    out.message_id = frame[3];
    out.payload.assign(frame + kHeaderBytes, frame + kHeaderBytes + length);
    out.byte_offset = buffer_offset_ + pos;
    out.frame_index = counters_.frames;
    ++counters_.frames;
    ++counters_.frames_by_type[type];
    pos += frame_bytes;
    on_frame(out);
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(pos));
  buffer_offset_ += pos;
}

void UbxFramer::finish() {
  if (!buffer_.empty()) {
    skipped_.flush(counters_);
    const bool frame_start = buffer_[0] == kSync1 && (buffer_.size() < 2 || buffer_[1] == kSync2);
    if (frame_start) {
      counters_.add(StreamProblem{StreamProblemKind::TruncatedFrame, buffer_offset_, counters_.frames,
                                  buffer_.size() >= 4 ? ((static_cast<int>(buffer_[2]) << 8) | buffer_[3]) : 0,
                                  "the stream ended " + std::to_string(buffer_.size()) + " byte(s) into a UBX frame"});
    } else {
      for (std::size_t i = 0; i < buffer_.size(); ++i) skipped_.skip(buffer_offset_ + i, buffer_[i]);
    }
    buffer_offset_ += buffer_.size();
    buffer_.clear();
  }
  skipped_.flush(counters_);
}

}  // namespace ppp
