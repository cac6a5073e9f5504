// rostest: ppp_smoother_node on ZIM2 (first 40 epochs = 20 min at 30 s), bag made
// by this test with the ppp_to_bag code, played at 20x real time. The node's
// filtered fixes must match `ppp_solve --estimator smoother` (its pipeline, same
// files, same parameters) epoch by epoch to 1 mm; the final error is below a bound
// that ppp_solve also meets (rostest_support.h compareWithPppSolveOnZim2); the
// smoothed path's last pose is the last filtered pose.
#include "rostest/rostest_support.h"

namespace {
// Final 3D error bound after 20 min [m]; ppp_solve's smoother meets it too (printed).
constexpr double kFinalErrorBound_m = 0.5;
}  // namespace

TEST(SmootherNodeZim2, MatchesPppSolveSmootherEpochByEpochTo1mm) {
  PPP_REQUIRE_SHARED_DATA();
  ppp_ros::test::NodeOutputs out;
  ppp_ros::test::compareWithPppSolveOnZim2("ppp_smoother_node", "smoother", 40, kFinalErrorBound_m, out);
  // The smoothed path (1 Hz re-read) ends at the last filtered pose.
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(5.0);
  nav_msgs::Path path;
  nav_msgs::Odometry last;
  while (ros::WallTime::now() < end) {
    {
      std::lock_guard<std::mutex> l(out.mutex);
      path = out.smoothed_path;
      if (!out.odometry.empty()) last = out.odometry.back();
    }
    if (!path.poses.empty() && path.poses.back().header.stamp == last.header.stamp) break;
    ros::WallDuration(0.1).sleep();
  }
  ASSERT_FALSE(path.poses.empty());
  ASSERT_EQ(path.poses.back().header.stamp, last.header.stamp);
  EXPECT_LT((ppp_ros::test::position(path.poses.back().pose) - ppp_ros::test::position(last.pose.pose)).norm(), 1e-3);
  std::lock_guard<std::mutex> l(out.mutex);
  EXPECT_EQ(path.poses.size(), out.odometry.size());
  EXPECT_EQ(out.smoothed_odometry.size(), out.odometry.size());
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rostest_smoother_zim2");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
