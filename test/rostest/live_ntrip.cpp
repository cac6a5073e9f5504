// rostest, NTRIP end to end into the PPP nodes: str2str (RTKLIB) as an
// NTRIP v2 caster on a free loopback port -> ppp_stream_node (started by the test with
// ntrip://rover:secret@127.0.0.1:PORT/STR24) -> rtcm_msgs/Message on /gnss/receiver ->
// ppp_ekf_node and ppp_smoother_node of launch/live.launch (example b). The test writes
// week-rollover-STR24.rtcm3 into the caster once the stream node is connected and
// both nodes subscribe (str2str passes its input on as fast as it comes: the writer
// paces it at 400 KiB/s, 19 min of data in about 3 s; the nodes' subscriber queues
// hold the whole file, test/rostest/live_str24.yaml). No epoch may be lost: the stream
// node publishes every frame of the file, and each node's fixes equal ppp_solve's on
// the file (EKF; smoother filtered) at every epoch but perhaps the last, to 1 mm.
#include "loopback_servers.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "rostest/live_support.h"

TEST(LiveNtrip, Str2strCasterToStreamNodeToBothNodesEqualsPppSolveTo1mm) {
  PPP_REQUIRE_SHARED_DATA();
  if (!ppp::test::str2strAvailable()) GTEST_SKIP() << "RTKLIB str2str is not installed (Debian package rtklib)";
  using namespace ppp_ros::test;
  PppSolveBoth offline;
  ASSERT_NO_FATAL_FAILURE(solveStr24Live("live_ntrip", &offline));

  const std::string recording = ppp::test::readFileBytes(str24Recording());
  ppp::Rtcm3Framer framer;
  std::size_t frames = 0;
  framer.feed(reinterpret_cast<const std::uint8_t*>(recording.data()), recording.size(),
              [&](const ppp::Rtcm3Frame&) { ++frames; });
  framer.finish();
  ASSERT_GT(frames, 6000u);  // 6857 good frames (ppp_stream_inspect)

  ros::NodeHandle nh;
  LiveLaunchOutputs out;
  out.subscribe(nh);

  const int port = ppp::test::freeLoopbackPort();
  ppp::test::Str2str caster("ntripc://rover:secret@:" + std::to_string(port) + "/STR24");
  ASSERT_TRUE(caster.running());
  // Connected (the caster answered), and both PPP nodes subscribe to the stream node's topic.
  StreamNodeDiagnostics stream;
  std::unique_ptr<ChildProcess> node;
  ASSERT_NO_FATAL_FAILURE(startConnectedStreamNode(
      nh,
      "ntrip://rover:secret@127.0.0.1:" + std::to_string(port) +
          "/STR24?version=2&reconnect_min_s=0.2&reconnect_max_s=1&stall_timeout_s=60",
      (ppp::test::tempDir("live_ntrip") / "ppp_stream_node.log").string(), stream, &node));

  // 2 KiB per write, 20 ms apart (Str2str::write): 100 KiB/s, 19 min of data in 13 s; the
  // nodes' outputs (publisher queues of 100) then come at about 90 epochs/s, which this test
  // node reads even on a loaded machine.
  for (std::size_t done = 0; done < recording.size(); done += 2048)
    ASSERT_TRUE(caster.write(recording.substr(done, 2048)));
  caster.closeInput();
  expectAllFramesPublished(stream, frames);
  waitAndExpectEqualTo(out, offline, "NTRIP (str2str) -> ppp_stream_node -> /gnss/receiver");
  EXPECT_EQ(stream.value("bytes"), std::to_string(recording.size()));
  EXPECT_EQ(stream.value("CRC errors"), "0");
  EXPECT_EQ(stream.value("garbage bytes"), std::to_string(framer.counters().garbage_bytes));
  EXPECT_EQ(stream.value("connects"), "1") << "reconnected during the stream";
  EXPECT_EQ(stream.value("reconnects"), "0");
  EXPECT_EQ(stream.value("input").find("secret"), std::string::npos) << stream.value("input");
  std::printf("[ figures  ] ppp_stream_node: %s bytes, %s frames published, %s garbage bytes, %s CRC errors\n",
              stream.value("bytes").c_str(), stream.value("frames published").c_str(),
              stream.value("garbage bytes").c_str(), stream.value("CRC errors").c_str());
}

int main(int argc, char** argv) { return ppp_ros::test::liveRostestMain(argc, argv, "rostest_live_ntrip"); }
