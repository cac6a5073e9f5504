// The node's outputs (ros/node_outputs.h) without a ROS master: status, NavSatFix,
// odometry, TF and paths built from epoch records; the smoothed outputs from a real
// smoother run on a simulated flight.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "node_test_messages.h"
#include "node_test_records.h"
#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/models/stream_bias_provider.h"
#include "ppp_bayes_tree/ros/node_outputs.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/types/frames.h"

namespace {

using node_test::day;
using node_test::equator;
using node_test::solvedRecord;
using ppp_ros::NodeOutputs;

/// Phase information from a provider (only its presence matters to the outputs).
struct WithPhaseBiases {
  ppp::StreamBiasProvider provider{900.0};
  ppp_ros::PhaseBiasChoice choice() const { return {&provider, "test phase biases"}; }
};

}  // namespace

TEST(NodeOutputs, NavSatFixStatusFollowsTheFixState) {
  // doc/ros_ambiguity_resolution.md "Outputs": float -> STATUS_FIX (0), fixed -> STATUS_GBAS_FIX (2).
  const Eigen::Matrix3d cov = Eigen::Vector3d(9e-4, 1e-4, 4e-4).asDiagonal();
  const ros::Time stamp(1778630382.0);
  const sensor_msgs::NavSatFix fixed =
      ppp_ros::navSatFix(equator(), cov, ppp_bayes_tree::PppStatus::FIX_FIXED, stamp, "gnss_antenna");
  const sensor_msgs::NavSatFix floating =
      ppp_ros::navSatFix(equator(), cov, ppp_bayes_tree::PppStatus::FIX_FLOAT, stamp, "gnss_antenna");
  EXPECT_EQ(fixed.status.status, sensor_msgs::NavSatStatus::STATUS_GBAS_FIX);
  EXPECT_EQ(fixed.status.status, 2);
  EXPECT_EQ(floating.status.status, sensor_msgs::NavSatStatus::STATUS_FIX);
  EXPECT_EQ(floating.status.status, 0);
  EXPECT_EQ(fixed.status.service, sensor_msgs::NavSatStatus::SERVICE_GPS);
  // REP-145: in the antenna's frame, ENU covariance. At (a, 0, 0): E = ECEF Y, N = Z, U = X.
  EXPECT_EQ(fixed.header.frame_id, "gnss_antenna");
  EXPECT_EQ(fixed.header.stamp, stamp);
  EXPECT_NEAR(fixed.latitude, 0.0, 1e-12);
  EXPECT_NEAR(fixed.longitude, 0.0, 1e-12);
  EXPECT_NEAR(fixed.altitude, 0.0, 1e-6);
  EXPECT_NEAR(fixed.position_covariance[0], 1e-4, 1e-12);  // east
  EXPECT_NEAR(fixed.position_covariance[4], 4e-4, 1e-12);  // north
  EXPECT_NEAR(fixed.position_covariance[8], 9e-4, 1e-12);  // up
  EXPECT_NEAR(fixed.position_covariance[1], 0.0, 1e-12);
  EXPECT_EQ(fixed.position_covariance_type, sensor_msgs::NavSatFix::COVARIANCE_TYPE_KNOWN);
}

TEST(NodeOutputs, SolutionStateFromTheSigmasAndThresholds) {
  ppp_ros::RosNodeOptions o;  // converged: horizontal <= 0.10 m and vertical <= 0.20 m
  using ppp_bayes_tree::PppStatus;
  EXPECT_EQ(ppp_ros::solutionState(true, {0.06, 0.08, 0.2}, o), PppStatus::CONVERGED);  // hypot = 0.10
  EXPECT_EQ(ppp_ros::solutionState(true, {0.06, 0.09, 0.2}, o), PppStatus::CONVERGING);
  EXPECT_EQ(ppp_ros::solutionState(true, {0.01, 0.01, 0.21}, o), PppStatus::CONVERGING);
  EXPECT_EQ(ppp_ros::solutionState(false, {0.01, 0.01, 0.01}, o), PppStatus::NO_SOLUTION);
  EXPECT_EQ(ppp_ros::solutionState(true, Eigen::Vector3d::Constant(std::nan("")), o), PppStatus::NO_SOLUTION);
  EXPECT_EQ(ppp_ros::solutionStateText(PppStatus::CONVERGED), "converged");
  EXPECT_EQ(ppp_ros::solutionStateText(PppStatus::NO_SOLUTION), "no_solution");
}

TEST(NodeOutputs, FixedEpochGivesTheStatusFixFieldsAndGbasFix) {
  NodeOutputs out(ppp_ros::RosNodeOptions{}, node_test::ignoreWarnings());
  WithPhaseBiases phase;
  out.setDatum(equator());
  ppp_bayes_tree::PppStatus counters;  // the inputs' counters
  counters.observations_lost = 3;
  // A float epoch first (time to first fix counts from the first solution), then fixed 10 s later.
  const ppp::PppEpochRecord first = solvedRecord(day(), equator(), false);
  const ppp_bayes_tree::PppStatus s0 = out.epochStatus(day(), first, counters, {}, phase.choice(), true);
  EXPECT_EQ(s0.fix_state, ppp_bayes_tree::PppStatus::FIX_FLOAT);
  EXPECT_EQ(s0.fix_state_text, "float");
  EXPECT_EQ(s0.float_reason, first.ambiguity_fix->text());
  EXPECT_EQ(s0.epochs_fixed, 0u);
  EXPECT_TRUE(std::isnan(s0.time_to_first_fix_s));

  const ppp::PppEpochRecord rec = solvedRecord(day() + 10.0, equator(), true);
  const ppp_bayes_tree::PppStatus s = out.epochStatus(day() + 10.0, rec, counters, {}, phase.choice(), true);
  EXPECT_EQ(s.fix_state, ppp_bayes_tree::PppStatus::FIX_FIXED);
  EXPECT_EQ(s.fix_state_text, "fixed");
  EXPECT_EQ(s.float_reason, "");
  EXPECT_TRUE(s.ambiguity_resolution_enabled);
  EXPECT_EQ(s.phase_bias_source, "test phase biases");
  EXPECT_EQ(s.ambiguities_fixed, 7u);
  EXPECT_EQ(s.wide_lanes_fixed, 9u);
  EXPECT_DOUBLE_EQ(s.ratio, 4.2);
  EXPECT_EQ(s.epochs_fixed, 1u);
  EXPECT_DOUBLE_EQ(s.time_to_first_fix_s, 10.0);
  EXPECT_EQ(s.first_fix_stamp, ppp_ros::utcStamp(day() + 10.0));
  // The rest of the status from the record: ENU sigmas, state, counts, counters carried.
  EXPECT_NEAR(s.sigma_east_m, 0.01, 1e-12);
  EXPECT_NEAR(s.sigma_north_m, 0.02, 1e-12);
  EXPECT_NEAR(s.sigma_up_m, 0.03, 1e-12);
  EXPECT_EQ(s.solution_state, ppp_bayes_tree::PppStatus::CONVERGED);
  EXPECT_NEAR(s.zwd_sigma_m, 0.02, 1e-12);
  EXPECT_EQ(s.satellites_used, 8u);
  EXPECT_EQ(s.used.front(), "G01");
  EXPECT_EQ(s0.epochs_processed, 1u);  // the outputs count the epochs whose status they build
  EXPECT_EQ(s.epochs_processed, 2u);
  EXPECT_EQ(out.counters().epochs_processed, 2u);
  EXPECT_EQ(s.observations_lost, 3u);  // the inputs' counters carried
  EXPECT_EQ(s.header.stamp, ppp_ros::utcStamp(day() + 10.0));
  ASSERT_TRUE(out.lastStatus());
  EXPECT_EQ(out.lastStatus()->fix_state, ppp_bayes_tree::PppStatus::FIX_FIXED);
  // ...and its NavSatFix is GBAS_FIX.
  const ppp_ros::SolutionMessages m = out.solution(rec, s, std::nullopt);
  EXPECT_EQ(m.fix.status.status, sensor_msgs::NavSatStatus::STATUS_GBAS_FIX);
  // A reset starts the fix figures afresh.
  out.resetTrajectory();
  EXPECT_EQ(out.epochsFixed(), 0u);
  EXPECT_FALSE(out.firstFixed());
}

TEST(NodeOutputs, FloatReasonSaysWhyWithoutPhaseInformation) {
  NodeOutputs out(ppp_ros::RosNodeOptions{}, node_test::ignoreWarnings());
  out.setDatum(equator());
  const ppp::PppEpochRecord rec = solvedRecord(day(), equator(), false);
  const auto off = out.epochStatus(day(), rec, {}, {}, {nullptr, "ambiguity resolution off"}, false);
  EXPECT_EQ(off.float_reason, "ambiguity resolution off");
  const auto none = out.epochStatus(day() + 1.0, rec, {}, {}, {nullptr, "no phase biases from the stream yet"}, true);
  EXPECT_EQ(none.fix_state, ppp_bayes_tree::PppStatus::FIX_FLOAT);
  EXPECT_EQ(none.float_reason, "no phase biases from the stream yet");
  EXPECT_EQ(none.phase_bias_source, "");
  const auto empty = out.emptyEpochStatus(day() + 2.0, {}, 12.5, {nullptr, "x"}, true);
  EXPECT_EQ(empty.fix_state, ppp_bayes_tree::PppStatus::FIX_NO_SOLUTION);
  EXPECT_EQ(empty.solution_state, ppp_bayes_tree::PppStatus::NO_SOLUTION);
  EXPECT_EQ(empty.reason, "empty epoch");
  EXPECT_DOUBLE_EQ(empty.corrections_stale_s, 12.5);
}

TEST(NodeOutputs, LateCorrectionsAreCountedInTheStatusAndWarned) {
  std::vector<std::string> warned;
  NodeOutputs out(ppp_ros::RosNodeOptions{}, [&](const std::string& c, const std::string&) { warned.push_back(c); });
  out.setDatum(equator());
  ppp::PppEpochRecord rec = solvedRecord(day(), equator(), false);
  ppp::EpochRejection r;
  r.satellite = {ppp::GnssSystem::GPS, 30};
  r.stage = ppp::RejectionStage::Model;
  r.reason = ppp::RejectionReason::NoClock;
  rec.rejected.push_back(r);
  // The outputs count the late satellites themselves: nothing is fed back through the inputs' counters.
  const ppp_bayes_tree::PppStatus counters;
  const auto s = out.epochStatus(day(), rec, counters, {}, {}, false);
  EXPECT_EQ(s.satellites_without_corrections, 1u);
  EXPECT_EQ(s.corrections_late, 1u);
  EXPECT_EQ(s.satellites_rejected, 1u);
  EXPECT_EQ(warned, std::vector<std::string>{"late"});
  const auto s1 = out.epochStatus(day() + 1.0, rec, counters, {}, {}, false);
  EXPECT_EQ(s1.satellites_without_corrections, 1u);
  EXPECT_EQ(s1.corrections_late, 2u);
  EXPECT_EQ(out.counters().corrections_late, 2u);
  // An empty epoch carries the counts, and is not counted as processed.
  const auto empty = out.emptyEpochStatus(day() + 2.0, counters, 0.0, {nullptr, "x"}, false);
  EXPECT_EQ(empty.corrections_late, 2u);
  EXPECT_EQ(empty.epochs_processed, 2u);
  // An epoch the node does not publish (not after the last one) adds to the inputs' out-of-order drops.
  ppp_bayes_tree::PppStatus dropped;
  dropped.epochs_out_of_order = 1;
  out.countNotPublished();
  EXPECT_EQ(out.emptyEpochStatus(day() + 3.0, dropped, 0.0, {nullptr, "x"}, false).epochs_out_of_order, 2u);
}

TEST(NodeOutputs, SolutionGoesToOdometryPathAndTf) {
  ppp_ros::RosNodeOptions o;
  NodeOutputs out(o, node_test::ignoreWarnings());
  EXPECT_FALSE(out.filteredPath());
  // The map datum at the first fix: earth -> map rotates map east onto ECEF +Y there.
  const geometry_msgs::TransformStamped datum = out.setDatum(equator());
  EXPECT_EQ(datum.header.frame_id, "earth");
  EXPECT_EQ(datum.child_frame_id, "map");
  const auto& q = datum.transform.rotation;
  const Eigen::Vector3d east_in_ecef = Eigen::Quaterniond(q.w, q.x, q.y, q.z) * Eigen::Vector3d::UnitX();
  EXPECT_NEAR((east_in_ecef - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-12);

  ppp_bayes_tree::PppStatus s;
  s.header.stamp = ppp_ros::utcStamp(day());
  out.solution(solvedRecord(day(), equator(), false), s, std::nullopt);
  // One metre east (ECEF +Y at the datum).
  s.header.stamp = ppp_ros::utcStamp(day() + 1.0);
  const ppp_ros::SolutionMessages m =
      out.solution(solvedRecord(day() + 1.0, equator() + Eigen::Vector3d(0, 1, 0), false), s, std::nullopt);
  EXPECT_EQ(m.odometry.header.frame_id, "map");
  EXPECT_EQ(m.odometry.child_frame_id, "base_link");
  EXPECT_NEAR(m.odometry.pose.pose.position.x, 1.0, 1e-9);
  EXPECT_NEAR(m.odometry.pose.pose.position.y, 0.0, 1e-9);
  EXPECT_NEAR(m.odometry.pose.covariance[0], 1e-4, 1e-12);  // east variance
  EXPECT_DOUBLE_EQ(m.odometry.pose.covariance[21], 1e6);    // orientation not estimated (no attitude)
  ASSERT_TRUE(m.tf);
  EXPECT_EQ(m.tf->header.frame_id, "map");
  EXPECT_EQ(m.tf->child_frame_id, "base_link");
  EXPECT_NEAR(m.tf->transform.translation.x, 1.0, 1e-9);
  const nav_msgs::Path* path = out.filteredPath();
  ASSERT_TRUE(path);
  EXPECT_EQ(path->poses.size(), 2u);
  EXPECT_EQ(path->header.stamp, ppp_ros::utcStamp(day() + 1.0));
  // Another node publishes odom -> base_link (0.5 m east): the TF is map -> odom.
  geometry_msgs::TransformStamped odom_base;
  odom_base.transform.translation.x = 0.5;
  odom_base.transform.rotation.w = 1.0;
  s.header.stamp = ppp_ros::utcStamp(day() + 2.0);
  const ppp_ros::SolutionMessages m2 =
      out.solution(solvedRecord(day() + 2.0, equator() + Eigen::Vector3d(0, 1, 0), false), s, odom_base);
  ASSERT_TRUE(m2.tf);
  EXPECT_EQ(m2.tf->child_frame_id, "odom");
  EXPECT_NEAR(m2.tf->transform.translation.x, 0.5, 1e-9);
  // A new datum clears the filtered path.
  out.clearPathsForDatum();
  EXPECT_FALSE(out.filteredPath());
}

TEST(NodeOutputs, AttitudeMovesBaseLinkByTheLeverArm) {
  ppp_ros::RosNodeOptions o;
  o.attitude_topic = "imu";
  o.antenna_lever_arm_m = Eigen::Vector3d(0.0, 0.0, 1.0);  // antenna 1 m above base_link
  NodeOutputs out(o, node_test::ignoreWarnings());
  out.setDatum(equator());
  sensor_msgs::Imu imu;
  imu.header.stamp = ppp_ros::utcStamp(day());
  imu.orientation.w = 1.0;
  imu.orientation_covariance[0] = -1.0;  // REP-145: no orientation
  out.receiveAttitude(imu);
  EXPECT_EQ(out.attitudeCounters().received, 1u);
  EXPECT_EQ(out.attitudeCounters().invalid, 1u);
  imu.orientation_covariance = {0.01, 0, 0, 0, 0.02, 0, 0, 0, 0.03};
  out.receiveAttitude(imu);
  EXPECT_EQ(out.attitudeCounters().invalid, 1u);
  ppp_bayes_tree::PppStatus s;
  s.header.stamp = ppp_ros::utcStamp(day());
  const auto m = out.solution(solvedRecord(day(), equator(), false), s, std::nullopt);
  EXPECT_NEAR(m.odometry.pose.pose.position.z, -1.0, 1e-9);  // base_link = antenna - R * lever arm
  EXPECT_DOUBLE_EQ(m.odometry.pose.covariance[21], 0.01);   // the attitude's orientation covariance
  // An epoch 10 s away from the only attitude (ros.attitude.max_age_s 0.5): at the antenna, counted.
  s.header.stamp = ppp_ros::utcStamp(day() + 10.0);
  const auto far = out.solution(solvedRecord(day() + 10.0, equator(), false), s, std::nullopt);
  EXPECT_NEAR(far.odometry.pose.pose.position.z, 0.0, 1e-9);
  EXPECT_EQ(out.attitudeCounters().epochs_without, 1u);
}

TEST(NodeOutputs, SmoothedUpdateRewritesThePath) {
  // The node's chain on a simulated flight: PppEpochProcessor + the full smoother, config/ppp.yaml.
  ppp::SimulationConfig sc;
  sc.duration_s = 40.0;
  const ppp::SimulatedFlight f = ppp::simulateFlight(sc, 7);
  const ppp::PppConfig c = ppp::flightPppConfig(ppp::loadPppConfig("config/ppp.yaml"), f);
  const std::unique_ptr<ppp::PppEstimator> estimator_made = ppp::makeEstimator("smoother", c);
  ppp::PppEstimator& estimator = *estimator_made;
  ppp::PppEpochProcessor processor(f.header, c, f.products, {}, nullptr, nullptr);
  estimator.setApproximatePosition(*f.header.approx_position_ecef_m);
  const ppp::SmoothedTrajectoryProvider& smoother = *estimator.smoothing();

  ppp_ros::RosNodeOptions o;
  NodeOutputs out(o, node_test::ignoreWarnings());
  std::vector<ros::Time> smoothed_stamps;
  std::size_t solved = 0;
  Eigen::Vector3d datum = Eigen::Vector3d::Zero();
  auto run = [&](std::size_t from, std::size_t to) {
    for (std::size_t k = from; k < to; ++k) {
      const ppp::PppEpochRecord rec = processor.process(f.epochs[k], estimator);
      if (!ppp_ros::solvedEpoch(rec)) continue;
      ++solved;
      if (!out.hasDatum()) {
        datum = *rec.solution.position_ecef_m;
        out.setDatum(datum);
      }
      if (auto odom = out.smoothedOdometry(smoother, f.epochs[k].time)) smoothed_stamps.push_back(odom->header.stamp);
      out.markSmoothedStale();
    }
  };
  EXPECT_FALSE(out.smoothedPath(smoother));  // nothing processed: nothing to publish
  run(0, 20);
  ASSERT_GT(solved, 10u);
  const std::optional<nav_msgs::Path> first = out.smoothedPath(smoother);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->poses.size(), solved);
  EXPECT_EQ(first->header.stamp, first->poses.back().header.stamp);
  EXPECT_FALSE(out.smoothedPath(smoother));  // no new epoch: not re-read
  run(20, f.epochs.size());
  const std::optional<nav_msgs::Path> second = out.smoothedPath(smoother);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->poses.size(), solved);
  EXPECT_EQ(out.smoothedPathPoses(), solved);
  // The later data re-estimated the early states: the first pose moved, to the smoother's value.
  const auto& p1 = first->poses.front().pose.position;
  const auto& p2 = second->poses.front().pose.position;
  EXPECT_EQ(first->poses.front().header.stamp, second->poses.front().header.stamp);
  EXPECT_GT(std::abs(p1.x - p2.x) + std::abs(p1.y - p2.y) + std::abs(p1.z - p2.z), 0.0);
  const std::vector<ppp::SmoothedEpoch> trajectory = smoother.smoothedTrajectory(false);
  ASSERT_EQ(trajectory.size(), solved);
  const ppp::Geodetic g = ppp::ecefToGeodetic(datum);
  const Eigen::Vector3d enu =
      ppp::rotationEnuFromEcef(g.latitude_rad, g.longitude_rad) * (trajectory.front().state.position_ecef_m - datum);
  EXPECT_NEAR(p2.x, enu.x(), 1e-9);
  EXPECT_NEAR(p2.y, enu.y(), 1e-9);
  EXPECT_NEAR(p2.z, enu.z(), 1e-9);
  // Full smoother, delay 0: the newest state after each epoch, each once, in time order.
  EXPECT_EQ(smoothed_stamps.size(), solved);
  for (std::size_t k = 1; k < smoothed_stamps.size(); ++k) EXPECT_GT(smoothed_stamps[k], smoothed_stamps[k - 1]);
}
