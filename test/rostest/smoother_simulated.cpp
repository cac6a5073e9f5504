// rostest: ppp_smoother_node on the simulated loiter flight of the EKF test (5 min
// at 1 Hz, 30 s corrections) played at 20x real time, with an attitude published
// before each epoch (yaw 90 deg: body x north). Shared cases (rostest_support.h):
// no drops, converged, final error, TF, diagnostics, robustness. Smoother-specific:
// the lever arm rotated by the attitude, ppp/path/smoothed (last pose = last
// filtered pose, earlier poses better than filtered), ppp/odometry/smoothed.
#include <sensor_msgs/Imu.h>

#include "rostest/rostest_support.h"

namespace {

ppp_ros::test::SimulatedNodeTest* g = nullptr;
ros::Publisher g_attitude;
const Eigen::Quaterniond kAttitude(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));  // facing north (ENU)
const Eigen::Vector3d kLeverArm(0.3, 0.1, 0.8);  // smoother_simulated.test

void publishAttitude(const ppp_bayes_tree::GnssObservations& m) {
  sensor_msgs::Imu imu;
  imu.header.stamp = m.header.stamp;  // the epoch's UTC stamp
  imu.header.frame_id = "base_link";
  imu.orientation.w = kAttitude.w();
  imu.orientation.x = kAttitude.x();
  imu.orientation.y = kAttitude.y();
  imu.orientation.z = kAttitude.z();
  imu.orientation_covariance = {1e-4, 0, 0, 0, 1e-4, 0, 0, 0, 4e-4};
  imu.angular_velocity_covariance[0] = imu.linear_acceleration_covariance[0] = -1.0;
  g_attitude.publish(imu);
}

}  // namespace

TEST(SmootherNodeSimulated, PlaysTheBagAt20xWithoutDropsAndConverges) { g->checkReplayAt20x(); }

TEST(SmootherNodeSimulated, FinalErrorBelowTheBoundTheOfflineSolverMeets) { g->checkFinalError(); }

TEST(SmootherNodeSimulated, SmoothedPathEndsAtTheLastFilteredPoseAndImprovesTheStart) {
  ASSERT_TRUE(g->ok);
  nav_msgs::Odometry last_filtered;
  {
    std::lock_guard<std::mutex> l(g->out.mutex);
    ASSERT_FALSE(g->out.odometry.empty());
    last_filtered = g->out.odometry.back();
  }
  // The path is re-published at ros.smoothed.path_publish_rate_hz (1 Hz): wait for one holding the last epoch.
  nav_msgs::Path path;
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(5.0);
  while (ros::WallTime::now() < end) {
    {
      std::lock_guard<std::mutex> l(g->out.mutex);
      path = g->out.smoothed_path;
    }
    if (!path.poses.empty() && path.poses.back().header.stamp == last_filtered.header.stamp) break;
    ros::WallDuration(0.1).sleep();
  }
  ASSERT_FALSE(path.poses.empty()) << "no ppp/path/smoothed received";
  ASSERT_EQ(path.poses.back().header.stamp, last_filtered.header.stamp);
  EXPECT_EQ(path.header.frame_id, "map");
  // The smoothed last epoch has the same data as the filtered one: the same state.
  const double last_difference = (ppp_ros::test::position(path.poses.back().pose) -
                                  ppp_ros::test::position(last_filtered.pose.pose)).norm();
  EXPECT_LT(last_difference, 1e-3);
  std::vector<nav_msgs::Odometry> filtered, smoothed;
  {
    std::lock_guard<std::mutex> l(g->out.mutex);
    filtered = g->out.odometry;
    smoothed = g->out.smoothed_odometry;
  }
  EXPECT_EQ(path.poses.size(), filtered.size()) << "one pose per solved epoch";

  // Smoothing uses the later data: over the first 60 epochs the smoothed path is
  // closer to the truth than the filtered odometry (both base_link in the map frame).
  const auto earth_map = g->tf_buffer->lookupTransform("earth", "map", ros::Time(0));
  const Eigen::Vector3d datum = ppp_ros::test::translation(earth_map);
  const auto& r = earth_map.transform.rotation;
  const Eigen::Matrix3d enu_from_ecef = Eigen::Quaterniond(r.w, r.x, r.y, r.z).toRotationMatrix().transpose();
  std::map<ros::Time, Eigen::Vector3d> truth_base;  // map frame
  for (const auto& t : g->flight.truth)
    truth_base[ppp_ros::utcStamp(t.trajectory.time)] =
        enu_from_ecef * (t.trajectory.position_ecef_m - datum) - kAttitude * kLeverArm;
  double filtered_error = 0.0, smoothed_error = 0.0;
  const std::size_t n = 60;
  ASSERT_GT(path.poses.size(), n);
  for (std::size_t k = 0; k < n; ++k) {
    ASSERT_EQ(path.poses[k].header.stamp, filtered[k].header.stamp);
    const Eigen::Vector3d truth = truth_base.at(filtered[k].header.stamp);
    filtered_error += (ppp_ros::test::position(filtered[k].pose.pose) - truth).norm() / n;
    smoothed_error += (ppp_ros::test::position(path.poses[k].pose) - truth).norm() / n;
  }
  std::printf("[ figures  ] first %zu epochs, mean 3D error: filtered %.3f m, smoothed %.3f m; smoothed last - "
              "filtered last %.3g mm\n", n, filtered_error, smoothed_error, 1e3 * last_difference);
  EXPECT_LT(smoothed_error, 0.7 * filtered_error);

  // ppp/odometry/smoothed (full smoother, odometry_delay_s 0): the newest state after
  // each epoch = the filtered one, once per solved epoch, with an ENU covariance.
  ASSERT_EQ(smoothed.size(), filtered.size());
  for (std::size_t k = 0; k < smoothed.size(); ++k) {
    ASSERT_EQ(smoothed[k].header.stamp, filtered[k].header.stamp);
    EXPECT_LT((ppp_ros::test::position(smoothed[k].pose.pose) - ppp_ros::test::position(filtered[k].pose.pose)).norm(),
              1e-3);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(smoothed[k].pose.covariance[i * 7], filtered[k].pose.covariance[i * 7],
                  1e-6 * filtered[k].pose.covariance[i * 7] + 1e-12);
  }
}

TEST(SmootherNodeSimulated, TfMapToBaseLinkAppliesTheLeverArmWithTheAttitude) {
  ASSERT_TRUE(g->ok);
  // gnss_antenna - base_link in the map frame = R(attitude) * lever arm: facing north,
  // body x (0.3 forward) points north and body y (0.1 left) points west.
  const Eigen::Vector3d offset = g->checkTfAndDiagnostics("gnss_antenna");
  EXPECT_LT((offset - Eigen::Vector3d(-0.1, 0.3, 0.8)).norm(), 1e-6) << offset.transpose();
  const auto base = g->tf_buffer->lookupTransform("map", "base_link", ros::Time(0));
  const auto& q = base.transform.rotation;
  EXPECT_LT(Eigen::Quaterniond(q.w, q.x, q.y, q.z).angularDistance(kAttitude), 1e-9);
  std::lock_guard<std::mutex> l(g->out.mutex);
  EXPECT_EQ(g->out.fixes.back().header.frame_id, "gnss_antenna");
  EXPECT_NEAR(g->out.odometry.back().pose.covariance[35], 4e-4, 1e-12) << "yaw variance from the attitude";
}

TEST(SmootherNodeSimulated, AdvertisesTheSmoothedTopics) {
  EXPECT_TRUE(ppp_ros::test::topicAdvertised("/ppp/odometry/smoothed"));
  EXPECT_TRUE(ppp_ros::test::topicAdvertised("/ppp/path/smoothed"));
}

TEST(SmootherNodeSimulated, DuplicateAndOutOfOrderEpochsAreDroppedAndCounted) {
  g->checkDuplicateAndOutOfOrderDropped();
}

TEST(SmootherNodeSimulated, EmptyEpochAndInvalidValuesAreHandled) { g->checkEmptyEpochAndInvalidValues(); }

TEST(SmootherNodeSimulated, CorrectionsForUnknownSatellitesAndAbsurdValuesAreHandled) {
  g->checkCorrectionsForUnknownSatellites();
}

TEST(SmootherNodeSimulated, TimeGoingBackwardsBeyondTheThresholdResetsTheEstimator) {
  g->checkTimeBackwardsResets();
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rostest_smoother_simulated");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ppp_ros::test::SimulatedNodeTest t("ppp_smoother_node", "smoother");
  g = &t;
  g_attitude = t.nh.advertise<sensor_msgs::Imu>("attitude", 5000);
  t.before_observation = publishAttitude;
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
