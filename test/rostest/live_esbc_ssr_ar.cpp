// rostest, the live path with SSR phase biases, for one node (the test's private
// parameter `estimator`: "ekf" in live_esbc_ssr_ar.test, "smoother" in
// live_esbc_ssr_ar_smoother.test, the node in the namespace of that name): the ESBC
// 2020-177 window 00:05-01:05 (30 s) made into one caster stream by the ppp_stream_make
// binary (1006/1033, MSM7, the broadcast records from their transmission time) and an
// SSR stream made by ppp_ssr_encode's code (models/ssr_from_precise.h): the GRG SP3/CLK
// against the broadcast file, GPS and Galileo, 5 s, centre of mass, with the clocks'
// reference code biases and the integer phase biases (1265/1267) from the wide-lane
// biases of the integer-recovery clock header. Published frame by frame
// (rtcm_msgs/Message) on /esbc/rtcm and /esbc/ssr (live_support.h, makeEsbcSsrLiveCase)
// to the node with the IGS14 satellite antennas, ambiguity_resolution.enabled: auto and
// ssr.antenna_model: IGS14 (live_esbc_ssr_ar.yaml). The node must fix, and equal
// `ppp_solve --rtcm MADE --nav MADE --ssr SSR --estimator <estimator>` (the smoother's
// filtered solution: the node's ppp/fix) with the same configuration epoch by epoch: the
// same fix state (PppStatus fix_state, NavSatFix STATUS_GBAS_FIX), positions within 1 mm.
#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/models/clock_wide_lane_bias_provider.h"
#include "esbc_stream_fixture.h"
#include "rostest/live_support.h"

namespace {

/// The SSR stream with phase biases for [first, last], as ppp_ssr_encode writes it
/// from the GRG products (GPS and Galileo).
std::vector<std::uint8_t> esbcSsrStreamWithPhaseBiases(const ppp::NavData& nav, const ppp::GnssTime& first,
                                                       const ppp::GnssTime& last) {
  const std::string clk = ppp::test::esbcPath("GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz");
  std::vector<std::string> problems;
  const auto wide_lane = ppp::integerRecoveryClockBiases({ppp::readRinexClockHeader(clk)}, {clk}, problems);
  EXPECT_NE(wide_lane, nullptr);
  ppp::SsrFromPreciseOptions options;
  options.systems = {ppp::GnssSystem::GPS, ppp::GnssSystem::Galileo};
  return ppp::test::ssrStreamBytes(ppp::ssrFromPrecise({nav}, ppp::test::esbcGrgPrecise(), nullptr, wide_lane.get(),
                                                       first, last, options, wide_lane.get()));
}

}  // namespace

TEST(LiveEsbcSsrAr, NodeFixesWithSsrPhaseBiasesAsPppSolve) {
  PPP_REQUIRE_SHARED_DATA();
  using namespace ppp_ros::test;
  std::string estimator = "ekf";
  ros::param::get("~estimator", estimator);
  ASSERT_TRUE(estimator == "ekf" || estimator == "smoother") << "~estimator: " << estimator;
  const std::string node = "ppp_" + estimator + "_node";
  const ppp::GnssTime start = ppp::test::gpst(2020, 6, 25, 0, 5, 0), until = start + 3600.0;
  const ppp::NavData nav = ppp::readRinexNav(ppp::test::esbcPath("ESBC00DNK_R_20201770000_01D_MN.rnx"));
  EsbcSsrLiveCase live;
  ASSERT_NO_FATAL_FAILURE(makeEsbcSsrLiveCase(ppp::test::tempDir("live_esbc_ssr_ar_" + estimator),
                                              esbcSsrStreamWithPhaseBiases(nav, start - 60.0, until + 60.0),
                                              "2020/06/25 00:05:00", 3600, &live));
  const std::string args =
      live.pppSolveArgs({"antex/igs14_2178_satellites.atx", "antex/igs05_esbc_receiver_trim.atx"},
                        {"config/ppp.yaml", "test/rostest/live_esbc_ssr_ar.yaml"});
  const std::string csv = estimator == "ekf" ? "live_ekf.csv" : "live_smoother_filtered.csv";
  const std::map<ros::Time, SolvedEpoch> offline =
      readSolutionCsv(runPppSolve(args, estimator, "live_esbc_ssr_ar_" + estimator) / csv);
  ASSERT_GT(offline.size(), 100u) << "ppp_solve solved too few epochs of " << live.stream;
  EXPECT_EQ(live.framing_problems, 0u);
  ASSERT_GT(live.frames({1265, 1267}), 1000u);  // 720 SSR epochs, GPS and Galileo each

  ros::NodeHandle nh;
  NodeOutputs out;
  out.subscribe(nh, "/" + estimator + "/");
  publishInOrder(nh, {"/esbc/rtcm", "/esbc/ssr"}, live.messages, 0.002, 1);
  waitForFixes(out, offline.size() - 1, 60.0);

  const std::size_t fixed = expectSameFixes(node + ", MSM7 + ephemerides + SSR with phase biases", out, offline);
  // ppp_solve fixes 49 of these epochs (every subset at the success rate 0.999,
  // doc/studies/ar_real_data.md "Restarts"): the node fixes, and as ppp_solve (above).
  EXPECT_GT(fixed, 40u);
  std::lock_guard<std::mutex> l(out.mutex);
  ASSERT_FALSE(out.statuses.empty());
  EXPECT_TRUE(out.statuses.back().ambiguity_resolution_enabled);
  EXPECT_NE(out.statuses.back().phase_bias_source.find("SSR"), std::string::npos)
      << out.statuses.back().phase_bias_source;
}

int main(int argc, char** argv) { return ppp_ros::test::liveRostestMain(argc, argv, "rostest_live_esbc_ssr_ar"); }
