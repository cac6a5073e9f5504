#pragma once
// StreamProblem / StreamCounters: what a binary stream decoder (RTCM 3, UBX)
// reports about its input. Every problem names where it happened: the byte
// offset in the stream (from the first byte fed) and the frame index (the
// number of well-framed messages before it), so that a user can find it with
// a hex viewer. Problems are counted by kind without limit; the first
// kMaxKeptProblems are kept with their text.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace ppp {

enum class StreamProblemKind {
  ChecksumError,        // RTCM CRC-24Q or UBX Fletcher checksum does not match
  TruncatedFrame,       // the stream ended inside a frame
  Garbage,              // bytes between frames that belong to no frame
  BadLength,            // a length field outside the protocol's limits
  UnknownMessage,       // a well-framed message of a type the decoder does not read
  MalformedMessage,     // a message shorter than its fields, or with values out of range
  InconsistentEphemeris,// an ephemeris whose IODs disagree (e.g. IODC vs IODE)
  UnresolvedTime,       // a time that cannot be placed (no week known)
  SsrWithoutBroadcast,  // an SSR correction for an IOD with no broadcast record
  SsrTooOld,            // an SSR correction older than its validity
  EpochTimeRefused,     // an observation epoch whose time does not continue the stream (io/epoch_time_screen.h)
  ImplausibleValue,     // a value beyond its physical bound (e.g. a bias: io/bias_bounds.h), not used
};

std::string_view streamProblemKindName(StreamProblemKind kind);

/// "byte 1234 (frame 56), type 1077" (the type left out when 0): where in a stream.
std::string streamPlace(std::uint64_t byte_offset, std::uint64_t frame_index, int message_type);

struct StreamProblem {
  StreamProblemKind kind = StreamProblemKind::Garbage;
  std::uint64_t byte_offset = 0;  // of the frame start (or of the first bad byte)
  std::uint64_t frame_index = 0;  // frames framed correctly before this point
  int message_type = 0;           // 0 when not known (RTCM type, or UBX class<<8|id)
  std::string detail;             // for people; never parsed

  /// "byte 1234 (frame 56), type 1077: CRC-24Q mismatch ..."
  std::string describe() const;
};

struct StreamCounters {
  static constexpr std::size_t kMaxKeptProblems = 1000;

  std::uint64_t bytes = 0;
  std::uint64_t frames = 0;                     // frames with a good checksum
  std::map<int, std::uint64_t> frames_by_type;  // good frames per message type
  std::map<StreamProblemKind, std::uint64_t> problems_by_kind;
  std::uint64_t garbage_bytes = 0;
  std::uint64_t nmea_bytes = 0;                 // NMEA text interleaved with UBX frames (not a problem)
  /// SSR bias values of a signal id that a satellite's block sends again, the
  /// first kept (not a problem: a known habit of real streams, counted and noted).
  std::uint64_t repeated_signals = 0;
  std::string first_repeated_signal;  // describe() of the first one
  std::vector<StreamProblem> problems;          // the first kMaxKeptProblems

  void add(StreamProblem problem);
  std::uint64_t count(StreamProblemKind kind) const;
  std::uint64_t totalProblems() const;
  /// For people: one line "  N x <kind>" per kind, then "  <describe()>" for the first
  /// `max_listed` problems kept (the tools print it after their summary line).
  std::string problemLines(std::size_t max_listed = 20) const;
};

}  // namespace ppp
