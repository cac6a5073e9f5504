// rostest, the live path with SSR phase biases: the ESBC 2020-177 window 00:05-01:05
// (30 s) made into one caster stream by the ppp_stream_make binary (1006/1033, MSM7,
// the broadcast records from their transmission time) and an SSR stream made by
// ppp_ssr_encode's code (models/ssr_from_precise.h): the GRG SP3/CLK against the
// broadcast file, GPS and Galileo, 5 s, centre of mass, with the clocks' reference
// code biases and the integer phase biases (1265/1267) from the wide-lane biases of
// the integer-recovery clock header. Published frame by frame (rtcm_msgs/Message) on
// /esbc/rtcm and /esbc/ssr to ppp_ekf_node (/ekf) with the IGS14 satellite antennas,
// ambiguity_resolution.enabled: auto and ssr.antenna_model: IGS14
// (live_esbc_ssr_ar.yaml). The node must fix, and equal `ppp_solve --rtcm MADE --nav
// MADE --ssr SSR` with the same configuration epoch by epoch: the same fix state
// (PppStatus fix_state, NavSatFix STATUS_GBAS_FIX), positions within 1 mm.
#include "ppp_bayes_tree/io/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rtcm3_framer.h"
#include "ppp_bayes_tree/io/rtcm_ssr_decoder.h"
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

TEST(LiveEsbcSsrAr, EkfNodeFixesWithSsrPhaseBiasesAsPppSolve) {
  PPP_REQUIRE_SHARED_DATA();
  using namespace ppp_ros::test;
  using ppp::test::esbcPath;
  const std::filesystem::path dir = ppp::test::tempDir("live_esbc_ssr_ar");
  const ppp::GnssTime start = ppp::test::gpst(2020, 6, 25, 0, 5, 0), until = start + 3600.0;
  const std::string nav = esbcPath("ESBC00DNK_R_20201770000_01D_MN.rnx");

  const std::string ssr = (dir / "SSRC00TST_esbc.rtcm3").string();
  ppp::test::writeFileBytes(ssr, esbcSsrStreamWithPhaseBiases(ppp::readRinexNav(nav), start - 60.0, until + 60.0));
  const std::string stream = makeEsbcCasterStream(dir, nav, ssr, "2020/06/25 00:05:00", 3600);
  ASSERT_FALSE(::testing::Test::HasFailure());

  const std::string args = "--rtcm " + stream + " --ref-date 2020/06/25 --nav " + stream + " --ssr " + ssr +
                           " --atx " + ppp::test::dataPath("antex/igs14_2178_satellites.atx") + " " +
                           ppp::test::dataPath("antex/igs05_esbc_receiver_trim.atx") + " --config " + PPP_REPO_DIR +
                           "/config/ppp.yaml " + PPP_REPO_DIR + "/test/rostest/live_esbc_ssr_ar.yaml";
  const std::map<ros::Time, SolvedEpoch> offline =
      readSolutionCsv(runPppSolve(args, "ekf", "live_esbc_ssr_ar") / "live_ekf.csv");
  ASSERT_GT(offline.size(), 100u) << "ppp_solve solved too few epochs of " << stream;

  const std::string bytes = ppp::test::readFileBytes(stream);
  std::vector<StreamMessage> messages;
  std::uint32_t seq = 0;
  std::size_t phase_bias_frames = 0;
  ppp::Rtcm3Framer framer;
  framer.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), [&](const ppp::Rtcm3Frame& f) {
    StreamMessage m;
    m.publisher = ppp::RtcmSsrDecoder::isSsrMessageType(f.message_type) ? 1 : 0;
    phase_bias_frames += (f.message_type == 1265 || f.message_type == 1267) ? 1 : 0;
    const auto* begin = reinterpret_cast<const std::uint8_t*>(bytes.data()) + f.byte_offset;
    m.message = rtcmMessage(std::vector<std::uint8_t>(begin, begin + f.payload.size() + 6), ++seq);
    messages.push_back(std::move(m));
  });
  EXPECT_EQ(framer.counters().totalProblems(), 0u);
  ASSERT_GT(phase_bias_frames, 1000u);  // 720 SSR epochs, GPS and Galileo each

  ros::NodeHandle nh;
  NodeOutputs ekf_out;
  ekf_out.subscribe(nh, "/ekf/");
  publishInOrder(nh, {"/esbc/rtcm", "/esbc/ssr"}, messages, 0.002, 1);
  waitForFixes(ekf_out, offline.size() - 1, 60.0);

  const std::size_t fixed = expectSameFixes("ppp_ekf_node, MSM7 + ephemerides + SSR with phase biases", ekf_out, offline);
  EXPECT_GT(fixed, 60u);  // ppp_solve fixes from about 17 min on
  std::lock_guard<std::mutex> l(ekf_out.mutex);
  ASSERT_FALSE(ekf_out.statuses.empty());
  EXPECT_TRUE(ekf_out.statuses.back().ambiguity_resolution_enabled);
  EXPECT_NE(ekf_out.statuses.back().phase_bias_source.find("SSR"), std::string::npos)
      << ekf_out.statuses.back().phase_bias_source;
}

int main(int argc, char** argv) { return ppp_ros::test::liveRostestMain(argc, argv, "rostest_live_esbc_ssr_ar"); }
