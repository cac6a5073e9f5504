#include "ppp_bayes_tree/ros/stream_node.h"

#include <cstdlib>
#include <stdexcept>

#include <ros/serialization.h>

#include "ppp_bayes_tree/GnssStreamBytes.h"
#include "ppp_bayes_tree/io/transport/byte_source_spec.h"
#include "ppp_bayes_tree/io/transport/credential_mask.h"
#include "ppp_bayes_tree/io/transport/ntrip_credentials.h"
#include "ppp_bayes_tree/ros/node_main.h"

namespace ppp_ros {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kWindowKeepBytes = 128 * 1024;  // > the largest frame (UBX 8192 + 8)
constexpr std::size_t kDetectBytes = 64 * 1024;        // give up detecting the format after this

/// An input error as shown in the log and the diagnostics: its detail quotes the caster's
/// answer already escaped (io/untrusted_text.h), and any spec in it is masked.
std::string shownError(const ppp::ByteSourceError& error) { return ppp::maskCredentials(error.describe()); }

template <typename T>
T param(const ros::NodeHandle& pnh, const std::string& key, const T& fallback) {
  if (!pnh.hasParam(key)) return fallback;
  T value;
  if (!pnh.getParam(key, value)) {
    throw std::runtime_error("parameter ~" + key + " has the wrong type");
  }
  return value;
}

}  // namespace

const char* const kRtcmMessageType = "rtcm_msgs/Message";
const char* const kRtcmMessageMd5 = "883b1fb65b83ccf75497c21f2d63052d";

std::string rtcmMessageDefinition() {
  return std::string("std_msgs/Header header\n\nuint8[] message\n\n") +
         "================================================================================\n"
         "MSG: std_msgs/Header\n" +
         ros::message_traits::Definition<std_msgs::Header>::value();
}

topic_tools::ShapeShifter makeRtcmMessage(const std_msgs::Header& header, const std::vector<std::uint8_t>& bytes) {
  const std::uint32_t length = ros::serialization::serializationLength(header) +
                               ros::serialization::serializationLength(bytes);
  std::vector<std::uint8_t> buffer(length);
  ros::serialization::OStream out(buffer.data(), length);
  ros::serialization::serialize(out, header);
  ros::serialization::serialize(out, bytes);
  topic_tools::ShapeShifter message;
  message.morph(kRtcmMessageMd5, kRtcmMessageType, rtcmMessageDefinition(), "false");
  ros::serialization::IStream in(buffer.data(), length);
  message.read(in);
  return message;
}

std::vector<std::uint8_t> rtcmMessageBytes(const topic_tools::ShapeShifter& message, std_msgs::Header* header) {
  if (message.getDataType() != kRtcmMessageType || message.getMD5Sum() != kRtcmMessageMd5) {
    throw std::runtime_error("not an rtcm_msgs/Message: " + message.getDataType() + " MD5 " + message.getMD5Sum());
  }
  std::vector<std::uint8_t> buffer(message.size());
  ros::serialization::OStream out(buffer.data(), static_cast<std::uint32_t>(buffer.size()));
  message.write(out);
  ros::serialization::IStream in(buffer.data(), static_cast<std::uint32_t>(buffer.size()));
  std_msgs::Header h;
  std::vector<std::uint8_t> bytes;
  ros::serialization::deserialize(in, h);
  ros::serialization::deserialize(in, bytes);
  if (header) *header = h;
  return bytes;
}

StreamNodeOptions loadStreamNodeOptions(const ros::NodeHandle& pnh) {
  StreamNodeOptions o;
  if (!pnh.getParam("input", o.input) || o.input.empty()) {
    throw std::runtime_error("parameter ~input (the input spec, e.g. ntrip://user@host:2101/MOUNT?credentials=PATH) "
                             "is required");
  }
  // A password written into the spec leaves the parameter server at once (masked copy),
  // before anything can fail: rosparam get shows "***" from here on.
  if (const std::string masked = ppp::maskCredentials(o.input); masked != o.input) {
    pnh.setParam("input", masked);
    ROS_WARN_STREAM("ppp_stream_node: the input spec ~input carries a password: replaced by *** in the parameter "
                    "server, but it may remain in the launch log and the shell history; give it with credentials=PATH "
                    "(a file readable by you only) or the environment variable "
                    << ppp::kNtripCredentialsEnvironment << " instead (io/transport/ntrip_credentials.h)");
  }
  o.format = param<std::string>(pnh, "format", o.format);
  if (!o.format.empty() && o.format != "rtcm3" && o.format != "ubx") {
    throw std::runtime_error("parameter ~format '" + o.format + "': expected rtcm3, ubx or \"\" (detect)");
  }
  o.output_topic = param<std::string>(pnh, "output_topic", o.output_topic);
  o.frame_id = param<std::string>(pnh, "frame_id", o.frame_id);
  o.queue_size = param<int>(pnh, "queue_size", o.queue_size);
  o.stall_warn_s = param<double>(pnh, "stall_warn_s", o.stall_warn_s);
  o.stall_error_s = param<double>(pnh, "stall_error_s", o.stall_error_s);
  // Ranges (config/stream.yaml states them).
  if (o.queue_size < 1 || o.queue_size > 1000000)
    throw std::runtime_error("parameter ~queue_size must be in [1, 1000000] messages");
  if (!(o.stall_warn_s > 0.0) || !(o.stall_error_s >= o.stall_warn_s)) {
    throw std::runtime_error("parameters ~stall_warn_s > 0 and ~stall_error_s >= ~stall_warn_s are required");
  }
  if (o.stall_warn_s > 3600.0 || o.stall_error_s > 86400.0)
    throw std::runtime_error("parameters ~stall_warn_s must be <= 3600 s and ~stall_error_s <= 86400 s");
  // diagnostic_updater reads ~diagnostic_period itself (0 would publish as fast as the loop runs).
  const double period_s = param<double>(pnh, "diagnostic_period", 1.0);
  if (!(period_s >= 0.1 && period_s <= 3600.0))
    throw std::runtime_error("parameter ~diagnostic_period must be in [0.1, 3600] s, got " + std::to_string(period_s));
  return o;
}

StreamNode::StreamNode(ros::NodeHandle nh, ros::NodeHandle pnh)
    : options_(loadStreamNodeOptions(pnh)), nh_(nh), pnh_(pnh), start_time_(Clock::now()), diagnostics_(nh, pnh) {
  ppp::ByteSourceSpec spec = ppp::parseByteSourceSpec(options_.input);  // throws with the reason (masked)
  const ppp::CredentialSource credentials =
      ppp::resolveNtripCredentials(spec, std::getenv(ppp::kNtripCredentialsEnvironment));
  if (credentials == ppp::CredentialSource::File || credentials == ppp::CredentialSource::Environment)
    ROS_INFO_STREAM("ppp_stream_node: NTRIP user and password from " << ppp::credentialSourceText(credentials));
  std::string format = options_.format.empty() ? spec.format.value_or("") : options_.format;
  if (format == "rtcm3") format_ = ppp::StreamFormat::Rtcm3;
  if (format == "ubx") format_ = ppp::StreamFormat::Ubx;
  source_ = ppp::openByteSource(spec);
  if (format_ != ppp::StreamFormat::Unknown) advertise();  // subscribers connect before the first frame
  diagnostics_.setHardwareID(source_->describe());
  diagnostics_.add("stream", this, &StreamNode::diagnose);
  sim_clock_watch_ = std::make_unique<SimClockWatch>(nh_, "ppp_stream_node");
  ROS_INFO_STREAM("ppp_stream_node: reading " << source_->describe() << ", publishing "
                                              << (format.empty() ? std::string("(format detected from the content)")
                                                                 : format)
                                              << " frames on " << nh_.resolveName(options_.output_topic));
}

void StreamNode::publishFrame(const std::vector<std::uint8_t>& bytes) {
  std_msgs::Header header;
  // Numbered here (roscpp numbers only typed publications, not ShapeShifter ones), so that
  // a subscriber sees lost messages as header.seq gaps.
  header.seq = static_cast<std::uint32_t>(published_);
  header.stamp = ros::Time::now();
  header.frame_id = options_.frame_id;
  if (!advertised_) advertise();
  if (format_ == ppp::StreamFormat::Rtcm3) {
    publisher_.publish(makeRtcmMessage(header, bytes));
  } else {
    ppp_bayes_tree::GnssStreamBytes message;
    message.header = header;
    message.format = "ubx";
    message.data = bytes;
    publisher_.publish(message);
  }
  ++published_;
}

void StreamNode::advertise() {
  const auto queue = static_cast<std::uint32_t>(options_.queue_size);
  if (format_ == ppp::StreamFormat::Rtcm3) {
    topic_tools::ShapeShifter prototype;
    prototype.morph(kRtcmMessageMd5, kRtcmMessageType, rtcmMessageDefinition(), "false");
    publisher_ = prototype.advertise(nh_, options_.output_topic, queue);
  } else {
    publisher_ = nh_.advertise<ppp_bayes_tree::GnssStreamBytes>(options_.output_topic, queue);
  }
  advertised_ = true;
}

void StreamNode::consume(const std::uint8_t* data, std::size_t size) {
  window_.insert(window_.end(), data, data + size);
  stream_bytes_ += size;
  if (format_ == ppp::StreamFormat::Unknown) {
    format_ = ppp::detectStreamFormat(window_.data(), window_.size());
    if (format_ == ppp::StreamFormat::Unknown) {
      if (window_.size() > kDetectBytes) {
        ROS_ERROR_STREAM_THROTTLE(10.0, "ppp_stream_node: no RTCM 3 or UBX frame in the first "
                                            << window_.size() << " bytes of " << source_->describe()
                                            << "; set ~format or format= in the spec");
        window_offset_ += window_.size();
        window_.clear();
      }
      return;
    }
    ROS_INFO_STREAM("ppp_stream_node: the stream is " << ppp::streamFormatName(format_));
    advertise();
    const std::vector<std::uint8_t> pending = std::move(window_);
    window_.clear();
    window_offset_ = stream_bytes_ - pending.size();
    framer_base_ = window_offset_;  // the framers count offsets from their first byte
    stream_bytes_ -= pending.size();
    consume(pending.data(), pending.size());
    return;
  }
  std::uint64_t last_end = window_offset_;
  const auto take = [&](std::uint64_t framer_offset, std::size_t frame_size) {
    const std::uint64_t offset = framer_base_ + framer_offset;
    const auto begin = window_.begin() + static_cast<long>(offset - window_offset_);
    publishFrame(std::vector<std::uint8_t>(begin, begin + static_cast<long>(frame_size)));
    last_end = offset + frame_size;
  };
  if (format_ == ppp::StreamFormat::Rtcm3) {
    rtcm_.feed(data, size, [&](const ppp::Rtcm3Frame& f) { take(f.byte_offset, f.payload.size() + 6); });
  } else {
    ubx_.feed(data, size, [&](const ppp::UbxFrame& f) { take(f.byte_offset, f.payload.size() + 8); });
  }
  // Keep the bytes after the last frame (a frame in progress), at most kWindowKeepBytes.
  std::uint64_t keep_from = std::max(last_end, window_offset_);
  if (stream_bytes_ - keep_from > kWindowKeepBytes) keep_from = stream_bytes_ - kWindowKeepBytes;
  if (keep_from > window_offset_) {
    window_.erase(window_.begin(), window_.begin() + static_cast<long>(keep_from - window_offset_));
    window_offset_ = keep_from;
  }
}

void StreamNode::run() {
  std::vector<std::uint8_t> buffer(16384);
  while (ros::ok()) {
    if (ended_) {
      ros::Duration(0.1).sleep();
    } else {
      const ppp::ByteSourceRead got = source_->read(buffer.data(), buffer.size(), std::chrono::milliseconds(50));
      if (got.status == ppp::ByteSourceStatus::Data) {
        last_byte_time_ = Clock::now();
        consume(buffer.data(), got.size);
      } else if (got.status == ppp::ByteSourceStatus::Closed) {
        ended_ = true;
        rtcm_.finish();
        ubx_.finish();
        ROS_INFO_STREAM("ppp_stream_node: " << source_->describe() << " ended after " << stream_bytes_
                                            << " bytes, " << published_ << " frames published");
      } else if (got.status == ppp::ByteSourceStatus::Error) {
        if (ppp::isPermanentByteSourceError(got.error->kind)) {
          ROS_ERROR_STREAM("ppp_stream_node: " << source_->describe() << ": " << shownError(*got.error));
        } else {
          ROS_WARN_STREAM("ppp_stream_node: " << source_->describe() << ": " << shownError(*got.error));
        }
      }
    }
    ros::spinOnce();
    diagnostics_.update();
  }
}

void StreamNode::diagnose(diagnostic_updater::DiagnosticStatusWrapper& s) {
  const ppp::ByteSourceCounters& c = source_->counters();
  const ppp::StreamCounters& f = format_ == ppp::StreamFormat::Ubx ? ubx_.counters() : rtcm_.counters();
  s.add("input", source_->describe());
  s.add("format", std::string(ppp::streamFormatName(format_)));
  s.add("bytes", stream_bytes_);
  s.add("frames", f.frames);
  s.add("frames published", published_);
  s.add("CRC errors", f.count(ppp::StreamProblemKind::ChecksumError));
  s.add("garbage bytes", f.garbage_bytes);
  s.add("truncated frames", f.count(ppp::StreamProblemKind::TruncatedFrame));
  s.add("connects", c.connects);
  s.add("reconnects", c.reconnects);
  s.add("stalls", c.stalls);
  s.add("GGA sent", c.gga_sent);
  s.add("errors", c.totalErrors());
  for (const auto& [kind, count] : c.errors_by_kind) {
    s.add("errors: " + std::string(ppp::byteSourceErrorKindName(kind)), count);
  }
  s.add("last error", c.last_error ? shownError(*c.last_error) : std::string("none"));
  const double age_s = std::chrono::duration<double>(Clock::now() - last_byte_time_.value_or(start_time_)).count();
  s.add("seconds since last byte", age_s);
  if (ended_) {
    s.summary(diagnostic_msgs::DiagnosticStatus::OK, "the replayed file ended");
  } else if (c.last_error && ppp::isPermanentByteSourceError(c.last_error->kind) && age_s > options_.stall_warn_s) {
    s.summary(diagnostic_msgs::DiagnosticStatus::ERROR, shownError(*c.last_error));
  } else if (age_s > options_.stall_error_s) {
    s.summaryf(diagnostic_msgs::DiagnosticStatus::ERROR, "no byte for %.1f s%s", age_s,
               c.last_error ? (" (" + shownError(*c.last_error) + ")").c_str() : "");
  } else if (age_s > options_.stall_warn_s) {
    s.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "no byte for %.1f s", age_s);
  } else if (format_ == ppp::StreamFormat::Unknown && stream_bytes_ > 0) {
    s.summary(diagnostic_msgs::DiagnosticStatus::WARN, "receiving, but no RTCM 3 or UBX frame found yet");
  } else {
    s.summary(diagnostic_msgs::DiagnosticStatus::OK, "receiving");
  }
}

int runStreamNode(int argc, char** argv, const std::string& node_name) {
  return runNode(argc, argv, node_name, [](ros::NodeHandle& nh) {
    StreamNode node(nh, ros::NodeHandle("~"));
    node.run();
  });
}

}  // namespace ppp_ros
