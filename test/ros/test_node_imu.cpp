// The node's IMU input (node_imu_input.h) and its odometry message at the IMU
// rate (ins_odometry.h), without a ROS master: the options of the filter from
// ros.imu, the screening with the topic, field and stamp named, the time-base
// check that leaves a GNSS outage alone, the hand-over per epoch, the GNSS epochs held
// until the IMU readings up to their time have arrived (imu_epoch_hold.h; by the steady
// clock when the ROS clock stops), and the
// odometry message of a state (the propagation itself: test_ins_odometry, core).
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <yaml-cpp/yaml.h>

#include "ins_odometry_states.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "ppp_bayes_tree/ros/imu_conversions.h"
#include "ppp_bayes_tree/ros/imu_epoch_hold.h"
#include "ppp_bayes_tree/ros/ins_odometry.h"
#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/ros/node_config.h"
#include "ppp_bayes_tree/ros/node_diagnostics.h"
#include "ppp_bayes_tree/ros/node_imu_input.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace {

using ppp_ros::NodeImuInput;

const ppp::GnssTime kT0 = ppp::GnssTime::fromGpsWeek(2418, 259200.0);  // 2026-05-13 00:00 GPST

/// A level reading at rest (z up: +g on z) at t0 + dt_s.
sensor_msgs::Imu restMessage(double dt_s, double g = 9.81) {
  ppp::ImuSample r;
  r.time = kT0 + dt_s;
  r.specific_force_mps2 = Eigen::Vector3d(0.0, 0.0, g);
  return ppp_ros::toImuMessage(r, "imu_link");
}

struct Warnings {
  std::vector<std::string> lines;
  ppp_ros::WarningSink sink() {
    return [this](const std::string&, const std::string& text) { lines.push_back(text); };
  }
  bool any(const std::string& part) const {
    for (const auto& l : lines)
      if (l.find(part) != std::string::npos) return true;
    return false;
  }
};

TEST(NodeImuOptions, EstimatorChoiceLeverArmAndStartFromRosImu) {
  // The EKF node may run ekf_ins (same solutions); the smoother node may not.
  const ppp_ros::NodeConfig c = ppp_ros::bindNodeConfig(
      YAML::Load("ros: {estimator: ekf_ins, frames: {antenna_lever_arm_m: [0.3, 0.1, 0.8]},"
                 " imu: {translation_m: [0.1, 0.0, 0.2], rotation_rpy_deg: [180, 0, 0], initial_rpy_deg: [0, 0, 90],"
                 " initial_velocity_enu_mps: [1, 2, 3], grade: tactical}}"),
      "test", "ekf");
  EXPECT_EQ(c.ros.estimator, "ekf_ins");
  const auto same = [](const std::string& topic) { return topic; };
  EXPECT_EQ(ppp_ros::startSummary(c.ros, "test", 0, {}, same).text.rfind("ppp_ekf_node: config from test", 0), 0u)
      << "the node keeps its name with ros.estimator ekf_ins";
  EXPECT_THROW(ppp_ros::bindNodeConfig(YAML::Load("ros: {estimator: ekf_ins}"), "test", "smoother"), ppp::ConfigError);
  EXPECT_THROW(ppp_ros::bindNodeConfig(YAML::Load("ros: {estimator: kalman}"), "test", "ekf"), ppp::ConfigError);
  EXPECT_EQ(ppp_ros::bindNodeConfig(YAML::Load("{}"), "test", "ekf").ros.estimator, "ekf");
  EXPECT_THROW(ppp_ros::bindNodeConfig(YAML::Load("ros: {imu: {extrinsics: guess}}"), "test", "ekf"), ppp::ConfigError);

  const ppp_ros::ImuExtrinsics e = ppp_ros::parameterExtrinsics(c.ros.imu);
  const ppp::InsEkfOptions ins = ppp_ros::insOptions(c.ros, e);
  // Antenna minus IMU in base_link (0.2, 0.1, 0.6), in the IMU's axes (x fwd, y right, z down).
  EXPECT_LT((ins.lever_arm_body_m - Eigen::Vector3d(0.2, -0.1, -0.6)).norm(), 1e-12);
  EXPECT_EQ(ins.noise.gyro_bias_instability_radps,
            ppp::imuNoisePreset(ppp::ImuGrade::Tactical).gyro_bias_instability_radps);
  // base_link yaw 90 deg in ENU: x north; the IMU (roll 180) then is level, heading 0 (north), x fwd y right z down.
  ASSERT_TRUE(ins.initial_rotation_ned_body.has_value());
  EXPECT_LT((*ins.initial_rotation_ned_body - ppp::rotationNedBody(0.0, 0.0, 0.0)).norm(), 1e-12);
  ASSERT_TRUE(ins.initial_velocity_ned_mps.has_value());
  EXPECT_LT((*ins.initial_velocity_ned_mps - Eigen::Vector3d(2.0, 1.0, -3.0)).norm(), 1e-12);

  ppp_ros::RosNodeOptions level = c.ros;
  level.imu.initial_attitude = ppp_ros::RosImuOptions::StartAttitude::LevelAtRest;
  level.imu.initial_rpy_deg = Eigen::Vector3d(0.0, 0.0, 0.0);  // x east: heading 90 deg
  const ppp::InsEkfOptions lv = ppp_ros::insOptions(level, e);
  ASSERT_TRUE(lv.initial_heading_rad.has_value());
  EXPECT_NEAR(*lv.initial_heading_rad, M_PI / 2.0, 1e-12);
  EXPECT_FALSE(lv.initial_rotation_ned_body.has_value());
  // The heading is base_link's, whatever the mounting: an IMU with its x axis straight down.
  level.imu.rotation_rpy_deg = Eigen::Vector3d(0.0, 90.0, 0.0);
  const ppp::InsEkfOptions down = ppp_ros::insOptions(level, ppp_ros::parameterExtrinsics(level.imu));
  ASSERT_TRUE(down.initial_heading_rad.has_value());
  EXPECT_NEAR(*down.initial_heading_rad, M_PI / 2.0, 1e-12);
}

TEST(NodeImuOptions, TheFilterRunsInBaseLinksForwardRightDownAxesWhateverTheMounting) {
  // The walk's u-blox IMU: x left, y back, z up in base_link (yaw 90 deg), 0.05 m right of it.
  const ppp_ros::NodeConfig c = ppp_ros::bindNodeConfig(
      YAML::Load("ros: {estimator: ekf_ins, imu: {translation_m: [0, -0.05, 0], rotation_rpy_deg: [0, 0, 90],"
                 " initial_rpy_deg: [0, 0, 90]}}"),
      "test", "ekf");
  const ppp_ros::ImuExtrinsics e = ppp_ros::parameterExtrinsics(c.ros.imu);
  // A reading along the IMU's x (left in base_link) is along -y of the body (x fwd, y right, z down);
  // along the IMU's z (up) it is along -z.
  const Eigen::Matrix3d body_imu = ppp_ros::bodyFromImu(e);
  EXPECT_LT((body_imu * Eigen::Vector3d::UnitX() - Eigen::Vector3d(0.0, -1.0, 0.0)).norm(), 1e-15);
  EXPECT_LT((body_imu * Eigen::Vector3d::UnitZ() - Eigen::Vector3d(0.0, 0.0, -1.0)).norm(), 1e-15);
  // ppp_solve --imu-rotation 180,0,-90 --lever-arm 0,-0.05,0 (doc/studies/ins_walk.md) is the same mounting.
  EXPECT_LT((body_imu - ppp::rotationNedBody(M_PI, 0.0, -M_PI / 2.0)).norm(), 1e-15);
  const ppp::InsEkfOptions ins = ppp_ros::insOptions(c.ros, e);
  EXPECT_LT((ins.lever_arm_body_m - Eigen::Vector3d(0.0, -0.05, 0.0)).norm(), 1e-15);
  // base_link level, x north: the body level, heading 0.
  ASSERT_TRUE(ins.initial_rotation_ned_body.has_value());
  EXPECT_LT((*ins.initial_rotation_ned_body - Eigen::Matrix3d::Identity()).norm(), 1e-15);
  // The odometry's frame: the body at the IMU's origin, turned back into base_link.
  const ppp_ros::ImuExtrinsics body = ppp_ros::filterBodyExtrinsics(e);
  EXPECT_EQ(body.translation_m, e.translation_m);
  EXPECT_LT((body.rotation_base_imu * Eigen::Vector3d::UnitZ() - Eigen::Vector3d(0.0, 0.0, -1.0)).norm(), 1e-15);

  // The readings handed on are in the body axes: 1 g up along the IMU's z reads -9.8 along the body's z.
  ppp_ros::NodeImuInput in(c.ros, [](const std::string&, const std::string&) {});
  for (int k = 0; k < 100; ++k) in.receive(restMessage(0.01 * k), std::nullopt, body_imu, 0.01 * k);
  const std::vector<ppp::ImuSample> taken = in.takeUpTo(kT0 + 1.0);
  ASSERT_FALSE(taken.empty());
  EXPECT_NEAR(taken.front().specific_force_mps2.z(), -restMessage(0.0).linear_acceleration.z, 1e-12);
}

TEST(NodeImuOptions, GapBridgeBoundFromItsKey) {
  // ros.imu.gap_bridge_max_s reaches the GNSS/INS estimators' options; the default is theirs (90 s).
  const auto bound = [](const std::string& yaml) {
    const ppp_ros::NodeConfig c = ppp_ros::bindNodeConfig(YAML::Load(yaml), "test", "ekf");
    return ppp_ros::insOptions(c.ros, ppp_ros::parameterExtrinsics(c.ros.imu)).gap_bridge_max_s;
  };
  EXPECT_EQ(bound("ros: {estimator: ekf_ins}"), ppp::InsEkfOptions{}.gap_bridge_max_s);
  EXPECT_EQ(bound("ros: {estimator: ekf_ins}"), 90.0);
  EXPECT_EQ(bound("ros: {estimator: ekf_ins, imu: {gap_bridge_max_s: 6}}"), 6.0);
  EXPECT_EQ(bound("ros: {estimator: ekf_ins, imu: {gap_bridge_max_s: 0}}"), 0.0);
  EXPECT_THROW(bound("ros: {estimator: ekf_ins, imu: {gap_bridge_max_s: -1}}"), ppp::ConfigError);
  EXPECT_THROW(bound("ros: {estimator: ekf_ins, imu: {gap_bridge_max_s: 3600}}"), ppp::ConfigError);
}

TEST(NodeImuOptions, ProcessNoiseAdaptationOnByDefaultAndSwitchedOffByItsKey) {
  // ros.imu.process_noise_adaptation reaches both GNSS/INS estimators' options; the default
  // is the estimators' own (on).
  const auto adaptation = [](const std::string& yaml) {
    const ppp_ros::NodeConfig c = ppp_ros::bindNodeConfig(YAML::Load(yaml), "test", "ekf");
    return ppp_ros::insOptions(c.ros, ppp_ros::parameterExtrinsics(c.ros.imu)).process_noise_adaptation.enabled;
  };
  EXPECT_TRUE(adaptation("ros: {estimator: ekf_ins}"));
  EXPECT_EQ(adaptation("ros: {estimator: ekf_ins}"), ppp::InsEkfOptions{}.process_noise_adaptation.enabled);
  EXPECT_FALSE(adaptation("ros: {estimator: ekf_ins, imu: {process_noise_adaptation: false}}"));
  EXPECT_TRUE(adaptation("ros: {estimator: ekf_ins, imu: {process_noise_adaptation: true}}"));
  EXPECT_THROW(adaptation("ros: {estimator: ekf_ins, imu: {process_noise_adaptation: sometimes}}"), ppp::ConfigError);
}

TEST(NodeImuOptions, AlignInMotionLeavesAttitudeAndHeadingToTheEstimator) {
  // As ppp_solve without --imu-heading: neither attitude nor heading given; the course's speed threshold set.
  const ppp_ros::NodeConfig c = ppp_ros::bindNodeConfig(
      YAML::Load("ros: {estimator: ekf_ins, imu: {rotation_rpy_deg: [180, 0, 0], initial_attitude: align_in_motion,"
                 " initial_rpy_deg: [5, 0, 90], heading_speed_mps: 2.5}}"),
      "test", "ekf");
  ASSERT_EQ(c.ros.imu.initial_attitude, ppp_ros::RosImuOptions::StartAttitude::AlignInMotion);
  EXPECT_EQ(ppp_ros::startAttitudeName(c.ros.imu.initial_attitude), "align_in_motion");
  const ppp::InsEkfOptions ins = ppp_ros::insOptions(c.ros, ppp_ros::parameterExtrinsics(c.ros.imu));
  EXPECT_FALSE(ins.initial_rotation_ecef_body.has_value());
  EXPECT_FALSE(ins.initial_rotation_ned_body.has_value());
  EXPECT_FALSE(ins.initial_heading_rad.has_value());
  EXPECT_EQ(ins.heading_alignment.min_horizontal_speed_mps, 2.5);
  EXPECT_TRUE(ins.validate().empty()) << ins.validate();
  // The default speed is the estimators' (ppp_solve --heading-speed's default).
  const ppp_ros::NodeConfig d = ppp_ros::bindNodeConfig(
      YAML::Load("ros: {estimator: smoother_ins, imu: {initial_attitude: align_in_motion}}"), "test", "smoother");
  EXPECT_EQ(ppp_ros::insOptions(d.ros, ppp_ros::parameterExtrinsics(d.ros.imu)).heading_alignment.min_horizontal_speed_mps,
            ppp::InsEkfOptions{}.heading_alignment.min_horizontal_speed_mps);

  // An unknown value or a speed out of range: refused, naming the key.
  const auto refusal = [](const std::string& yaml) {
    try {
      ppp_ros::bindNodeConfig(YAML::Load(yaml), "test", "ekf");
    } catch (const ppp::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string unknown = refusal("ros: {estimator: ekf_ins, imu: {initial_attitude: align_on_the_move}}");
  EXPECT_NE(unknown.find("ros.imu.initial_attitude"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("align_on_the_move"), std::string::npos) << unknown;
  const std::string slow = refusal("ros: {estimator: ekf_ins, imu: {initial_attitude: align_in_motion, heading_speed_mps: 0}}");
  EXPECT_NE(slow.find("ros.imu.heading_speed_mps"), std::string::npos) << slow;

  // The course sets the heading of the filter's body, whose axes are base_link's turned forward-right-down
  // whatever the IMU's mounting: an IMU turned in base_link is accepted as well.
  ppp_ros::RosNodeOptions turned = c.ros;
  turned.imu.rotation_rpy_deg = Eigen::Vector3d(180.0, 0.0, 90.0);
  const ppp::InsEkfOptions t = ppp_ros::insOptions(turned, ppp_ros::parameterExtrinsics(turned.imu));
  EXPECT_FALSE(t.initial_rotation_ned_body || t.initial_rotation_ecef_body || t.initial_heading_rad);
}

TEST(NodeImuOptions, RpyInDegreesIsTheCoreEulerRotationInRadians) {
  // The parameters' [roll, pitch, yaw] [deg] compose as ppp::rotationNedBody [rad]: Rz Ry Rx.
  const Eigen::Matrix3d r = ppp_ros::rotationFromRpyDeg(Eigen::Vector3d(30.0, -20.0, 120.0));
  EXPECT_LT((r - ppp::rotationNedBody(M_PI / 6.0, -M_PI / 9.0, 2.0 * M_PI / 3.0)).norm(), 1e-15);
  // A yaw of 90 deg turns x into y.
  EXPECT_LT((ppp_ros::rotationFromRpyDeg(Eigen::Vector3d(0.0, 0.0, 90.0)) * Eigen::Vector3d::UnitX() -
             Eigen::Vector3d::UnitY()).norm(), 1e-15);
}

TEST(NodeImuInput, ScreensNamesTopicFieldAndStampAndHandsReadingsPerEpoch) {
  ppp_ros::RosNodeOptions o;
  Warnings w;
  NodeImuInput in(o, w.sink());
  std::size_t released = 0;
  const Eigen::Matrix3d same = Eigen::Matrix3d::Identity();  // an IMU whose axes are the body's
  EXPECT_FALSE(in.progress().newest_reading);
  // Arriving 50 s (ROS time) after their stamps' offset from t0.
  for (int k = 0; k < 100; ++k) released += in.receive(restMessage(0.01 * k), std::nullopt, same, 50.0 + 0.01 * k).size();
  EXPECT_EQ(released, 100u);  // the first 50 held until the units are decided, then all
  EXPECT_EQ(in.counters().used, 100u);
  // The newest accepted reading and its arrival: what held GNSS epochs wait on (imu_epoch_hold.h).
  ASSERT_TRUE(in.progress().newest_reading && in.progress().newest_arrival_s);
  EXPECT_NEAR(*in.progress().newest_reading - (kT0 + 0.99), 0.0, 1e-9);  // through the stamp (ns)
  EXPECT_DOUBLE_EQ(*in.progress().newest_arrival_s, 50.99);
  // A duplicate stamp and a field marked "not given": refused, named, counted (the progress unchanged).
  in.receive(restMessage(0.99), std::nullopt, Eigen::Matrix3d::Identity(), 51.0);
  sensor_msgs::Imu none = restMessage(1.0);
  none.angular_velocity_covariance[0] = -1.0;
  EXPECT_TRUE(in.receive(none, std::nullopt, Eigen::Matrix3d::Identity(), 51.01).empty());
  EXPECT_DOUBLE_EQ(*in.progress().newest_arrival_s, 50.99);
  EXPECT_EQ(in.counters().rejected, 2u);
  EXPECT_TRUE(w.any("topic imu/data, field header.stamp, stamp ")) << (w.lines.empty() ? "" : w.lines[0]);
  EXPECT_TRUE(w.any("duplicate time"));
  EXPECT_TRUE(w.any("field angular_velocity"));
  EXPECT_NE(in.problemSummary().find("1 duplicate time"), std::string::npos) << in.problemSummary();
  // Missing extrinsics: not used, counted, named.
  EXPECT_TRUE(in.receive(restMessage(1.01), std::nullopt, std::nullopt, 51.02).empty());
  EXPECT_TRUE(w.any("IMU extrinsics missing"));
  EXPECT_EQ(in.counters().rejected, 3u);
  // The epoch at t0 + 0.5 takes the readings up to it; the rest waits.
  const std::vector<ppp::ImuSample> epoch = in.takeUpTo(kT0 + 0.5);
  ASSERT_EQ(epoch.size(), 51u);
  EXPECT_EQ(in.lastTaken()->time - (kT0 + 0.5), 0.0);
  EXPECT_EQ(in.pending().size(), 49u);
  // The newest reading taken by an epoch too is still the newest; a reset forgets it.
  EXPECT_EQ(in.takeUpTo(kT0 + 2.0).size(), 49u);
  EXPECT_NEAR(*in.progress().newest_reading - (kT0 + 0.99), 0.0, 1e-9);  // through the stamp (ns)
  EXPECT_DOUBLE_EQ(*in.progress().newest_arrival_s, 50.99);
  in.reset();
  EXPECT_FALSE(in.progress().newest_reading);
  EXPECT_FALSE(in.progress().newest_arrival_s);
}

TEST(NodeImuInput, TimeBaseFarFromGnssRefusedButAGnssOutageLeavesTheReadingsAlone) {
  ppp_ros::RosNodeOptions o;
  Warnings w;
  NodeImuInput in(o, w.sink());
  // Readings 20 s past the newest GNSS epoch (an outage): only the first after each epoch is
  // compared, and it is near; the rest are not compared at all.
  const ppp::GnssTime epoch = kT0;
  for (int k = 0; k < 2000; ++k) in.receive(restMessage(0.01 * k), epoch, Eigen::Matrix3d::Identity(), 0.01 * k);
  EXPECT_EQ(in.screen().count(ppp::ImuInputProblem::FarFromGnssTime), 0u);
  EXPECT_EQ(in.counters().used, 2000u);
  // A stream on another time base (100 s off): refused from the first reading after the epoch on.
  NodeImuInput far(o, w.sink());
  std::size_t used = 0;
  for (int k = 0; k < 100; ++k)
    used += far.receive(restMessage(100.0 + 0.01 * k), epoch, Eigen::Matrix3d::Identity(), 0.01 * k).size();
  EXPECT_EQ(used, 0u);
  EXPECT_EQ(far.screen().count(ppp::ImuInputProblem::FarFromGnssTime), 100u);
  EXPECT_EQ(far.counters().rejected, 100u);
  EXPECT_TRUE(w.any("far from the GNSS time"));
}

// ---- GNSS epochs waiting for the IMU (imu_epoch_hold.h) ----
// Times: data times from kT0 (GPST), arrivals in ROS seconds from 100.0; ros.imu.max_wait_s 0.1.

using ppp_ros::ImuWaitOutcome;
constexpr double kMaxWait_s = 0.1;
constexpr double kReady_s = 100.0;  // the epoch at kT0 + 1 becomes ready (ROS time)

/// A call to the hold at ROS time `ros_s` with the ROS clock running (steady time alike).
ppp_ros::HoldClock at(double ros_s) { return {ros_s, ros_s}; }

/// The IMU input's progress (NodeImuInput::progress) after a reading at kT0 + `newest_dt_s`
/// accepted at `arrival_s`.
void accept(ppp_ros::ImuProgress& imu, double newest_dt_s, double arrival_s) {
  imu.newest_reading = kT0 + newest_dt_s;
  imu.newest_arrival_s = arrival_s;
}

TEST(ImuEpochHold, AnEpochWaitsUntilAReadingAtOrAfterItsTimeAndTheOrderHolds) {
  ppp_ros::ImuEpochHold<int> hold(kMaxWait_s);
  ppp_ros::ImuProgress imu;
  // The IMU 30 ms behind the GNSS epoch at kT0 + 1 when it becomes ready.
  accept(imu, 0.97, kReady_s - 0.001);
  hold.hold(1, kT0 + 1.0, at(kReady_s));
  hold.hold(2, kT0 + 1.05, at(kReady_s));  // the next epoch (20 Hz), ready with it (both waited for corrections)
  EXPECT_FALSE(hold.release(at(kReady_s), imu));
  ASSERT_TRUE(hold.deadline_s());
  EXPECT_DOUBLE_EQ(*hold.deadline_s(), kReady_s + kMaxWait_s);
  // A reading 10 ms before it: still waiting (the readings up to it may still come).
  accept(imu, 0.99, kReady_s + 0.02);
  EXPECT_FALSE(hold.release(at(kReady_s + 0.02), imu));
  // The reading at its time: it goes on at once, not at the deadline; the next one stays.
  accept(imu, 1.0, kReady_s + 0.03);
  const auto first = hold.release(at(kReady_s + 0.03), imu);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->epoch, 1);
  EXPECT_EQ(first->decision.outcome, ImuWaitOutcome::Covered);
  ASSERT_TRUE(first->decision.imu_lag_s);
  EXPECT_EQ(*first->decision.imu_lag_s, 0.0);
  EXPECT_NEAR(first->waited_s, 0.03, 1e-9);
  EXPECT_FALSE(hold.release(at(kReady_s + 0.03), imu));
  EXPECT_EQ(hold.size(), 1u);
  // A reading after the second epoch's time releases it too (at or after: an 80 Hz IMU need not hit it).
  for (int k = 1; k <= 4; ++k) accept(imu, 1.0034 + 0.0125 * k, kReady_s + 0.03 + 0.0125 * k);
  const auto second = hold.release(at(kReady_s + 0.08), imu);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->epoch, 2);
  EXPECT_EQ(second->decision.outcome, ImuWaitOutcome::Covered);
  EXPECT_TRUE(hold.empty());
  EXPECT_FALSE(hold.deadline_s());
  EXPECT_EQ(hold.counters().held, 2u);
  EXPECT_EQ(hold.counters().covered, 2u);
  EXPECT_EQ(hold.counters().waited_out, 0u);
  EXPECT_NEAR(hold.counters().longest_wait_s, 0.08, 1e-9);
}

TEST(ImuEpochHold, AnEpochCoveredWhenReadyGoesOnAtOnceUncounted) {
  ppp_ros::ImuEpochHold<int> hold(kMaxWait_s);
  ppp_ros::ImuProgress imu;
  accept(imu, 1.01, kReady_s - 0.001);  // the IMU ahead of the GNSS epoch (the usual case)
  hold.hold(7, kT0 + 1.0, at(kReady_s));
  const auto r = hold.release(at(kReady_s), imu);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->decision.outcome, ImuWaitOutcome::Covered);
  EXPECT_NEAR(*r->decision.imu_lag_s, -0.01, 1e-9);
  EXPECT_EQ(r->waited_s, 0.0);
  EXPECT_EQ(hold.counters().held, 0u);
  EXPECT_EQ(hold.counters().covered, 0u);
}

TEST(ImuEpochHold, AfterMaxWaitTheEpochGoesOnWithTheImuLagCountedAndNamed) {
  ppp_ros::ImuEpochHold<int> hold(kMaxWait_s);
  ppp_ros::ImuProgress imu;
  // Readings up to 35 ms before the epoch, still arriving during the wait (the IMU lags, it is not silent).
  accept(imu, 0.95, kReady_s - 0.01);
  hold.hold(1, kT0 + 1.0, at(kReady_s));
  EXPECT_FALSE(hold.release(at(kReady_s), imu));
  accept(imu, 0.965, kReady_s + 0.05);
  EXPECT_FALSE(hold.release(at(kReady_s + 0.05), imu));
  EXPECT_FALSE(hold.release(at(kReady_s + 0.0999), imu));
  const auto r = hold.release(at(kReady_s + kMaxWait_s + 1e-3), imu);  // just after the deadline (the node's timer)
  ASSERT_TRUE(r);
  EXPECT_EQ(r->decision.outcome, ImuWaitOutcome::WaitedOut);
  ASSERT_TRUE(r->decision.imu_lag_s);
  EXPECT_NEAR(*r->decision.imu_lag_s, 0.035, 1e-9);
  EXPECT_NEAR(r->waited_s, kMaxWait_s + 1e-3, 1e-9);
  EXPECT_EQ(hold.counters().held, 1u);
  EXPECT_EQ(hold.counters().waited_out, 1u);
  EXPECT_EQ(hold.counters().covered, 0u);
  EXPECT_NEAR(hold.counters().largest_lag_s, 0.035, 1e-9);
  const std::string text = ppp_ros::imuWaitedOutText(r->time, r->waited_s, r->decision, "/imu/data", kMaxWait_s);
  EXPECT_NE(text.find("waiting 0.101 s for the IMU on /imu/data (ros.imu.max_wait_s 0.1)"), std::string::npos) << text;
  EXPECT_NE(text.find("newest reading 35.0 ms before the epoch"), std::string::npos) << text;
}

TEST(ImuEpochHold, ASilentOrStoppedImuHoldsNoEpoch) {
  // No reading yet (before the first message, extrinsics missing): at once.
  ppp_ros::ImuEpochHold<int> hold(kMaxWait_s);
  ppp_ros::ImuProgress imu;
  hold.hold(1, kT0 + 1.0, at(kReady_s));
  auto r = hold.release(at(kReady_s), imu);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->decision.outcome, ImuWaitOutcome::ImuSilent);
  EXPECT_FALSE(r->decision.imu_lag_s);
  // The newest reading arrived longer than max_wait_s before the epoch became ready: the IMU
  // stopped, the epoch goes on at once (the estimator finds the readings missing, the node
  // falls back to GNSS only) instead of every epoch waiting out.
  accept(imu, 0.6, kReady_s - 0.4);
  hold.hold(2, kT0 + 1.0, at(kReady_s));
  r = hold.release(at(kReady_s), imu);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->decision.outcome, ImuWaitOutcome::ImuSilent);
  EXPECT_NEAR(*r->decision.imu_lag_s, 0.4, 1e-9);
  // A reading within max_wait_s before: not silent (it waits, then goes on at the deadline).
  accept(imu, 0.61, kReady_s + 1.0 - 0.05);
  hold.hold(3, kT0 + 2.0, at(kReady_s + 1.0));
  EXPECT_FALSE(hold.release(at(kReady_s + 1.0), imu));
  EXPECT_EQ(hold.release(at(kReady_s + 1.0 + kMaxWait_s + 1e-3), imu)->decision.outcome, ImuWaitOutcome::WaitedOut);
  // After an estimator reset the IMU input starts afresh: silent until a reading is accepted.
  imu = {};
  hold.hold(4, kT0 + 3.0, at(kReady_s + 2.0));
  EXPECT_EQ(hold.release(at(kReady_s + 2.0), imu)->decision.outcome, ImuWaitOutcome::ImuSilent);
  EXPECT_EQ(hold.counters().silent, 3u);
  EXPECT_EQ(hold.counters().waited_out, 1u);
}

TEST(ImuEpochHold, NoWaitWithMaxWaitZeroOrAnEstimatorWithoutReadings) {
  ppp_ros::ImuEpochHold<int> never(0.0);
  ppp_ros::ImuProgress imu;
  accept(imu, 0.5, kReady_s - 0.001);
  never.hold(1, kT0 + 1.0, at(kReady_s));
  EXPECT_EQ(never.release(at(kReady_s), imu)->decision.outcome, ImuWaitOutcome::NoWait);
  // The estimator fell back to GNSS only (`waiting` false): every held epoch goes on, in order.
  ppp_ros::ImuEpochHold<int> hold(kMaxWait_s);
  accept(imu, 0.99, kReady_s - 0.001);
  hold.hold(1, kT0 + 1.0, at(kReady_s));
  hold.hold(2, kT0 + 1.25, at(kReady_s));
  EXPECT_FALSE(hold.release(at(kReady_s), imu));
  const auto a = hold.release(at(kReady_s + 0.01), imu, false), b = hold.release(at(kReady_s + 0.01), imu, false);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->epoch, 1);
  EXPECT_EQ(b->epoch, 2);
  EXPECT_EQ(a->decision.outcome, ImuWaitOutcome::NoWait);
  EXPECT_EQ(hold.counters().waited_out, 0u);
  EXPECT_EQ(hold.counters().silent, 0u);
}

TEST(ImuEpochHold, AStoppedRosClockReleasesTheEpochsByTheSteadyClock) {
  // Under /use_sim_time the bag's /clock stops (the player ended or paused) with the epoch at
  // kT0 + 1 held, the IMU 30 ms behind it: no ROS timer fires, no reading comes, ROS time stays
  // at kReady_s + 0.01. Steady time runs from 500 s. The epoch goes on, counted and named as
  // waited out with the clock stopped, and so does the one that became ready after the stop.
  ppp_ros::ImuEpochHold<int> hold(kMaxWait_s);
  ppp_ros::ImuProgress imu;
  accept(imu, 0.97, kReady_s - 0.001);
  const double stopped_s = kReady_s + 0.01;
  hold.hold(1, kT0 + 1.0, {kReady_s, 500.0});
  EXPECT_FALSE(hold.release({stopped_s, 500.01}, imu));  // the clock's last move
  EXPECT_FALSE(hold.release({stopped_s, 500.05}, imu));
  hold.hold(2, kT0 + 1.05, {stopped_s, 500.2});  // ready after the stop (a GNSS message in flight)
  std::vector<ppp_ros::ReleasedEpoch<int>> released;
  for (double steady_s = 500.06; steady_s < 510.0 && !hold.empty(); steady_s += kMaxWait_s)  // the steady timer
    while (auto r = hold.release({stopped_s, steady_s}, imu)) released.push_back(*r);
  ASSERT_EQ(released.size(), 2u);
  EXPECT_EQ(released[0].epoch, 1);
  EXPECT_EQ(released[1].epoch, 2);
  for (const auto& r : released) {
    EXPECT_EQ(r.decision.outcome, ImuWaitOutcome::ClockStopped);
    EXPECT_GE(r.waited_s, kMaxWait_s);  // steady time
  }
  EXPECT_EQ(hold.counters().held, 2u);
  EXPECT_EQ(hold.counters().waited_out, 2u);
  EXPECT_EQ(hold.counters().clock_stopped, 2u);
  EXPECT_NEAR(hold.counters().largest_lag_s, 0.08, 1e-9);  // the second epoch's
  const std::string text =
      ppp_ros::imuWaitedOutText(released[0].time, released[0].waited_s, released[0].decision, "/imu/data", kMaxWait_s);
  EXPECT_NE(text.find("s of steady time, the ROS clock standing still"), std::string::npos) << text;
  EXPECT_EQ(ppp_ros::imuWaitOutcomeText(ImuWaitOutcome::ClockStopped), "clock stopped");

  // A running clock, however slow (a replay at a quarter of the rate), keeps the wait in ROS time:
  // steady time past max_wait_s does not release the epoch, its ROS deadline does.
  ppp_ros::ImuEpochHold<int> slow(kMaxWait_s);
  slow.hold(1, kT0 + 1.0, {kReady_s, 600.0});
  for (int k = 1; k <= 39; ++k) EXPECT_FALSE(slow.release({kReady_s + 0.0025 * k, 600.0 + 0.01 * k}, imu)) << k;
  const auto r = slow.release({kReady_s + kMaxWait_s + 1e-3, 600.404}, imu);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->decision.outcome, ImuWaitOutcome::WaitedOut);
  EXPECT_EQ(slow.counters().clock_stopped, 0u);
}

TEST(ImuEpochHold, AnImuDriverSlowerThanTheReceiverGivesTheEpochAllItsReadings) {
  // A 100 Hz IMU whose readings arrive 30 ms after their time, a GNSS epoch at kT0 + 1 ready
  // 10 ms after its time (ROS time = 100 s + data time from kT0). Taken when it is ready, the
  // epoch would get the readings up to kT0 + 0.98: the last 20 ms of its interval missing, and
  // those readings, older than the epoch, would come after it. Held, it goes on at the arrival
  // of the reading at its time with every reading up to it.
  ppp_ros::RosNodeOptions o;
  Warnings w;
  NodeImuInput in(o, w.sink()), unheld(o, w.sink());
  ppp_ros::ImuEpochHold<int> hold(o.imu.max_wait_s);
  const double imu_latency_s = 0.03, gnss_latency_s = 0.01;
  std::optional<std::vector<ppp::ImuSample>> taken, taken_when_ready;
  for (int k = 0; k <= 110; ++k) {  // IMU arrivals in time order, the epoch's readiness among them
    const double arrival_s = kReady_s + 0.01 * k + imu_latency_s;
    const double epoch_ready_s = kReady_s + 1.0 + gnss_latency_s;
    if (!taken_when_ready && arrival_s > epoch_ready_s) {
      taken_when_ready = unheld.takeUpTo(kT0 + 1.0);
      hold.hold(1, kT0 + 1.0, at(epoch_ready_s));
      EXPECT_FALSE(hold.release(at(epoch_ready_s), in.progress()));
    }
    for (NodeImuInput* input : {&in, &unheld})
      input->receive(restMessage(0.01 * k), kT0, Eigen::Matrix3d::Identity(), arrival_s);
    if (auto r = hold.release(at(arrival_s), in.progress())) {
      EXPECT_EQ(r->decision.outcome, ImuWaitOutcome::Covered);
      EXPECT_NEAR(r->waited_s, imu_latency_s - gnss_latency_s, 1e-9);
      taken = in.takeUpTo(r->time);
    }
  }
  ASSERT_TRUE(taken && taken_when_ready);
  ASSERT_FALSE(taken->empty());
  EXPECT_EQ(taken->size(), 101u);  // kT0 + 0.00 ... kT0 + 1.00
  EXPECT_EQ(taken->back().time - (kT0 + 1.0), 0.0);
  ASSERT_FALSE(taken_when_ready->empty());
  EXPECT_EQ(taken_when_ready->size(), 99u);
  EXPECT_NEAR(taken_when_ready->back().time - (kT0 + 1.0), -0.02, 1e-9);
  // The two readings that came late wait in the buffer for the next epoch, older than the one taken.
  EXPECT_NEAR(unheld.pending().front().time - (kT0 + 1.0), -0.01, 1e-9);
}

TEST(ImuEpochHold, MaxWaitFromRosImuDefaultAndRange) {
  // Default 0.1 s (config/ppp.yaml); [0, 1] s.
  EXPECT_EQ(ppp_ros::bindNodeConfig(YAML::Load("ros: {estimator: ekf_ins}"), "test", "ekf").ros.imu.max_wait_s, 0.1);
  EXPECT_EQ(
      ppp_ros::bindNodeConfig(YAML::Load("ros: {imu: {max_wait_s: 0.0}}"), "test", "ekf").ros.imu.max_wait_s, 0.0);
  EXPECT_THROW(ppp_ros::bindNodeConfig(YAML::Load("ros: {imu: {max_wait_s: 1.5}}"), "test", "ekf"), ppp::ConfigError);
  EXPECT_THROW(ppp_ros::bindNodeConfig(YAML::Load("ros: {imu: {max_wait_s: -0.1}}"), "test", "ekf"), ppp::ConfigError);
}

using ppp::test::movingState;

TEST(InsOdometry, MessageHasBaseLinkPoseInTheMapAndTwistInBaseLink) {
  // IMU x fwd, y right, z down, 1 m ahead of base_link (x fwd, y left, z up); level, heading north.
  ppp_ros::ImuExtrinsics e;
  e.translation_m = Eigen::Vector3d(1.0, 0.0, 0.0);
  e.rotation_base_imu = ppp_ros::rotationFromRpyDeg(Eigen::Vector3d(180.0, 0.0, 0.0));
  ppp_ros::InsState s = movingState(kT0);
  // The gyros read the Earth rate (the attitude fixed to the Earth): no turn of base_link.
  s.angular_rate_radps =
      s.nav.rotation_world_body.transpose() * Eigen::Vector3d(0.0, 0.0, ppp::kEarthRotationRate_radps);
  ppp_ros::OdometryFrame frame{"map", "base_link", s.nav.position_world_m,
                               ppp::rotationEcefNed(s.nav.position_world_m).transpose()};
  frame.enu_from_ecef = Eigen::Matrix3d();
  frame.enu_from_ecef << 0, 1, 0, 1, 0, 0, 0, 0, -1;  // ENU <- NED
  frame.enu_from_ecef = frame.enu_from_ecef * ppp::rotationEcefNed(s.nav.position_world_m).transpose();
  const nav_msgs::Odometry m = ppp_ros::insOdometryMessage(s, e, frame);
  EXPECT_EQ(m.header.frame_id, "map");
  EXPECT_EQ(m.child_frame_id, "base_link");
  // base_link is 1 m behind the IMU (south of the datum at the IMU): (0, -1, 0) in ENU.
  EXPECT_NEAR(m.pose.pose.position.x, 0.0, 1e-9);
  EXPECT_NEAR(m.pose.pose.position.y, -1.0, 1e-9);
  EXPECT_NEAR(m.pose.pose.position.z, 0.0, 1e-9);
  // Orientation: x north = yaw 90 deg about the map's z (REP-103).
  const Eigen::Quaterniond q(m.pose.pose.orientation.w, m.pose.pose.orientation.x, m.pose.pose.orientation.y,
                             m.pose.pose.orientation.z);
  EXPECT_LT((q.toRotationMatrix() - ppp_ros::rotationFromRpyDeg(Eigen::Vector3d(0.0, 0.0, 90.0))).norm(), 1e-9);
  // Twist in base_link: 10 m/s forward; the position and attitude covariances from the filter.
  EXPECT_NEAR(m.twist.twist.linear.x, 10.0, 1e-9);
  EXPECT_NEAR(m.twist.twist.linear.y, 0.0, 1e-9);
  EXPECT_NEAR(m.twist.twist.angular.z, 0.0, 1e-15);
  EXPECT_NEAR(m.pose.covariance[0], 1e-4, 1e-12);
  EXPECT_NEAR(m.pose.covariance[21], 1e-4, 1e-12);
  EXPECT_NEAR(m.twist.covariance[0], 1e-4, 1e-12);
  EXPECT_NEAR(ppp_ros::attitudeSigma_rad(s), 1e-2, 1e-12);
}

}  // namespace
