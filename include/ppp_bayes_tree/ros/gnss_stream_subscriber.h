#pragma once
// GnssStreamSubscriber: one ROS topic carrying a raw GNSS stream, of a message
// type that is not in this package. The topic is subscribed with
// topic_tools::ShapeShifter; the type is recognised at run time by its name AND
// its MD5 (the publisher's connection header), and every message becomes one
// ppp::StreamChunk (stream = the resolved topic name) for ppp::LiveGnssInput,
// which holds the one decoder (RTCM 3 / UBX) of the package:
//   rtcm_msgs/Message       (std_msgs/Header header, uint8[] message): one RTCM 3
//                           frame or any chunk of the byte stream -> Rtcm3 chunk;
//   mavros_msgs/RTCM        (std_msgs/Header header, uint8[] data) -> Rtcm3 chunk;
//   ublox_msgs/RxmRAWX      (no header; the fields of UBX-RXM-RAWX) and
//   ublox_msgs/RxmSFRBX     (no header; the fields of UBX-RXM-SFRBX): the ROS fields
//                           are deserialized here and re-encoded as the UBX frame
//                           the receiver sent (Fletcher checksum), so that the same
//                           core UbxDecoder decodes them (one decoding point). All
//                           payload bytes are fields of the ROS messages, so the frame
//                           is byte for byte the receiver's; reserved0 of
//                           RxmRAWX_Meas is the sigId of F9 receivers, reserved0 of
//                           RxmSFRBX the sigId of message version 2;
//   ppp_bayes_tree/GnssStreamBytes (Header header, string format, uint8[] data):
//                           format "rtcm3" or "ubx" (case-insensitive; "" = the
//                           topic's format hint, else detected from the bytes).
// MD5s and definitions: rtcm_msgs and mavros_msgs as their packages define them; ublox_msgs
// from KumarRobotics/ublox master (ublox_msgs/msg/RxmRAWX.msg, RxmRAWX_Meas.msg,
// RxmSFRBX.msg, last changed in fc92537, 2018-08-10), MD5 computed with genmsg 0.6
// (gentools.compute_md5): RxmRAWX a2df4b27b6a2a1565e42f5669dbb11b5,
// RxmSFRBX c76473d828cc8e80de3a2d83cd6b9dff.
// Arrival time (StreamChunk::arrival_time_s, which LiveGnssInput's waits for the
// station and the corrections, its latency and its stall state are measured in):
// ros::Time::now() at the message. Under sim time (use_sim_time: a bag replayed
// with rosbag play --clock, launch/live.launch example c) that clock is zero
// until this node has its first /clock message, which can come after the bag's
// first messages (separate connections; at 10 Hz many): such a message is held,
// its order kept, and handed on stamped with the first valid time (at the next
// message or releaseHeld()), never with time zero, which would make an epoch
// look as old as the bag's time (no wait for its corrections, wrong latency).
// ROS serialization (wiki.ros.org/roscpp/Overview/MessagesSerializationAndAdaptingTypes,
// "Serialization"): little endian, a variable array or string = uint32 length +
// elements, a fixed array = its elements only, a time = uint32 sec + uint32 nsec.
// A wrong type or MD5, or a malformed message (short buffer, an array length beyond
// the buffer, bytes left over, NaN, a count field that disagrees with its array)
// is a ROS error naming the topic, the type and the field with its byte offset,
// counted per topic (diagnostics); the message is dropped, never a crash.
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
