#pragma once
// The ROS nodes' own options: the `ros:` section of config/ppp.yaml (every key
// documented there), bound strictly like the core sections (unknown key, wrong
// type or out-of-range value -> ppp::ConfigError naming the key path).
// The whole private namespace of a node (~) is one configuration document: the
// node converts it to YAML (xmlRpcToYaml) and hands the node to the core binder
// (ppp::bindPppConfig, no text round trip: the XmlRpc types stay), which keeps
// `ros:` raw for bindRosNodeOptions.
#include <optional>
#include <string>
#include <vector>

#include <xmlrpcpp/XmlRpcValue.h>
#include <yaml-cpp/yaml.h>
#include <Eigen/Core>

#include "ppp_bayes_tree/app/live_gnss_input.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"
#include "ppp_bayes_tree/ppp/estimators/ins_ekf_options.h"

namespace ppp_ros {

/// One raw stream topic of the live input (ros.live): "topic" or "topic:rtcm3" / "topic:ubx"
/// (the format hint, used for ppp_bayes_tree/GnssStreamBytes messages without a format).
struct LiveStreamTopic {
  std::string topic;
  std::optional<ppp::StreamFormat> format;
};

/// ros.imu: the IMU input of an estimator with inertial states (ekf_ins, smoother_ins). The
/// IMU frame is the frame of the readings (sensor_msgs/Imu, REP-145); its pose in
/// base_link comes from the parameters or from TF.
struct RosImuOptions {
  std::string topic = "imu/data";
  std::string grade = "industrial_mems";  // consumer_mems | industrial_mems | tactical (imu_noise.h)
  bool extrinsics_from_tf = false;        // extrinsics: parameters | tf
  /// IMU origin in base_link [m] and the IMU axes in base_link: roll, pitch, yaw [deg]
  /// (R_base_imu = Rz(yaw) Ry(pitch) Rx(roll)).
  Eigen::Vector3d translation_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotation_rpy_deg = Eigen::Vector3d::Zero();
  /// How the start attitude is found (initial_attitude): given | level_at_rest | align_in_motion.
  enum class StartAttitude {
    Given,          ///< initial_rpy_deg: base_link roll, pitch, yaw in the map frame (ENU, REP-103) [deg]
    LevelAtRest,    ///< roll and pitch from the readings up to the first epoch, the yaw of initial_rpy_deg
    AlignInMotion,  ///< roll and pitch from the latest static interval, the heading from the course over ground
  };
  StartAttitude initial_attitude = StartAttitude::Given;
  Eigen::Vector3d initial_rpy_deg = Eigen::Vector3d::Zero();
  /// align_in_motion: the course sets the heading once the antenna moves at least this fast [m/s].
  double heading_speed_mps = 0.5;
  Eigen::Vector3d initial_velocity_enu_mps = Eigen::Vector3d::Zero();  // of base_link in the map [m/s]
  double max_gap_s = 0.1;                 // a longer step between readings is a gap (counted; the INS stops)
  double max_gnss_offset_s = 2.0;         // |IMU stamp - newest GNSS epoch| above: refused (time base)
  double accel_full_scale_mps2 = 0.0;     // 0: saturation not checked
  double gyro_full_scale_radps = 0.0;
  double attitude_sigma_valid_deg = 5.0;  // largest attitude sigma at which the attitude is published as valid
  double buffer_s = 60.0;                 // readings kept ahead of the newest processed epoch [s]
  /// A GNSS epoch waits at most this long for the IMU readings up to its time [s] (0: never;
  /// imu_epoch_hold.h).
  double max_wait_s = 0.1;
  /// Scale the accelerometers' process noise when the phases find the inertial prediction
  /// inconsistent (InsEkfOptions::process_noise_adaptation, ins_process_noise_adaptation.h).
  bool process_noise_adaptation = true;
  /// GNSS gaps up to this long do not end the arcs of ekf_ins / smoother_ins: the gap
  /// bridge tests them against the INS prediction (InsEkfOptions::gap_bridge_max_s) [s];
  /// 0: every gap longer than the arc tracker's maximum ends them.
  double gap_bridge_max_s = ppp::InsEkfOptions{}.gap_bridge_max_s;  // the estimators' default
};

struct RosNodeOptions {
  std::string estimator = "ekf";  // the node's own (its main) unless ros.estimator names another of its kind
  // topics (relative to the node's namespace)
  std::string observations_topic = "gnss/observations";
  std::string corrections_topic = "gnss/corrections";
  // products (paths; relative paths are taken from the working directory)
  std::vector<std::string> atx;
  std::string bias;  // Bias-SINEX OSB file ("" = none)
  std::string blq;   // ocean loading ("" = none)
  // frames (REP-105 / REP-103)
  std::string earth_frame = "earth";
  std::string map_frame = "map";
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  std::string antenna_frame = "gnss_antenna";  // child of base_link at the lever arm (static TF)
  bool publish_tf = true;
  /// gnss_antenna lever arm: antenna position in base_link [m] (x forward, y left, z up).
  Eigen::Vector3d antenna_lever_arm_m = Eigen::Vector3d::Zero();
  // attitude source for the lever arm (optional)
  std::string attitude_topic;        // sensor_msgs/Imu, orientation of base_link in the map (ENU); "" = none
  double attitude_max_age_s = 0.5;   // an attitude farther from the epoch (stamps) is not used
  // datum of the map frame
  std::string datum_mode = "first_fix";  // first_fix | configured
  double datum_latitude_deg = 0.0, datum_longitude_deg = 0.0, datum_height_m = 0.0;
  // input handling
  double correction_wait_s = 35.0;          // longest wait for corrections covering an epoch (data or ROS time)
  double correction_history_s = 900.0;      // correction batches kept
  double reset_backwards_threshold_s = 60.0;  // a step back by more is a time jump (resets once confirmed)
  double max_forward_step_s = 600.0;          // a step forward by more is a time jump (accepted once confirmed)
  std::size_t time_jump_confirm_epochs = 3;   // consecutive consistent epochs that confirm a time jump
  std::size_t max_pending_epochs = 1000;
  std::size_t observation_queue_size = 2000;  // subscriber queue [messages] (>= max_pending_epochs)
  std::size_t correction_queue_size = 1000;   // subscriber queue [messages]
  // status thresholds
  double converged_horizontal_sigma_m = 0.10;
  double converged_vertical_sigma_m = 0.20;
  // diagnostics
  double expected_observation_rate_hz = 0.0;  // 0 = not checked
  double max_correction_latency_s = 10.0;     // latency above: WARN
  double corrections_stale_warn_s = 60.0;     // observations ahead of the newest correction by more: WARN
  double corrections_stale_error_s = 180.0;   // ... by more: ERROR (> the WARN threshold)
  double path_publish_rate_hz = 1.0;
  std::size_t path_max_poses = 20000;
  // smoother node only: ppp/odometry/smoothed and ppp/path/smoothed
  double smoothed_path_publish_rate_hz = 1.0;
  double smoothed_odometry_delay_s = 0.0;  // 0: the lag boundary (fixed lag) / the newest state (full smoother)
  std::string smoothed_trajectory_csv;     // fixed lag: states past the lag written here ("" = no file)
  // live input (ros.live): raw stream topics decoded by ppp::LiveGnssInput.
  // No observation topic = the GnssObservations / PreciseCorrections path (ros.topics).
  std::vector<LiveStreamTopic> live_observation_topics;
  std::vector<LiveStreamTopic> live_correction_topics;
  std::size_t live_queue_size = 1000;  // subscriber queue per stream topic [messages]
  ppp::LiveInputOptions live_input;
  bool live() const { return !live_observation_topics.empty(); }
  // the IMU input (ros.imu), used when the estimator has inertial states
  RosImuOptions imu;
  std::string configured_estimator;  // ros.estimator ("" = the node's own)
  std::string node_estimator;        // the node's own estimator (its name: ppp_<node_estimator>_node)
};

/// The parameter value of a start attitude: "given", "level_at_rest", "align_in_motion".
std::string startAttitudeName(RosImuOptions::StartAttitude attitude);

/// Binds `ros:` (a mapping or null) strictly. Throws ppp::ConfigError.
RosNodeOptions bindRosNodeOptions(const YAML::Node& ros, const std::string& source_name);

/// Converts a parameter-server value (a struct for a namespace) to YAML. A
/// string value is tagged "!" like a quoted scalar of a file, so "7" or "true"
/// given as a string is refused where a number or a bool is expected.
YAML::Node xmlRpcToYaml(XmlRpc::XmlRpcValue& value);

}  // namespace ppp_ros
