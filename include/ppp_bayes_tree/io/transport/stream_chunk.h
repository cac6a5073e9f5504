#pragma once
// StreamChunk: the bytes of one receiver or correction stream as they arrived
// (a serial read, a TCP/NTRIP read, one rtcm_msgs/Message, one UBX message of a
// driver topic), in any chunking: a frame may be split over chunks and a chunk
// may hold several frames. The consumer (app/live_gnss_input.h) frames them.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/transport/stream_format.h"

namespace ppp {

/// Bytes of one receiver or correction stream as they arrived, in any chunking.
struct StreamChunk {
  std::string stream;                          // name used in messages and counters: topic, device, mountpoint
  StreamFormat format = StreamFormat::Rtcm3;   // io/transport/stream_format.h (Rtcm3 or Ubx)
  std::vector<std::uint8_t> bytes;
  std::optional<double> arrival_time_s;        // receive time (ROS/wall clock, s) for latency and stall; nullopt: unknown
};

}  // namespace ppp
