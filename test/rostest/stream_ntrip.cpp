// rostest: str2str (RTKLIB) as an NTRIP caster on loopback -> ppp_stream_node
// -> rtcm_msgs/Message on /rtcm. The frames received, in order, must be the
// RTCM 3 frames of msm7.rtcm byte for byte (cut by the core framer from the
// file), the type must be rtcm_msgs/Message with its MD5, and the node's
// diagnostics must count the bytes and frames.
#include <gtest/gtest.h>

#include <atomic>
#include <map>
#include <mutex>
#include <thread>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>
#include <topic_tools/shape_shifter.h>

#include "loopback_servers.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/ros/stream_node.h"
#include "test_support.h"

namespace {

constexpr int kCasterPort = 27865;  // as in stream_ntrip.test

struct Received {
  std::mutex mutex;
  std::vector<std::vector<std::uint8_t>> frames;
  std::vector<std::string> types;
  std::map<std::string, std::string> diagnostics;  // of the "stream" task
  std::uint8_t level = 255;
};

std::string value(Received& r, const std::string& key) {
  std::lock_guard<std::mutex> lock(r.mutex);
  const auto it = r.diagnostics.find(key);
  return it == r.diagnostics.end() ? "" : it->second;
}

TEST(StreamNodeNtrip, FramesEqualTheRecording) {
  if (!std::filesystem::is_directory(ppp::test::dataPath("streams/rtcm"))) {
    GTEST_SKIP() << "no ../shared/data/streams (set PPP_SHARED_DATA)";
  }
  if (!ppp::test::str2strAvailable()) GTEST_SKIP() << "RTKLIB str2str is not installed (Debian package rtklib)";
  const std::string recording = ppp::test::readFileBytes(ppp::test::dataPath("streams/rtcm/msm7.rtcm"));
  std::vector<std::vector<std::uint8_t>> expected;
  ppp::Rtcm3Framer framer;
  framer.feed(reinterpret_cast<const std::uint8_t*>(recording.data()), recording.size(),
              [&](const ppp::Rtcm3Frame& f) {
                const auto begin = recording.begin() + static_cast<long>(f.byte_offset);
                expected.emplace_back(begin, begin + static_cast<long>(f.payload.size() + 6));
              });
  ASSERT_GT(expected.size(), 100u);

  ros::NodeHandle nh;
  Received received;
  ros::Subscriber rtcm = nh.subscribe<topic_tools::ShapeShifter>(
      "/rtcm", 1000, [&](const topic_tools::ShapeShifter::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(received.mutex);
        received.types.push_back(m->getDataType() + " " + m->getMD5Sum());
        received.frames.push_back(ppp_ros::rtcmMessageBytes(*m));
      });
  ros::Subscriber diagnostics = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 100, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        for (const auto& status : m->status) {
          if (status.name.find("stream") == std::string::npos) continue;
          std::lock_guard<std::mutex> lock(received.mutex);
          received.level = status.level;
          for (const auto& kv : status.values) received.diagnostics[kv.key] = kv.value;
        }
      });

  ppp::test::Str2str caster("ntripc://rover:secret@:" + std::to_string(kCasterPort) + "/MSM7");
  ASSERT_TRUE(caster.running());
  // Connected: the node's diagnostics count a connection and no error since
  // (the caster answered ICY 200 inside the same read, before the diagnostics).
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::WallTime::now() < until &&
         !(value(received, "connects") != "" && value(received, "connects") != "0" && rtcm.getNumPublishers() > 0)) {
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_NE(value(received, "connects"), "") << "no diagnostics from ppp_stream_node";
  ASSERT_NE(value(received, "connects"), "0") << "ppp_stream_node did not connect: " << value(received, "last error");
  ASSERT_GT(rtcm.getNumPublishers(), 0u) << "/rtcm is not advertised";
  ros::WallDuration(0.5).sleep();  // one more diagnostics period: still connected
  const std::string connects_before = value(received, "connects");

  std::thread feeder([&] {
    caster.write(recording);
    caster.closeInput();
  });
  const ros::WallTime frames_until = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::WallTime::now() < frames_until) {
    {
      std::lock_guard<std::mutex> lock(received.mutex);
      if (received.frames.size() >= expected.size()) break;
    }
    ros::WallDuration(0.05).sleep();
  }
  feeder.join();
  ros::WallDuration(0.5).sleep();
  std::lock_guard<std::mutex> lock(received.mutex);
  ASSERT_EQ(received.frames.size(), expected.size());
  EXPECT_TRUE(received.frames == expected) << "the frames differ from msm7.rtcm's";
  for (const std::string& type : received.types) {
    ASSERT_EQ(type, std::string(ppp_ros::kRtcmMessageType) + " " + ppp_ros::kRtcmMessageMd5);
  }
  EXPECT_EQ(received.diagnostics["connects"], connects_before);  // no reconnection during the stream
  EXPECT_EQ(received.diagnostics["CRC errors"], "0");
  EXPECT_EQ(received.diagnostics["frames published"], std::to_string(expected.size()));
  EXPECT_EQ(received.diagnostics["bytes"], std::to_string(recording.size()));
  EXPECT_EQ(received.diagnostics["input"].find("secret"), std::string::npos) << received.diagnostics["input"];
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rostest_stream_ntrip");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
