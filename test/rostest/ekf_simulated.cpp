// rostest: ppp_ekf_node on a simulated loiter flight (5 min at 1 Hz, 30 s
// corrections) made into a bag by this test and played at 20x real time; then
// each robustness case publishes its bad input and checks that the node goes on
// (the cases are shared with the smoother node: rostest_support.h).
// ekf_simulated.test sets a lever arm and no attitude source: base_link is then
// the antenna position (documented in config/ppp.yaml).
#include "rostest/rostest_support.h"

namespace {
ppp_ros::test::SimulatedNodeTest* g = nullptr;
}  // namespace

TEST(EkfNodeSimulated, PlaysTheBagAt20xWithoutDropsAndConverges) { g->checkReplayAt20x(); }

TEST(EkfNodeSimulated, FinalErrorBelowTheBoundTheOfflineSolverMeets) { g->checkFinalError(); }

TEST(EkfNodeSimulated, TfMapToBaseLinkResolvesWithoutAttitudeAtTheAntennaAndDiagnosticsAreNotError) {
  ASSERT_TRUE(g->ok);
  // Without an attitude source the lever arm is not applied: base_link is at the fix
  // (the antenna position); the static base_link -> gnss_antenna transform still holds
  // the lever arm, unrotated (identity orientation), as documented in config/ppp.yaml.
  const Eigen::Vector3d offset = g->checkTfAndDiagnostics("base_link");
  const ppp_ros::NodeConfig config = ppp_ros::loadNodeConfig(ros::NodeHandle("/ppp_ekf_node"));
  ASSERT_GT(config.ros.antenna_lever_arm_m.norm(), 0.1) << "ekf_simulated.test sets a lever arm";
  EXPECT_LT((offset - config.ros.antenna_lever_arm_m).norm(), 1e-6);
  std::lock_guard<std::mutex> l(g->out.mutex);
  ASSERT_FALSE(g->out.odometry.empty());
  const auto& odom = g->out.odometry.back();
  EXPECT_EQ(odom.pose.pose.orientation.w, 1.0) << "no attitude: identity orientation";
  EXPECT_EQ(g->out.fixes.back().header.frame_id, "gnss_antenna");
}

TEST(EkfNodeSimulated, DoesNotAdvertiseTheSmoothedTopics) {
  EXPECT_TRUE(ppp_ros::test::topicAdvertised("/ppp/odometry/filtered"));
  EXPECT_FALSE(ppp_ros::test::topicAdvertised("/ppp/odometry/smoothed"));
  EXPECT_FALSE(ppp_ros::test::topicAdvertised("/ppp/path/smoothed"));
}

TEST(EkfNodeSimulated, DuplicateAndOutOfOrderEpochsAreDroppedAndCounted) { g->checkDuplicateAndOutOfOrderDropped(); }

TEST(EkfNodeSimulated, EmptyEpochAndInvalidValuesAreHandled) { g->checkEmptyEpochAndInvalidValues(); }

TEST(EkfNodeSimulated, CorrectionsForUnknownSatellitesAndAbsurdValuesAreHandled) {
  g->checkCorrectionsForUnknownSatellites();
}

TEST(EkfNodeSimulated, TimeGoingBackwardsBeyondTheThresholdResetsTheEstimator) { g->checkTimeBackwardsResets(); }

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rostest_ekf_simulated");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ppp_ros::test::SimulatedNodeTest t("ppp_ekf_node", "ekf");
  g = &t;
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
