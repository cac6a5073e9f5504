// rostest, live input with corrections through rtcm_msgs/Message:
// the ESBC 2020-177 window 00:30-01:15 (30 s) made into one caster stream by the
// ppp_stream_make binary (1006/1033, MSM7 of every system, the broadcast file's
// records 1019/1045/1046 from their transmission time with repeats) and an SSR
// stream made by ppp_ssr_encode's code (models/ssr_from_precise.h: GRG SP3/CLK
// against the broadcast file, GPS, 5 s, centre of mass), published with the exact
// foreign type name and MD5 (topic_tools::ShapeShifter), one frame per message in
// the caster's order: observations and ephemerides on /esbc/rtcm, SSR on /esbc/ssr.
// Two nodes take them side by side: ppp_ekf_node (/ekf) and ppp_smoother_node
// (/smoother). Each node's fixes must equal those of one `ppp_solve --rtcm MADE
// --ref-date 2020/06/25 --nav MADE --ssr SSR --estimator both` with its estimator
// (the smoother's filtered solution), epoch by epoch to 1 mm, in precise (SSR) mode
// throughout.
#include "ppp_bayes_tree/io/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rtcm3_framer.h"
#include "ppp_bayes_tree/io/rtcm_ssr_decoder.h"
#include "esbc_stream_fixture.h"
#include "rostest/live_support.h"

TEST(LiveEsbcSsr, EkfAndSmootherNodesEqualPppSolveOnTheMadeStreams) {
  PPP_REQUIRE_SHARED_DATA();
  using namespace ppp_ros::test;
  using ppp::test::esbcPath;
  const std::filesystem::path dir = ppp::test::tempDir("live_esbc_ssr");
  const ppp::GnssTime start = ppp::test::gpst(2020, 6, 25, 0, 30, 0), until = start + 2700.0;
  const std::string nav = esbcPath("ESBC00DNK_R_20201770000_01D_MN.rnx");

  // The SSR stream (ppp_ssr_encode's core) for the window and a minute around it.
  const std::string ssr = (dir / "SSRC00TST_esbc.rtcm3").string();
  ppp::test::writeFileBytes(ssr, ppp::test::esbcGpsSsrStream(ppp::readRinexNav(nav), start - 60.0, until + 60.0));
  // The caster stream (ppp_stream_make), SSR interleaved.
  const std::string stream = makeEsbcCasterStream(dir, nav, ssr, "2020/06/25 00:30:00", 2700);
  ASSERT_FALSE(::testing::Test::HasFailure());

  const std::string args = "--rtcm " + stream + " --ref-date 2020/06/25 --nav " + stream + " --ssr " + ssr +
                           " --atx " + ppp::test::dataPath("antex/igs20_gps_satellites_trim.atx") + " " +
                           ppp::test::dataPath("antex/igs05_esbc_receiver_trim.atx") + " --config " + PPP_REPO_DIR +
                           "/config/ppp.yaml";
  const PppSolveBoth offline = pppSolveBoth(args, "live_esbc");
  ASSERT_GT(offline.ekf.size(), 80u) << "ppp_solve solved too few epochs of " << stream;
  ASSERT_GT(offline.smoother_filtered.size(), 80u);

  // One rtcm_msgs/Message per frame, in the caster's order; SSR on the correction topic.
  const std::string bytes = ppp::test::readFileBytes(stream);
  std::vector<StreamMessage> messages;
  std::uint32_t seq = 0;
  std::size_t ssr_frames = 0, ephemeris_frames = 0;
  ppp::Rtcm3Framer framer;
  framer.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), [&](const ppp::Rtcm3Frame& f) {
    StreamMessage m;
    const bool correction = ppp::RtcmSsrDecoder::isSsrMessageType(f.message_type);
    m.publisher = correction ? 1 : 0;
    ssr_frames += correction ? 1 : 0;
    ephemeris_frames += (f.message_type == 1019 || f.message_type == 1045 || f.message_type == 1046) ? 1 : 0;
    const auto* begin = reinterpret_cast<const std::uint8_t*>(bytes.data()) + f.byte_offset;
    m.message = rtcmMessage(std::vector<std::uint8_t>(begin, begin + f.payload.size() + 6), ++seq);
    messages.push_back(std::move(m));
  });
  EXPECT_EQ(framer.counters().totalProblems(), 0u);
  ASSERT_GT(ssr_frames, 500u);
  ASSERT_GT(ephemeris_frames, 1000u);
  std::printf("[ figures  ] %zu rtcm_msgs/Message: %zu SSR on /esbc/ssr, the rest (%zu ephemeris frames) on /esbc/rtcm\n",
              messages.size(), ssr_frames, ephemeris_frames);

  ros::NodeHandle nh;
  NodeOutputs ekf_out, smoother_out;
  ekf_out.subscribe(nh, "/ekf/");
  smoother_out.subscribe(nh, "/smoother/");
  publishInOrder(nh, {"/esbc/rtcm", "/esbc/ssr"}, messages, 0.002, 2);
  waitForFixes(ekf_out, offline.ekf.size() - 1, 60.0);
  waitForFixes(smoother_out, offline.smoother_filtered.size() - 1, 30.0);

  std::lock_guard<std::mutex> l1(ekf_out.mutex), l2(smoother_out.mutex);
  expectEqualToPppSolve("ppp_ekf_node, MSM7 + ephemerides + SSR", ekf_out.fixes, offline.ekf);
  expectEqualToPppSolve("ppp_smoother_node, MSM7 + ephemerides + SSR", smoother_out.fixes, offline.smoother_filtered);
  for (const auto* out : {&ekf_out, &smoother_out}) {
    ASSERT_FALSE(out->statuses.empty());
    for (const auto& s : out->statuses) EXPECT_EQ(s.product_mode, ppp_bayes_tree::PppStatus::PRODUCTS_PRECISE);
  }
}

int main(int argc, char** argv) { return ppp_ros::test::liveRostestMain(argc, argv, "rostest_live_esbc_ssr"); }
