#pragma once
// Helpers of the rostests: play a bag made by the test at a speed factor
// (header stamps give the data time), and collect what a PPP node publishes.
// SimulatedNodeTest and compareWithPppSolveOnZim2 hold the checks shared by the
// EKF and smoother node tests (ekf_*.cpp, smoother_*.cpp).
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/NavSatFix.h>

#include "ppp_bayes_tree/GnssObservations.h"
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>

#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "ppp_dataset.h"
#include "ppp_bayes_tree/PppStatus.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_epoch_processor.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/ros/bag_writer.h"
#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/ros/ppp_node.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/PreciseCorrections.h"
#include <Eigen/Core>

namespace ppp_ros::test {

/// Hands the bag's observation and correction messages to the callbacks at `speed` x real
/// time (bag time spacing / speed); returns the observation messages.
inline std::size_t playBagTo(const std::string& path, double speed,
                             const std::function<void(const ppp_bayes_tree::GnssObservations&)>& on_observation,
                             const std::function<void(const ppp_bayes_tree::PreciseCorrections&)>& on_corrections) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag);
  std::size_t epochs = 0;
  const ros::WallTime start = ros::WallTime::now();
  ros::Time first;
  for (const rosbag::MessageInstance& m : view) {
    if (first.isZero()) first = m.getTime();
    // Wall time at which this message is due.
    const ros::WallTime due = start + ros::WallDuration((m.getTime() - first).toSec() / speed);
    const ros::WallDuration wait = due - ros::WallTime::now();
    if (wait > ros::WallDuration(0)) wait.sleep();
    if (auto o = m.instantiate<ppp_bayes_tree::GnssObservations>()) {
      on_observation(*o);
      ++epochs;
    } else if (auto c = m.instantiate<ppp_bayes_tree::PreciseCorrections>()) {
      on_corrections(*c);
    }
  }
  return epochs;
}

/// Publishes the bag's two topics at `speed` x real time (bag time spacing / speed);
/// `before_observation` (optional) runs just before each observation message.
inline std::size_t playBag(const std::string& path, ros::Publisher& obs, ros::Publisher& corr, double speed,
                           const std::function<void(const ppp_bayes_tree::GnssObservations&)>& before_observation = {}) {
  return playBagTo(
      path, speed,
      [&](const ppp_bayes_tree::GnssObservations& o) {
        if (before_observation) before_observation(o);
        obs.publish(o);
      },
      [&](const ppp_bayes_tree::PreciseCorrections& c) { corr.publish(c); });
}

/// Everything the node publishes, collected under a mutex.
struct NodeOutputs {
  std::mutex mutex;
  std::vector<nav_msgs::Odometry> odometry;
  std::vector<sensor_msgs::NavSatFix> fixes;
  std::vector<ppp_bayes_tree::PppStatus> statuses;
  std::map<std::string, std::uint8_t> worst_diagnostic;  // status name -> worst level seen
  std::vector<nav_msgs::Odometry> smoothed_odometry;      // smoother node only
  nav_msgs::Path smoothed_path;                           // the last one received
  std::size_t smoothed_paths = 0;
  ros::Subscriber subs[6];

  void subscribe(ros::NodeHandle& nh, const std::string& prefix = "") {
    subs[0] = nh.subscribe<nav_msgs::Odometry>(prefix + "ppp/odometry/filtered", 10000, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      odometry.push_back(*m);
    });
    subs[1] = nh.subscribe<sensor_msgs::NavSatFix>(prefix + "ppp/fix", 10000, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      fixes.push_back(*m);
    });
    subs[2] = nh.subscribe<ppp_bayes_tree::PppStatus>(prefix + "ppp/status", 10000, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      statuses.push_back(*m);
    });
    subs[4] = nh.subscribe<nav_msgs::Odometry>(prefix + "ppp/odometry/smoothed", 10000, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      smoothed_odometry.push_back(*m);
    });
    subs[5] = nh.subscribe<nav_msgs::Path>(prefix + "ppp/path/smoothed", 10, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      smoothed_path = *m;
      ++smoothed_paths;
    });
    subs[3] = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 1000, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      for (const auto& s : m->status) {
        auto& w = worst_diagnostic[s.name];
        w = std::max<std::uint8_t>(w, s.level);
      }
    });
  }
  std::size_t statusCount() {
    std::lock_guard<std::mutex> l(mutex);
    return statuses.size();
  }
  /// Waits (wall time) until `n` statuses arrived or the timeout.
  bool waitForStatuses(std::size_t n, double timeout_s) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while (ros::WallTime::now() < end) {
      if (statusCount() >= n) return true;
      ros::WallDuration(0.05).sleep();
    }
    return statusCount() >= n;
  }
  ppp_bayes_tree::PppStatus lastStatus() {
    std::lock_guard<std::mutex> l(mutex);
    return statuses.empty() ? ppp_bayes_tree::PppStatus() : statuses.back();
  }
};

/// Whether any node advertises `topic` (resolved name) on the master.
inline bool topicAdvertised(const std::string& topic) {
  ros::master::V_TopicInfo topics;
  ros::master::getTopics(topics);
  for (const auto& t : topics)
    if (t.name == topic) return true;
  return false;
}

inline Eigen::Vector3d position(const geometry_msgs::Pose& p) { return {p.position.x, p.position.y, p.position.z}; }

/// Waits until the node subscribes to both inputs.
inline bool waitForSubscribers(ros::Publisher& a, ros::Publisher& b, double timeout_s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::WallTime::now() < end) {
    if (a.getNumSubscribers() > 0 && b.getNumSubscribers() > 0) return true;
    ros::WallDuration(0.05).sleep();
  }
  return false;
}

inline Eigen::Vector3d fixEcef(const sensor_msgs::NavSatFix& f) {
  return ppp::geodeticToEcef({f.latitude * ppp::kDegToRad, f.longitude * ppp::kDegToRad, f.altitude});
}

inline Eigen::Vector3d translation(const geometry_msgs::TransformStamped& t) {
  return {t.transform.translation.x, t.transform.translation.y, t.transform.translation.z};
}

// ------------------------------------------------------------ simulated flight
/// A PPP node (name, estimator) on a simulated loiter flight (5 min at 1 Hz, 30 s
/// corrections, seed 7) made into a bag by the test and played at 20x real time;
/// then each robustness case publishes its bad input and checks that the node goes on.
struct SimulatedNodeTest {
  std::string node, estimator;
  ros::NodeHandle nh;
  ros::Publisher obs, corr;
  NodeOutputs out;
  ppp::SimulatedFlight flight;
  std::string bag;
  std::size_t played = 0;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener;
  std::function<void(const ppp_bayes_tree::GnssObservations&)> before_observation;  // e.g. publish an attitude
  std::size_t next_shift = 1;  // epochs beyond the flight: the last one shifted by whole seconds
  bool ok = false;

  /// Final 3D error bound [m], met by the offline chain on the same flight (checkFinalError).
  static constexpr double kFinalErrorBound_m = 1.5;  // 5 min of float PPP: ppp_solve's EKF chain 1.10 m (seed 7)

  SimulatedNodeTest(std::string node_name, std::string estimator_name)
      : node(std::move(node_name)), estimator(std::move(estimator_name)) {
    obs = nh.advertise<ppp_bayes_tree::GnssObservations>("gnss/observations", 5000);
    corr = nh.advertise<ppp_bayes_tree::PreciseCorrections>("gnss/corrections", 500);
    out.subscribe(nh);
    tf_buffer = std::make_unique<tf2_ros::Buffer>();
    tf_listener = std::make_unique<tf2_ros::TransformListener>(*tf_buffer);
    try {
      ppp::SimulationConfig c;
      c.profile = ppp::FlightProfile::Loiter;
      c.duration_s = 300.0;
      c.rate_hz = 1.0;
      flight = ppp::simulateFlight(c, 7);
      bag = (std::filesystem::temp_directory_path() / ("ppp_rostest_simulated_" + estimator + ".bag")).string();
      std::size_t k = 0;
      const auto summary = writeReplayBag(bag, flight.header, [&](ppp::ObsEpoch& e) {
        if (k >= flight.epochs.size()) return false;
        e = flight.epochs[k++];
        return true;
      }, flight.products, BagWriteOptions{});
      ok = summary.epochs == flight.epochs.size() && summary.batches > 10;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "cannot make the bag: " << e.what();
    }
  }

  /// Every epoch processed at 20x without drops, update time reported, converged.
  void checkReplayAt20x() {
    ASSERT_TRUE(ok) << "setup failed";
    ASSERT_TRUE(waitForSubscribers(obs, corr, 30.0)) << node << " did not subscribe";
    const ros::WallTime start = ros::WallTime::now();
    played = playBag(bag, obs, corr, 20.0, before_observation);
    ASSERT_EQ(played, flight.epochs.size());
    ASSERT_TRUE(out.waitForStatuses(played, 30.0)) << "only " << out.statusCount() << " of " << played;
    const double wall = (ros::WallTime::now() - start).toSec();
    const auto last = out.lastStatus();
    EXPECT_EQ(last.estimator, estimator);
    EXPECT_EQ(last.epochs_processed, played);
    EXPECT_EQ(last.epochs_duplicate + last.epochs_out_of_order + last.estimator_resets, 0u);
    EXPECT_EQ(last.epochs_time_jump_dropped + last.observations_lost + last.corrections_lost, 0u);
    EXPECT_EQ(last.corrections_late, 0u);
    std::vector<double> updates;
    bool converged = false;
    std::uint64_t reeliminated = 0;
    {
      std::lock_guard<std::mutex> l(out.mutex);
      for (const auto& s : out.statuses) {
        updates.push_back(s.update_time_s);
        converged |= s.solution_state == ppp_bayes_tree::PppStatus::CONVERGED;
        reeliminated += s.variables_reeliminated;
      }
    }
    std::sort(updates.begin(), updates.end());
    double sum = 0.0;
    for (double u : updates) sum += u;
    EXPECT_GT(updates.back(), 0.0);
    EXPECT_GT(reeliminated, 0u);
    std::printf("[ figures  ] %s: %zu epochs at 20x in %.1f s wall; update time mean %.2f ms, median %.2f ms, "
                "max %.2f ms; variables re-eliminated per epoch %.1f\n",
                node.c_str(), played, wall, 1e3 * sum / updates.size(), 1e3 * updates[updates.size() / 2],
                1e3 * updates.back(), static_cast<double>(reeliminated) / updates.size());
    EXPECT_TRUE(converged) << "status never reached converged (thresholds " << last.converged_horizontal_sigma_m
                           << " / " << last.converged_vertical_sigma_m << " m)";
    EXPECT_EQ(last.solution_state, ppp_bayes_tree::PppStatus::CONVERGED);
  }

  /// NavSatFix covariance finite; the final error below a bound the offline chain
  /// (PppEpochProcessor + the same estimator, as ppp_solve) meets on the same flight.
  void checkFinalError() {
    ASSERT_TRUE(ok);
    std::vector<sensor_msgs::NavSatFix> fixes;
    {
      std::lock_guard<std::mutex> l(out.mutex);
      fixes = out.fixes;
    }
    ASSERT_FALSE(fixes.empty());
    for (const auto& fx : fixes) {
      for (double c : fx.position_covariance) ASSERT_TRUE(std::isfinite(c));
      ASSERT_GT(fx.position_covariance[0], 0.0);
      ASSERT_EQ(fx.position_covariance_type, sensor_msgs::NavSatFix::COVARIANCE_TYPE_KNOWN);
    }
    const Eigen::Vector3d truth = flight.truth.back().trajectory.position_ecef_m;
    const NodeConfig config = loadNodeConfig(ros::NodeHandle("/" + node));
    std::string why;
    auto est = ppp::makeEstimator(estimator, config.ppp, &why);
    ASSERT_TRUE(est) << why;
    ppp::PppEpochProcessor offline(flight.header, config.ppp, flight.products, {}, nullptr, nullptr);
    est->setApproximatePosition(*flight.header.approx_position_ecef_m);
    std::optional<Eigen::Vector3d> last;
    for (const auto& e : flight.epochs) {
      const auto rec = offline.process(e, *est);
      if (rec.solution.position_ecef_m) last = rec.solution.position_ecef_m;
    }
    ASSERT_TRUE(last.has_value());
    const double offline_error = (*last - truth).norm(), node_error = (fixEcef(fixes.back()) - truth).norm();
    std::printf("[ figures  ] %s final 3D error: node %.3f m, offline %.3f m (bound %.2f m)\n", node.c_str(),
                node_error, offline_error, kFinalErrorBound_m);
    EXPECT_LT(offline_error, kFinalErrorBound_m);
    EXPECT_LT(node_error, kFinalErrorBound_m);
  }

  /// map -> base_link and earth -> gnss_antenna resolve; `frame_at_fix` (gnss_antenna
  /// with an attitude, base_link without: ros/lever_arm.h) is at the last fix (1 mm);
  /// diagnostics never ERROR. Returns gnss_antenna - base_link in the map frame.
  Eigen::Vector3d checkTfAndDiagnostics(const std::string& frame_at_fix) {
    std::string err;
    EXPECT_TRUE(tf_buffer->canTransform("map", "base_link", ros::Time(0), ros::Duration(3.0), &err)) << err;
    EXPECT_TRUE(tf_buffer->canTransform("earth", "gnss_antenna", ros::Time(0), ros::Duration(3.0), &err)) << err;
    Eigen::Vector3d offset = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    try {
      const Eigen::Vector3d at_fix = translation(tf_buffer->lookupTransform("earth", frame_at_fix, ros::Time(0)));
      sensor_msgs::NavSatFix last_fix;
      {
        std::lock_guard<std::mutex> l(out.mutex);
        if (!out.fixes.empty()) last_fix = out.fixes.back();
      }
      EXPECT_LT((at_fix - fixEcef(last_fix)).norm(), 1e-3) << frame_at_fix << " is not at the fix";
      offset = translation(tf_buffer->lookupTransform("map", "gnss_antenna", ros::Time(0))) -
               translation(tf_buffer->lookupTransform("map", "base_link", ros::Time(0)));
    } catch (const std::exception& e) {
      ADD_FAILURE() << e.what();
    }
    ros::WallDuration(1.5).sleep();  // one more diagnostics period
    std::lock_guard<std::mutex> l(out.mutex);
    EXPECT_FALSE(out.worst_diagnostic.empty()) << "no diagnostics received";
    bool solution_seen = false;
    for (const auto& [name, level] : out.worst_diagnostic) {
      EXPECT_LT(level, diagnostic_msgs::DiagnosticStatus::ERROR) << name;
      solution_seen |= name.find("solution") != std::string::npos;
    }
    EXPECT_TRUE(solution_seen);
    return offset;
  }

  // -------------------------------------------------------------- robustness
  ppp_bayes_tree::GnssObservations epochMessage(std::size_t k, double shift_s = 0.0) const {
    ppp::ObsEpoch e = flight.epochs.at(k);
    e.time = e.time + shift_s;
    return toMessage(e, flight.header);
  }
  /// Publishes and waits until the node reports (a status after the message), returns the last status.
  ppp_bayes_tree::PppStatus publishAndSettle(const ppp_bayes_tree::GnssObservations& m, bool expect_status) {
    const std::size_t before = out.statusCount();
    if (before_observation) before_observation(m);
    obs.publish(m);
    if (expect_status) out.waitForStatuses(before + 1, 10.0);
    else ros::WallDuration(0.5).sleep();
    return out.lastStatus();
  }
  /// The next regular epoch after the flight (the geometry hardly changes; the point
  /// is that the node processes it; corrections cover it: 60 s margin).
  ppp_bayes_tree::PppStatus publishNextGoodEpoch() {
    return publishAndSettle(epochMessage(flight.epochs.size() - 1, static_cast<double>(next_shift++)), true);
  }

  void checkDuplicateAndOutOfOrderDropped() {
    ASSERT_TRUE(ok);
    const auto before = out.lastStatus();
    const auto s1 = publishNextGoodEpoch();
    EXPECT_EQ(s1.epochs_processed, before.epochs_processed + 1);
    // The same epoch again, then an older one (within the reset threshold).
    publishAndSettle(epochMessage(flight.epochs.size() - 1, static_cast<double>(next_shift - 1)), false);
    publishAndSettle(epochMessage(flight.epochs.size() - 5), false);
    const auto s2 = publishNextGoodEpoch();
    EXPECT_EQ(s2.epochs_duplicate, before.epochs_duplicate + 1);
    EXPECT_EQ(s2.epochs_out_of_order, before.epochs_out_of_order + 1);
    EXPECT_EQ(s2.epochs_processed, s1.epochs_processed + 1) << "the node must go on";
  }

  void checkEmptyEpochAndInvalidValues() {
    ASSERT_TRUE(ok);
    const auto before = out.lastStatus();
    auto empty = epochMessage(flight.epochs.size() - 1, static_cast<double>(next_shift++));
    empty.satellites.clear();
    const auto s_empty = publishAndSettle(empty, true);
    EXPECT_EQ(s_empty.empty_epochs, before.empty_epochs + 1);
    EXPECT_EQ(s_empty.reason, "empty epoch");
    // NaN is "absent"; +inf and an absurd pseudorange are excluded and counted.
    auto bad = epochMessage(flight.epochs.size() - 1, static_cast<double>(next_shift++));
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

  void checkCorrectionsForUnknownSatellites() {
    ASSERT_TRUE(ok);
    const auto before = out.lastStatus();
    ppp_bayes_tree::PreciseCorrections c;
    const ppp::GnssTime t = flight.epochs.back().time + 3600.0;  // far ahead: does not disturb the buffer's rules
    const auto mt = toMessageTime(t);
    c.header.stamp = utcStamp(t);
    c.week = mt.week;
    c.seconds_of_week = mt.seconds_of_week;
    c.time_system = "GPS";
    ppp_bayes_tree::SatelliteCorrection x;
    x.satellite = "X99";
    x.position_ecef_m.x = 2.6e7;
    c.satellites.push_back(x);
    ppp_bayes_tree::PreciseCorrections bad_time = c;
    bad_time.seconds_of_week = std::numeric_limits<double>::quiet_NaN();
    corr.publish(bad_time);
    // The same unknown satellite at a valid time: counted, the empty batch ignored
    // (at the epoch of a batch already held: a duplicate, so the buffer is unchanged).
    const ppp::GnssTime held = ppp::GnssTime::fromGpsSeconds(flight.epochs.front().time.wholeSeconds() / 30 * 30);
    c.seconds_of_week = toMessageTime(held).seconds_of_week;
    corr.publish(c);
    ros::WallDuration(0.5).sleep();
    const auto s = publishNextGoodEpoch();
    EXPECT_EQ(s.corrections_unknown_satellites, before.corrections_unknown_satellites + 1);
    EXPECT_EQ(s.epochs_processed, before.epochs_processed + 1) << "the node must go on";
  }

  void checkTimeBackwardsResets() {
    ASSERT_TRUE(ok);
    const auto before = out.lastStatus();
    // A rosbag loop: the flight from its first epoch again (5 min back > 60 s threshold).
    // The jump is held until ros.input.time_jump_confirm_epochs (3) consecutive epochs
    // confirm it; then the estimator resets and the held epochs are processed.
    publishAndSettle(epochMessage(0), false);
    publishAndSettle(epochMessage(1), false);
    EXPECT_EQ(out.lastStatus().estimator_resets, before.estimator_resets) << "reset before the jump was confirmed";
    const std::size_t n = out.statusCount();
    publishAndSettle(epochMessage(2), true);
    out.waitForStatuses(n + 3, 10.0);
    const auto s = out.lastStatus();
    EXPECT_EQ(s.estimator_resets, before.estimator_resets + 1);
    EXPECT_EQ(s.epochs_processed, before.epochs_processed + 3) << "the held epochs are processed after the reset";
    EXPECT_EQ(s.epochs_time_jump_dropped, before.epochs_time_jump_dropped);
    const auto s2 = publishAndSettle(epochMessage(3), true);
    EXPECT_EQ(s2.epochs_processed, s.epochs_processed + 1);
    EXPECT_NE(s2.solution_state, ppp_bayes_tree::PppStatus::NO_SOLUTION) << s2.reason;
  }
};

// ------------------------------------------------------------------- ZIM2
/// A node on ZIM2 (first `epochs` epochs at 30 s), bag made with the ppp_to_bag code
/// and played at 20x: its fixes match ppp_solve's pipeline with the same estimator and
/// the node's own parameters epoch by epoch to 1 mm; the final error is below
/// `bound_m`, which ppp_solve meets too; TF resolves, diagnostics not ERROR.
/// `out` collects what the node published (for further checks by the caller).
inline void compareWithPppSolveOnZim2(const std::string& node, const std::string& estimator, std::size_t epochs,
                                      double bound_m, NodeOutputs& out) {
  ros::NodeHandle nh;
  ros::Publisher obs = nh.advertise<ppp_bayes_tree::GnssObservations>("gnss/observations", 5000);
  ros::Publisher corr = nh.advertise<ppp_bayes_tree::PreciseCorrections>("gnss/corrections", 500);
  out.subscribe(nh);
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);
  const ppp::test::PppDataset d = ppp::test::zim2Dataset();

  const std::string bag = (std::filesystem::temp_directory_path() / ("ppp_rostest_zim2_" + estimator + ".bag")).string();
  {
    const ppp::PreciseEphemeris products = ppp::PreciseEphemeris::load(d.sp3, d.clk);
    auto reader = ppp::RinexObsReader::open(d.obs);
    BagWriteOptions o;
    o.max_epochs = epochs;
    const auto s = writeReplayBag(bag, reader.header(), [&](ppp::ObsEpoch& e) { return reader.next(e); }, products, o);
    ASSERT_EQ(s.epochs, epochs);
  }
  // ppp_solve's pipeline with the node's own parameters and estimator.
  const NodeConfig config = loadNodeConfig(ros::NodeHandle("/" + node));
  const ppp::PppInputFiles files =
      ppp::preciseInputFiles(d.obs, d.sp3, d.clk, config.ros.atx, config.ros.bias);
  ppp::PppPipeline pipeline(files, config.ppp);
  std::string why;
  auto est = ppp::makeEstimator(estimator, config.ppp, &why);
  ASSERT_TRUE(est) << why;
  std::map<ros::Time, Eigen::Vector3d> offline;
  pipeline.run(*est, [&](const ppp::PppEpochRecord& r) {
    if (r.solution.position_ecef_m) offline[utcStamp(r.solution.time)] = *r.solution.position_ecef_m;
  });
  ASSERT_GT(offline.size(), epochs - 2);

  ASSERT_TRUE(waitForSubscribers(obs, corr, 30.0)) << node << " did not subscribe";
  const std::size_t played = playBag(bag, obs, corr, 20.0);
  ASSERT_EQ(played, epochs);
  ASSERT_TRUE(out.waitForStatuses(played, 30.0)) << out.statusCount() << " of " << played;
  EXPECT_EQ(out.lastStatus().epochs_processed, played);

  std::lock_guard<std::mutex> l(out.mutex);
  ASSERT_GE(out.fixes.size(), epochs - 1);
  double worst = 0.0;
  for (const auto& f : out.fixes) {
    const auto it = offline.find(f.header.stamp);
    ASSERT_NE(it, offline.end()) << "no ppp_solve epoch at " << f.header.stamp;
    worst = std::max(worst, (fixEcef(f) - it->second).norm());
    for (double c : f.position_covariance) ASSERT_TRUE(std::isfinite(c));
  }
  std::printf("[ figures  ] %s: %zu epochs compared with ppp_solve --estimator %s: largest difference %.3g mm\n",
              node.c_str(), out.fixes.size(), estimator.c_str(), worst * 1e3);
  EXPECT_LT(worst, 1e-3);

  const auto& lastfix = out.fixes.back();
  const double node_error = (fixEcef(lastfix) - d.truth_ecef_m).norm(),
               offline_error = (offline.at(lastfix.header.stamp) - d.truth_ecef_m).norm();
  std::printf("[ figures  ] %s final 3D error after %zu epochs: node %.3f m, ppp_solve %.3f m (bound %.1f m)\n",
              node.c_str(), epochs, node_error, offline_error, bound_m);
  EXPECT_LT(offline_error, bound_m);
  EXPECT_LT(node_error, bound_m);
  std::string err;
  EXPECT_TRUE(tf_buffer.canTransform("map", "base_link", ros::Time(0), ros::Duration(3.0), &err)) << err;
  for (const auto& [name, level] : out.worst_diagnostic) EXPECT_LT(level, diagnostic_msgs::DiagnosticStatus::ERROR) << name;
}

/// The GNSS/INS test nodes' ~estimator parameter (ekf_ins by default); nullopt, with the
/// reason on stderr, when it names neither ekf_ins nor smoother_ins.
inline std::optional<std::string> insEstimatorParam() {
  std::string estimator = "ekf_ins";
  ros::param::get("~estimator", estimator);
  if (estimator == "ekf_ins" || estimator == "smoother_ins") return estimator;
  std::fprintf(stderr, "~estimator: \"%s\" is neither ekf_ins nor smoother_ins\n", estimator.c_str());
  return std::nullopt;
}

}  // namespace ppp_ros::test
