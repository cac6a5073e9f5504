#include "ppp_bayes_tree/io/rtcm3_framer.h"

#include <array>
#include <stdexcept>
#include <string>

namespace ppp {
namespace {

constexpr std::uint8_t kPreamble = 0xD3;
constexpr std::size_t kHeaderBytes = 3;
constexpr std::size_t kCrcBytes = 3;

std::array<std::uint32_t, 256> makeCrc24qTable() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t crc = i << 16;
    for (int bit = 0; bit < 8; ++bit) {
      crc <<= 1;
      if (crc & 0x1000000u) crc ^= 0x1864CFBu;
    }
    table[i] = crc & 0xFFFFFFu;
  }
  return table;
}

}  // namespace

std::uint32_t crc24q(const std::uint8_t* data, std::size_t size) {
  static const std::array<std::uint32_t, 256> table = makeCrc24qTable();
  std::uint32_t crc = 0;
  for (std::size_t i = 0; i < size; ++i) {
    crc = ((crc << 8) & 0xFFFFFFu) ^ table[((crc >> 16) ^ data[i]) & 0xFFu];
  }
  return crc;
}

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
  counters_.bytes += size;
  buffer_.insert(buffer_.end(), data, data + size);
  scan(on_frame);
}

void Rtcm3Framer::scan(const FrameHandler& on_frame) {
  std::size_t pos = 0;
  auto skipByte = [&]() {
    skipped_.skip(buffer_offset_ + pos, buffer_[pos]);
    ++pos;
  };
  while (pos < buffer_.size()) {
    if (buffer_[pos] != kPreamble) {
      skipByte();
      continue;
    }
    if (buffer_.size() - pos < kHeaderBytes) break;  // wait for the length
    const std::size_t length = (static_cast<std::size_t>(buffer_[pos + 1] & 0x03u) << 8) | buffer_[pos + 2];
    if ((buffer_[pos + 1] & 0xFCu) != 0) {
      // Reserved bits set: not a frame start (RTCM 10403.3 requires them zero).
      skipByte();
      continue;
    }
    const std::size_t frame_bytes = kHeaderBytes + length + kCrcBytes;
    if (buffer_.size() - pos < frame_bytes) break;  // wait for the rest
    const std::uint8_t* frame = buffer_.data() + pos;
    const std::uint32_t expected = (static_cast<std::uint32_t>(frame[kHeaderBytes + length]) << 16) |
                                   (static_cast<std::uint32_t>(frame[kHeaderBytes + length + 1]) << 8) |
                                   frame[kHeaderBytes + length + 2];
    const std::uint32_t computed = crc24q(frame, kHeaderBytes + length);
    if (computed != expected) {
      skipped_.flush(counters_);
      const int type = length >= 2 ? static_cast<int>((frame[3] << 4) | (frame[4] >> 4)) : 0;
      counters_.add(StreamProblem{StreamProblemKind::ChecksumError, buffer_offset_ + pos, counters_.frames, type,
                                  "CRC-24Q mismatch over a " + std::to_string(length) +
                                      "-byte frame; searching for the next preamble"});
      skipByte();  // resynchronise from the byte after the false preamble
      continue;
    }
    skipped_.flush(counters_);
    Rtcm3Frame out;
    out.payload.assign(frame + kHeaderBytes, frame + kHeaderBytes + length);
    out.message_type = length >= 2 ? static_cast<int>((out.payload[0] << 4) | (out.payload[1] >> 4)) : 0;
    out.byte_offset = buffer_offset_ + pos;
    out.frame_index = counters_.frames;
    ++counters_.frames;
    ++counters_.frames_by_type[out.message_type];
    pos += frame_bytes;
    on_frame(out);
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(pos));
  buffer_offset_ += pos;
}

void Rtcm3Framer::finish() {
  if (!buffer_.empty()) {
    skipped_.flush(counters_);
    if (buffer_[0] == kPreamble) {
      counters_.add(StreamProblem{StreamProblemKind::TruncatedFrame, buffer_offset_, counters_.frames, 0,
                                  "the stream ended " + std::to_string(buffer_.size()) +
                                      " byte(s) into a frame"});
    } else {
      for (std::size_t i = 0; i < buffer_.size(); ++i) skipped_.skip(buffer_offset_ + i, buffer_[i]);
    }
    buffer_offset_ += buffer_.size();
    buffer_.clear();
  }
  skipped_.flush(counters_);
}

}  // namespace ppp
