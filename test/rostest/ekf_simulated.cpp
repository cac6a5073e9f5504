// rostest: ppp_ekf_node on a simulated loiter flight (5 min at 1 Hz, 30 s
// corrections) made into a bag by this test and played at 20x real time; then
// each robustness case publishes its bad input and checks that the node goes on.
#include <cmath>
#include <filesystem>

#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "ppp_bayes_tree/ppp/epoch_estimator.h"
#include "ppp_bayes_tree/ppp/ppp_epoch_processor.h"
#include "ppp_bayes_tree/ros/bag_writer.h"
#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/ros/ppp_node.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/types/frames.h"
#include "rostest/rostest_support.h"

namespace {

using ppp_ros::test::NodeOutputs;

struct Fixture {
  ros::NodeHandle nh;
  ros::Publisher obs, corr;
  NodeOutputs out;
  ppp::SimulatedFlight flight;
  std::string bag;
  std::size_t played = 0;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener;
  bool ok = false;
};
Fixture* g = nullptr;

ppp::SimulationConfig flightConfig() {
  ppp::SimulationConfig c;
  c.profile = ppp::FlightProfile::Loiter;
  c.duration_s = 300.0;
  c.rate_hz = 1.0;
  return c;
}

// Final 3D error bound [m], met by the offline pipeline on the same flight (checked below).
constexpr double kFinalErrorBound_m = 1.5;  // 5 min of float PPP: ppp_solve's chain gives 1.10 m (seed 7)

}  // namespace

TEST(EkfNodeSimulated, PlaysTheBagAt20xWithoutDropsAndConverges) {
  ASSERT_TRUE(g->ok) << "setup failed";
  ASSERT_TRUE(ppp_ros::test::waitForSubscribers(g->obs, g->corr, 30.0)) << "ppp_ekf_node did not subscribe";
  const ros::WallTime start = ros::WallTime::now();
  g->played = ppp_ros::test::playBag(g->bag, g->obs, g->corr, 20.0);
  ASSERT_EQ(g->played, g->flight.epochs.size());
  ASSERT_TRUE(g->out.waitForStatuses(g->played, 30.0)) << "only " << g->out.statusCount() << " of " << g->played;
  const double wall = (ros::WallTime::now() - start).toSec();
  const auto last = g->out.lastStatus();
  // Every epoch processed: no drops at 20x.
  EXPECT_EQ(last.epochs_processed, g->played);
  EXPECT_EQ(last.epochs_duplicate + last.epochs_out_of_order + last.estimator_resets, 0u);
  EXPECT_EQ(last.corrections_late, 0u);
  // Update time reported.
  double max_update = 0.0, sum_update = 0.0;
  bool converged = false;
  {
    std::lock_guard<std::mutex> l(g->out.mutex);
    for (const auto& s : g->out.statuses) {
      max_update = std::max(max_update, s.update_time_s);
      sum_update += s.update_time_s;
      converged |= s.solution_state == ppp_bayes_tree::PppStatus::CONVERGED;
    }
  }
  EXPECT_GT(max_update, 0.0);
  std::printf("[ figures  ] %zu epochs at 20x in %.1f s wall; update time mean %.2f ms, max %.2f ms\n", g->played, wall,
              1e3 * sum_update / g->played, 1e3 * max_update);
  EXPECT_TRUE(converged) << "status never reached converged (thresholds "
                         << last.converged_horizontal_sigma_m << " / " << last.converged_vertical_sigma_m << " m)";
  EXPECT_EQ(last.solution_state, ppp_bayes_tree::PppStatus::CONVERGED);
}

TEST(EkfNodeSimulated, FinalErrorBelowTheBoundTheOfflineSolverMeets) {
  ASSERT_TRUE(g->ok);
  std::vector<sensor_msgs::NavSatFix> fixes;
  {
    std::lock_guard<std::mutex> l(g->out.mutex);
    fixes = g->out.fixes;
  }
  ASSERT_FALSE(fixes.empty());
  const auto& f = fixes.back();
  const Eigen::Vector3d node = ppp::geodeticToEcef({f.latitude * ppp::kDegToRad, f.longitude * ppp::kDegToRad, f.altitude});
  const Eigen::Vector3d truth = g->flight.truth.back().trajectory.position_ecef_m;
  // NavSatFix covariance finite and positive on the diagonal.
  for (const auto& fx : fixes) {
    for (double c : fx.position_covariance) ASSERT_TRUE(std::isfinite(c));
    ASSERT_GT(fx.position_covariance[0], 0.0);
    ASSERT_EQ(fx.position_covariance_type, sensor_msgs::NavSatFix::COVARIANCE_TYPE_KNOWN);
  }
  // The offline chain (PppEpochProcessor + EkfEstimator, as ppp_solve) on the same flight and config.
  const ppp_ros::NodeConfig config = ppp_ros::loadNodeConfig(ros::NodeHandle("/ppp_ekf_node"));
  ppp::EkfEstimator ekf(config.ppp);
  ppp::PppEpochProcessor offline(g->flight.header, config.ppp, g->flight.products, {}, nullptr, nullptr);
  ekf.setApproximatePosition(*g->flight.header.approx_position_ecef_m);
  std::optional<Eigen::Vector3d> last;
  for (const auto& e : g->flight.epochs) {
    const auto rec = offline.process(e, ekf);
    if (rec.solution.position_ecef_m) last = rec.solution.position_ecef_m;
  }
  ASSERT_TRUE(last.has_value());
  const double offline_error = (*last - truth).norm(), node_error = (node - truth).norm();
  std::printf("[ figures  ] final 3D error: node %.3f m, offline %.3f m (bound %.2f m)\n", node_error, offline_error,
              kFinalErrorBound_m);
  EXPECT_LT(offline_error, kFinalErrorBound_m);
  EXPECT_LT(node_error, kFinalErrorBound_m);
}

TEST(EkfNodeSimulated, TfMapToBaseLinkResolvesAndDiagnosticsAreNotError) {
  ASSERT_TRUE(g->ok);
  std::string err;
  EXPECT_TRUE(g->tf_buffer->canTransform("map", "base_link", ros::Time(0), ros::Duration(3.0), &err)) << err;
  EXPECT_TRUE(g->tf_buffer->canTransform("earth", "base_link", ros::Time(0), ros::Duration(3.0), &err)) << err;
  ros::WallDuration(1.5).sleep();  // one more diagnostics period
  std::lock_guard<std::mutex> l(g->out.mutex);
  ASSERT_FALSE(g->out.worst_diagnostic.empty()) << "no diagnostics received";
  bool solution_seen = false;
  for (const auto& [name, level] : g->out.worst_diagnostic) {
    EXPECT_LT(level, diagnostic_msgs::DiagnosticStatus::ERROR) << name;
    solution_seen |= name.find("solution") != std::string::npos;
  }
  EXPECT_TRUE(solution_seen);
}

// ---------------------------------------------------------------- robustness
namespace {

ppp_bayes_tree::GnssObservations epochMessage(std::size_t k, double shift_s = 0.0) {
  ppp::ObsEpoch e = g->flight.epochs.at(k);
  e.time = e.time + shift_s;
  return ppp_ros::toMessage(e, g->flight.header);
}

/// Publishes and waits until the node reports (a status after the message), returns the last status.
ppp_bayes_tree::PppStatus publishAndSettle(const ppp_bayes_tree::GnssObservations& m, bool expect_status) {
  const std::size_t before = g->out.statusCount();
  g->obs.publish(m);
  if (expect_status) g->out.waitForStatuses(before + 1, 10.0);
  else ros::WallDuration(0.5).sleep();
  return g->out.lastStatus();
}

/// The next regular epoch after the flight (corrections cover it: 60 s margin).
std::size_t g_next_shift = 1;
ppp_bayes_tree::PppStatus publishNextGoodEpoch() {
  // Epochs beyond the flight are the last epoch shifted by whole seconds (the
  // geometry hardly changes; the point is that the node processes them).
  const auto m = epochMessage(g->flight.epochs.size() - 1, static_cast<double>(g_next_shift++));
  return publishAndSettle(m, true);
}

}  // namespace

TEST(EkfNodeSimulated, DuplicateAndOutOfOrderEpochsAreDroppedAndCounted) {
  ASSERT_TRUE(g->ok);
  const auto before = g->out.lastStatus();
  const auto s1 = publishNextGoodEpoch();
  EXPECT_EQ(s1.epochs_processed, before.epochs_processed + 1);
  // The same epoch again, then an older one (within the reset threshold).
  publishAndSettle(epochMessage(g->flight.epochs.size() - 1, static_cast<double>(g_next_shift - 1)), false);
  publishAndSettle(epochMessage(g->flight.epochs.size() - 5), false);
  const auto s2 = publishNextGoodEpoch();
  EXPECT_EQ(s2.epochs_duplicate, before.epochs_duplicate + 1);
  EXPECT_EQ(s2.epochs_out_of_order, before.epochs_out_of_order + 1);
  EXPECT_EQ(s2.epochs_processed, s1.epochs_processed + 1) << "the node must go on";
}

TEST(EkfNodeSimulated, EmptyEpochAndInvalidValuesAreHandled) {
  ASSERT_TRUE(g->ok);
  const auto before = g->out.lastStatus();
  auto empty = epochMessage(g->flight.epochs.size() - 1, static_cast<double>(g_next_shift++));
  empty.satellites.clear();
  const auto s_empty = publishAndSettle(empty, true);
  EXPECT_EQ(s_empty.empty_epochs, before.empty_epochs + 1);
  EXPECT_EQ(s_empty.reason, "empty epoch");
  // NaN is "absent"; +inf and an absurd pseudorange are excluded and counted.
  auto bad = epochMessage(g->flight.epochs.size() - 1, static_cast<double>(g_next_shift++));
  bad.satellites.at(0).signals.at(0).pseudorange_m = std::numeric_limits<double>::infinity();
  bad.satellites.at(1).signals.at(0).pseudorange_m = -5.0;
  bad.satellites.at(2).signals.at(0).carrier_phase_cycles = std::numeric_limits<double>::quiet_NaN();
  bad.satellites.push_back(bad.satellites.at(3));
  bad.satellites.back().satellite = "Q77";  // unknown system letter
  const auto s_bad = publishAndSettle(bad, true);
  EXPECT_GE(s_bad.observations_invalid, before.observations_invalid + 3);
  EXPECT_EQ(s_bad.epochs_processed, before.epochs_processed + 1);
  const auto s_next = publishNextGoodEpoch();
  EXPECT_EQ(s_next.epochs_processed, s_bad.epochs_processed + 1);
}

TEST(EkfNodeSimulated, CorrectionsForUnknownSatellitesAndAbsurdValuesAreHandled) {
  ASSERT_TRUE(g->ok);
  const auto before = g->out.lastStatus();
  ppp_bayes_tree::PreciseCorrections c;
  const ppp::GnssTime t = g->flight.epochs.back().time + 3600.0;  // far ahead: does not disturb the buffer's rules
  const auto mt = ppp_ros::toMessageTime(t);
  c.header.stamp = ppp_ros::utcStamp(t);
  c.week = mt.week;
  c.seconds_of_week = mt.seconds_of_week;
  c.time_system = "GPS";
  ppp_bayes_tree::SatelliteCorrection x;
  x.satellite = "X99";
  x.position_ecef_m.x = 2.6e7;
  c.satellites.push_back(x);
  c.week = mt.week;
  ppp_bayes_tree::PreciseCorrections bad_time = c;
  bad_time.seconds_of_week = std::numeric_limits<double>::quiet_NaN();
  g->corr.publish(bad_time);
  // The same unknown satellite at a valid time: counted, the empty batch ignored.
  // (at the epoch of a batch already held: a duplicate, so the buffer is unchanged)
  const ppp::GnssTime held = ppp::GnssTime::fromGpsSeconds(g->flight.epochs.front().time.wholeSeconds() / 30 * 30);
  c.seconds_of_week = ppp_ros::toMessageTime(held).seconds_of_week;
  g->corr.publish(c);
  ros::WallDuration(0.5).sleep();
  const auto s = publishNextGoodEpoch();
  EXPECT_EQ(s.corrections_unknown_satellites, before.corrections_unknown_satellites + 1);
  EXPECT_EQ(s.epochs_processed, before.epochs_processed + 1) << "the node must go on";
}

TEST(EkfNodeSimulated, TimeGoingBackwardsBeyondTheThresholdResetsTheEstimator) {
  ASSERT_TRUE(g->ok);
  const auto before = g->out.lastStatus();
  // A rosbag loop: the first epoch of the flight again (5 min back > 60 s threshold).
  const auto s = publishAndSettle(epochMessage(0), true);
  EXPECT_EQ(s.estimator_resets, before.estimator_resets + 1);
  EXPECT_EQ(s.epochs_processed, before.epochs_processed + 1);
  const auto s2 = publishAndSettle(epochMessage(1), true);
  EXPECT_EQ(s2.epochs_processed, s.epochs_processed + 1);
  EXPECT_NE(s2.solution_state, ppp_bayes_tree::PppStatus::NO_SOLUTION) << s2.reason;
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rostest_ekf_simulated");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  Fixture f;
  g = &f;
  f.obs = f.nh.advertise<ppp_bayes_tree::GnssObservations>("gnss/observations", 5000);
  f.corr = f.nh.advertise<ppp_bayes_tree::PreciseCorrections>("gnss/corrections", 500);
  f.out.subscribe(f.nh);
  f.tf_buffer = std::make_unique<tf2_ros::Buffer>();
  f.tf_listener = std::make_unique<tf2_ros::TransformListener>(*f.tf_buffer);
  try {
    f.flight = ppp::simulateFlight(flightConfig(), 7);
    f.bag = (std::filesystem::temp_directory_path() / "ppp_rostest_simulated.bag").string();
    std::size_t k = 0;
    const auto summary = ppp_ros::writeReplayBag(f.bag, f.flight.header, [&](ppp::ObsEpoch& e) {
      if (k >= f.flight.epochs.size()) return false;
      e = f.flight.epochs[k++];
      return true;
    }, f.flight.products, ppp_ros::BagWriteOptions{});
    f.ok = summary.epochs == f.flight.epochs.size() && summary.batches > 10;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "cannot make the bag: " << e.what();
  }
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
