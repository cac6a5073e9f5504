#pragma once
// SkippedBytes: the bytes a framer (RTCM 3, UBX) passes over between frames,
// gathered into runs so that one run is one report. A run that is NMEA text (it
// starts with '$' and holds only printable characters and line ends) is another
// protocol the receiver interleaves, counted as NMEA bytes and not a problem;
// any other run is garbage: one StreamProblem naming its first byte offset.
#include <cstdint>
#include <string>

#include "ppp_bayes_tree/io/stream_problem.h"

namespace ppp {

class SkippedBytes {
 public:
  /// `protocol` names the frames in the problem text ("RTCM 3", "UBX").
  explicit SkippedBytes(std::string protocol) : protocol_(std::move(protocol)) {}

  /// One byte at stream offset `offset` is not part of a frame.
  void skip(std::uint64_t offset, std::uint8_t byte);
  /// Ends the current run (before a frame or a problem is reported, and at the end).
  void flush(StreamCounters& counters);

 private:
  std::string protocol_;
  std::uint64_t start_ = 0;
  std::uint64_t length_ = 0;
  bool nmea_ = false;  // the run is NMEA text so far
};

}  // namespace ppp
