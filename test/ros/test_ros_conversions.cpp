// Conversions ROS messages <-> core types, and the CorrectionBuffer rules.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ppp_bayes_tree/models/correction_buffer.h"
#include "ppp_bayes_tree/models/stream_bias_provider.h"
#include "ppp_bayes_tree/ros/bag_writer.h"
#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/ros/node_options.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"

namespace {

const ppp::SimulatedFlight& flight() {
  static const ppp::SimulatedFlight f = [] {
    ppp::SimulationConfig c;
    c.duration_s = 120.0;
    return ppp::simulateFlight(c, 3);
  }();
  return f;
}

}  // namespace

TEST(RosTime, WeekSecondsAndUtcStampOfKnownInstants) {
  // 2026-05-13 00:00:00 GPST: GPS week 2418 (2026-05-10 is a Sunday), Wednesday = 3 days = 259200 s.
  const ppp::GnssTime t = ppp::GnssTime::fromCalendar({2026, 5, 13, 0, 0, 0.0});
  const auto m = ppp_ros::toMessageTime(t);
  EXPECT_EQ(m.week, 2418);
  EXPECT_DOUBLE_EQ(m.seconds_of_week, 259200.0);
  EXPECT_EQ(m.time_system, "GPS");
  EXPECT_EQ(ppp_ros::fromMessageTime(m.week, m.seconds_of_week, "GPS"), t);
  // UTC = GPST - 18 s (IERS Bulletin C, since 2017): POSIX 1778630400 is 2026-05-13 00:00:00 UTC.
  EXPECT_EQ(ppp_ros::utcStamp(t).sec, 1778630400u - 18u);
  // ...and back from the stamp (ppp_bag_solve reads truth/path stamps so).
  EXPECT_EQ(ppp_ros::fromUtcStamp(ros::Time(1778630400u - 18u, 0)), t);
  EXPECT_NEAR(ppp_ros::fromUtcStamp(ppp_ros::utcStamp(t + 0.25)) - (t + 0.25), 0.0, 1e-9);
  // The same instant read in UTC and back.
  const auto u = ppp_ros::toMessageTime(t + 0.1234567, ppp::TimeSystem::UTC);
  EXPECT_DOUBLE_EQ(u.seconds_of_week, 259200.0 - 18.0 + 0.1234567);
  EXPECT_NEAR(ppp_ros::fromMessageTime(u.week, u.seconds_of_week, u.time_system) - (t + 0.1234567), 0.0, 1e-9);
  EXPECT_THROW(ppp_ros::fromMessageTime(2418, std::nan(""), "GPS"), std::invalid_argument);
  EXPECT_THROW(ppp_ros::fromMessageTime(2418, 10.0, "XYZ"), std::invalid_argument);
}

TEST(RosObservations, RoundTripIsLossless) {
  const ppp::SimulatedFlight& f = flight();
  ppp::RinexObsHeader layout;
  for (std::size_t k = 0; k < 5; ++k) {
    const ppp::ObsEpoch& e = f.epochs[k];
    const auto msg = ppp_ros::toMessage(e, f.header);
    EXPECT_EQ(msg.satellites.size(), e.satellites.size());
    ppp::ObsEpoch back;
    ppp_ros::ConversionIssues issues;
    ppp_ros::fromMessage(msg, layout, back, issues);
    EXPECT_EQ(issues.total(), 0u);
    EXPECT_EQ(back.time, e.time);
    ASSERT_EQ(back.satellites.size(), e.satellites.size());
    for (std::size_t i = 0; i < e.satellites.size(); ++i) {
      for (const ppp::Observation* o = e.begin(i); o != e.end(i); ++o) {
        const ppp::Observation* b = back.find(e.satellites[i].satellite, o->code);
        ASSERT_NE(b, nullptr) << o->code.toString();
        EXPECT_EQ(b->value, o->value);
        EXPECT_EQ(b->lli, o->lli);
        EXPECT_EQ(b->ssi, o->ssi);
      }
    }
  }
  EXPECT_EQ(layout.antenna_type, f.header.antenna_type);
}

TEST(RosObservations, AbsurdValuesAndUnknownIdsAreExcludedAndCounted) {
  auto msg = ppp_ros::toMessage(flight().epochs[0], flight().header);
  msg.satellites[0].signals[0].pseudorange_m = std::numeric_limits<double>::infinity();
  msg.satellites[1].signals[0].pseudorange_m = 12.0;  // below 1000 km: absurd
  msg.satellites[2].satellite = "??";
  ppp::RinexObsHeader layout;
  ppp::ObsEpoch e;
  ppp_ros::ConversionIssues issues;
  ppp_ros::fromMessage(msg, layout, e, issues);
  EXPECT_EQ(issues.counts["observation excluded: non-finite value"], 1u);
  EXPECT_EQ(issues.counts["observation excluded: pseudorange outside [1e6, 1e8] m"], 1u);
  EXPECT_EQ(issues.counts["unknown satellite id '??'"], 1u);
  EXPECT_EQ(e.satellites.size(), msg.satellites.size() - 1);
}

// A GLONASS slot whose channel first comes with a later message changes the layout
// (the node then remakes its signal selection, which takes the frequencies from it).
TEST(RosObservations, AGlonassChannelLearnedLaterChangesTheLayout) {
  auto msg = ppp_ros::toMessage(flight().epochs[0], flight().header);
  msg.satellites[0].satellite = "R05";
  msg.satellites[0].glonass_channel = ppp_bayes_tree::GnssSatelliteObservations::GLONASS_CHANNEL_UNKNOWN;
  ppp::RinexObsHeader layout;
  ppp::ObsEpoch e;
  ppp_ros::ConversionIssues issues;
  EXPECT_TRUE(ppp_ros::fromMessage(msg, layout, e, issues));    // new types
  EXPECT_FALSE(ppp_ros::fromMessage(msg, layout, e, issues));   // nothing new
  EXPECT_FALSE(layout.glonass_channels.channel(5).has_value());
  msg.satellites[0].glonass_channel = 1;
  EXPECT_TRUE(ppp_ros::fromMessage(msg, layout, e, issues));    // the channel of R05 learned
  EXPECT_EQ(layout.glonass_channels.channel(5), std::optional<int>(1));
  EXPECT_FALSE(ppp_ros::fromMessage(msg, layout, e, issues));
  EXPECT_EQ(issues.total(), 0u);
}

TEST(CorrectionBuffer, MatchesTheFileProductsAndNeverExtrapolates) {
  const ppp::SimulatedFlight& f = flight();
  ppp_ros::BagWriteOptions o;
  const auto batches = ppp_ros::sampleCorrections(f.products, f.epochs.front().time, f.epochs.back().time, o);
  ASSERT_GT(batches.size(), 4u);
  ppp::CorrectionBuffer buffer;
  for (const auto& b : batches) {
    // Through the message and back, as the node receives them.
    ppp_ros::ConversionIssues issues;
    ASSERT_EQ(buffer.add(ppp_ros::fromMessage(ppp_ros::toMessage(b), issues)), ppp::BatchAddResult::Added);
    EXPECT_EQ(issues.total(), 0u);
  }
  EXPECT_EQ(buffer.add(batches[1]), ppp::BatchAddResult::Duplicate);
  // Between batches: Hermite orbits within 1 mm of the SP3 Lagrange, clocks identical (both linear in CLK).
  double worst_orbit = 0.0, worst_clock = 0.0;
  for (double dt = 0.0; dt < 100.0; dt += 7.3) {
    const ppp::GnssTime t = f.epochs.front().time + dt;
    for (const auto& s : batches.front().satellites) {
      const auto a = buffer.ephemeris().orbit(s.satellite, t), b = f.products.orbit(s.satellite, t);
      const auto ca = buffer.ephemeris().clock(s.satellite, t), cb = f.products.clock(s.satellite, t);
      ASSERT_TRUE(a.ok() && b.ok() && ca.ok() && cb.ok()) << a.reason << ca.reason;
      worst_orbit = std::max(worst_orbit, (a.value->position_ecef_m - b.value->position_ecef_m).norm());
      worst_clock = std::max(worst_clock, std::abs(ca.value->clock_bias_s - cb.value->clock_bias_s));
    }
  }
  EXPECT_LT(worst_orbit, 1e-3);
  EXPECT_LT(worst_clock * 299792458.0, 1e-6);
  // After the newest batch: the reason, no value.
  const auto late = buffer.ephemeris().clock(batches.front().satellites[0].satellite, *buffer.newest() + 1.0);
  EXPECT_FALSE(late.ok());
  EXPECT_EQ(late.status, ppp::ProductStatus::OutsideSpan);
  const auto late_orbit = buffer.ephemeris().orbit(batches.front().satellites[0].satellite, *buffer.newest() + 1.0);
  EXPECT_FALSE(late_orbit.ok());
  EXPECT_FALSE(buffer.covers(*buffer.newest() + 0.5));
}

TEST(RosNodeOptions, TemplateBindsAndUnknownKeysFail) {
  const ppp::PppConfig c = ppp::loadPppConfig(std::string(PPP_REPO_DIR) + "/config/ppp.yaml");
  const auto o = ppp_ros::bindRosNodeOptions(c.ros, "ppp.yaml");
  EXPECT_EQ(o.map_frame, "map");
  EXPECT_DOUBLE_EQ(o.correction_wait_s, 35.0);
  // The template documents the built-in defaults of the time guard, queues and staleness.
  const ppp_ros::RosNodeOptions defaults;
  EXPECT_EQ(o.time_jump_confirm_epochs, defaults.time_jump_confirm_epochs);
  EXPECT_DOUBLE_EQ(o.max_forward_step_s, defaults.max_forward_step_s);
  EXPECT_DOUBLE_EQ(o.reset_backwards_threshold_s, defaults.reset_backwards_threshold_s);
  EXPECT_EQ(o.observation_queue_size, defaults.observation_queue_size);
  EXPECT_EQ(o.correction_queue_size, defaults.correction_queue_size);
  EXPECT_DOUBLE_EQ(o.corrections_stale_warn_s, defaults.corrections_stale_warn_s);
  EXPECT_DOUBLE_EQ(o.corrections_stale_error_s, defaults.corrections_stale_error_s);
  // A queue smaller than what the correction wait buffers, and an ERROR threshold not above the WARN one, fail.
  const ppp::PppConfig small = ppp::parsePppConfig(
      "ros: {input: {max_pending_epochs: 100, observation_queue_size: 50}}", "text");
  EXPECT_THROW(ppp_ros::bindRosNodeOptions(small.ros, "text"), ppp::ConfigError);
  const ppp::PppConfig stale = ppp::parsePppConfig(
      "ros: {diagnostics: {corrections_stale_warn_s: 60, corrections_stale_error_s: 60}}", "text");
  EXPECT_THROW(ppp_ros::bindRosNodeOptions(stale.ros, "text"), ppp::ConfigError);
  const ppp::PppConfig bad = ppp::parsePppConfig("ros: {frames: {mapp: x}}", "text");
  EXPECT_THROW(ppp_ros::bindRosNodeOptions(bad.ros, "text"), ppp::ConfigError);
  const ppp::PppConfig bad2 = ppp::parsePppConfig("ros: {input: {correction_wait_s: -1}}", "text");
  EXPECT_THROW(ppp_ros::bindRosNodeOptions(bad2.ros, "text"), ppp::ConfigError);
}

// The nodes bind their ROS parameters (XmlRpc-typed) with the core binder: a
// string parameter is text, refused where a number, a bool or a list is
// expected (the parameter-server twin of a quoted "7" in a file), with the key path.
TEST(RosNodeOptions, ParameterServerTypesAreKeptAndStringsAreNeverNumbers) {
  const auto error_of = [](XmlRpc::XmlRpcValue params) -> std::string {
    try {
      const ppp::PppConfig c = ppp::bindPppConfig(ppp_ros::xmlRpcToYaml(params), "ROS parameters /node");
      ppp_ros::bindRosNodeOptions(c.ros, c.source_name);
    } catch (const ppp::ConfigError& e) {
      return e.what();
    }
    return "";
  };
  XmlRpc::XmlRpcValue ok;
  ok["stochastic"]["position"]["initial_sigma_m"] = 7;  // an int where a double is expected: fine
  ok["estimator"]["postfit_check"] = false;
  ok["measurement_model"]["troposphere"]["mapping"] = std::string("niell");
  ok["ros"]["status"]["converged_horizontal_sigma_m"] = 0.25;
  ok["ros"]["products"]["atx"][0] = std::string("/data/a.atx");
  ok["ros"]["frames"]["antenna_lever_arm_m"][0] = 0.1;
  ok["ros"]["frames"]["antenna_lever_arm_m"][1] = 0;
  ok["ros"]["frames"]["antenna_lever_arm_m"][2] = 0.9;
  EXPECT_EQ(error_of(ok), "");
  const ppp::PppConfig c = ppp::bindPppConfig(ppp_ros::xmlRpcToYaml(ok), "ROS parameters /node");
  EXPECT_EQ(c.stochastic.position.initial_sigma_m, 7.0);
  EXPECT_FALSE(c.estimator.screening.postfit_check);
  EXPECT_EQ(c.model.mapping, ppp::TroposphereMapping::Niell);
  const auto o = ppp_ros::bindRosNodeOptions(c.ros, c.source_name);
  EXPECT_EQ(o.atx, std::vector<std::string>{"/data/a.atx"});
  EXPECT_DOUBLE_EQ(o.antenna_lever_arm_m.z(), 0.9);
  EXPECT_DOUBLE_EQ(o.converged_horizontal_sigma_m, 0.25);

  XmlRpc::XmlRpcValue number;
  number["stochastic"]["position"]["initial_sigma_m"] = std::string("7");
  EXPECT_NE(error_of(number).find("ROS parameters /node: stochastic.position.initial_sigma_m: expected a number, got "
                                  "the text \"7\""),
            std::string::npos)
      << error_of(number);
  XmlRpc::XmlRpcValue boolean;
  boolean["smoother"]["robust"] = std::string("true");
  EXPECT_NE(error_of(boolean).find("smoother.robust: expected true or false"), std::string::npos) << error_of(boolean);
  XmlRpc::XmlRpcValue ros_number;
  ros_number["ros"]["status"]["converged_vertical_sigma_m"] = std::string("0.2");
  EXPECT_NE(error_of(ros_number).find("ros.status.converged_vertical_sigma_m: expected a number"), std::string::npos)
      << error_of(ros_number);
  XmlRpc::XmlRpcValue list;
  list["ros"]["products"]["atx"] = std::string("/data/a.atx");  // a path list given as one string
  EXPECT_NE(error_of(list).find("ros.products.atx: expected a list"), std::string::npos) << error_of(list);
  XmlRpc::XmlRpcValue arm;
  arm["ros"]["frames"]["antenna_lever_arm_m"][0] = std::string("0.1");
  arm["ros"]["frames"]["antenna_lever_arm_m"][1] = 0.0;
  arm["ros"]["frames"]["antenna_lever_arm_m"][2] = 0.0;
  EXPECT_NE(error_of(arm).find("ros.frames.antenna_lever_arm_m: expected finite numbers"), std::string::npos)
      << error_of(arm);
}

TEST(StreamBiases, ThroughTheMessagesTheyAnswerAsTheProductsFromTheirBatchOn) {
  // A simulated flight whose products carry phase OSBs (constant UPDs, code OSB 0):
  // each batch message carries them for the header's code and phase types; the
  // node's StreamBiasProvider answers exactly the products' values from the first
  // batch on, and nothing before it.
  ppp::SimulationConfig c;
  c.duration_s = 120.0;
  c.errors.ambiguity.satellite_phase_biases = true;
  const ppp::SimulatedFlight f = ppp::simulateFlight(c, 5);
  ASSERT_FALSE(f.phase_biases.empty());
  ppp_ros::BagWriteOptions o;
  const auto batches = ppp_ros::sampleCorrections(f.products, f.epochs.front().time, f.epochs.back().time, o);
  ASSERT_GT(batches.size(), 4u);
  ppp::StreamBiasProvider stream;
  std::size_t carried = 0;
  for (const auto& b : batches) {
    auto msg = ppp_ros::toMessage(b);
    std::vector<ppp::SatelliteId> sats;
    for (const auto& s : b.satellites) sats.push_back(s.satellite);
    ppp_ros::addBiases(msg, ppp::sampleBiases(f.phase_biases, b.time, f.header, sats));
    EXPECT_EQ(msg.ar_bias_source, f.phase_biases.describeSource());
    for (const auto& s : msg.satellites) carried += s.biases.size();
    ppp_ros::ConversionIssues issues;
    stream.add(ppp_ros::biasesFromMessage(msg, issues));
    EXPECT_EQ(issues.total(), 0u);
  }
  ASSERT_GT(carried, 0u);
  const ppp::SatelliteId sat = batches.front().satellites.front().satellite;
  const ppp::ObservationCode l1 = *ppp::ObservationCode::parse("L1C"), c1 = *ppp::ObservationCode::parse("C1C");
  EXPECT_FALSE(stream.phaseBias(sat, l1, batches.front().time - 1.0).value_m) << "before the first batch";
  std::size_t compared = 0;
  for (const auto& e : f.epochs) {
    if (e.time < batches.front().time) continue;
    for (const auto& so : e.satellites)
      for (const ppp::ObservationCode& code : f.header.types(so.satellite.system)) {
        const bool phase = code.type == ppp::ObservableType::CarrierPhase;
        if (!phase && code.type != ppp::ObservableType::Pseudorange) continue;
        const auto want = phase ? f.phase_biases.phaseBias(so.satellite, code, e.time)
                                : f.phase_biases.codeBias(so.satellite, code, e.time);
        const auto got = phase ? stream.phaseBias(so.satellite, code, e.time) : stream.codeBias(so.satellite, code, e.time);
        ASSERT_EQ(want.value_m.has_value(), got.value_m.has_value()) << so.satellite.toString() << " " << code.toString();
        if (want.value_m) EXPECT_EQ(*want.value_m, *got.value_m);
        ++compared;
      }
  }
  EXPECT_GT(compared, 100u);
  EXPECT_TRUE(stream.codeBias(sat, c1, f.epochs.back().time).value_m.has_value() ==
              f.phase_biases.codeBias(sat, c1, f.epochs.back().time).value_m.has_value());
}

TEST(StreamBiases, BadBiasesAreExcludedAndCountedANewerBatchReplacesAndOldOnesAreDropped) {
  ppp::CorrectionBatch b;
  b.time = ppp::GnssTime::fromGpsWeek(2100, 3600.0);
  b.satellites.resize(1);
  b.satellites[0].satellite = *ppp::SatelliteId::parse("G05");
  b.satellites[0].clock_bias_s = 1e-4;
  auto msg = ppp_ros::toMessage(b);
  ppp_bayes_tree::ObservableBias ok, unknown, absurd, nan;
  ok.observable = "L1C";
  ok.bias_m = 0.05;
  unknown.observable = "Q1C";
  unknown.bias_m = 0.1;
  absurd.observable = "L2W";
  absurd.bias_m = 5000.0;
  nan.observable = "C1C";
  nan.bias_m = std::numeric_limits<double>::quiet_NaN();
  msg.satellites[0].biases = {ok, unknown, absurd, nan};
  ppp_ros::ConversionIssues issues;
  // Biases without their source are not used (nobody vouches that they go with the clocks).
  EXPECT_TRUE(ppp_ros::biasesFromMessage(msg, issues).biases.empty());
  EXPECT_EQ(issues.total(), 1u);
  msg.ar_bias_source = "test biases";
  issues = {};
  const ppp::SatelliteBiasBatch batch = ppp_ros::biasesFromMessage(msg, issues);
  EXPECT_EQ(issues.total(), 3u);  // unknown observable, absurd, NaN
  ASSERT_EQ(batch.biases.size(), 1u);
  ASSERT_EQ(batch.biases.begin()->second.size(), 1u);

  ppp::StreamBiasProvider stream(600.0);
  stream.add(batch);
  const ppp::SatelliteId g05 = *ppp::SatelliteId::parse("G05");
  const ppp::ObservationCode l1 = *ppp::ObservationCode::parse("L1C");
  EXPECT_EQ(*stream.phaseBias(g05, l1, b.time + 10.0).value_m, 0.05);
  EXPECT_NE(stream.describeSource().find("test biases"), std::string::npos);
  ppp::SatelliteBiasBatch newer = batch;
  newer.time = b.time + 30.0;
  newer.biases.begin()->second[0].bias_m = 0.07;
  stream.add(newer);
  EXPECT_EQ(*stream.phaseBias(g05, l1, b.time + 10.0).value_m, 0.05);  // the older batch's epoch
  EXPECT_EQ(*stream.phaseBias(g05, l1, b.time + 40.0).value_m, 0.07);
  ppp::SatelliteBiasBatch much_later = newer;
  much_later.time = b.time + 1000.0;
  much_later.biases.begin()->second[0].bias_m = 0.09;
  stream.add(much_later);
  EXPECT_EQ(stream.batches(), 1u);  // the two first are older than the 600 s history: dropped
  EXPECT_EQ(*stream.phaseBias(g05, l1, b.time + 1000.0).value_m, 0.09);
  EXPECT_FALSE(stream.phaseBias(g05, l1, b.time + 500.0).value_m);
}
