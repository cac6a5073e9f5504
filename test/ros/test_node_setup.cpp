// The node's set-up pieces (ppp_node.h keeps only their order) without a ROS master:
// the configuration (node_config.h), the products (assembleNodeProducts), the live
// subscriptions, the processor's products, the start notes, the datum and the
// epoch figures.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "node_test_messages.h"
#include "node_test_records.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ros/node_config.h"
#include "ppp_bayes_tree/ros/node_diagnostics.h"
#include "ppp_bayes_tree/ros/node_inputs.h"
#include "ppp_bayes_tree/ros/node_outputs.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace {

using ppp_ros::RosNodeOptions;

ppp_ros::NodeConfig configOf(const std::string& yaml, const std::string& estimator = "") {
  return ppp_ros::bindNodeConfig(YAML::Load(yaml), "test parameters", estimator);
}

std::string resolve(const std::string& topic) { return "/ns/" + topic; }

}  // namespace

TEST(NodeSetup, TheLiveInputTakesTheBroadcastFallbackOfTheSsrSection) {
  const ppp_ros::NodeConfig defaults = configOf("{}", "smoother");
  EXPECT_EQ(defaults.ros.estimator, "smoother");
  EXPECT_TRUE(defaults.ros.live_input.fallback.enabled);
  EXPECT_EQ(defaults.ros.live_input.fallback.min_ssr_satellites, 4);
  const ppp_ros::NodeConfig c = configOf(
      "ssr: {broadcast_fallback: false, min_ssr_satellites: 7, broadcast_orbit_sigma_m: 3.0}\n"
      "ros: {live: {observations: [rtcm]}}");
  EXPECT_EQ(c.ros.estimator, "ekf");  // RosNodeOptions' default
  // The one rule of ppp_solve --nav --ssr and the live input: the same keys.
  EXPECT_FALSE(c.ros.live_input.fallback.enabled);
  EXPECT_EQ(c.ros.live_input.fallback.min_ssr_satellites, 7);
  EXPECT_DOUBLE_EQ(c.ros.live_input.fallback.orbit_sigma_m, 3.0);
  EXPECT_EQ(c.ros.live_input.fallback.min_ssr_satellites, c.ppp.ssr.fallback.min_ssr_satellites);
  // The keys are no longer the live section's: refused there, naming the key and where it went.
  for (const char* key : {"broadcast_fallback: true", "min_ssr_satellites: 5", "broadcast_orbit_sigma_m: 2.0",
                          "broadcast_clock_sigma_m: 2.0"}) {
    try {
      configOf(std::string("ros: {live: {") + key + "}}");
      ADD_FAILURE() << "ros.live." << key << " was accepted";
    } catch (const ppp::ConfigError& e) {
      const std::string name = std::string(key).substr(0, std::string(key).find(':'));
      EXPECT_NE(std::string(e.what()).find("ros.live." + name), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("moved to ssr." + name), std::string::npos) << e.what();
    }
  }
}

TEST(NodeSetup, ProductsNeedAntexFilesWhenTheAntennaCorrectionsAreOn) {
  const ppp_ros::NodeConfig c = configOf("{}");
  ASSERT_TRUE(c.ppp.model.satellite_antenna);
  try {
    ppp_ros::assembleNodeProducts(c.ppp, c.ros);
    ADD_FAILURE() << "no ANTEX file was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("ros/products/atx is empty"), std::string::npos) << e.what();
  }
}

TEST(NodeSetup, ALiveSsrFeedTakesTheConfiguredAntennaModel) {
  const std::string corrections_off =
      "measurement_model: {corrections: {satellite_antenna: false}}\n";
  // Streamed corrections topic: the products name no model yet (the first batch declares it).
  const ppp_ros::NodeConfig topic = configOf(corrections_off);
  const ppp::ProductAssembly a = ppp_ros::assembleNodeProducts(topic.ppp, topic.ros);
  EXPECT_EQ(a.ephemeris(), nullptr);
  EXPECT_EQ(a.arGate().detail.find("ssr.antenna_model"), std::string::npos) << a.arGate().detail;
  // A live SSR feed (ros.live corrections): its model is ssr.antenna_model, here not set.
  const ppp_ros::NodeConfig live = configOf(corrections_off + "ros: {live: {observations: [rtcm], corrections: [ssr]}}");
  const ppp::ProductAssembly b = ppp_ros::assembleNodeProducts(live.ppp, live.ros);
  EXPECT_NE(b.arGate().detail.find("set ssr.antenna_model"), std::string::npos) << b.arGate().detail;
}

TEST(NodeSetup, ObservationTopicsAreOneReceiverStreamCorrectionsEachTheirOwn) {
  const ppp_ros::NodeConfig c =
      configOf("ros: {live: {observations: [rawx, 'sfrbx:ubx'], corrections: [ssr_a, ssr_b]}}");
  const auto subs = ppp_ros::liveSubscriptions(c.ros, resolve);
  ASSERT_EQ(subs.size(), 4u);
  EXPECT_EQ(subs[0].topic.topic, "rawx");
  EXPECT_EQ(subs[0].stream, "/ns/rawx+/ns/sfrbx");
  EXPECT_EQ(subs[1].stream, "/ns/rawx+/ns/sfrbx");
  EXPECT_EQ(subs[1].topic.format, ppp::StreamFormat::Ubx);
  EXPECT_EQ(subs[2].topic.topic, "ssr_a");
  EXPECT_EQ(subs[2].stream, "");
  EXPECT_EQ(subs[3].stream, "");
  EXPECT_TRUE(ppp_ros::liveSubscriptions(RosNodeOptions{}, resolve).empty());  // topic input
}

TEST(NodeSetup, TheTopicInputsProcessorTakesTheCorrectionBatchesAndTheProductsBiases) {
  node_test::Warnings w;
  ppp_ros::NodeInputs in(RosNodeOptions{}, w.sink());
  const ppp_ros::NodeConfig c =
      configOf("measurement_model: {corrections: {satellite_antenna: false}}\n");
  const ppp::ProductAssembly products = ppp_ros::assembleNodeProducts(c.ppp, c.ros);
  EXPECT_EQ(&in.ephemeris(), static_cast<const ppp::EphemerisSource*>(&in.corrections()));
  EXPECT_EQ(in.codeBiases(products), nullptr);  // no Bias-SINEX file, no live input
}

TEST(NodeSetup, TheSmootherSaysWhatItCostsAndWhereItsStatesGo) {
  const ppp_ros::StartNote full = ppp_ros::smootherCostNote(0.0, "");
  EXPECT_TRUE(full.warning);
  EXPECT_NE(full.text.find("full smoother (smoother/fixed_lag_s 0)"), std::string::npos) << full.text;
  const ppp_ros::StartNote lag = ppp_ros::smootherCostNote(30.0, "/tmp/states.csv");
  EXPECT_FALSE(lag.warning);
  EXPECT_EQ(lag.text, "ppp_smoother_node: fixed-lag smoother, lag 30 s: memory and update time bounded; states "
                      "leaving the lag written to /tmp/states.csv");
  EXPECT_NE(ppp_ros::smootherCostNote(2.5, "").text.find("lag 2.5 s"), std::string::npos);
  EXPECT_NE(ppp_ros::smootherCostNote(2.5, "").text.find("not written"), std::string::npos);
}

TEST(NodeSetup, TheStartSummaryNamesTheInputsItWaitsFor) {
  RosNodeOptions o;
  o.bias = "COD.BIA";
  const ppp_ros::StartNote topics = ppp_ros::startSummary(o, "config/ppp.yaml", 2, {}, resolve);
  EXPECT_EQ(topics.text, "ppp_ekf_node: config from config/ppp.yaml, 2 ANTEX file(s), bias COD.BIA, waiting for "
                         "/ns/gnss/observations and /ns/gnss/corrections, no attitude source");
  o.live_observation_topics = {{"rtcm", std::nullopt}};
  o.attitude_topic = "imu";
  o.bias.clear();
  const ppp_ros::StartNote live = ppp_ros::startSummary(o, "p", 1, {"/ns/rtcm", "/ns/ssr"}, resolve);
  EXPECT_EQ(live.text, "ppp_ekf_node: config from p, 1 ANTEX file(s), bias none, waiting for the live streams "
                       "/ns/rtcm /ns/ssr, attitude from /ns/imu");
}

TEST(NodeSetup, TheDatumOfARequestOrOfTheConfiguration) {
  const ppp_ros::DatumRequest ok = ppp_ros::datumRequest(47.0, 8.0, 500.0);
  ASSERT_TRUE(ok.position_ecef_m);
  EXPECT_EQ(ok.message, "datum set");
  const Eigen::Vector3d expected = ppp::geodeticToEcef({47.0 * ppp::kDegToRad, 8.0 * ppp::kDegToRad, 500.0});
  EXPECT_LT((*ok.position_ecef_m - expected).norm(), 1e-9);
  for (const auto& bad : {ppp_ros::datumRequest(91.0, 0.0, 0.0), ppp_ros::datumRequest(0.0, NAN, 0.0),
                          ppp_ros::datumRequest(0.0, 0.0, 2e6)}) {
    EXPECT_FALSE(bad.position_ecef_m);
    EXPECT_NE(bad.message.find("invalid datum"), std::string::npos);
  }
  RosNodeOptions o;
  EXPECT_FALSE(ppp_ros::configuredDatum(o));  // first_fix
  o.datum_mode = "configured";
  o.datum_latitude_deg = 47.0;
  o.datum_longitude_deg = 8.0;
  o.datum_height_m = 500.0;
  ASSERT_TRUE(ppp_ros::configuredDatum(o));
  EXPECT_LT((*ppp_ros::configuredDatum(o) - expected).norm(), 1e-9);
}

TEST(NodeSetup, EpochFiguresTakeTheInputsAndTheEstimatorsState) {
  node_test::Warnings w;
  ppp_ros::NodeInputs in(RosNodeOptions{}, w.sink());
  const ppp_ros::NodeConfig c = configOf("{}");
  std::string why;
  auto ekf = ppp::makeEstimator("ekf", c.ppp, &why);
  ASSERT_TRUE(ekf) << why;
  ppp::ObsEpoch epoch;
  epoch.time = node_test::day();
  ppp::PppEpochRecord rec = node_test::solvedRecord(epoch.time, node_test::equator(), false);
  rec.active_biases = 5;
  const ppp_ros::EpochFigures f = ppp_ros::epochFigures(in, *ekf, epoch, rec, 0.002, {"antenna warning"});
  EXPECT_DOUBLE_EQ(f.update_time_s, 0.002);
  EXPECT_TRUE(std::isnan(f.correction_latency_s));  // no correction batch yet
  EXPECT_EQ(f.product_mode, in.productMode());
  // The EKF updates its whole state: the layout and the active biases.
  EXPECT_EQ(f.variables_reeliminated, static_cast<std::uint32_t>(ekf->layout().dim() + 5));
  ASSERT_EQ(f.warnings.size(), 1u);
  EXPECT_EQ(f.warnings[0], "antenna warning");
}
