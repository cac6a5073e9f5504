// The node's inputs (ros/node_inputs.h) without a ROS master: messages in, the time
// guard's and the correction gate's decisions out, everything counted and named.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "node_test_messages.h"
#include "ppp_bayes_tree/ros/node_inputs.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"

namespace {

using node_test::corrections;
using node_test::day;
using node_test::observations;
using node_test::Warnings;
using ppp_ros::NodeInputs;

const ros::Time kArrival(1778630400.0);

/// Observations through the guard and admitted; returns the epochs without satellites.
std::vector<ppp::GnssTime> feed(NodeInputs& in, const ppp::GnssTime& t, std::uint32_t seq,
                                const std::string& publisher = "/receiver", std::size_t satellites = 1) {
  std::vector<ppp::GnssTime> empty;
  ppp_ros::ObservationIntake intake = in.receiveObservations(observations(t, seq, satellites), publisher, kArrival);
  in.admitObservations(intake, [&](const ppp::GnssTime& e) { empty.push_back(e); });
  return empty;
}

}  // namespace

TEST(NodeInputs, ObservationTimeGoingBackIsDroppedCountedAndNamed) {
  Warnings w;
  NodeInputs in(ppp_ros::RosNodeOptions{}, w.sink());
  const ppp::GnssTime t = day();
  feed(in, t, 1);
  feed(in, t + 1.0, 2);
  // Half a second back (inside ros.input.reset_backwards_threshold_s, 60 s): out of order.
  ppp_ros::ObservationIntake intake = in.receiveObservations(observations(t + 0.5, 3), "/receiver", kArrival);
  EXPECT_TRUE(intake.outcome.accepted.empty());
  EXPECT_FALSE(intake.reset_why);
  EXPECT_EQ(in.counters().epochs_out_of_order, 1u);
  // The drop names the message kind, its time and its step back.
  EXPECT_EQ(in.lastTimeDrop(), "observation epoch " + (t + 0.5).toString() + " (-0.500 s): " +
                                   ppp::text(ppp::TimeDropReason::OutOfOrder));
  EXPECT_TRUE(w.has("obs_drop:" + ppp::text(ppp::TimeDropReason::OutOfOrder), "dropped (counted)"));
  // The same stamp again: a duplicate.
  feed(in, t + 1.0, 4);
  EXPECT_EQ(in.counters().epochs_duplicate, 1u);
  EXPECT_EQ(in.pendingEpochs(), 2u);  // t and t + 1 wait for corrections
  EXPECT_EQ(in.observationMessages(), 4u);
}

TEST(NodeInputs, UnreadableTimeIsCountedAsAnInvalidObservation) {
  Warnings w;
  NodeInputs in(ppp_ros::RosNodeOptions{}, w.sink());
  auto msg = boost::make_shared<ppp_bayes_tree::GnssObservations>(*observations(day(), 1));
  msg->time_system = "XYZ";
  ppp_ros::ObservationIntake intake = in.receiveObservations(msg, "/receiver", kArrival);
  EXPECT_TRUE(intake.outcome.accepted.empty());
  EXPECT_EQ(in.counters().observations_invalid, 1u);
  EXPECT_TRUE(w.has("obs_time", "ppp: observation epoch dropped: "));
}

TEST(NodeInputs, SequenceGapsAreCountedPerPublisher) {
  ppp_ros::SequenceGapCounter gaps;
  EXPECT_EQ(gaps.gap("/a", 7), 0u);  // the first message of a publisher: nothing known before it
  EXPECT_EQ(gaps.gap("/a", 8), 0u);
  EXPECT_EQ(gaps.gap("/a", 11), 2u);  // 9 and 10 lost
  EXPECT_EQ(gaps.gap("/b", 100), 0u);  // another publisher numbers its own
  EXPECT_EQ(gaps.gap("/a", 0), 0u);    // a restarted publisher: counted afresh
  EXPECT_EQ(gaps.gap("/a", 1), 0u);

  Warnings w;
  ppp_ros::RosNodeOptions o;
  o.observation_queue_size = 123;
  NodeInputs in(o, w.sink());
  feed(in, day(), 1);
  feed(in, day() + 1.0, 5);  // 2, 3, 4 lost
  EXPECT_EQ(in.counters().observations_lost, 3u);
  EXPECT_TRUE(w.has("obs_lost", "3 observation message(s) lost before the node (header.seq gap from /receiver; "
                                "queue ros.input.observation_queue_size 123)"));
  in.receiveCorrections(corrections(day(), 10), "/products");
  in.receiveCorrections(corrections(day() + 30.0, 12), "/products");
  EXPECT_EQ(in.counters().corrections_lost, 1u);
  EXPECT_EQ(in.correctionMessages(), 2u);
}

TEST(NodeInputs, SustainedJumpBackResetsBeforeTheNewTimeLine) {
  Warnings w;
  ppp_ros::RosNodeOptions o;  // 3 consecutive epochs confirm a jump (ros.input.time_jump_confirm_epochs)
  NodeInputs in(o, w.sink());
  const ppp::GnssTime t = day();
  for (int k = 0; k < 5; ++k) feed(in, t + k, static_cast<std::uint32_t>(k + 1));
  EXPECT_EQ(in.pendingEpochs(), 5u);
  // A bag loop: an hour back. Two epochs are held as a candidate, the third confirms.
  for (int k = 0; k < 2; ++k) {
    ppp_ros::ObservationIntake held = in.receiveObservations(observations(t - 3600.0 + k, 6 + k), "/r", kArrival);
    EXPECT_TRUE(held.outcome.accepted.empty());
    EXPECT_FALSE(held.reset_why);
  }
  EXPECT_EQ(in.epochsHeld(), 2u);
  ppp_ros::ObservationIntake intake = in.receiveObservations(observations(t - 3598.0, 8), "/r", kArrival);
  ASSERT_TRUE(intake.reset_why);
  // Step from the last accepted epoch (t + 4) to the first of the new line (t - 3600).
  EXPECT_EQ(*intake.reset_why, "time went back by -3604.000 s (beyond 60.000000 s), confirmed by 3 consecutive epochs");
  ASSERT_EQ(intake.outcome.accepted.size(), 3u);
  // The node resets its estimator here: the epochs waiting for corrections are discarded.
  EXPECT_EQ(in.resetForEstimator(), 5u);
  EXPECT_EQ(in.counters().estimator_resets, 1u);
  EXPECT_EQ(in.counters().epochs_discarded_at_reset, 5u);
  in.admitObservations(intake, [](const ppp::GnssTime&) { FAIL() << "no empty epoch"; });
  EXPECT_EQ(in.pendingEpochs(), 3u);
  EXPECT_EQ(in.counters().epochs_time_jump_dropped, 0u);
}

TEST(NodeInputs, IsolatedBadStampIsDroppedNotReset) {
  Warnings w;
  NodeInputs in(ppp_ros::RosNodeOptions{}, w.sink());
  const ppp::GnssTime t = day();
  feed(in, t, 1);
  feed(in, t - 3600.0, 2);  // held as a candidate jump
  feed(in, t + 1.0, 3);     // the time line goes on: the candidate was an isolated bad stamp
  EXPECT_EQ(in.counters().epochs_time_jump_dropped, 1u);
  EXPECT_EQ(in.counters().estimator_resets, 0u);
  EXPECT_NE(in.lastTimeDrop().find("observation epoch " + (t - 3600.0).toString() + " (-3600.000 s)"),
            std::string::npos);
}

TEST(NodeInputs, CorrectionGateHoldsAnEpochUntilCorrectionsCoverIt) {
  Warnings w;
  ppp_ros::RosNodeOptions o;  // ros.input.correction_wait_s 35 s
  NodeInputs in(o, w.sink());
  const ppp::GnssTime t = day();
  feed(in, t + 10.0, 1);
  EXPECT_FALSE(in.nextReady(kArrival.toSec() + 1.0));  // no corrections yet: it waits
  // A batch at t + 30 covers t + 10 (the buffer interpolates between batches, never extrapolates).
  for (const double dt : {0.0, 30.0}) {
    auto input = in.receiveCorrections(corrections(t + dt, 1), "/products");
    ASSERT_TRUE(input);
    in.admitCorrections(corrections(t + dt, 1), std::move(*input), ppp_ros::utcStamp(t + dt));
  }
  const auto ready = in.nextReady(kArrival.toSec() + 1.0);
  ASSERT_TRUE(ready);
  EXPECT_EQ(ready->time, t + 10.0);
  EXPECT_EQ(in.pendingEpochs(), 0u);
  // An epoch past the newest batch waits at most correction_wait_s (ROS time since its arrival).
  feed(in, t + 40.0, 2);
  EXPECT_FALSE(in.nextReady(kArrival.toSec() + 34.0));
  EXPECT_TRUE(in.nextReady(kArrival.toSec() + 35.5));
}

TEST(NodeInputs, EmptyEpochIsCountedAndGoesToTheStatusNotTheGate) {
  Warnings w;
  NodeInputs in(ppp_ros::RosNodeOptions{}, w.sink());
  const std::vector<ppp::GnssTime> empty = feed(in, day(), 1, "/receiver", 0);
  ASSERT_EQ(empty.size(), 1u);
  EXPECT_EQ(empty[0], day());
  EXPECT_EQ(in.counters().empty_epochs, 1u);
  EXPECT_EQ(in.pendingEpochs(), 0u);
  EXPECT_TRUE(w.has("empty", "ppp: empty epoch " + day().toString() + " (no satellites): no solution"));
}

TEST(NodeInputs, CorrectionProblemsAreCountedByReason) {
  Warnings w;
  NodeInputs in(ppp_ros::RosNodeOptions{}, w.sink());
  // Only an unknown satellite: counted, and the batch has no usable satellite.
  EXPECT_FALSE(in.receiveCorrections(corrections(day(), 1, "X99"), "/products"));
  EXPECT_EQ(in.counters().corrections_unknown_satellites, 1u);
  EXPECT_TRUE(w.has("corr_empty", "correction batch without a usable satellite ignored"));
  std::size_t issues = 0;
  for (const auto& [reason, n] : in.issues().counts)
    if (reason.find("unknown satellite") != std::string::npos) issues += n;
  EXPECT_EQ(issues, 1u);
  // An unreadable batch time: dropped with the reason.
  auto bad = corrections(day(), 2);
  bad.time_system = "XYZ";
  EXPECT_FALSE(in.receiveCorrections(bad, "/products"));
  EXPECT_TRUE(w.has("corrections_time", "ppp: correction batch dropped: "));
}

TEST(NodeInputs, StalenessIsTheLargerOfDataTimeAndArrivalTime) {
  Warnings w;
  NodeInputs in(ppp_ros::RosNodeOptions{}, w.sink());
  const ppp::GnssTime t = day();
  EXPECT_FALSE(in.correctionsStale_s());
  auto input = in.receiveCorrections(corrections(t, 1), "/products");
  in.admitCorrections(corrections(t, 1), std::move(*input), kArrival - ros::Duration(5.0));
  EXPECT_DOUBLE_EQ(in.lastCorrectionAge_s(), (kArrival - ros::Duration(5.0) - ppp_ros::utcStamp(t)).toSec());
  feed(in, t + 100.0, 1);  // data 100 s ahead, arrival 5 s later
  ASSERT_TRUE(in.correctionsStale_s());
  EXPECT_DOUBLE_EQ(*in.correctionsStale_s(), 100.0);
}

TEST(NodeInputs, ObservationMessageToCoreEpochFollowsTheLayout) {
  ppp::SimulationConfig c;
  c.duration_s = 10.0;
  const ppp::SimulatedFlight f = ppp::simulateFlight(c, 3);
  Warnings w;
  NodeInputs in(ppp_ros::RosNodeOptions{}, w.sink());
  ppp_ros::PendingObservation p;
  p.msg = boost::make_shared<ppp_bayes_tree::GnssObservations>(ppp_ros::toMessage(f.epochs[0], f.header));
  p.time = f.epochs[0].time;
  const std::optional<ppp::ObsEpoch> epoch = in.toEpoch(p);
  ASSERT_TRUE(epoch);
  EXPECT_EQ(epoch->time, f.epochs[0].time);
  EXPECT_EQ(epoch->satellites.size(), f.epochs[0].satellites.size());
  EXPECT_TRUE(in.takeLayoutChanged());  // the first message brings the observation types
  EXPECT_FALSE(in.takeLayoutChanged());
  EXPECT_EQ(in.counters().observations_invalid, 0u);
}

TEST(NodeInputs, LiveReceiverRestartAndProductMode) {
  Warnings w;
  ppp_ros::RosNodeOptions o;
  o.live_input.expect_corrections = true;
  NodeInputs in(o, w.sink());
  ppp::LiveReadyEpoch ready;
  ready.epoch.time = day();
  ready.epoch.satellites.resize(1);
  ready.mode = ppp::LiveProductMode::BroadcastOnly;
  EXPECT_FALSE(in.liveRestart(ready, std::nullopt, kArrival));
  EXPECT_FALSE(in.liveRestart(ready, day() - 1.0, kArrival));
  // Not after the last output: the receiver restarted.
  const auto why = in.liveRestart(ready, day() + 10.0, kArrival);
  ASSERT_TRUE(why);
  EXPECT_EQ(*why, "receiver restart: observation time went back by -10.000 s (live input)");
  EXPECT_EQ(in.liveReceiverRestarts(), 1u);
  EXPECT_EQ(in.observationMessages(), 3u);
  EXPECT_TRUE(in.admitLiveEpoch(ready));
  EXPECT_EQ(in.productMode(), ppp_bayes_tree::PppStatus::PRODUCTS_BROADCAST_ONLY);
  EXPECT_EQ(in.productModeText(), std::string(ppp::liveProductModeName(ppp::LiveProductMode::BroadcastOnly)));
  EXPECT_TRUE(w.has("broadcast_only", "broadcast orbits and clocks only (widened sigmas)"));
  ready.epoch.satellites.clear();
  ready.mode = ppp::LiveProductMode::PreciseSsr;
  EXPECT_FALSE(in.admitLiveEpoch(ready));
  EXPECT_EQ(in.counters().empty_epochs, 1u);
  EXPECT_EQ(in.productMode(), ppp_bayes_tree::PppStatus::PRODUCTS_PRECISE);
  for (int k = 0; k < 1005; ++k) in.recordLiveLatency(0.001 * k);
  EXPECT_EQ(in.liveLatencies_s().size(), NodeInputs::kLatencyWindow);
  EXPECT_DOUBLE_EQ(in.liveLatencies_s().front(), 0.005);  // the oldest 5 left the window
}
