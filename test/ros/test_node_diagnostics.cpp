// The node's diagnostics (ros/node_diagnostics.h) without a ROS master: the levels and
// texts of each task for the states of the inputs and outputs that raise them.
#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "node_test_messages.h"
#include "node_test_records.h"
#include "ppp_bayes_tree/models/stream_bias_provider.h"
#include "ppp_bayes_tree/ros/node_diagnostics.h"

namespace {

using diagnostic_msgs::DiagnosticStatus;
using diagnostic_updater::DiagnosticStatusWrapper;
using node_test::corrections;
using node_test::day;
using node_test::observations;
using ppp_ros::NodeDiagnostics;
using ppp_ros::NodeInputs;
using ppp_ros::NodeOutputs;

std::optional<std::string> value(const DiagnosticStatusWrapper& s, const std::string& key) {
  for (const auto& kv : s.values)
    if (kv.key == key) return kv.value;
  return std::nullopt;
}

const ros::WallTime kStart(1000.0);
const ros::Time kArrival(1778630400.0);

void observe(NodeInputs& in, const ppp::GnssTime& t, std::uint32_t seq, const ros::Time& arrival = kArrival) {
  ppp_ros::ObservationIntake intake = in.receiveObservations(observations(t, seq), "/receiver", arrival);
  in.admitObservations(intake, [](const ppp::GnssTime&) {});
}

void correct(NodeInputs& in, const ppp::GnssTime& t, std::uint32_t seq, const ros::Time& arrival = kArrival) {
  auto input = in.receiveCorrections(corrections(t, seq), "/products");
  ASSERT_TRUE(input);
  in.admitCorrections(corrections(t, seq), std::move(*input), arrival);
}

}  // namespace

TEST(NodeDiagnostics, InputsWarnWithoutObservationsAndOnLossesSinceTheLastReport) {
  ppp_ros::RosNodeOptions o;
  NodeInputs in(o, node_test::ignoreWarnings());
  NodeOutputs out(o, node_test::ignoreWarnings());
  NodeDiagnostics diagnostics(o, kStart);
  DiagnosticStatusWrapper s0;
  diagnostics.inputs(s0, in, out, kStart + ros::WallDuration(1.0));
  EXPECT_EQ(s0.level, DiagnosticStatus::WARN);
  EXPECT_EQ(s0.message, "no observations received yet");

  observe(in, day(), 1);
  observe(in, day() + 1.0, 4);  // seq 2 and 3 lost
  DiagnosticStatusWrapper s1;
  diagnostics.inputs(s1, in, out, kStart + ros::WallDuration(2.0));
  EXPECT_EQ(s1.level, DiagnosticStatus::WARN);
  EXPECT_EQ(s1.message, "2 message(s) lost before the node since the last report");
  EXPECT_EQ(value(s1, "observation messages lost before the node (header.seq gaps)"), "2");
  EXPECT_EQ(value(s1, "observation messages"), "2");
  EXPECT_EQ(value(s1, "observation rate [Hz, wall]"), "2");  // 2 messages in the 1 s since the last report
  EXPECT_EQ(value(s1, "pending epochs"), "2");
  EXPECT_FALSE(value(s1, "attitude messages"));  // no attitude source configured

  // No new loss since: OK.
  observe(in, day() + 2.0, 5);
  DiagnosticStatusWrapper s2;
  diagnostics.inputs(s2, in, out, kStart + ros::WallDuration(3.0));
  EXPECT_EQ(s2.level, DiagnosticStatus::OK);
  EXPECT_EQ(s2.message, "receiving");
  EXPECT_EQ(value(s2, "last stamp dropped"), "none");
}

TEST(NodeDiagnostics, InputsWarnBelowHalfTheExpectedRate) {
  ppp_ros::RosNodeOptions o;
  o.expected_observation_rate_hz = 10.0;
  NodeInputs in(o, node_test::ignoreWarnings());
  NodeOutputs out(o, node_test::ignoreWarnings());
  NodeDiagnostics diagnostics(o, kStart);
  for (std::uint32_t k = 0; k < 4; ++k) observe(in, day() + k, k + 1);
  DiagnosticStatusWrapper s;
  diagnostics.inputs(s, in, out, kStart + ros::WallDuration(1.0));  // 4 Hz < 5 Hz
  EXPECT_EQ(s.level, DiagnosticStatus::WARN);
  EXPECT_EQ(s.message, "observation rate below half the expected rate");
}

TEST(NodeDiagnostics, CorrectionsLevelsFollowTheStaleThresholds) {
  ppp_ros::RosNodeOptions o;  // stale WARN 60 s, ERROR 180 s; late arrival WARN 10 s
  NodeDiagnostics diagnostics(o, kStart);
  const NodeOutputs out(o, node_test::ignoreWarnings());
  {
    NodeInputs in(o, node_test::ignoreWarnings());
    DiagnosticStatusWrapper s;
    diagnostics.corrections(s, in, out);
    EXPECT_EQ(s.level, DiagnosticStatus::WARN);
    EXPECT_EQ(s.message, "no corrections received yet");
  }
  struct Case {
    double observations_ahead_s;
    std::uint8_t level;
    std::string message;
  };
  const ppp::GnssTime t = day();
  for (const Case& c : {Case{30.0, DiagnosticStatus::OK, "corrections current"},
                        Case{100.0, DiagnosticStatus::WARN, "corrections stale: observations 100 s ahead of the newest batch"},
                        Case{200.0, DiagnosticStatus::ERROR,
                             "corrections stopped: observations 200 s ahead of the newest batch " + t.toString()}}) {
    NodeInputs in(o, node_test::ignoreWarnings());
    correct(in, t, 1, ppp_ros::utcStamp(t));  // arrives at its own stamp: age 0
    observe(in, t + c.observations_ahead_s, 1, ppp_ros::utcStamp(t));
    DiagnosticStatusWrapper s;
    diagnostics.corrections(s, in, out);
    EXPECT_EQ(s.level, c.level) << c.observations_ahead_s;
    EXPECT_EQ(s.message, c.message);
    EXPECT_EQ(value(s, "batches held"), "1");
  }
  // Current but arriving 15 s after their stamp: late.
  NodeInputs in(o, node_test::ignoreWarnings());
  correct(in, t, 1, ppp_ros::utcStamp(t) + ros::Duration(15.0));
  DiagnosticStatusWrapper s;
  diagnostics.corrections(s, in, out);
  EXPECT_EQ(s.level, DiagnosticStatus::WARN);
  EXPECT_EQ(s.message, "corrections arrive late");
}

TEST(NodeDiagnostics, EachPartsCountersAreRead) {
  // The inputs count the epochs the time guard drops; the outputs count the epochs processed,
  // those not published and the satellites without corrections: the diagnostics read both.
  ppp_ros::RosNodeOptions o;
  NodeInputs in(o, node_test::ignoreWarnings());
  NodeOutputs out(o, node_test::ignoreWarnings());
  NodeDiagnostics diagnostics(o, kStart);
  observe(in, day() + 1.0, 1);
  observe(in, day() + 0.5, 2);  // back in time: dropped by the inputs
  ASSERT_EQ(in.counters().epochs_out_of_order, 1u);
  out.countNotPublished();
  ppp::PppEpochRecord rec;
  rec.reason = "too few satellites (3 < 4)";
  ppp::EpochRejection late;
  late.satellite = {ppp::GnssSystem::GPS, 30};
  late.stage = ppp::RejectionStage::Model;
  late.reason = ppp::RejectionReason::NoClock;
  rec.rejected = {late, late};
  out.epochStatus(day(), rec, in.counters(), {}, {}, false);
  out.epochStatus(day() + 1.0, rec, in.counters(), {}, {}, false);
  DiagnosticStatusWrapper inputs, corrections, solution;
  diagnostics.inputs(inputs, in, out, kStart + ros::WallDuration(1.0));
  diagnostics.corrections(corrections, in, out);
  diagnostics.solution(solution, in, out, nullptr, 0);
  EXPECT_EQ(value(inputs, "out-of-order epochs dropped"), "2");
  EXPECT_EQ(value(corrections, "satellite-epochs without corrections"), "4");
  EXPECT_EQ(value(solution, "epochs processed"), "2");
  EXPECT_EQ(in.counters().epochs_processed, 0u);  // nothing of the outputs' is counted in the inputs
  EXPECT_EQ(in.counters().corrections_late, 0u);
}

TEST(NodeDiagnostics, SolutionReportsTheLastStatus) {
  ppp_ros::RosNodeOptions o;
  o.estimator = "ekf";
  NodeInputs in(o, node_test::ignoreWarnings());
  NodeOutputs out(o, node_test::ignoreWarnings());
  NodeDiagnostics diagnostics(o, kStart);
  DiagnosticStatusWrapper s0;
  diagnostics.solution(s0, in, out, nullptr, 0);
  EXPECT_EQ(s0.level, DiagnosticStatus::WARN);
  EXPECT_EQ(s0.message, "no epoch processed yet");
  EXPECT_EQ(value(s0, "estimator"), "ekf");

  ppp::PppEpochRecord none;
  none.reason = "too few satellites (3 < 4)";
  out.epochStatus(day(), none, in.counters(), {}, {}, false);
  DiagnosticStatusWrapper s1;
  diagnostics.solution(s1, in, out, nullptr, 0);
  EXPECT_EQ(s1.level, DiagnosticStatus::WARN);
  EXPECT_EQ(s1.message, "no solution: too few satellites (3 < 4)");

  out.setDatum(node_test::equator());
  out.epochStatus(day() + 1.0, node_test::solvedRecord(day() + 1.0, node_test::equator(), false), in.counters(), {}, {},
                  false);
  DiagnosticStatusWrapper s2;
  diagnostics.solution(s2, in, out, nullptr, 2);
  EXPECT_EQ(s2.level, DiagnosticStatus::OK);
  EXPECT_EQ(s2.message, "converged");
  EXPECT_EQ(value(s2, "estimator restarts after a failed update"), "2");
  EXPECT_EQ(value(s2, "satellites used"), "8");
  EXPECT_FALSE(value(s2, "smoother: fixed lag [s] (0: full)"));  // the EKF: no smoother figures

  ppp_ros::EpochFigures figures;
  figures.warnings = {"receiver antenna TRM59800.00 SCIS not in the ANTEX file"};
  out.epochStatus(day() + 2.0, node_test::solvedRecord(day() + 2.0, node_test::equator(), false), in.counters(),
                  figures, {}, false);
  DiagnosticStatusWrapper s3;
  diagnostics.solution(s3, in, out, nullptr, 2);
  EXPECT_EQ(s3.level, DiagnosticStatus::WARN);
  EXPECT_EQ(s3.message, "converged; receiver antenna TRM59800.00 SCIS not in the ANTEX file");
}

TEST(NodeDiagnostics, AmbiguityResolutionLevels) {
  // doc/ros_ambiguity_resolution.md: OK "float: ..." / "fixed (N held)", WARN without phase information.
  ppp_ros::RosNodeOptions o;
  NodeOutputs out(o, node_test::ignoreWarnings());
  NodeDiagnostics diagnostics(o, kStart);
  ppp::StreamBiasProvider provider(900.0);
  const ppp_ros::PhaseBiasChoice with{&provider, "stream phase biases"};
  const ppp_ros::PhaseBiasChoice without{nullptr, "ambiguity resolution: float (enabled: true): no phase biases"};
  auto check = [&](bool enabled, const ppp_ros::PhaseBiasChoice& phase, std::uint8_t level, const std::string& text) {
    DiagnosticStatusWrapper s;
    diagnostics.ambiguities(s, enabled, phase, out);
    EXPECT_EQ(s.level, level) << text;
    EXPECT_EQ(s.message, text);
  };
  check(false, without, DiagnosticStatus::OK, "off (float)");
  check(true, with, DiagnosticStatus::OK, "on, no epoch processed yet");
  out.setDatum(node_test::equator());
  const ppp::PppEpochRecord floating = node_test::solvedRecord(day(), node_test::equator(), false);
  out.epochStatus(day(), floating, {}, {}, without, true);
  check(true, without, DiagnosticStatus::WARN, without.source);
  out.epochStatus(day() + 1.0, floating, {}, {}, with, true);
  check(true, with, DiagnosticStatus::OK, "float: " + floating.ambiguity_fix->text());
  out.epochStatus(day() + 2.0, node_test::solvedRecord(day() + 2.0, node_test::equator(), true), {}, {}, with, true);
  check(true, with, DiagnosticStatus::OK, "fixed (7 held)");
  DiagnosticStatusWrapper s;
  diagnostics.ambiguities(s, true, with, out);
  EXPECT_EQ(value(s, "epochs fixed"), "1");
  EXPECT_EQ(value(s, "first fix"), (day() + 2.0).toString());
  EXPECT_EQ(value(s, "phase information"), "stream phase biases");
}

TEST(NodeDiagnostics, LiveStreamsWarnBeforeTheFirstEpochAndOnBroadcastFallback) {
  ppp_ros::RosNodeOptions o;
  NodeInputs in(o, node_test::ignoreWarnings());
  in.startLive(o.live_input);
  const NodeOutputs out(o, node_test::ignoreWarnings());
  NodeDiagnostics diagnostics(o, kStart);
  const std::vector<std::unique_ptr<ppp_ros::GnssStreamSubscriber>> no_subscribers;
  DiagnosticStatusWrapper s;
  diagnostics.live(s, in, out, no_subscribers, 0.0, kArrival.toSec());
  EXPECT_EQ(s.level, DiagnosticStatus::WARN);
  EXPECT_EQ(s.message, "no observation epoch decoded yet");
  EXPECT_EQ(value(s, "product mode"), std::string(ppp::liveProductModeName(in.live()->mode())));
  EXPECT_EQ(value(s, "estimator resets at receiver restarts"), "0");
}
