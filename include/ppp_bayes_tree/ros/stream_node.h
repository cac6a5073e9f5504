#pragma once
// StreamNode (ppp_stream_node): a direct input (serial port, TCP server, NTRIP
// caster, or a recording replayed at real-time speed; spec syntax in
// io/transport/byte_source_spec.h) as ROS topics, for users without a driver node.
//
// The input is a ppp::ReconnectingByteSource (back-off, counted), framed by the
// core framers, and published one message per complete frame (the frame's
// bytes unchanged, preamble/sync to CRC/checksum):
//   RTCM 3 -> ~output_topic as rtcm_msgs/Message (std_msgs/Header header,
//             uint8[] message), the type of the common NTRIP client node and of
//             ublox_gps. rtcm_msgs is not in Debian: the message is published
//             through topic_tools::ShapeShifter with its exact type name, MD5 and
//             definition (the serialization is written here).
//   UBX    -> ~output_topic as ppp_bayes_tree/GnssStreamBytes (format "ubx").
// Diagnostics (/diagnostics, task "stream"): bytes, frames, CRC errors, garbage
// bytes, reconnects, stalls, errors by kind, the last error, the age of the
// last byte (WARN past ~stall_warn_s, ERROR past ~stall_error_s or on a
// permanent error such as a refused password). Passwords are never logged.
// Parameters: config/stream.yaml (every key with meaning, unit and default).
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <std_msgs/Header.h>
#include <topic_tools/shape_shifter.h>

#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/transport/byte_source.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"
#include "ppp_bayes_tree/io/ubx/ubx_framer.h"
#include "ppp_bayes_tree/ros/sim_clock_watch.h"

namespace ppp_ros {

/// rtcm_msgs/Message: type name, MD5 (= md5("<std_msgs/Header MD5> header\nuint8[] message"),
/// genmsg's rule) and the full definition text (with std_msgs/Header's).
extern const char* const kRtcmMessageType;
extern const char* const kRtcmMessageMd5;
std::string rtcmMessageDefinition();
/// One rtcm_msgs/Message holding `bytes`, ready to publish.
topic_tools::ShapeShifter makeRtcmMessage(const std_msgs::Header& header, const std::vector<std::uint8_t>& bytes);
/// The `message` bytes of a serialized rtcm_msgs/Message (throws std::runtime_error when
/// the type or the MD5 is another).
std::vector<std::uint8_t> rtcmMessageBytes(const topic_tools::ShapeShifter& message, std_msgs::Header* header = nullptr);

struct StreamNodeOptions {
  std::string input;               // the input spec (required)
  std::string format;              // "rtcm3", "ubx", or "" (the spec's format=, else detected)
  std::string output_topic = "rtcm";
  std::string frame_id = "gnss";
  int queue_size = 100;
  double stall_warn_s = 2.0;       // no byte for this long: diagnostics WARN
  double stall_error_s = 10.0;     // no byte for this long: diagnostics ERROR
};

/// Reads the private parameters (config/stream.yaml); throws std::runtime_error naming the key.
StreamNodeOptions loadStreamNodeOptions(const ros::NodeHandle& pnh);

class StreamNode {
 public:
  StreamNode(ros::NodeHandle nh, ros::NodeHandle pnh);
  /// Reads and publishes until ROS shuts down.
  void run();

 private:
  void consume(const std::uint8_t* data, std::size_t size);
  void advertise();  // ~output_topic with the type of format_
  void publishFrame(const std::vector<std::uint8_t>& bytes);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  StreamNodeOptions options_;
  ros::NodeHandle nh_, pnh_;
  std::unique_ptr<ppp::ByteSource> source_;
  ppp::StreamFormat format_ = ppp::StreamFormat::Unknown;
  ppp::Rtcm3Framer rtcm_;
  ppp::UbxFramer ubx_;
  std::vector<std::uint8_t> window_;  // recent bytes (frames are cut from here)
  std::uint64_t window_offset_ = 0;   // stream offset of window_[0]
  std::uint64_t framer_base_ = 0;     // stream offset of the first byte fed to the framer
  std::uint64_t stream_bytes_ = 0;
  std::uint64_t published_ = 0;
  ros::Publisher publisher_;
  bool advertised_ = false;
  bool ended_ = false;                // a replayed file ended
  std::optional<std::chrono::steady_clock::time_point> last_byte_time_;
  std::chrono::steady_clock::time_point start_time_;
  diagnostic_updater::Updater diagnostics_;
  std::unique_ptr<SimClockWatch> sim_clock_watch_;  // says so while /use_sim_time waits for /clock
};

/// The whole main() of ppp_stream_node (ros/node_main.h runNode): 0 after shutdown, 1 when it could not start.
int runStreamNode(int argc, char** argv, const std::string& node_name);

}  // namespace ppp_ros
