#pragma once
// FramerBase: the search for frames in a binary stream fed in chunks of any
// size, common to the RTCM 3 and UBX framers (io/rtcm/rtcm3_framer.h,
// io/ubx/ubx_framer.h). A format says, through examine(), what the bytes at a
// candidate frame start are; the base does the rest the same way for every
// format:
//   - bytes that start no frame are skipped and counted by io/skipped_bytes.h
//     (NMEA text, or garbage: one problem per run, at the run's first offset);
//   - a frame header whose frame is bad (checksum, length) is one problem at
//     the offset of its first byte, and the search resumes at the next byte,
//     so a frame hidden behind a false sync is still found;
//   - a frame cut by the end of a chunk waits for the next feed;
//   - finish() reports a frame the stream ended inside (TruncatedFrame) or
//     skips the bytes left.
// Byte offsets count from the first byte fed; frame indices count the good
// frames before.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/skipped_bytes.h"
#include "ppp_bayes_tree/io/stream_problem.h"

namespace ppp {

/// A frame header that is not a good frame: what is wrong, for StreamCounters.
struct FrameFault {
  StreamProblemKind kind = StreamProblemKind::ChecksumError;
  int message_type = 0;  // 0 when not known
  std::string detail;
};

/// What a format makes of the bytes from a candidate frame start on.
struct FrameCandidate {
  enum class Verdict {
    NotAFrame,      // no frame starts at this byte: it is skipped
    NeedMoreBytes,  // too few bytes to tell: wait for the next feed
    Rejected,       // a frame header whose frame is bad (`fault`): resync from the next byte
    Good,           // a whole frame whose check holds
  };
  Verdict verdict = Verdict::NotAFrame;
  std::size_t frame_bytes = 0;  // Good: header, payload and check bytes
  int message_type = 0;         // Good: the key of StreamCounters::frames_by_type
  FrameFault fault;             // Rejected

  static FrameCandidate notAFrame() { return {}; }
  static FrameCandidate needMoreBytes() { return {Verdict::NeedMoreBytes, 0, 0, {}}; }
  static FrameCandidate rejected(FrameFault fault) { return {Verdict::Rejected, 0, 0, std::move(fault)}; }
  static FrameCandidate good(std::size_t frame_bytes, int message_type) {
    return {Verdict::Good, frame_bytes, message_type, {}};
  }
};

/// A good frame in the framer's buffer, valid during the call it is given to.
struct FrameBytes {
  const std::uint8_t* data = nullptr;  // the whole frame, from its first sync byte
  std::size_t size = 0;
  int message_type = 0;
  std::uint64_t byte_offset = 0;  // of data[0], from the first byte fed
  std::uint64_t frame_index = 0;  // 0-based count of good frames
};

class FramerBase {
 public:
  const StreamCounters& counters() const { return counters_; }
  StreamCounters& counters() { return counters_; }
  /// The stream ended: a partial frame is counted as truncated.
  void finish();

 protected:
  /// `protocol` names the frames in problem texts ("RTCM 3", "UBX").
  explicit FramerBase(std::string protocol) : skipped_(std::move(protocol)) {}
  virtual ~FramerBase() = default;
  FramerBase(const FramerBase&) = default;
  FramerBase& operator=(const FramerBase&) = default;
  FramerBase(FramerBase&&) = default;
  FramerBase& operator=(FramerBase&&) = default;

  /// The format's rules for the `available` bytes from `data` on (at least one).
  virtual FrameCandidate examine(const std::uint8_t* data, std::size_t available) const = 0;
  /// At the end of the stream: the fault when the `available` bytes left (at
  /// least one) are the start of a frame, nullopt when they are to be skipped.
  virtual std::optional<FrameFault> truncatedFrame(const std::uint8_t* data, std::size_t available) const = 0;

  /// Appends bytes and calls `on_frame` for every good frame, in stream order.
  void feedBytes(const std::uint8_t* data, std::size_t size, const std::function<void(const FrameBytes&)>& on_frame);

 private:
  void scan(const std::function<void(const FrameBytes&)>& on_frame);

  std::vector<std::uint8_t> buffer_;  // unconsumed bytes
  std::uint64_t buffer_offset_ = 0;   // stream offset of buffer_[0]
  SkippedBytes skipped_;
  StreamCounters counters_;
};

}  // namespace ppp
