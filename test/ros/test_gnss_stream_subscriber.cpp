// GnssStreamSubscriber's conversions (ros/gnss_stream_subscriber.h): the foreign
// stream messages -> StreamChunk, and their malformed forms. No roscore needed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "ppp_bayes_tree/GnssStreamBytes.h"
#include "ppp_bayes_tree/io/ubx/ubx_framer.h"
#include "ppp_bayes_tree/ros/gnss_stream_subscriber.h"
#include "ros/ublox_ros_messages.h"
#include "test_support.h"

namespace {

using ppp_ros::StreamMessageError;
using ppp_ros::StreamMessageType;
using ppp_ros::streamChunkFromMessage;

std::vector<ppp::UbxFrame> ubxFrames(const std::string& path) {
  const std::string bytes = ppp::test::readFileBytes(path);
  std::vector<ppp::UbxFrame> frames;
  ppp::UbxFramer framer;
  framer.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(),
              [&](const ppp::UbxFrame& f) { frames.push_back(f); });
  return frames;
}

std::string errorOf(StreamMessageType type, const std::vector<std::uint8_t>& m) {
  try {
    streamChunkFromMessage(type, "/t", m.data(), m.size());
  } catch (const StreamMessageError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(GnssStreamSubscriber, RecognisesTypesByNameAndMd5) {
  std::string why;
  EXPECT_EQ(ppp_ros::recogniseStreamMessageType("rtcm_msgs/Message", "883b1fb65b83ccf75497c21f2d63052d", &why),
            StreamMessageType::RtcmMessage);
  EXPECT_EQ(ppp_ros::recogniseStreamMessageType("mavros_msgs/RTCM", "8903b686ebe5db3477e83c6d0bb149f8", &why),
            StreamMessageType::MavrosRtcm);
  EXPECT_EQ(ppp_ros::recogniseStreamMessageType("ublox_msgs/RxmRAWX", "a2df4b27b6a2a1565e42f5669dbb11b5", &why),
            StreamMessageType::UbloxRxmRawx);
  EXPECT_EQ(ppp_ros::recogniseStreamMessageType(ros::message_traits::datatype<ppp_bayes_tree::GnssStreamBytes>(),
                                                ros::message_traits::md5sum<ppp_bayes_tree::GnssStreamBytes>(), &why),
            StreamMessageType::GnssStreamBytes);
  // The right name with another definition's MD5 (an older ublox_msgs), and another type.
  EXPECT_FALSE(ppp_ros::recogniseStreamMessageType("ublox_msgs/RxmRAWX", "0123456789abcdef0123456789abcdef", &why));
  EXPECT_NE(why.find("not the accepted definition"), std::string::npos) << why;
  EXPECT_FALSE(ppp_ros::recogniseStreamMessageType("std_msgs/String", "992ce8a1687cec8c8bd883ec73ca41d1", &why));
  EXPECT_NE(why.find("not a GNSS stream type"), std::string::npos) << why;
}

TEST(GnssStreamSubscriber, RtcmMessageCarriesItsBytes) {
  const std::vector<std::uint8_t> bytes = {0xD3, 0x00, 0x01, 0x02, 0x03};  // any chunk: not framed here
  const auto m = ppp_ros::test::serializeHeaderAndBytes(bytes, 7, 1700000000, 5);
  const ppp::StreamChunk c = streamChunkFromMessage(StreamMessageType::RtcmMessage, "/rtcm", m.data(), m.size());
  EXPECT_EQ(c.stream, "/rtcm");
  EXPECT_EQ(c.format, ppp::StreamFormat::Rtcm3);
  EXPECT_EQ(c.bytes, bytes);
  const ppp::StreamChunk d = streamChunkFromMessage(StreamMessageType::MavrosRtcm, "/m", m.data(), m.size());
  EXPECT_EQ(d.bytes, bytes);
}

TEST(GnssStreamSubscriber, UbloxMessagesBecomeTheReceiversUbxFramesByteForByte) {
  PPP_REQUIRE_SHARED_DATA();
  const std::string path = ppp::test::dataPath("streams/ubx/gnss_1730.ubx");
  const std::vector<ppp::UbxFrame> frames = ubxFrames(path);
  std::size_t rawx = 0, sfrbx = 0;
  for (const ppp::UbxFrame& f : frames) {
    if (f.message_class != 0x02 || (f.message_id != 0x15 && f.message_id != 0x13)) continue;
    const bool is_rawx = f.message_id == 0x15;
    const auto m = is_rawx ? ppp_ros::test::serializeRxmRawx(f.payload) : ppp_ros::test::serializeRxmSfrbx(f.payload);
    const ppp::StreamChunk c = streamChunkFromMessage(
        is_rawx ? StreamMessageType::UbloxRxmRawx : StreamMessageType::UbloxRxmSfrbx, "/ublox", m.data(), m.size());
    ASSERT_EQ(c.format, ppp::StreamFormat::Ubx);
    ASSERT_EQ(c.bytes, ppp::encodeUbxFrame(f.message_class, f.message_id, f.payload)) << "frame " << f.frame_index;
    (is_rawx ? rawx : sfrbx)++;
  }
  // Counts of the recording (shared/data README: 536 RXM-RAWX epochs, 2,328 RXM-SFRBX).
  EXPECT_EQ(rawx, 536u);
  EXPECT_EQ(sfrbx, 2328u);
}

TEST(GnssStreamSubscriber, MalformedMessagesNameFieldAndOffset) {
  // RXM-RAWX with one measurement (16-byte head + 32 bytes), numMeas 1.
  std::vector<std::uint8_t> payload(48, 0);
  payload[11] = 1;
  const double pr = 2.2e7;
  std::memcpy(payload.data() + 16, &pr, 8);
  auto good = ppp_ros::test::serializeRxmRawx(payload);
  EXPECT_EQ(errorOf(StreamMessageType::UbloxRxmRawx, good), "");

  auto shortened = good;
  shortened.resize(shortened.size() - 5);
  EXPECT_NE(errorOf(StreamMessageType::UbloxRxmRawx, shortened).find("meas"), std::string::npos);

  auto nan = good;
  const double q = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(nan.data() + 20 + 8, &q, 8);  // meas[0].cpMes (head 16 + length 4 + prMes 8)
  EXPECT_NE(errorOf(StreamMessageType::UbloxRxmRawx, nan).find("meas[0].cpMes at byte 28"), std::string::npos)
      << errorOf(StreamMessageType::UbloxRxmRawx, nan);

  auto beyond = good;
  beyond[16] = 200;  // meas length 200 x 32 bytes
  EXPECT_NE(errorOf(StreamMessageType::UbloxRxmRawx, beyond).find("field meas at byte 16"), std::string::npos)
      << errorOf(StreamMessageType::UbloxRxmRawx, beyond);

  auto count = good;
  count[11] = 2;  // numMeas 2, one element
  EXPECT_NE(errorOf(StreamMessageType::UbloxRxmRawx, count).find("numMeas 2"), std::string::npos);

  auto extra = good;
  extra.push_back(0);
  EXPECT_NE(errorOf(StreamMessageType::UbloxRxmRawx, extra).find("after the last field"), std::string::npos);

  const std::vector<std::uint8_t> header_only(8, 0);  // header cut in the stamp
  EXPECT_NE(errorOf(StreamMessageType::RtcmMessage, header_only).find("header.seq/stamp at byte 0"), std::string::npos);
}

TEST(GnssStreamSubscriber, GnssStreamBytesFormatFieldHintOrContent) {
  const std::vector<std::uint8_t> ubx = ppp::encodeUbxFrame(0x01, 0x07, std::vector<std::uint8_t>(4, 0));
  auto message = [&](const std::string& format) {
    ppp_bayes_tree::GnssStreamBytes m;
    m.format = format;
    m.data = ubx;
    std::vector<std::uint8_t> out(ros::serialization::serializationLength(m));
    ros::serialization::OStream s(out.data(), static_cast<std::uint32_t>(out.size()));
    ros::serialization::serialize(s, m);
    return out;
  };
  auto chunk = [&](const std::vector<std::uint8_t>& m, std::optional<ppp::StreamFormat> hint) {
    return streamChunkFromMessage(StreamMessageType::GnssStreamBytes, "/b", m.data(), m.size(), hint);
  };
  EXPECT_EQ(chunk(message("rtcm3"), std::nullopt).format, ppp::StreamFormat::Rtcm3);  // the field wins
  EXPECT_EQ(chunk(message("UBX"), ppp::StreamFormat::Rtcm3).format, ppp::StreamFormat::Ubx);
  EXPECT_EQ(chunk(message(""), ppp::StreamFormat::Rtcm3).format, ppp::StreamFormat::Rtcm3);  // then the hint
  EXPECT_EQ(chunk(message(""), std::nullopt).format, ppp::StreamFormat::Ubx);                // then the content
  EXPECT_EQ(chunk(message("ubx"), std::nullopt).bytes, ubx);
  EXPECT_NE(errorOf(StreamMessageType::GnssStreamBytes, message("nmea")).find("field format"), std::string::npos);
}
