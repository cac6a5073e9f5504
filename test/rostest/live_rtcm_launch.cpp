// rostest, live input through launch/live.launch: ppp_ekf_node and
// ppp_smoother_node side by side on the same raw topic, configured as live.launch
// configures them (config/ppp.yaml + config/live.yaml, i.e. the fixed-lag smoother;
// test/rostest/live_str24.yaml: reference date, broadcast only). The recording
// week-rollover-STR24.rtcm3 (GMSD, MSM7 + GPS/GLONASS ephemerides, across a week
// boundary) is published on /gnss/receiver as rtcm_msgs/Message (exact type name and
// MD5) in arbitrary chunks cutting through frames (1 to 700 bytes, seeded). The EKF
// node's fixes must equal `ppp_solve --rtcm F --ref-date 2018/07/14 --nav F --config
// config/live.yaml` EKF, and the smoother node's fixes (its filtered estimate, the
// newest state) that run's smoother filtered solution, epoch by epoch to 1 mm.

#include "rostest/live_support.h"

TEST(LiveRtcmLaunch, EkfAndSmootherEqualPppSolveEpochByEpochTo1mm) {
  PPP_REQUIRE_SHARED_DATA();
  using namespace ppp_ros::test;
  PppSolveBoth offline;
  ASSERT_NO_FATAL_FAILURE(solveStr24Live("live_rtcm_launch", &offline));
  ASSERT_GT(offline.smoother_filtered.size(), 1000u);

  std::vector<StreamMessage> messages =
      rtcmChunkMessages(ppp::test::readFileBytes(str24Recording()), 1414);

  ros::NodeHandle nh;
  LiveLaunchOutputs out;
  out.subscribe(nh);
  // 3 ms apart (19 min of data in about 12 s): the nodes' outputs (publisher queues of 100)
  // come at about 100 epochs/s, which this test node reads even on a loaded machine.
  publishInOrder(nh, {"/gnss/receiver"}, messages, 0.003, 2);  // both nodes subscribed
  waitAndExpectEqualTo(out, offline, "rtcm_msgs/Message chunks on /gnss/receiver");
  std::lock_guard<std::mutex> l(out.ekf.mutex);
  for (const auto& [name, level] : out.ekf.worst_diagnostic)
    if (name.find("live streams") != std::string::npos) EXPECT_LT(level, diagnostic_msgs::DiagnosticStatus::ERROR) << name;
}

int main(int argc, char** argv) { return ppp_ros::test::liveRostestMain(argc, argv, "rostest_live_rtcm_launch"); }
