#pragma once
// FileReplaySource: a recorded RTCM 3 or UBX stream replayed at real-time
// speed times a factor, paced by the stream's own epoch times: the epoch time
// of RTCM MSM messages (DF004/DF248/DF427 time of week, RTCM 10403.3 table
// 3.5-78; GLONASS MSM is not used, its time is of day) and the receiver time
// of week of UBX RXM-RAWX (rcvTOW). A frame is released when the wall time
// since the first timed frame reaches (its epoch time - the first) / speed;
// untimed frames go with the timed frame before them. A recording without
// times (e.g. only ephemerides) is paced by a byte rate. Times that go back
// or jump ahead by more than a minute re-anchor the pacing (counted).
// The frames are found by the existing framers (io/rtcm/rtcm3_framer.h,
// io/ubx/ubx_framer.h); every byte of the file is delivered unchanged, including
// bytes outside frames.
#include <chrono>
#include <cstdint>
#include <deque>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/transport/byte_source.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"
#include "ppp_bayes_tree/io/ubx/ubx_framer.h"

namespace ppp {

/// Epoch time of week [s] carried by an RTCM 3 frame's payload (MSM1-7 of
/// GPS, Galileo, SBAS, QZSS, BeiDou; BeiDou moved to GPS time), nullopt otherwise.
std::optional<double> rtcm3EpochTimeOfWeek_s(const std::vector<std::uint8_t>& payload);
/// rcvTOW [s] of a UBX RXM-RAWX frame, nullopt for other frames.
std::optional<double> ubxEpochTimeOfWeek_s(const UbxFrame& frame);

class FileReplaySource : public ByteSource {
 public:
  /// `speed` <= 0 replays as fast as read; `format` Unknown is detected from the content.
  FileReplaySource(std::string path, double speed, double byte_rate_bytes_per_s,
                   StreamFormat format = StreamFormat::Unknown);

  /// A recording that cannot be opened gives its OpenFailed error once (naming
  /// the file), then Closed: there is nothing to replay (close() tries again).
  ByteSourceRead read(std::uint8_t* buffer, std::size_t capacity,
                      std::chrono::milliseconds timeout) override;
  std::string describe() const override;
  void close() override;

  StreamFormat format() const { return format_; }
  std::uint64_t timedFrames() const { return timed_frames_; }
  std::uint64_t reanchors() const { return reanchors_; }

 private:
  struct Segment {
    std::uint64_t end_offset;  // file offset one past the segment
    std::chrono::steady_clock::time_point release;
  };
  std::optional<ByteSourceError> open();
  bool readMore();  // false at end of file
  void onFrame(std::uint64_t end_offset, std::optional<double> epoch_s);

  std::string path_;
  double speed_;
  double byte_rate_;
  StreamFormat format_;
  std::ifstream file_;
  bool opened_ = false;
  bool open_failed_ = false;  // the open failed: read() reports Closed until close()
  bool eof_ = false;
  Rtcm3Framer rtcm_;
  UbxFramer ubx_;
  std::vector<std::uint8_t> pending_;  // read from the file, not yet delivered
  std::uint64_t pending_offset_ = 0;   // file offset of pending_[0]
  std::uint64_t read_offset_ = 0;      // file offset of the next byte to read
  std::deque<Segment> segments_;       // release times of the bytes in pending_
  std::uint64_t released_end_ = 0;    // bytes before this offset may go
  std::chrono::steady_clock::time_point start_wall_;
  std::optional<double> anchor_epoch_s_;
  std::chrono::steady_clock::time_point anchor_wall_;
  std::optional<double> last_epoch_s_;
  std::chrono::steady_clock::time_point last_release_;
  std::uint64_t timed_frames_ = 0;
  std::uint64_t reanchors_ = 0;
};

}  // namespace ppp
