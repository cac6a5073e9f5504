// rostest, live input through rtcm_msgs/Message: the RTCM 3 recording
// week-rollover-STR24.rtcm3 (GMSD, MSM7 GPS/GLONASS/QZSS/BeiDou with GPS and GLONASS
// ephemerides 1019/1020 in the stream, no corrections: broadcast only) published
// with the exact foreign type name and MD5 through topic_tools::ShapeShifter, to two
// ppp_ekf_node instances: one RTCM frame per message (/frames/rtcm) and arbitrary
// chunks cutting through frames (/chunks/rtcm, 1 to 700 bytes). Each node's fixes
// must equal `ppp_solve --rtcm F --ref-date 2018/07/14 --nav F --estimator ekf` on
// the same file and configuration epoch by epoch to 1 mm.
#include <random>

#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "rostest/live_support.h"

TEST(LiveRtcmEkf, FramesAndChunksEqualPppSolveEpochByEpochTo1mm) {
  PPP_REQUIRE_SHARED_DATA();
  using namespace ppp_ros::test;
  const std::string rtcm = ppp::test::dataPath("streams/rtcm/week-rollover-STR24.rtcm3");
  const std::string atx = ppp::test::dataPath("antex/igs20_gps_satellites_trim.atx");
  const std::map<ros::Time, Eigen::Vector3d> offline =
      pppSolveEkf("--rtcm " + rtcm + " --ref-date 2018/07/14 --nav " + rtcm + " --atx " + atx + " --config " +
                      PPP_REPO_DIR + "/config/ppp.yaml",
                  "live_rtcm");
  ASSERT_FALSE(offline.empty()) << "ppp_solve solved no epoch of " << rtcm;

  const std::string bytes = ppp::test::readFileBytes(rtcm);
  const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
  std::vector<StreamMessage> messages;
  std::uint32_t seq = 0;
  auto add = [&](std::size_t publisher, std::size_t begin, std::size_t end) {
    StreamMessage m;
    m.publisher = publisher;
    m.message = rtcmMessage(std::vector<std::uint8_t>(data + begin, data + end), ++seq);
    messages.push_back(std::move(m));
  };
  // Publisher 0: one frame per message, in file order.
  ppp::Rtcm3Framer framer;
  std::vector<std::pair<std::size_t, std::size_t>> frames;
  framer.feed(data, bytes.size(), [&](const ppp::Rtcm3Frame& f) {
    frames.emplace_back(f.byte_offset, f.byte_offset + 3 + f.payload.size() + 3);
  });
  // Publisher 1: the byte stream cut at random places (seeded), interleaved with the frames.
  std::mt19937 random(14);
  std::uniform_int_distribution<std::size_t> size(1, 700);
  std::size_t cut = 0, frame = 0;
  while (cut < bytes.size() || frame < frames.size()) {
    if (frame < frames.size() && (cut >= bytes.size() || frames[frame].second <= cut)) {
      add(0, frames[frame].first, frames[frame].second);
      ++frame;
    } else {
      const std::size_t end = std::min(bytes.size(), cut + size(random));
      add(1, cut, end);
      cut = end;
    }
  }
  ASSERT_GT(frames.size(), 6000u);  // 6857 good frames (ppp_stream_inspect)

  ros::NodeHandle nh;
  NodeOutputs frames_out, chunks_out;
  frames_out.subscribe(nh, "/frames/");
  chunks_out.subscribe(nh, "/chunks/");
  publishInOrder(nh, {"/frames/rtcm", "/chunks/rtcm"}, messages, 0.001);
  waitForFixes(frames_out, offline.size() - 1, 60.0);
  waitForFixes(chunks_out, offline.size() - 1, 20.0);

  std::lock_guard<std::mutex> l1(frames_out.mutex), l2(chunks_out.mutex);
  expectEqualToPppSolve("one frame per rtcm_msgs/Message", frames_out.fixes, offline);
  expectEqualToPppSolve("arbitrary chunks per rtcm_msgs/Message", chunks_out.fixes, offline);
  ASSERT_FALSE(frames_out.statuses.empty());
  // No correction stream: broadcast only is the configured operation.
  EXPECT_EQ(frames_out.statuses.back().product_mode, ppp_bayes_tree::PppStatus::PRODUCTS_BROADCAST_ONLY);
  EXPECT_EQ(frames_out.statuses.back().product_mode_text, "broadcast only");
  for (const auto& [name, level] : frames_out.worst_diagnostic)
    if (name.find("live streams") != std::string::npos) EXPECT_LT(level, diagnostic_msgs::DiagnosticStatus::ERROR) << name;
}

int main(int argc, char** argv) { return ppp_ros::test::liveRostestMain(argc, argv, "rostest_live_rtcm_ekf"); }
