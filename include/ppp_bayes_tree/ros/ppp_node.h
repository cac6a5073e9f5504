#pragma once
// PppNode: the ROS adapter around one PppEstimator (ppp_ekf_node: "ekf";
// ppp_smoother_node: "smoother", same class). Everything per epoch is the
// core's PppEpochProcessor, exactly as in ppp_solve; the node only converts
// messages, buffers observations until corrections cover them, and publishes.
//
// Subscribes: gnss/observations (GnssObservations), gnss/corrections (PreciseCorrections),
//             optionally an attitude (sensor_msgs/Imu, ros.attitude.topic; see below).
// Live input (ros.live with an observation topic): INSTEAD of the two topics
//             above, raw receiver and correction streams (rtcm_msgs/Message, mavros_msgs/RTCM,
//             ublox_msgs/RxmRAWX + RxmSFRBX, GnssStreamBytes; ros/gnss_stream_subscriber.h)
//             go into one ppp::LiveGnssInput; its ready epochs take the same PppEpochProcessor
//             path with its ephemeris (broadcast + SSR) and are published the same way.
//             Why the nodes decode (no bridge node publishing our messages): equality with
//             ppp_solve to 1 mm needs the same broadcast + SSR evaluation code in the node,
//             and decoding costs < 0.1 % of a core, so both nodes side by side can decode;
//             transport-only nodes (ppp_stream_node: serial, TCP, NTRIP, file) move bytes.
//             A timer takes ready epochs every 0.1 s (ROS clock) so that the broadcast-only
//             fallback happens when corrections stop. A receiver restart (time back beyond
//             ros.live.restart_jump_s) resets the estimator as a bag loop does.
// Publishes:  ppp/odometry/filtered (nav_msgs/Odometry, map frame, ENU covariance),
//             ppp/fix (sensor_msgs/NavSatFix in the gnss_antenna frame, ENU covariance;
//               status STATUS_GBAS_FIX when the ambiguities are fixed, STATUS_FIX when float,
//               as ublox_gps reports carrier-phase fixed solutions),
//             ppp/status (PppStatus), ppp/path/filtered (nav_msgs/Path, at
//             ros.diagnostics.path_publish_rate_hz), /diagnostics (inputs, corrections,
//             solution), TF earth -> map (static), base_link -> gnss_antenna (static, the
//             lever arm), map -> base_link (or map -> odom when odom -> base_link exists).
// Smoother node only (the EKF node does not advertise them):
//             ppp/odometry/smoothed (nav_msgs/Odometry, ENU covariance): after each epoch t,
//               with smoother.fixed_lag_s > 0 the state at the lag boundary x(t-lag | t)
//               (the oldest state still in the window: final, the lag no longer changes
//               it); with the full smoother the newest state x(t | t) (= the filtered
//               one); with ros.smoothed.odometry_delay_s = d > 0 the newest state at least
//               d old, x(t-d | t). Each state is published once, in time order.
//             ppp/path/smoothed (nav_msgs/Path): the whole trajectory re-estimated with
//               all data so far, re-read only at ros.smoothed.path_publish_rate_hz (never
//               per epoch); its last pose is the last filtered one.
//             The status carries the smoother's variables re-eliminated per update; the
//             diagnostics its iSAM2 update time, relinearized/marginalized variables and
//             the cost of the last path re-read.
// Lever arm:  PPP estimates the antenna position. With an attitude source (the newest
//             attitude within ros.attitude.max_age_s of the epoch) base_link =
//             antenna - R(attitude) * ros.frames.antenna_lever_arm_m and the odometry/TF
//             carry the attitude; without one, base_link IS the antenna position with an
//             identity orientation (logged once), and the TF gnss_antenna frame (base_link
//             + the unrotated lever arm) is not the antenna: ppp/fix is.
// Ambiguity resolution (ambiguity_resolution.enabled): the phase information comes from
//             the corrections (PreciseCorrections ar_bias_source and satellites[].biases),
//             on the live input from SSR phase biases (RTCM 1265-1270, IGS-SSR), or from a
//             Bias-SINEX file with phase OSBs of the clocks' analysis centre (ros.products.bias);
//             without any the node stays float and says so (log once, status, diagnostics).
//             The smoother holds the integers as factors of its graph: the smoothed outputs
//             after a fix carry them back.
// Service:    set_datum (SetDatum).
// Parameters: the whole private namespace = config/ppp.yaml (core sections +
//             `ros:`), loaded strictly at start-up (node_config.h).
// Parts:     node_config.h (the parameters), node_inputs.h (the products, messages ->
//             core types, time guard, correction gate, header.seq gaps, live input and
//             its subscriptions), node_outputs.h (status, odometry, fix, TF, paths,
//             smoothed outputs and file, the datum, the epoch figures),
//             node_diagnostics.h (/diagnostics, the start notes). The node keeps the
//             order of the set-up steps and the per-epoch call.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include "ppp_bayes_tree/GnssObservations.h"
#include "ppp_bayes_tree/PppStatus.h"
#include "ppp_bayes_tree/PreciseCorrections.h"
#include "ppp_bayes_tree/SetDatum.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_epoch_processor.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"
#include "ppp_bayes_tree/ros/gnss_stream_subscriber.h"
#include "ppp_bayes_tree/ros/node_config.h"
#include "ppp_bayes_tree/ros/node_diagnostics.h"
#include "ppp_bayes_tree/ros/node_inputs.h"
#include "ppp_bayes_tree/ros/node_options.h"
#include "ppp_bayes_tree/ros/node_outputs.h"
#include "ppp_bayes_tree/ros/sim_clock_watch.h"
#include "ppp_bayes_tree/ros/throttled_warnings.h"

namespace ppp_ros {

class PppNode {
 public:
  /// Throws std::runtime_error / ppp::ConfigError with a clear message on a
  /// missing or invalid parameter or product file.
  PppNode(ros::NodeHandle nh, ros::NodeHandle private_nh, const std::string& estimator);
  /// Fixed lag: hands the rest of the window to the trajectory output (CSV).
  ~PppNode();

 private:
  // set-up (the configuration: node_config.h; the products: assembleNodeProducts)
  void subscribe();
  void advertise();
  void addDiagnostics();
  void logStart() const;
  void logNote(const StartNote& note) const;
  void startLiveInput();
  // inputs
  void onObservations(const ros::MessageEvent<ppp_bayes_tree::GnssObservations const>& event);
  void onCorrections(const ros::MessageEvent<ppp_bayes_tree::PreciseCorrections const>& event);
  void onStreamChunk(ppp::StreamChunk&& chunk);
  void onTimer(const ros::TimerEvent&);
  void drain();
  void drainLive();
  void processLiveEpoch(const ppp::LiveReadyEpoch& ready);
  // the epoch
  /// One epoch through the processor and out (both inputs).
  void processObsEpoch(const ppp::ObsEpoch& epoch);
  void startProcessor();
  void publishSolution(const ppp::GnssTime& time, const ppp::PppEpochRecord& rec,
                       const ppp_bayes_tree::PppStatus& status);
  void publishEmptyEpoch(const ppp::GnssTime& time);
  void resetEstimator(const std::string& why);
  // outputs on timers and services
  void onPathTimer(const ros::TimerEvent&);
  void onSmoothedPathTimer(const ros::TimerEvent&);
  bool onSetDatum(ppp_bayes_tree::SetDatum::Request& req, ppp_bayes_tree::SetDatum::Response& res);
  void setDatum(const Eigen::Vector3d& position_ecef_m);
  /// The smoothed trajectory when the estimator smooths (nullptr for the EKF).
  const ppp::SmoothedTrajectoryProvider* smoother() const { return estimator_->smoothing(); }
  // ambiguity resolution (ambiguity_resolution.enabled)
  bool arEnabled() const { return products_.arGate().mode != ppp::AmbiguityResolutionMode::Off; }
  /// Hands the processor the phase information of this epoch; logs when it changes.
  void updatePhaseBiases();

  ros::NodeHandle nh_, pnh_;
  NodeConfig config_;
  ThrottledWarnings warnings_;
  NodeInputs inputs_;
  NodeOutputs outputs_;
  NodeDiagnostics diagnosis_;
  ppp::ProductAssembly products_;  // ANTEX, Bias-SINEX, BLQ, the systems and the PPP-AR gate (core)
  std::unique_ptr<ppp::PppEstimator> estimator_;
  std::unique_ptr<ppp::PppEpochProcessor> processor_;
  const ppp::BiasProvider* processor_biases_ = nullptr;  // the bias provider the processor was made with
  std::optional<ppp::GnssTime> last_output_time_;        // newest epoch published (outputs never go back)
  std::size_t estimator_restarts_ = 0;  // after a failed update (the core restarts; counted here)
  double estimator_cpu_s_ = 0.0;        // thread CPU time in PppEpochProcessor::process
  // ambiguity resolution: the phase information in use (its source text)
  PhaseBiasChoice phase_biases_;
  bool phase_bias_logged_ = false;

  ros::Subscriber obs_sub_, corr_sub_, attitude_sub_;
  std::vector<std::unique_ptr<GnssStreamSubscriber>> stream_subs_;  // live input
  ros::Publisher odom_pub_, fix_pub_, status_pub_, path_pub_;
  ros::Publisher smoothed_odom_pub_, smoothed_path_pub_;  // smoother node only
  ros::ServiceServer datum_srv_;
  ros::Timer timer_, path_timer_, smoothed_path_timer_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  diagnostic_updater::Updater diagnostics_;
  std::unique_ptr<SimClockWatch> sim_clock_watch_;  // says so while /use_sim_time waits for /clock
};

}  // namespace ppp_ros
