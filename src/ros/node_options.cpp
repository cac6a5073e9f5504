#include "ppp_bayes_tree/ros/node_options.h"

#include <cmath>

#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "ppp_bayes_tree/ros/gnss_stream_subscriber.h"

namespace ppp_ros {
namespace {

std::vector<LiveStreamTopic> liveTopics(ppp::YamlSection& s, const std::string& key) {
  std::vector<LiveStreamTopic> topics;
  for (const std::string& entry : s.textList(key, {}, true)) {
    LiveStreamTopic t;
    const std::size_t colon = entry.rfind(':');
    t.topic = entry.substr(0, colon);
    if (colon != std::string::npos) {
      t.format = parseStreamFormatHint(entry.substr(colon + 1));
      if (!t.format) s.fail(key, "\"" + entry + "\": the format after ':' must be rtcm3 or ubx");
    }
    if (t.topic.empty()) s.fail(key, "\"" + entry + "\": empty topic name");
    topics.push_back(t);
  }
  return topics;
}

/// ros.topics: the input topics.
void bindTopics(ppp::YamlSection& s, RosNodeOptions& o) {
  ppp::YamlSection t = s.section("topics");
  o.observations_topic = t.text("observations", o.observations_topic);
  o.corrections_topic = t.text("corrections", o.corrections_topic);
  t.finish();
}

/// ros.products: the product files the node reads (ANTEX, Bias-SINEX, BLQ).
void bindProducts(ppp::YamlSection& s, RosNodeOptions& o) {
  ppp::YamlSection p = s.section("products");
  o.atx = p.textList("atx", {}, true);
  o.bias = p.text("bias", "");
  o.blq = p.text("blq", "");
  p.finish();
}

/// ros.frames: the TF frames, whether the node publishes TF, and the antenna lever arm.
void bindFrames(ppp::YamlSection& s, RosNodeOptions& o) {
  ppp::YamlSection f = s.section("frames");
  o.earth_frame = f.text("earth", o.earth_frame);
  o.map_frame = f.text("map", o.map_frame);
  o.odom_frame = f.text("odom", o.odom_frame);
  o.base_frame = f.text("base_link", o.base_frame);
  o.antenna_frame = f.text("gnss_antenna", o.antenna_frame);
  o.publish_tf = f.boolean("publish_tf", o.publish_tf);
  const auto arm = f.numberList("antenna_lever_arm_m", {0.0, 0.0, 0.0}, 3);
  for (int i = 0; i < 3; ++i) o.antenna_lever_arm_m[i] = arm[static_cast<std::size_t>(i)];
  f.finish();
}

/// ros.attitude: the attitude topic that turns the lever arm into the frame of the map.
void bindAttitude(ppp::YamlSection& s, RosNodeOptions& o) {
  ppp::YamlSection a = s.section("attitude");
  o.attitude_topic = a.text("topic", o.attitude_topic);
  o.attitude_max_age_s = a.number("max_age_s", o.attitude_max_age_s, ppp::Bound::Positive);
  a.finish();
}

/// ros.datum: the local datum of the map frame.
void bindDatum(ppp::YamlSection& s, RosNodeOptions& o) {
  ppp::YamlSection d = s.section("datum");
  o.datum_mode = d.choice("mode", o.datum_mode, {"first_fix", "configured"});
  o.datum_latitude_deg = d.number("latitude_deg", o.datum_latitude_deg);
  o.datum_longitude_deg = d.number("longitude_deg", o.datum_longitude_deg);
  o.datum_height_m = d.number("height_m", o.datum_height_m);
  if (std::abs(o.datum_latitude_deg) > 90.0) d.fail("latitude_deg", "must be in [-90, 90]");
  if (std::abs(o.datum_longitude_deg) > 360.0) d.fail("longitude_deg", "must be in [-360, 360]");
  d.finish();
}

/// ros.input: the epoch queue and the wait for corrections.
void bindInput(ppp::YamlSection& s, RosNodeOptions& o) {
  ppp::YamlSection i = s.section("input");
  o.correction_wait_s = i.number("correction_wait_s", o.correction_wait_s, ppp::Bound::NonNegative);
  o.correction_history_s = i.number("correction_history_s", o.correction_history_s, ppp::Bound::Positive);
  o.reset_backwards_threshold_s =
      i.number("reset_backwards_threshold_s", o.reset_backwards_threshold_s, ppp::Bound::Positive);
  o.max_forward_step_s = i.number("max_forward_step_s", o.max_forward_step_s, ppp::Bound::Positive);
  o.time_jump_confirm_epochs = static_cast<std::size_t>(i.integer("time_jump_confirm_epochs", 3, 1));
  if (o.time_jump_confirm_epochs > 100) i.fail("time_jump_confirm_epochs", "must be in [1, 100] epochs");
  o.max_pending_epochs = static_cast<std::size_t>(i.integer("max_pending_epochs", 1000, 1));
  o.observation_queue_size = static_cast<std::size_t>(i.integer("observation_queue_size", 2000, 1));
  if (o.observation_queue_size < o.max_pending_epochs)
    i.fail("observation_queue_size", "must be at least max_pending_epochs (" + std::to_string(o.max_pending_epochs) +
                                         "): the queue must hold what the correction wait buffers");
  o.correction_queue_size = static_cast<std::size_t>(i.integer("correction_queue_size", 1000, 1));
  i.finish();
}

/// ros.status: when PppStatus says converged.
void bindStatus(ppp::YamlSection& s, RosNodeOptions& o) {
  ppp::YamlSection st = s.section("status");
  o.converged_horizontal_sigma_m =
      st.number("converged_horizontal_sigma_m", o.converged_horizontal_sigma_m, ppp::Bound::Positive);
  o.converged_vertical_sigma_m =
      st.number("converged_vertical_sigma_m", o.converged_vertical_sigma_m, ppp::Bound::Positive);
  st.finish();
}

/// ros.diagnostics: the diagnostics thresholds and the path publication.
void bindDiagnostics(ppp::YamlSection& s, RosNodeOptions& o) {
  ppp::YamlSection dg = s.section("diagnostics");
  o.expected_observation_rate_hz =
      dg.number("expected_observation_rate_hz", o.expected_observation_rate_hz, ppp::Bound::NonNegative);
  o.max_correction_latency_s = dg.number("max_correction_latency_s", o.max_correction_latency_s, ppp::Bound::Positive);
  o.corrections_stale_warn_s =
      dg.number("corrections_stale_warn_s", o.corrections_stale_warn_s, ppp::Bound::Positive);
  o.corrections_stale_error_s =
      dg.number("corrections_stale_error_s", o.corrections_stale_error_s, ppp::Bound::Positive);
  if (o.corrections_stale_error_s <= o.corrections_stale_warn_s)
    dg.fail("corrections_stale_error_s", "must exceed corrections_stale_warn_s (" +
                                             std::to_string(o.corrections_stale_warn_s) + " s)");
  o.path_publish_rate_hz = dg.number("path_publish_rate_hz", o.path_publish_rate_hz, ppp::Bound::Positive);
  o.path_max_poses = static_cast<std::size_t>(dg.integer("path_max_poses", 20000, 1));
  dg.finish();
}

/// ros.smoothed: the smoother's smoothed outputs.
void bindSmoothed(ppp::YamlSection& s, RosNodeOptions& o) {
  ppp::YamlSection sm = s.section("smoothed");
  o.smoothed_path_publish_rate_hz =
      sm.number("path_publish_rate_hz", o.smoothed_path_publish_rate_hz, ppp::Bound::Positive);
  if (o.smoothed_path_publish_rate_hz > 10.0)
    sm.fail("path_publish_rate_hz", "must be in (0, 10] Hz (each publication re-reads the whole trajectory)");
  o.smoothed_odometry_delay_s = sm.number("odometry_delay_s", o.smoothed_odometry_delay_s, ppp::Bound::NonNegative);
  if (o.smoothed_odometry_delay_s > 3600.0)
    sm.fail("odometry_delay_s", "must be in [0, 3600] s (the marginal's cost grows with the delay)");
  o.smoothed_trajectory_csv = sm.text("trajectory_csv", o.smoothed_trajectory_csv);
  sm.finish();
}

/// ros.imu.initial_attitude: given | level_at_rest | align_in_motion.
RosImuOptions::StartAttitude startAttitude(ppp::YamlSection& m) {
  using A = RosImuOptions::StartAttitude;
  const std::string name = m.choice("initial_attitude", "given", {"given", "level_at_rest", "align_in_motion"});
  if (name == "level_at_rest") return A::LevelAtRest;
  if (name == "align_in_motion") return A::AlignInMotion;
  return A::Given;
}

/// ros.imu: the IMU input of an estimator with inertial states.
void bindImu(ppp::YamlSection& s, RosNodeOptions& o) {
  ppp::YamlSection m = s.section("imu");
  RosImuOptions& i = o.imu;
  i.topic = m.text("topic", i.topic);
  if (i.topic.empty()) m.fail("topic", "empty topic name");
  i.grade = m.choice("grade", i.grade, {"consumer_mems", "industrial_mems", "tactical"});
  i.extrinsics_from_tf = m.choice("extrinsics", "parameters", {"parameters", "tf"}) == "tf";
  const auto vector3 = [&m](const std::string& key, double bound) {
    const std::vector<double> v = m.numberList(key, {0.0, 0.0, 0.0}, 3);
    for (double x : v)
      if (!(std::abs(x) <= bound)) m.fail(key, "each value must be in [-" + std::to_string(bound) + ", " + std::to_string(bound) + "]");
    return Eigen::Vector3d(v[0], v[1], v[2]);
  };
  i.translation_m = vector3("translation_m", 100.0);
  i.rotation_rpy_deg = vector3("rotation_rpy_deg", 360.0);
  i.initial_attitude = startAttitude(m);
  i.initial_rpy_deg = vector3("initial_rpy_deg", 360.0);
  i.heading_speed_mps = m.number("heading_speed_mps", i.heading_speed_mps, ppp::Bound::Positive);
  if (i.heading_speed_mps > 100.0)
    m.fail("heading_speed_mps", "must be in (0, 100] m/s (the course sets the heading once the antenna moves this fast)");
  i.initial_velocity_enu_mps = vector3("initial_velocity_enu_mps", 1000.0);
  i.max_gap_s = m.number("max_gap_s", i.max_gap_s, ppp::Bound::Positive);
  i.max_gnss_offset_s = m.number("max_gnss_offset_s", i.max_gnss_offset_s, ppp::Bound::Positive);
  i.accel_full_scale_mps2 = m.number("accel_full_scale_mps2", i.accel_full_scale_mps2, ppp::Bound::NonNegative);
  i.gyro_full_scale_radps = m.number("gyro_full_scale_radps", i.gyro_full_scale_radps, ppp::Bound::NonNegative);
  i.attitude_sigma_valid_deg = m.number("attitude_sigma_valid_deg", i.attitude_sigma_valid_deg, ppp::Bound::Positive);
  i.buffer_s = m.number("buffer_s", i.buffer_s, ppp::Bound::Positive);
  if (i.buffer_s > 3600.0) m.fail("buffer_s", "must be in (0, 3600] s (the readings are kept in memory)");
  i.max_wait_s = m.number("max_wait_s", i.max_wait_s, ppp::Bound::NonNegative);
  if (i.max_wait_s > 1.0)
    m.fail("max_wait_s", "must be in [0, 1] s (each epoch the IMU does not cover waits this long: the fix is as late)");
  i.process_noise_adaptation = m.boolean("process_noise_adaptation", i.process_noise_adaptation);
  i.gap_bridge_max_s = m.number("gap_bridge_max_s", i.gap_bridge_max_s, ppp::Bound::NonNegative);
  if (i.gap_bridge_max_s > 600.0)
    m.fail("gap_bridge_max_s", "must be in [0, 600] s (an INS coast longer than 10 min cannot tell one cycle)");
  m.finish();
}

/// ros.live: raw live streams (RTCM 3, UBX) and the live input.
void bindLive(ppp::YamlSection& s, RosNodeOptions& o) {
  ppp::YamlSection l = s.section("live");
  o.live_observation_topics = liveTopics(l, "observations");
  o.live_correction_topics = liveTopics(l, "corrections");
  if (o.live_observation_topics.empty() && !o.live_correction_topics.empty())
    l.fail("corrections", "correction stream topics need an observation stream topic (ros.live.observations)");
  o.live_queue_size = static_cast<std::size_t>(l.integer("queue_size", 1000, 1));
  ppp::LiveInputOptions& in = o.live_input;
  in.navigation_files = l.textList("navigation_files", {}, true);
  const std::string date = l.text("reference_date", "");
  if (!date.empty() && !(in.reference_time = ppp::parseReferenceDate(date)))
    l.fail("reference_date", "\"" + date + "\" is not YYYY/MM/DD or YYYY/MM/DD HH:MM:SS (GPST)");
  const std::string reference = l.choice("ssr_reference", "auto", {"auto", "apc", "com"});
  if (reference == "apc") in.ssr_reference = ppp::EphemerisReference::AntennaPhaseCentre;
  if (reference == "com") in.ssr_reference = ppp::EphemerisReference::CentreOfMass;
  in.ssr.use_high_rate_clock = l.boolean("ssr_high_rate_clock", in.ssr.use_high_rate_clock);
  in.ssr.allow_unhealthy = l.boolean("ssr_allow_unhealthy", in.ssr.allow_unhealthy);
  in.ssr_age_limits.orbit_max_age_s =
      l.number("ssr_orbit_max_age_s", in.ssr_age_limits.orbit_max_age_s, ppp::Bound::Positive);
  in.ssr_age_limits.clock_max_age_s =
      l.number("ssr_clock_max_age_s", in.ssr_age_limits.clock_max_age_s, ppp::Bound::Positive);
  in.ssr_age_limits.high_rate_clock_max_age_s =
      l.number("ssr_high_rate_clock_max_age_s", in.ssr_age_limits.high_rate_clock_max_age_s, ppp::Bound::Positive);
  in.ssr_age_limits.bias_max_age_s =
      l.number("ssr_bias_max_age_s", in.ssr_age_limits.bias_max_age_s, ppp::Bound::Positive);
  in.correction_wait_s = l.number("correction_wait_s", in.correction_wait_s, ppp::Bound::NonNegative);
  in.expect_corrections = l.boolean("expect_corrections", !o.live_correction_topics.empty());
  in.stall_warn_s = l.number("stall_warn_s", in.stall_warn_s, ppp::Bound::Positive);
  in.stall_error_s = l.number("stall_error_s", in.stall_error_s, ppp::Bound::Positive);
  if (in.stall_error_s <= in.stall_warn_s)
    l.fail("stall_error_s", "must exceed stall_warn_s (" + std::to_string(in.stall_warn_s) + " s)");
  in.restart_jump_s = l.number("restart_jump_s", in.restart_jump_s, ppp::Bound::Positive);
  in.max_held_epochs = static_cast<std::size_t>(l.integer("max_held_epochs", static_cast<int>(in.max_held_epochs), 1));
  in.keep_history_s = l.number("keep_history_s", in.keep_history_s, ppp::Bound::Positive);
  // The broadcast fallback is one rule for ppp_solve and the nodes, read from ssr:.
  for (const char* key : {"broadcast_fallback", "min_ssr_satellites", "broadcast_orbit_sigma_m",
                          "broadcast_clock_sigma_m"})
    l.refuseMoved(key, std::string("ssr.") + key);
  l.finish();
}

}  // namespace

std::string startAttitudeName(RosImuOptions::StartAttitude attitude) {
  switch (attitude) {
    case RosImuOptions::StartAttitude::Given: return "given";
    case RosImuOptions::StartAttitude::LevelAtRest: return "level_at_rest";
    case RosImuOptions::StartAttitude::AlignInMotion: return "align_in_motion";
  }
  return "given";
}

RosNodeOptions bindRosNodeOptions(const YAML::Node& ros, const std::string& source_name) {
  RosNodeOptions o;
  ppp::YamlSection s(ros, source_name, "ros");
  bindTopics(s, o);
  bindProducts(s, o);
  bindFrames(s, o);
  bindAttitude(s, o);
  bindDatum(s, o);
  bindInput(s, o);
  bindStatus(s, o);
  bindDiagnostics(s, o);
  bindSmoothed(s, o);
  bindLive(s, o);
  bindImu(s, o);
  o.configured_estimator = s.text("estimator", "");
  s.finish();
  return o;
}

YAML::Node xmlRpcToYaml(XmlRpc::XmlRpcValue& v) {
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean: return YAML::Node(static_cast<bool>(v));
    case XmlRpc::XmlRpcValue::TypeInt: return YAML::Node(static_cast<int>(v));
    case XmlRpc::XmlRpcValue::TypeDouble: return YAML::Node(static_cast<double>(v));
    case XmlRpc::XmlRpcValue::TypeString: {
      // Tagged as a quoted scalar of a file: a string parameter ("7", "true")
      // is text, refused where a number or a bool is expected (yaml_section.h).
      YAML::Node n(static_cast<std::string>(v));
      n.SetTag("!");
      return n;
    }
    case XmlRpc::XmlRpcValue::TypeArray: {
      YAML::Node n(YAML::NodeType::Sequence);
      for (int i = 0; i < v.size(); ++i) n.push_back(xmlRpcToYaml(v[i]));
      return n;
    }
    case XmlRpc::XmlRpcValue::TypeStruct: {
      YAML::Node n(YAML::NodeType::Map);
      for (auto it = v.begin(); it != v.end(); ++it) n[it->first] = xmlRpcToYaml(it->second);
      return n;
    }
    default: return YAML::Node();
  }
}

}  // namespace ppp_ros
