// rostest, live input through ublox_gps's messages: the u-blox recording
// gnss_1730.ubx (F9, 536 RXM-RAWX epochs at 4 Hz, 2,328 RXM-SFRBX) decoded by this
// test into ublox_msgs/RxmRAWX and ublox_msgs/RxmSFRBX (the ROS serialization of their
// definitions, test/ros/ublox_ros_messages.h), published with the exact type names and
// MD5s on /ublox/rxmraw and /ublox/rxmsfrb in the file's order, to ppp_ekf_node and
// ppp_smoother_node of launch/live.launch example a (config/ppp.yaml + config/live.yaml;
// test/rostest/live_ubx.yaml: GPS + Galileo, broadcast only). Each node re-frames them
// as UBX for the one UbxDecoder. The file carries no station position: each estimator
// starts from the Earth centre on the start model (PppEstimator step 1) once four
// satellites have an ephemeris received before the epoch (11 records in 2 min: 338 of
// the 536 epochs solve, the first 46 s in). The EKF node's fixes must equal `ppp_solve
// --ubx F --nav F --config config/live.yaml test/rostest/live_ubx.yaml` EKF, and the
// smoother node's fixes (its filtered estimate) that run's smoother filtered solution,
// epoch by epoch to 1 mm (as live_rtcm_launch); each node processes every epoch.
#include "ppp_bayes_tree/io/ubx/ubx_framer.h"
#include "rostest/live_support.h"

namespace {

const char* kRawxType = "ublox_msgs/RxmRAWX";
const char* kRawxMd5 = "a2df4b27b6a2a1565e42f5669dbb11b5";
const char* kSfrbxType = "ublox_msgs/RxmSFRBX";
const char* kSfrbxMd5 = "c76473d828cc8e80de3a2d83cd6b9dff";

}  // namespace

TEST(LiveUbx, RxmRawxAndSfrbxToBothNodesEqualPppSolveEpochByEpochTo1mm) {
  PPP_REQUIRE_SHARED_DATA();
  using namespace ppp_ros::test;
  const std::string ubx = ppp::test::dataPath("streams/ubx/gnss_1730.ubx");
  const std::string atx = ppp::test::dataPath("antex/igs20_gps_satellites_trim.atx");
  const PppSolveBoth offline =
      pppSolveBoth("--ubx " + ubx + " --nav " + ubx + " --atx " + atx + " --config " + PPP_REPO_DIR +
                       "/config/live.yaml " + PPP_REPO_DIR + "/test/rostest/live_ubx.yaml",
                   "live_ubx");
  const std::size_t epochs = offline.ekf_rows;
  ASSERT_EQ(epochs, 536u);
  ASSERT_EQ(offline.smoother_rows, epochs);
  ASSERT_GT(offline.ekf.size(), 300u) << "ppp_solve solved too few epochs of " << ubx;
  ASSERT_GT(offline.smoother_filtered.size(), 300u);

  const std::string bytes = ppp::test::readFileBytes(ubx);
  std::vector<StreamMessage> messages;
  ppp::UbxFramer framer;
  framer.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), [&](const ppp::UbxFrame& f) {
    if (f.message_class != 0x02 || (f.message_id != 0x15 && f.message_id != 0x13)) return;  // RXM-RAWX, RXM-SFRBX only
    StreamMessage m;
    if (f.message_id == 0x15) {
      m.publisher = 0;
      m.message = shapeShifter(kRawxType, kRawxMd5, kRxmRawxDefinition, serializeRxmRawx(f.payload));
    } else {
      m.publisher = 1;
      m.message = shapeShifter(kSfrbxType, kSfrbxMd5, kRxmSfrbxDefinition, serializeRxmSfrbx(f.payload));
    }
    messages.push_back(std::move(m));
  });
  ASSERT_EQ(messages.size(), 536u + 2328u);  // shared/data README

  ros::NodeHandle nh;
  LiveLaunchOutputs out;
  out.subscribe(nh);
  publishInOrder(nh, {"/ublox/rxmraw", "/ublox/rxmsfrb"}, messages, 0.002, 2);  // both nodes subscribed
  ASSERT_TRUE(out.ekf.waitForStatuses(epochs - 1, 60.0)) << out.ekf.statusCount() << " EKF statuses of " << epochs;
  ASSERT_TRUE(out.smoother.waitForStatuses(epochs - 1, 30.0))
      << out.smoother.statusCount() << " smoother statuses of " << epochs;
  waitForFixes(out.ekf, offline.ekf.size() - 1, 30.0);
  waitForFixes(out.smoother, offline.smoother_filtered.size() - 1, 30.0);
  {
    std::lock_guard<std::mutex> l(out.ekf.mutex);
    std::lock_guard<std::mutex> m(out.smoother.mutex);
    for (const NodeOutputs* o : {&out.ekf, &out.smoother}) {
      EXPECT_GE(o->statuses.size() + 1, epochs);
      EXPECT_LE(o->statuses.size(), epochs);
    }
  }
  out.expectEqualTo(offline, "ublox_msgs/RxmRAWX + RxmSFRBX on /ublox/rxmraw + /ublox/rxmsfrb");
}

int main(int argc, char** argv) { return ppp_ros::test::liveRostestMain(argc, argv, "rostest_live_ubx"); }
