// rostest, live input with corrections through rtcm_msgs/Message:
// the ESBC 2020-177 window 00:30-01:15 (30 s) made into one caster stream by the
// ppp_stream_make binary (1006/1033, MSM7 of every system, the broadcast file's
// records 1019/1045/1046 from their transmission time with repeats) and an SSR
// stream made by ppp_ssr_encode's code (models/ssr_from_precise.h: GRG SP3/CLK
// against the broadcast file, GPS, 5 s, centre of mass), published with the exact
// foreign type name and MD5 (topic_tools::ShapeShifter), one frame per message in
// the caster's order: observations and ephemerides on /esbc/rtcm, SSR on /esbc/ssr
// (live_support.h, makeEsbcSsrLiveCase). Two nodes take them side by side:
// ppp_ekf_node (/ekf) and ppp_smoother_node (/smoother). Each node's fixes must
// equal those of one `ppp_solve --rtcm MADE --ref-date 2020/06/25 --nav MADE --ssr
// SSR --estimator both` with its estimator (the smoother's filtered solution), epoch
// by epoch to 1 mm, in precise (SSR) mode throughout.
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "esbc_stream_fixture.h"
#include "rostest/live_support.h"

TEST(LiveEsbcSsr, EkfAndSmootherNodesEqualPppSolveOnTheMadeStreams) {
  PPP_REQUIRE_SHARED_DATA();
  using namespace ppp_ros::test;
  const ppp::GnssTime start = ppp::test::gpst(2020, 6, 25, 0, 30, 0), until = start + 2700.0;
  const ppp::NavData nav = ppp::readRinexNav(ppp::test::esbcPath("ESBC00DNK_R_20201770000_01D_MN.rnx"));
  // The SSR stream (ppp_ssr_encode's core) for the window and a minute around it.
  EsbcSsrLiveCase live;
  ASSERT_NO_FATAL_FAILURE(makeEsbcSsrLiveCase(ppp::test::tempDir("live_esbc_ssr"),
                                              ppp::test::esbcGpsSsrStream(nav, start - 60.0, until + 60.0),
                                              "2020/06/25 00:30:00", 2700, &live));
  const PppSolveBoth offline = pppSolveBoth(
      live.pppSolveArgs({"antex/igs20_gps_satellites_trim.atx", "antex/igs05_esbc_receiver_trim.atx"},
                        {"config/ppp.yaml"}),
      "live_esbc");
  ASSERT_GT(offline.ekf.size(), 80u) << "ppp_solve solved too few epochs of " << live.stream;
  ASSERT_GT(offline.smoother_filtered.size(), 80u);

  EXPECT_EQ(live.framing_problems, 0u);
  ASSERT_GT(live.ssr_frames, 500u);
  const std::size_t ephemeris_frames = live.frames({1019, 1045, 1046});
  ASSERT_GT(ephemeris_frames, 1000u);
  std::printf("[ figures  ] %zu rtcm_msgs/Message: %zu SSR on /esbc/ssr, the rest (%zu ephemeris frames) on /esbc/rtcm\n",
              live.messages.size(), live.ssr_frames, ephemeris_frames);

  ros::NodeHandle nh;
  NodeOutputs ekf_out, smoother_out;
  ekf_out.subscribe(nh, "/ekf/");
  smoother_out.subscribe(nh, "/smoother/");
  publishInOrder(nh, {"/esbc/rtcm", "/esbc/ssr"}, live.messages, 0.002, 2);
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
