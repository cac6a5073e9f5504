#pragma once
// Test helper: the ROS serialization of the foreign stream messages the PPP nodes
// accept (ros/gnss_stream_subscriber.h), written from the message definitions
// (rtcm_msgs/Message, ublox_msgs RxmRAWX/RxmRAWX_Meas/RxmSFRBX of KumarRobotics/ublox
// master), and a ShapeShifter holding one such message for a publisher of the
// exact foreign type name and MD5. The UBX payload fields are in the same order as
// the ROS fields; the ROS messages add only the uint32 length of the repeated block.
#include <cstdint>
#include <string>
#include <vector>

#include <ros/serialization.h>
#include <topic_tools/shape_shifter.h>

#include "ppp_bayes_tree/io/ubx/ubx_framer.h"

namespace ppp_ros::test {

// rtcm_msgs/Message: its type name and MD5.
inline const char* kRtcmMessageType = "rtcm_msgs/Message";
inline const char* kRtcmMessageMd5 = "883b1fb65b83ccf75497c21f2d63052d";

// Full definitions as `rosmsg show` prints them (what a publisher announces); the
// subscriber checks name and MD5 only.
inline const char* kRtcmMessageDefinition =
    "std_msgs/Header header\nuint8[] message\n\n"
    "================================================================================\nMSG: std_msgs/Header\n"
    "uint32 seq\ntime stamp\nstring frame_id\n";
inline const char* kRxmRawxDefinition =
    "uint8 CLASS_ID=2\nuint8 MESSAGE_ID=21\nfloat64 rcvTOW\nuint16 week\nint8 leapS\nuint8 numMeas\nuint8 recStat\n"
    "uint8 REC_STAT_LEAP_SEC=1\nuint8 REC_STAT_CLK_RESET=2\nuint8 version\nuint8[2] reserved1\nRxmRAWX_Meas[] meas\n\n"
    "================================================================================\nMSG: ublox_msgs/RxmRAWX_Meas\n"
    "float64 prMes\nfloat64 cpMes\nfloat32 doMes\nuint8 gnssId\nuint8 svId\nuint8 reserved0\nuint8 freqId\n"
    "uint16 locktime\nint8 cno\nuint8 prStdev\nuint8 cpStdev\nuint8 doStdev\nuint8 trkStat\n"
    "uint8 TRK_STAT_PR_VALID=1\nuint8 TRK_STAT_CP_VALID=2\nuint8 TRK_STAT_HALF_CYC=4\nuint8 TRK_STAT_SUB_HALF_CYC=8\n"
    "uint8 reserved1\n";
inline const char* kRxmSfrbxDefinition =
    "uint8 CLASS_ID=2\nuint8 MESSAGE_ID=19\nuint8 gnssId\nuint8 svId\nuint8 reserved0\nuint8 freqId\nuint8 numWords\n"
    "uint8 chn\nuint8 version\nuint8 reserved1\nuint32[] dwrd\n";

inline void putU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

/// std_msgs/Header (seq, stamp, empty frame_id) + uint8[] bytes: rtcm_msgs/Message, mavros_msgs/RTCM.
inline std::vector<std::uint8_t> serializeHeaderAndBytes(const std::vector<std::uint8_t>& bytes, std::uint32_t seq = 0,
                                                         std::uint32_t sec = 0, std::uint32_t nsec = 0) {
  std::vector<std::uint8_t> out;
  putU32(out, seq);
  putU32(out, sec);
  putU32(out, nsec);
  putU32(out, 0);  // frame_id ""
  putU32(out, static_cast<std::uint32_t>(bytes.size()));
  out.insert(out.end(), bytes.begin(), bytes.end());
  return out;
}

/// ublox_msgs/RxmRAWX from a UBX-RXM-RAWX payload (16-byte head + 32 bytes per measurement).
inline std::vector<std::uint8_t> serializeRxmRawx(const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> out(payload.begin(), payload.begin() + 16);
  const std::uint32_t n = (static_cast<std::uint32_t>(payload.size()) - 16) / 32;
  putU32(out, n);
  out.insert(out.end(), payload.begin() + 16, payload.begin() + 16 + 32 * n);
  return out;
}

/// ublox_msgs/RxmSFRBX from a UBX-RXM-SFRBX payload (8-byte head + 4 bytes per word).
inline std::vector<std::uint8_t> serializeRxmSfrbx(const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> out(payload.begin(), payload.begin() + 8);
  const std::uint32_t n = (static_cast<std::uint32_t>(payload.size()) - 8) / 4;
  putU32(out, n);
  out.insert(out.end(), payload.begin() + 8, payload.begin() + 8 + 4 * n);
  return out;
}

/// A ShapeShifter holding `serialized` as a message of `datatype`/`md5`.
inline topic_tools::ShapeShifter shapeShifter(const std::string& datatype, const std::string& md5,
                                              const std::string& definition, std::vector<std::uint8_t> serialized) {
  topic_tools::ShapeShifter s;
  s.morph(md5, datatype, definition, "false");
  ros::serialization::IStream in(serialized.data(), static_cast<std::uint32_t>(serialized.size()));
  s.read(in);
  return s;
}

/// One rtcm_msgs/Message (header.seq `seq`) carrying `bytes`, as a ShapeShifter.
inline topic_tools::ShapeShifter rtcmMessage(const std::vector<std::uint8_t>& bytes, std::uint32_t seq) {
  return shapeShifter(kRtcmMessageType, kRtcmMessageMd5, kRtcmMessageDefinition, serializeHeaderAndBytes(bytes, seq));
}

}  // namespace ppp_ros::test
