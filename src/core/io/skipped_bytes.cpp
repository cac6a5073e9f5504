#include "ppp_bayes_tree/io/skipped_bytes.h"

namespace ppp {

void SkippedBytes::skip(std::uint64_t offset, std::uint8_t byte) {
  if (length_ == 0) {
    start_ = offset;
    nmea_ = byte == '$';
  } else {
    nmea_ = nmea_ && ((byte >= 0x20 && byte < 0x7F) || byte == '\r' || byte == '\n');
  }
  ++length_;
}

void SkippedBytes::flush(StreamCounters& counters) {
  if (length_ == 0) return;
  if (nmea_) {
    counters.nmea_bytes += length_;
  } else {
    counters.garbage_bytes += length_;
    counters.add(StreamProblem{StreamProblemKind::Garbage, start_, counters.frames, 0,
                               std::to_string(length_) + " byte(s) outside any " + protocol_ + " frame skipped"});
  }
  length_ = 0;
}

}  // namespace ppp
