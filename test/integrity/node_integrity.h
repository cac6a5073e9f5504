#pragma once
// Node integrity cases (test/integrity/node_integrity_<estimator>.test):
// four nodes of one estimator in the namespaces clean/, stamps/, burst/ and stale/
// get the simulated loiter flight of the rostests (5 min at 1 Hz, 30 s corrections,
// seed 7) made into a bag by this test:
//   clean/   the flight as it is: the reference;
//   stamps/  the same flight plus one extra message after some epochs: a copy with
//            GPS week 0, with week 65535, shifted +1 h, -1 h and +1 day, the epoch of
//            100 s before re-sent, and the epoch itself again (a duplicate stamp);
//   stale/   the flight with the corrections stopping at 150 s (thresholds 20 / 60 s
//            in the .test);
//   burst/   all correction batches, the first epoch, then the other 300 at once into a 5-message
//            subscriber queue (ros.input.observation_queue_size in the .test).
// Checks: no reset on isolated bad stamps, each counted with its reason; output stamps
// strictly increasing, one fix per stamp, the same stamps and (to 1 cm) the same fixes
// as clean/; the error after the bad stamps not worse than clean's by more than 1 cm;
// in the burst every message counted: processed + lost (header.seq gaps) == sent;
// the corrections diagnostic of stale/ goes WARN and then ERROR.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "rostest/rostest_support.h"

namespace ppp_ros::integrity {

using ppp_bayes_tree::GnssObservations;
using ppp_bayes_tree::PreciseCorrections;

/// One node under test: its input publishers and its outputs.
struct NodeUnderTest {
  std::string ns;
  ros::Publisher obs, corr;
  test::NodeOutputs out;
  NodeUnderTest(ros::NodeHandle& nh, const std::string& name) : ns(name) {
    obs = nh.advertise<GnssObservations>(ns + "/gnss/observations", 5000);
    corr = nh.advertise<PreciseCorrections>(ns + "/gnss/corrections", 5000);
    out.subscribe(nh, ns + "/");
  }
};

/// Each diagnostic status over time (level, summary), in arrival order.
struct DiagnosticHistory {
  struct Report {
    std::uint8_t level;
    std::string message;
  };
  std::mutex mutex;
  std::map<std::string, std::vector<Report>> levels;  // status name ("ns/node: task") -> reports
  ros::Subscriber sub;
  void subscribe(ros::NodeHandle& nh) {
    sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 1000, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      for (const auto& s : m->status) levels[s.name].push_back(Report{s.level, s.message});
    });
  }
  /// The reports of the status whose name contains both parts.
  std::vector<Report> of(const std::string& part1, const std::string& part2) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& [name, v] : levels)
      if (name.find(part1) != std::string::npos && name.find(part2) != std::string::npos) return v;
    return {};
  }
};

struct NodeIntegrityTest {
  std::string estimator;
  ros::NodeHandle nh;
  NodeUnderTest clean, stamps, stale, burst;
  DiagnosticHistory diagnostics;
  ppp::SimulatedFlight flight;
  std::vector<rosbag::MessageInstance> messages;
  std::unique_ptr<rosbag::Bag> bag;
  std::vector<GnssObservations> epochs;  // the flight's epochs as messages
  ppp::GnssTime first_epoch;
  bool ok = false;
  bool played = false;
  std::size_t stamps_sent = 0, stamps_bad_jumps = 0, stamps_duplicates = 0;

  static constexpr double kCorrectionsStop_s = 150.0;  // stale/: no batch after first epoch + this

  explicit NodeIntegrityTest(std::string est)
      : estimator(std::move(est)), clean(nh, "clean"), stamps(nh, "stamps"), stale(nh, "stale"), burst(nh, "burst") {
    diagnostics.subscribe(nh);
    try {
      ppp::SimulationConfig c;
      c.profile = ppp::FlightProfile::Loiter;
      c.duration_s = 300.0;
      c.rate_hz = 1.0;
      flight = ppp::simulateFlight(c, 7);
      const std::string path =
          (std::filesystem::temp_directory_path() / ("ppp_integrity_" + estimator + ".bag")).string();
      std::size_t k = 0;
      const auto summary = writeReplayBag(path, flight.header, [&](ppp::ObsEpoch& e) {
        if (k >= flight.epochs.size()) return false;
        e = flight.epochs[k++];
        return true;
      }, flight.products, BagWriteOptions{});
      bag = std::make_unique<rosbag::Bag>(path, rosbag::bagmode::Read);
      rosbag::View view(*bag);
      for (const rosbag::MessageInstance& m : view) messages.push_back(m);
      for (const auto& e : flight.epochs) epochs.push_back(toMessage(e, flight.header));
      first_epoch = flight.epochs.front().time;
      ok = summary.epochs == flight.epochs.size() && summary.batches > 10;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "cannot make the bag: " << e.what();
    }
  }

  bool waitForNodes() {
    for (NodeUnderTest* n : {&clean, &stamps, &stale, &burst})
      if (!test::waitForSubscribers(n->obs, n->corr, 30.0)) {
        ADD_FAILURE() << n->ns << " did not subscribe";
        return false;
      }
    return true;
  }

  /// The extra bad message published after epoch k on stamps/ (none: nullopt).
  std::optional<GnssObservations> badAfter(std::size_t k) {
    GnssObservations m = epochs.at(k);
    switch (k) {
      case 60: m.week = 0; return m;                                 // GPS week 0
      case 90: m.week = 65535; return m;                             // week 65535
      case 120: return toMessage(shifted(k, 3600.0), flight.header);   // +1 h
      case 150: return toMessage(shifted(k, -3600.0), flight.header);  // -1 h
      case 180: return toMessage(shifted(k, 86400.0), flight.header);  // +1 day
      case 210: return epochs.at(k - 100);                           // re-sent 100 s late
      case 240: return m;                                            // the same stamp again
      default: return std::nullopt;
    }
  }
  ppp::ObsEpoch shifted(std::size_t k, double dt_s) const {
    ppp::ObsEpoch e = flight.epochs.at(k);
    e.time = e.time + dt_s;
    return e;
  }

  /// clean/, stamps/ and stale/ get the bag at 20x real time (stale/ without the
  /// batches after kCorrectionsStop_s); stamps/ the extra bad messages.
  void play() {
    if (played) return;
    played = true;
    ASSERT_TRUE(ok);
    ASSERT_TRUE(waitForNodes());
    const double speed = 20.0;
    const ros::WallTime start = ros::WallTime::now();
    const ros::Time t0 = messages.front().getTime();
    std::size_t k = 0;
    for (const rosbag::MessageInstance& m : messages) {
      const ros::WallDuration wait = start + ros::WallDuration((m.getTime() - t0).toSec() / speed) - ros::WallTime::now();
      if (wait > ros::WallDuration(0)) wait.sleep();
      if (auto c = m.instantiate<PreciseCorrections>()) {
        clean.corr.publish(c);
        stamps.corr.publish(c);
        const ppp::GnssTime t = fromMessageTime(c->week, c->seconds_of_week, c->time_system);
        if (t - first_epoch <= kCorrectionsStop_s) stale.corr.publish(c);
      } else if (auto o = m.instantiate<GnssObservations>()) {
        clean.obs.publish(o);
        stamps.obs.publish(o);
        stale.obs.publish(o);
        ++stamps_sent;
        if (auto bad = badAfter(k)) {
          stamps.obs.publish(*bad);
          ++stamps_sent;
          if (k == 240) ++stamps_duplicates;
          else ++stamps_bad_jumps;
        }
        ++k;
      }
    }
    ASSERT_EQ(k, epochs.size());
    for (NodeUnderTest* n : {&clean, &stamps})
      EXPECT_TRUE(n->out.waitForStatuses(epochs.size(), 60.0)) << n->ns << ": " << n->out.statusCount() << " statuses";
    ros::WallDuration(2.0).sleep();  // stale/ releases its last epochs after the correction wait
  }

  // ---------------------------------------------------------------- cases
  void checkIsolatedBadStampsDroppedAndCounted() {
    ASSERT_NO_FATAL_FAILURE(play());
    const auto s = stamps.out.lastStatus();
    const auto c = clean.out.lastStatus();
    std::printf("[ figures  ] %s stamps/: %zu messages sent (%zu bad stamps, %zu duplicates): processed %u, time jumps "
                "dropped %u, duplicates %u, out of order %u, resets %u, lost %u\n",
                estimator.c_str(), stamps_sent, stamps_bad_jumps, stamps_duplicates, s.epochs_processed,
                s.epochs_time_jump_dropped, s.epochs_duplicate, s.epochs_out_of_order, s.estimator_resets,
                s.observations_lost);
    EXPECT_EQ(s.estimator, estimator);
    EXPECT_EQ(s.estimator_resets, 0u) << "an isolated bad stamp must not reset";
    EXPECT_EQ(s.epochs_discarded_at_reset, 0u);
    EXPECT_EQ(s.epochs_time_jump_dropped, stamps_bad_jumps);
    EXPECT_EQ(s.epochs_duplicate, stamps_duplicates);
    EXPECT_EQ(s.epochs_processed, epochs.size());
    EXPECT_EQ(s.epochs_processed + s.epochs_time_jump_dropped + s.epochs_duplicate + s.epochs_out_of_order +
                  s.observations_invalid + s.observations_lost,
              stamps_sent)
        << "every message processed or counted";
    EXPECT_EQ(c.epochs_processed, epochs.size());
    EXPECT_EQ(c.estimator_resets + c.epochs_time_jump_dropped + c.epochs_duplicate + c.observations_lost, 0u);
  }

  void checkOutputsMonotonicOneFixPerStampAndAsGoodAsClean() {
    ASSERT_NO_FATAL_FAILURE(play());
    std::vector<sensor_msgs::NavSatFix> bad_fixes, clean_fixes;
    std::vector<ppp_bayes_tree::PppStatus> statuses;
    {
      std::lock_guard<std::mutex> l(stamps.out.mutex);
      bad_fixes = stamps.out.fixes;
      statuses = stamps.out.statuses;
    }
    {
      std::lock_guard<std::mutex> l(clean.out.mutex);
      clean_fixes = clean.out.fixes;
    }
    ASSERT_GT(clean_fixes.size(), epochs.size() - 5);
    for (std::size_t i = 1; i < bad_fixes.size(); ++i)
      ASSERT_GT(bad_fixes[i].header.stamp, bad_fixes[i - 1].header.stamp) << "fix " << i << ": output went back in time";
    for (std::size_t i = 1; i < statuses.size(); ++i)
      ASSERT_GT(statuses[i].header.stamp, statuses[i - 1].header.stamp) << "status " << i;
    ASSERT_EQ(bad_fixes.size(), clean_fixes.size()) << "one fix per stamp, the same stamps as without the bad ones";
    const Eigen::Vector3d truth = flight.truth.back().trajectory.position_ecef_m;
    std::map<ros::Time, Eigen::Vector3d> truth_at;
    for (const auto& t : flight.truth) truth_at[utcStamp(t.trajectory.time)] = t.trajectory.position_ecef_m;
    double worst_difference = 0.0, mean_bad = 0.0, mean_clean = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < bad_fixes.size(); ++i) {
      ASSERT_EQ(bad_fixes[i].header.stamp, clean_fixes[i].header.stamp);
      const Eigen::Vector3d b = test::fixEcef(bad_fixes[i]), c = test::fixEcef(clean_fixes[i]);
      worst_difference = std::max(worst_difference, (b - c).norm());
      const auto it = truth_at.find(bad_fixes[i].header.stamp);
      if (i + 60 >= bad_fixes.size() && it != truth_at.end()) {  // the last minute
        mean_bad += (b - it->second).norm();
        mean_clean += (c - it->second).norm();
        ++n;
      }
    }
    ASSERT_GT(n, 50u);
    mean_bad /= n;
    mean_clean /= n;
    const double final_bad = (test::fixEcef(bad_fixes.back()) - truth).norm(),
                 final_clean = (test::fixEcef(clean_fixes.back()) - truth).norm();
    std::printf("[ figures  ] %s: with the bad stamps / clean: last-minute mean 3D error %.3f / %.3f m, final %.3f / "
                "%.3f m; largest fix difference %.3g mm over %zu fixes\n",
                estimator.c_str(), mean_bad, mean_clean, final_bad, final_clean, 1e3 * worst_difference,
                bad_fixes.size());
    EXPECT_LT(worst_difference, 0.01);
    EXPECT_LT(mean_bad, mean_clean + 0.01);
    EXPECT_LT(final_bad, final_clean + 0.01);
  }

  void checkBurstDropsAllCounted() {
    ASSERT_NO_FATAL_FAILURE(play());
    // All batches first (the epochs find their corrections), then every epoch at once.
    std::size_t batches = 0;
    for (const rosbag::MessageInstance& m : messages)
      if (auto c = m.instantiate<PreciseCorrections>()) {
        burst.corr.publish(c);
        ++batches;
      }
    ros::WallDuration(1.0).sleep();
    // The first epoch alone: the node learns the publisher's numbering (losses before the
    // first message of a publisher cannot be told from messages it sent before the node
    // connected: config/ppp.yaml ros.input.observation_queue_size).
    burst.obs.publish(epochs.front());
    ASSERT_TRUE(burst.out.waitForStatuses(1, 10.0)) << "burst/ did not process the first epoch";
    const ros::WallTime start = ros::WallTime::now();
    for (std::size_t k = 1; k < epochs.size(); ++k) burst.obs.publish(epochs[k]);
    const double publish_s = (ros::WallTime::now() - start).toSec();
    // The last message always arrives (a full roscpp queue drops its oldest): wait for its status.
    const ros::Time last_stamp = epochs.back().header.stamp;
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(60.0);
    ppp_bayes_tree::PppStatus s;
    while (ros::WallTime::now() < end) {
      s = burst.out.lastStatus();
      if (s.header.stamp == last_stamp) break;
      ros::WallDuration(0.05).sleep();
    }
    ASSERT_EQ(s.header.stamp, last_stamp) << "the last epoch of the burst was not processed";
    std::printf("[ figures  ] %s burst/: %zu epochs published in %.3f s into a 5-message queue: processed %u, lost "
                "(header.seq gaps) %u, sum %u; correction batches %zu, lost %u; satellite-epochs without "
                "corrections %u\n",
                estimator.c_str(), epochs.size(), publish_s, s.epochs_processed, s.observations_lost,
                s.epochs_processed + s.observations_lost, batches, s.corrections_lost, s.corrections_late);
    EXPECT_GT(s.observations_lost, 0u) << "the burst did not overflow the queue: the case tests nothing";
    EXPECT_EQ(s.epochs_processed + s.observations_lost + s.epochs_duplicate + s.epochs_out_of_order +
                  s.epochs_time_jump_dropped,
              epochs.size())
        << "counted + processed == sent";
    EXPECT_EQ(s.estimator_resets, 0u);
    // The inputs diagnostic reported the losses (WARN, "... lost before the node ...").
    ros::WallDuration(1.5).sleep();
    bool warned = false;
    for (const auto& r : diagnostics.of("burst/", "inputs"))
      warned |= r.level == diagnostic_msgs::DiagnosticStatus::WARN && r.message.find("lost") != std::string::npos;
    EXPECT_TRUE(warned) << "the losses were not reported in the inputs diagnostic";
  }

  /// After the other cases: two epochs beyond the corrections wait in stamps/ (not
  /// covered), then the flight starts again (a rosbag loop, 371 s back): the reset comes
  /// with the third epoch of the loop and counts the two epochs it discards.
  void checkLoopResetsAfterConfirmationAndCountsWhatItDiscards() {
    ASSERT_NO_FATAL_FAILURE(play());
    const auto before = stamps.out.lastStatus();
    const std::size_t n_before = stamps.out.statusCount();
    for (double shift : {70.0, 71.0}) stamps.obs.publish(toMessage(shifted(epochs.size() - 1, shift), flight.header));
    ros::WallDuration(0.5).sleep();
    EXPECT_EQ(stamps.out.statusCount(), n_before) << "the epochs beyond the corrections should wait";
    stamps.obs.publish(epochs.at(0));
    stamps.obs.publish(epochs.at(1));
    ros::WallDuration(0.5).sleep();
    EXPECT_EQ(stamps.out.lastStatus().estimator_resets, before.estimator_resets) << "reset before the confirmation";
    stamps.obs.publish(epochs.at(2));
    ASSERT_TRUE(stamps.out.waitForStatuses(n_before + 3, 10.0)) << "the loop's epochs were not processed";
    const auto s = stamps.out.lastStatus();
    std::printf("[ figures  ] %s stamps/ loop: resets %u, epochs discarded at the reset %u, loop epochs processed %u, "
                "state %s\n",
                estimator.c_str(), s.estimator_resets - before.estimator_resets,
                s.epochs_discarded_at_reset - before.epochs_discarded_at_reset,
                s.epochs_processed - before.epochs_processed, s.solution_state_text.c_str());
    EXPECT_EQ(s.estimator_resets, before.estimator_resets + 1);
    EXPECT_EQ(s.epochs_discarded_at_reset, before.epochs_discarded_at_reset + 2);
    EXPECT_EQ(s.epochs_processed, before.epochs_processed + 3);
    EXPECT_EQ(s.header.stamp, epochs.at(2).header.stamp);
    EXPECT_NE(s.solution_state, ppp_bayes_tree::PppStatus::NO_SOLUTION) << s.reason;
  }

  void checkCorrectionsDiagnosticWarnsThenErrors() {
    ASSERT_NO_FATAL_FAILURE(play());
    const auto reports = diagnostics.of("stale/", "corrections");
    ASSERT_FALSE(reports.empty()) << "no corrections diagnostic of stale/";
    // While batches flow: held, not stale (the latency WARN of a simulated 2026 stamp
    // against the wall clock may be on: not this case); then WARN "stale", then ERROR "stopped".
    std::optional<std::size_t> first_current, first_stale, first_stopped;
    for (std::size_t i = 0; i < reports.size(); ++i) {
      const auto& r = reports[i];
      const bool stale_text = r.message.find("stale") != std::string::npos;
      const bool stopped_text = r.message.find("stopped") != std::string::npos;
      if (!first_current && r.level < diagnostic_msgs::DiagnosticStatus::ERROR && !stale_text && !stopped_text &&
          r.message.find("no corrections") == std::string::npos)
        first_current = i;
      if (first_current && !first_stale && stale_text && r.level == diagnostic_msgs::DiagnosticStatus::WARN)
        first_stale = i;
      if (!first_stopped && stopped_text && r.level == diagnostic_msgs::DiagnosticStatus::ERROR) first_stopped = i;
    }
    std::string text;
    for (const auto& r : reports) text += std::to_string(r.level);
    std::printf("[ figures  ] %s stale/: corrections diagnostic levels over time (0 OK, 1 WARN, 2 ERROR): %s; last "
                "\"%s\"; final staleness %.1f s\n",
                estimator.c_str(), text.c_str(), reports.back().message.c_str(),
                stale.out.lastStatus().corrections_stale_s);
    ASSERT_TRUE(first_current) << "never current while the corrections flowed";
    ASSERT_TRUE(first_stale) << "no WARN (stale) after the corrections stopped";
    ASSERT_TRUE(first_stopped) << "no ERROR (stopped) after the corrections stopped";
    EXPECT_LT(*first_current, *first_stale);
    EXPECT_LT(*first_stale, *first_stopped);
    EXPECT_GT(stale.out.lastStatus().corrections_stale_s, 60.0);
    // The reference never had stale corrections.
    for (const auto& r : diagnostics.of("clean/", "corrections")) EXPECT_LT(r.level, diagnostic_msgs::DiagnosticStatus::ERROR);
  }
};

}  // namespace ppp_ros::integrity
