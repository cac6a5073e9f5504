// The gnss_antenna lever arm geometry (ros/lever_arm.h) and the `ros:` keys of the
// smoother node and the attitude source (node_options.h, config/ppp.yaml).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ros/lever_arm.h"
#include "ppp_bayes_tree/ros/node_options.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Quaterniond yawPitchRoll(double yaw, double pitch, double roll) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
}

}  // namespace

TEST(LeverArm, LevelBodyFacingEastSubtractsTheArmUnrotated) {
  // REP-103: body x forward, y left, z up; ENU map; yaw 0 = x pointing east.
  const Eigen::Vector3d antenna(10.0, 20.0, 30.0), arm(0.5, 0.2, 1.0);
  const Eigen::Vector3d base = ppp_ros::baseLinkFromAntenna(antenna, Eigen::Quaterniond::Identity(), arm);
  EXPECT_NEAR((base - Eigen::Vector3d(9.5, 19.8, 29.0)).norm(), 0.0, 1e-12);
}

TEST(LeverArm, YawNorthRotatesForwardIntoNorth) {
  // Facing north (yaw +90 deg): body x = map y (north), body y (left) = map -x (west).
  const Eigen::Vector3d antenna(0.0, 0.0, 0.0), arm(1.0, 0.5, 0.0);
  const Eigen::Vector3d base = ppp_ros::baseLinkFromAntenna(antenna, yawPitchRoll(kPi / 2, 0, 0), arm);
  // antenna = base + (x: -0.5, y: 1.0) -> base = (0.5, -1.0, 0).
  EXPECT_NEAR((base - Eigen::Vector3d(0.5, -1.0, 0.0)).norm(), 0.0, 1e-12);
}

TEST(LeverArm, RolledUpsideDownMastPointsDown) {
  // Roll 180 deg: the body z axis (an antenna mast 1.2 m up) points down in the map.
  const Eigen::Vector3d antenna(3.0, 4.0, 5.0), arm(0.0, 0.0, 1.2);
  const Eigen::Vector3d base = ppp_ros::baseLinkFromAntenna(antenna, yawPitchRoll(0, 0, kPi), arm);
  EXPECT_NEAR((base - Eigen::Vector3d(3.0, 4.0, 6.2)).norm(), 0.0, 1e-12);
}

TEST(LeverArm, ArmLengthIsKeptForAnyAttitudeAndInvalidQuaternionsAreRefused) {
  const Eigen::Vector3d antenna(1.0, 2.0, 3.0), arm(0.3, -0.4, 1.2);
  for (double yaw : {-2.0, 0.3, 1.7})
    for (double pitch : {-0.4, 0.2}) {
      const Eigen::Quaterniond q = yawPitchRoll(yaw, pitch, 0.1);
      const Eigen::Vector3d base = ppp_ros::baseLinkFromAntenna(antenna, q, arm);
      EXPECT_NEAR((antenna - base).norm(), arm.norm(), 1e-12);
      EXPECT_NEAR((q.inverse() * (antenna - base) - arm).norm(), 0.0, 1e-12);  // back in the body frame
    }
  EXPECT_TRUE(ppp_ros::validAttitude(yawPitchRoll(0.3, 0.1, -0.2)));
  EXPECT_FALSE(ppp_ros::validAttitude(Eigen::Quaterniond(0, 0, 0, 0)));  // an unset Imu orientation
  EXPECT_FALSE(ppp_ros::validAttitude(Eigen::Quaterniond(std::numeric_limits<double>::quiet_NaN(), 0, 0, 0)));
  EXPECT_FALSE(ppp_ros::validAttitude(Eigen::Quaterniond(2, 0, 0, 0)));
}

TEST(RosNodeOptions, SmoothedAttitudeAndAntennaKeysBindStrictly) {
  const ppp::PppConfig c = ppp::loadPppConfig(std::string(PPP_REPO_DIR) + "/config/ppp.yaml");
  const auto o = ppp_ros::bindRosNodeOptions(c.ros, "ppp.yaml");
  // Defaults as written in config/ppp.yaml (ros.smoothed, ros.attitude, ros.frames).
  EXPECT_DOUBLE_EQ(o.smoothed_path_publish_rate_hz, 1.0);
  EXPECT_DOUBLE_EQ(o.smoothed_odometry_delay_s, 0.0);
  EXPECT_EQ(o.attitude_topic, "");
  EXPECT_DOUBLE_EQ(o.attitude_max_age_s, 0.5);
  EXPECT_EQ(o.antenna_frame, "gnss_antenna");
  const auto bind = [](const std::string& text) {
    return ppp_ros::bindRosNodeOptions(ppp::parsePppConfig(text, "text").ros, "text");
  };
  const auto set = bind("ros: {smoothed: {path_publish_rate_hz: 0.2, odometry_delay_s: 30}, attitude: {topic: imu, "
                        "max_age_s: 0.1}, frames: {gnss_antenna: ant, antenna_lever_arm_m: [0.1, 0, 0.9]}}");
  EXPECT_DOUBLE_EQ(set.smoothed_path_publish_rate_hz, 0.2);
  EXPECT_DOUBLE_EQ(set.smoothed_odometry_delay_s, 30.0);
  EXPECT_EQ(set.attitude_topic, "imu");
  EXPECT_DOUBLE_EQ(set.attitude_max_age_s, 0.1);
  EXPECT_EQ(set.antenna_frame, "ant");
  EXPECT_DOUBLE_EQ(set.antenna_lever_arm_m.z(), 0.9);
  for (const char* bad : {"ros: {smoothed: {path_publish_rate_hz: 0}}", "ros: {smoothed: {path_publish_rate_hz: 11}}",
                          "ros: {smoothed: {path_publish_rate_hz: fast}}", "ros: {smoothed: {odometry_delay_s: -1}}",
                          "ros: {smoothed: {odometry_delay_s: 4000}}", "ros: {smoothed: {rate: 1}}",
                          "ros: {attitude: {max_age_s: 0}}", "ros: {attitude: {topc: imu}}",
                          "ros: {frames: {antenna_lever_arm_m: [1, 2]}}"})
    EXPECT_THROW(bind(bad), ppp::ConfigError) << bad;
}
