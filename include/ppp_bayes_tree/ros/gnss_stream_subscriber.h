#pragma once
// GnssStreamSubscriber: one ROS topic carrying a raw GNSS stream, of a message
// type that is not in this package (rtcm_msgs/Message, mavros_msgs/RTCM,
// ublox_msgs/RxmRAWX and RxmSFRBX) or GnssStreamBytes. The topic is subscribed
// with topic_tools::ShapeShifter; the type is recognised at run time by its name
// AND its MD5, and every message becomes one ppp::StreamChunk for
// ppp::LiveGnssInput (u-blox messages re-encoded as the UBX frame the receiver
// sent, so that one decoder serves all). Under sim time a message that arrives
// before the first /clock is held, never stamped with time zero. A wrong type or
// MD5 or a malformed message is a ROS error naming the topic, the type and the
// field with its byte offset, counted; the message is dropped, never a crash.
// The types, MD5s, serialization and arrival-time rules: doc/live_input.md,
// "Stream topics".
// References: wiki.ros.org/roscpp/Overview/MessagesSerializationAndAdaptingTypes;
// KumarRobotics/ublox ublox_msgs (RxmRAWX, RxmSFRBX); u-blox F9 HPG interface
// description (UBX-18010854).
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <ros/ros.h>
#include <topic_tools/shape_shifter.h>

#include "ppp_bayes_tree/io/transport/stream_chunk.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"

namespace ppp_ros {

enum class StreamMessageType { RtcmMessage, MavrosRtcm, UbloxRxmRawx, UbloxRxmSfrbx, GnssStreamBytes };

struct StreamMessageTypeInfo {
  StreamMessageType type;
  std::string name;  // ROS data type, e.g. "rtcm_msgs/Message"
  std::string md5;
};
/// Every accepted type (GnssStreamBytes with this build's generated MD5).
const std::vector<StreamMessageTypeInfo>& acceptedStreamMessageTypes();
/// The accepted type of this name and MD5; nullopt with the reason (unknown name,
/// or a known name with another MD5: another version of the definition).
std::optional<StreamMessageType> recogniseStreamMessageType(const std::string& datatype, const std::string& md5,
                                                            std::string* why);
std::string streamMessageTypeName(StreamMessageType type);

/// A malformed message: the field and the byte offset in the serialized message.
class StreamMessageError : public std::runtime_error {
 public:
  StreamMessageError(const std::string& field, std::size_t byte_offset, const std::string& what);
  const std::string& field() const { return field_; }
  std::size_t byteOffset() const { return byte_offset_; }

 private:
  std::string field_;
  std::size_t byte_offset_;
};

/// Parses "rtcm3"/"rtcm" or "ubx" (case-insensitive); nullopt for anything else.
std::optional<ppp::StreamFormat> parseStreamFormatHint(const std::string& text);

/// One serialized message (ROS serialization) of `type` -> its chunk (stream =
/// `topic`, no arrival time). `format_hint`: GnssStreamBytes without a format.
/// `header_seq` (optional): set to header.seq for the types with a header, as soon as
/// the header is read (also when the message then throws). Throws StreamMessageError.
ppp::StreamChunk streamChunkFromMessage(StreamMessageType type, const std::string& topic, const std::uint8_t* data,
                                        std::size_t size, std::optional<ppp::StreamFormat> format_hint = std::nullopt,
                                        std::optional<std::uint32_t>* header_seq = nullptr);

class GnssStreamSubscriber {
 public:
  using ChunkHandler = std::function<void(ppp::StreamChunk&&)>;
  struct Counters {
    std::size_t messages = 0;        // received (any type)
    std::size_t bytes = 0;           // stream bytes handed on
    std::size_t wrong_type = 0;      // messages of a type/MD5 not accepted (dropped)
    std::size_t malformed = 0;       // messages that did not deserialize (dropped)
    std::string type;                // the publisher's type of the last message ("" = none yet)
    std::string last_error;          // the last wrong-type / malformed message, with the reason
    std::optional<ros::Time> last_arrival;
    /// Messages lost before the node: gaps in header.seq per publisher (types with a
    /// header; a subscriber or publisher queue overflow leaves a gap). A publisher that
    /// does not number its messages (seq constant) shows none.
    std::size_t lost = 0;
    /// Thread CPU time spent turning messages into chunks (re-serializing, checking,
    /// re-framing RAWX/SFRBX as UBX) [s]; the decoding itself is LiveGnssInput's.
    double conversion_cpu_s = 0.0;
    /// Messages that arrived before the ROS clock was valid (sim time before the first
    /// /clock), held and handed on with the first valid time.
    std::size_t held_for_clock = 0;
  };

  /// Subscribes `topic` (relative to nh's namespace); chunks go to `on_chunk` with
  /// stream = `stream_name` ("" = the resolved topic: topics of one receiver, e.g.
  /// ublox_gps's RxmRAWX and RxmSFRBX, share one stream, so one decoder sees both).
  GnssStreamSubscriber(ros::NodeHandle& nh, const std::string& topic, std::optional<ppp::StreamFormat> format_hint,
                       std::uint32_t queue_size, ChunkHandler on_chunk, const std::string& stream_name = "");
  GnssStreamSubscriber(const GnssStreamSubscriber&) = delete;
  GnssStreamSubscriber& operator=(const GnssStreamSubscriber&) = delete;

  const std::string& topic() const { return topic_; }  // resolved name
  const Counters& counters() const { return counters_; }
  /// Hands on the chunks held for the clock, stamped now, once the ROS clock is valid
  /// (the node calls it from its timer, which runs only then); nothing otherwise.
  void releaseHeld();

 private:
  void onMessage(const ros::MessageEvent<topic_tools::ShapeShifter const>& event);
  void error(const std::string& text);

  std::string topic_;
  std::string stream_;
  std::optional<ppp::StreamFormat> format_hint_;
  ChunkHandler on_chunk_;
  Counters counters_;
  ros::Subscriber sub_;
  ros::WallTime last_error_log_;
  std::map<std::string, std::uint32_t> last_seq_;  // per publisher (caller id)
  std::vector<ppp::StreamChunk> held_;             // arrived before the clock was valid, in order
};

}  // namespace ppp_ros
