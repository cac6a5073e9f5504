#include "ppp_bayes_tree/ros/gnss_stream_subscriber.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

#include <ros/message_traits.h>

#include "ppp_bayes_tree/GnssStreamBytes.h"
#include "ppp_bayes_tree/io/untrusted_text.h"
#include "ppp_bayes_tree/io/ubx/ubx_framer.h"
#include "ppp_bayes_tree/types/thread_cpu_time.h"

namespace ppp_ros {
namespace {

constexpr std::uint8_t kUbxClassRxm = 0x02;
constexpr std::uint8_t kUbxIdRawx = 0x15;
constexpr std::uint8_t kUbxIdSfrbx = 0x13;
constexpr std::size_t kRawxMeasBytes = 32;  // UBX-RXM-RAWX repeated block

std::uint32_t littleEndianU32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16) | (std::uint32_t(p[3]) << 24);
}

/// Reads ROS serialization (little endian) with bounds checks naming the field.
class RosReader {
 public:
  RosReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::size_t offset() const { return offset_; }
  std::size_t left() const { return size_ - offset_; }

  const std::uint8_t* take(std::size_t n, const std::string& field) {
    if (n > left())
      throw StreamMessageError(field, offset_, "needs " + std::to_string(n) + " byte(s), " + std::to_string(left()) +
                                                   " left of " + std::to_string(size_));
    const std::uint8_t* p = data_ + offset_;
    offset_ += n;
    return p;
  }
  std::uint8_t u8(const std::string& field) { return *take(1, field); }
  std::uint16_t u16(const std::string& field) {
    const std::uint8_t* p = take(2, field);
    return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
  }
  std::uint32_t u32(const std::string& field) { return littleEndianU32(take(4, field)); }
  /// A variable array's length (uint32), checked against the bytes left.
  std::uint32_t arrayLength(const std::string& field, std::size_t element_bytes) {
    const std::size_t at = offset_;
    const std::uint32_t n = u32(field + " length");
    if (std::uint64_t{n} * element_bytes > left())
      throw StreamMessageError(field, at, "array length " + std::to_string(n) + " x " + std::to_string(element_bytes) +
                                              " byte(s) beyond the message (" + std::to_string(left()) + " left)");
    return n;
  }
  /// A std_msgs/Header; returns its seq.
  std::uint32_t header(const std::string& field) {
    const std::uint32_t seq = littleEndianU32(take(12, field + ".seq/stamp"));
    const std::uint32_t n = arrayLength(field + ".frame_id", 1);
    take(n, field + ".frame_id");
    return seq;
  }
  std::string string(const std::string& field) {
    const std::uint32_t n = arrayLength(field, 1);
    const std::uint8_t* p = take(n, field);
    return std::string(reinterpret_cast<const char*>(p), n);
  }
  std::vector<std::uint8_t> bytes(const std::string& field) {
    const std::uint32_t n = arrayLength(field, 1);
    const std::uint8_t* p = take(n, field);
    return std::vector<std::uint8_t>(p, p + n);
  }
  void finish(const std::string& type) {
    if (left() != 0)
      throw StreamMessageError("(end)", offset_, std::to_string(left()) + " byte(s) after the last field of " + type);
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
};

/// Copies `n` bytes of a float field (little endian in both encodings), refusing NaN/inf.
void copyFloat(RosReader& r, std::vector<std::uint8_t>& out, std::size_t n, const std::string& field) {
  const std::size_t at = r.offset();
  const std::uint8_t* p = r.take(n, field);
  double value = 0.0;
  if (n == 8) {
    std::uint64_t bits = 0;
    for (int i = 7; i >= 0; --i) bits = (bits << 8) | p[i];
    std::memcpy(&value, &bits, 8);
  } else {
    std::uint32_t bits = 0;
    for (int i = 3; i >= 0; --i) bits = (bits << 8) | p[i];
    float f = 0.0f;
    std::memcpy(&f, &bits, 4);
    value = f;
  }
  if (!std::isfinite(value)) throw StreamMessageError(field, at, "not a finite number");
  out.insert(out.end(), p, p + n);
}

void copyBytes(RosReader& r, std::vector<std::uint8_t>& out, std::size_t n, const std::string& field) {
  const std::uint8_t* p = r.take(n, field);
  out.insert(out.end(), p, p + n);
}

/// ublox_msgs/RxmRAWX -> the UBX-RXM-RAWX frame. ROS field order = UBX payload order.
std::vector<std::uint8_t> rawxFrame(RosReader& r) {
  std::vector<std::uint8_t> payload;
  copyFloat(r, payload, 8, "rcvTOW");
  copyBytes(r, payload, 2, "week");
  copyBytes(r, payload, 1, "leapS");
  const std::size_t num_at = r.offset();
  const std::uint8_t num_meas = r.u8("numMeas");
  payload.push_back(num_meas);
  copyBytes(r, payload, 1, "recStat");
  copyBytes(r, payload, 1, "version");
  copyBytes(r, payload, 2, "reserved1");  // uint8[2]: fixed array, no length
  const std::uint32_t n = r.arrayLength("meas", kRawxMeasBytes);
  if (n != num_meas)
    throw StreamMessageError("numMeas", num_at, "numMeas " + std::to_string(num_meas) + " but meas holds " +
                                                    std::to_string(n) + " element(s)");
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::string m = "meas[" + std::to_string(k) + "].";
    copyFloat(r, payload, 8, m + "prMes");
    copyFloat(r, payload, 8, m + "cpMes");
    copyFloat(r, payload, 4, m + "doMes");
    // gnssId, svId, reserved0 (= sigId), freqId, locktime (2), cno, prStdev, cpStdev, doStdev, trkStat, reserved1
    copyBytes(r, payload, 12, m + "gnssId..reserved1");
  }
  r.finish("ublox_msgs/RxmRAWX");
  return ppp::encodeUbxFrame(kUbxClassRxm, kUbxIdRawx, payload);
}

/// ublox_msgs/RxmSFRBX -> the UBX-RXM-SFRBX frame.
std::vector<std::uint8_t> sfrbxFrame(RosReader& r) {
  std::vector<std::uint8_t> payload;
  copyBytes(r, payload, 3, "gnssId/svId/reserved0");
  copyBytes(r, payload, 1, "freqId");
  const std::size_t num_at = r.offset();
  const std::uint8_t num_words = r.u8("numWords");
  payload.push_back(num_words);
  copyBytes(r, payload, 3, "chn/version/reserved1");
  const std::uint32_t n = r.arrayLength("dwrd", 4);
  if (n != num_words)
    throw StreamMessageError("numWords", num_at, "numWords " + std::to_string(num_words) + " but dwrd holds " +
                                                     std::to_string(n) + " word(s)");
  copyBytes(r, payload, 4u * n, "dwrd");
  r.finish("ublox_msgs/RxmSFRBX");
  return ppp::encodeUbxFrame(kUbxClassRxm, kUbxIdSfrbx, payload);
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace

StreamMessageError::StreamMessageError(const std::string& field, std::size_t byte_offset, const std::string& what)
    : std::runtime_error("field " + field + " at byte " + std::to_string(byte_offset) + ": " + what),
      field_(field),
      byte_offset_(byte_offset) {}

const std::vector<StreamMessageTypeInfo>& acceptedStreamMessageTypes() {
  static const std::vector<StreamMessageTypeInfo> types = {
      {StreamMessageType::RtcmMessage, "rtcm_msgs/Message", "883b1fb65b83ccf75497c21f2d63052d"},
      {StreamMessageType::MavrosRtcm, "mavros_msgs/RTCM", "8903b686ebe5db3477e83c6d0bb149f8"},
      {StreamMessageType::UbloxRxmRawx, "ublox_msgs/RxmRAWX", "a2df4b27b6a2a1565e42f5669dbb11b5"},
      {StreamMessageType::UbloxRxmSfrbx, "ublox_msgs/RxmSFRBX", "c76473d828cc8e80de3a2d83cd6b9dff"},
      {StreamMessageType::GnssStreamBytes, ros::message_traits::datatype<ppp_bayes_tree::GnssStreamBytes>(),
       ros::message_traits::md5sum<ppp_bayes_tree::GnssStreamBytes>()},
  };
  return types;
}

std::string streamMessageTypeName(StreamMessageType type) {
  for (const auto& t : acceptedStreamMessageTypes())
    if (t.type == type) return t.name;
  return "unknown";
}

std::optional<StreamMessageType> recogniseStreamMessageType(const std::string& datatype, const std::string& md5,
                                                            std::string* why) {
  for (const auto& t : acceptedStreamMessageTypes()) {
    if (t.name != datatype) continue;
    if (t.md5 == md5) return t.type;
    if (why) *why = "type " + datatype + " with MD5 " + md5 + ", not the accepted definition's " + t.md5;
    return std::nullopt;
  }
  if (why) {
    *why = "type " + datatype + " (MD5 " + md5 + ") is not a GNSS stream type; accepted:";
    for (const auto& t : acceptedStreamMessageTypes()) *why += " " + t.name;
  }
  return std::nullopt;
}

std::optional<ppp::StreamFormat> parseStreamFormatHint(const std::string& text) {
  const std::string t = lower(text);
  if (t == "rtcm3" || t == "rtcm") return ppp::StreamFormat::Rtcm3;
  if (t == "ubx") return ppp::StreamFormat::Ubx;
  return std::nullopt;
}

ppp::StreamChunk streamChunkFromMessage(StreamMessageType type, const std::string& topic, const std::uint8_t* data,
                                        std::size_t size, std::optional<ppp::StreamFormat> format_hint,
                                        std::optional<std::uint32_t>* header_seq) {
  ppp::StreamChunk chunk;
  chunk.stream = topic;
  RosReader r(data, size);
  switch (type) {
    case StreamMessageType::RtcmMessage:
    case StreamMessageType::MavrosRtcm: {
      const std::string field = type == StreamMessageType::RtcmMessage ? "message" : "data";
      const std::uint32_t seq = r.header("header");
      if (header_seq) *header_seq = seq;
      chunk.format = ppp::StreamFormat::Rtcm3;
      chunk.bytes = r.bytes(field);
      r.finish(streamMessageTypeName(type));
      break;
    }
    case StreamMessageType::UbloxRxmRawx:
      chunk.format = ppp::StreamFormat::Ubx;
      chunk.bytes = rawxFrame(r);
      break;
    case StreamMessageType::UbloxRxmSfrbx:
      chunk.format = ppp::StreamFormat::Ubx;
      chunk.bytes = sfrbxFrame(r);
      break;
    case StreamMessageType::GnssStreamBytes: {
      const std::uint32_t seq = r.header("header");
      if (header_seq) *header_seq = seq;
      const std::size_t at = r.offset();
      const std::string format = r.string("format");
      chunk.bytes = r.bytes("data");
      r.finish("ppp_bayes_tree/GnssStreamBytes");
      if (!format.empty()) {
        const auto f = parseStreamFormatHint(format);
        if (!f) throw StreamMessageError("format", at, "\"" + format + "\" is neither \"rtcm3\" nor \"ubx\"");
        chunk.format = *f;
      } else if (format_hint) {
        chunk.format = *format_hint;
      } else {
        const ppp::StreamFormat f = ppp::detectStreamFormat(chunk.bytes.data(), chunk.bytes.size());
        if (f == ppp::StreamFormat::Unknown)
          throw StreamMessageError("format", at, "empty, no format hint for the topic, and no complete RTCM 3 or UBX "
                                                 "frame in the data to tell");
        chunk.format = f;
      }
      break;
    }
  }
  return chunk;
}

void GnssStreamSubscriber::releaseHeld() {
  if (held_.empty()) return;
  const ros::Time now = ros::Time::now();
  if (now.isZero()) return;
  counters_.last_arrival = now;
  std::vector<ppp::StreamChunk> held;
  held.swap(held_);
  for (auto& chunk : held) {
    chunk.arrival_time_s = now.toSec();
    on_chunk_(std::move(chunk));
  }
}

GnssStreamSubscriber::GnssStreamSubscriber(ros::NodeHandle& nh, const std::string& topic,
                                           std::optional<ppp::StreamFormat> format_hint, std::uint32_t queue_size,
                                           ChunkHandler on_chunk, const std::string& stream_name)
    : topic_(nh.resolveName(topic)),
      stream_(stream_name.empty() ? topic_ : stream_name),
      format_hint_(format_hint),
      on_chunk_(std::move(on_chunk)) {
  // TCP_NODELAY: a stream's messages are small and frequent; with Nagle's algorithm (and the
  // peer's delayed ACK) one topic's messages can stall for tens of ms while another topic of
  // the same receiver (ublox_gps: RxmRAWX and RxmSFRBX) goes on, which reorders the receiver's
  // one byte stream at this node (and adds latency).
  sub_ = nh.subscribe(topic, queue_size, &GnssStreamSubscriber::onMessage, this, ros::TransportHints().tcpNoDelay());
}

void GnssStreamSubscriber::error(const std::string& text) {
  // The text quotes what a publisher's connection header says (type, MD5, caller id): escaped.
  counters_.last_error = ppp::printableText(text, 400);
  // Each message is counted; the log at most once a second per topic.
  const ros::WallTime now = ros::WallTime::now();
  if (!last_error_log_.isZero() && (now - last_error_log_).toSec() < 1.0) return;
  last_error_log_ = now;
  ROS_ERROR_STREAM("ppp: " << counters_.last_error);
}

void GnssStreamSubscriber::onMessage(const ros::MessageEvent<topic_tools::ShapeShifter const>& event) {
  const topic_tools::ShapeShifter::ConstPtr& msg = event.getMessage();
  ++counters_.messages;
  const ros::Time now = ros::Time::now();  // zero only under sim time before the first /clock
  if (!now.isZero()) {
    releaseHeld();
    counters_.last_arrival = now;
  }
  const std::string datatype = msg->getDataType(), md5 = msg->getMD5Sum();
  counters_.type = ppp::printableText(datatype);
  std::string why;
  const std::optional<StreamMessageType> type = recogniseStreamMessageType(datatype, md5, &why);
  if (!type) {
    ++counters_.wrong_type;
    error("topic " + topic_ + " from " + event.getPublisherName() + ": " + why + ": message dropped (counted)");
    return;
  }
  const double cpu0_s = ppp::threadCpu_s();
  std::vector<std::uint8_t> buffer(msg->size());
  ros::serialization::OStream out(buffer.data(), static_cast<std::uint32_t>(buffer.size()));
  msg->write(out);
  std::optional<ppp::StreamChunk> chunk;
  std::optional<std::uint32_t> seq;  // header.seq of the types with a header
  try {
    chunk = streamChunkFromMessage(*type, stream_, buffer.data(), buffer.size(), format_hint_, &seq);
  } catch (const StreamMessageError& e) {
    ++counters_.malformed;
    error("topic " + topic_ + ", type " + datatype + ": malformed message (" + e.what() + "): dropped (counted)");
  }
  // Gaps in header.seq are messages lost on the way (also counted when the message is malformed after its header).
  if (seq) {
    const auto [it, first] = last_seq_.try_emplace(event.getPublisherName(), *seq);
    if (!first) {
      if (*seq > it->second + 1) counters_.lost += *seq - it->second - 1;
      it->second = *seq;  // a step back (publisher restarted) starts counting anew
    }
  }
  if (!chunk) return;
  counters_.bytes += chunk->bytes.size();
  counters_.conversion_cpu_s += ppp::threadCpu_s() - cpu0_s;
  if (now.isZero()) {  // no valid clock yet: held (in order) until there is one
    ++counters_.held_for_clock;
    held_.push_back(std::move(*chunk));
    return;
  }
  chunk->arrival_time_s = now.toSec();
  on_chunk_(std::move(*chunk));
}

}  // namespace ppp_ros
