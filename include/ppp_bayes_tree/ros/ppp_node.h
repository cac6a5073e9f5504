#pragma once
// PppNode: the ROS adapter around one PppEstimator (ppp_ekf_node: "ekf";
// ppp_smoother_node: "smoother", same class). Everything per epoch is the
// core's PppEpochProcessor, exactly as in ppp_solve; the node only converts
// messages, buffers observations until corrections cover them, and publishes.
// Inputs: gnss/observations + gnss/corrections, or raw receiver and correction
// streams through one ppp::LiveGnssInput (ros.live), and an optional attitude;
// with an estimator that has inertial states (ros.estimator ekf_ins or smoother_ins) the IMU on
// ros.imu.topic (node_imu_input.h), whose readings go to the estimator with each
// epoch (an epoch waits for the readings up to its time, at most ros.imu.max_wait_s:
// imu_epoch_hold.h), and ppp/odometry/filtered and TF at the IMU rate (ins_odometry.h).
// When the IMU stops after the start, the node goes on with the GNSS-only estimator.
// Outputs: ppp/odometry/filtered, ppp/fix, ppp/status, ppp/path/filtered,
// /diagnostics and TF; the smoother node adds ppp/odometry/smoothed and
// ppp/path/smoothed. Service: set_datum. Parameters: the whole private
// namespace = config/ppp.yaml, loaded strictly at start-up (node_config.h).
// Parts: node_config.h (the parameters), node_inputs.h (products, messages ->
// core types, time guard, correction gate, header.seq gaps, live input),
// node_outputs.h (status, odometry, fix, TF, paths, smoothed outputs, datum),
// node_diagnostics.h (/diagnostics, the start notes). The node keeps the order
// of the set-up steps and the per-epoch call.
// Topics, frames, the lever arm and the smoothed outputs: doc/ros_interface.md;
// live streams: doc/live_input.md; ambiguity resolution:
// doc/ros_ambiguity_resolution.md.
#include <memory>
#include <optional>
#include <string>
#include <variant>
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
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_epoch_processor.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"
#include "ppp_bayes_tree/ros/gnss_stream_subscriber.h"
#include "ppp_bayes_tree/ros/imu_epoch_hold.h"
#include "ppp_bayes_tree/ros/ins_odometry.h"
#include "ppp_bayes_tree/ros/node_config.h"
#include "ppp_bayes_tree/ros/node_diagnostics.h"
#include "ppp_bayes_tree/ros/node_imu_input.h"
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
  /// The epochs ready from the inputs, admitted (processed or held), then releaseAndDiagnose().
  void drain();
  /// The held epochs that may go on, then /diagnostics: the end of a drain and of the hold's timers.
  void releaseAndDiagnose();
  void drainLive();
  void processLiveEpoch(const ppp::LiveReadyEpoch& ready);
  // epochs waiting for the IMU (imu_epoch_hold.h): a topic's epoch released by the
  // correction gate (converted when it goes on), or a live input's ready epoch
  using HeldEpoch = std::variant<PendingObservation, ppp::LiveReadyEpoch>;
  /// The estimator takes IMU readings now: its epochs wait for them.
  bool waitsForImu() const;
  /// A ready epoch: processed now when nothing waits and the estimator takes no readings, else held.
  void admitEpoch(HeldEpoch epoch, const ppp::GnssTime& time, double now_s);
  /// The held epochs that may go on, in order (`all`: every one, e.g. before an estimator reset).
  void releaseHeldEpochs(bool all = false);
  void processHeld(HeldEpoch& epoch);
  /// A one-shot timer at the oldest held epoch's deadline (a silent IMU sends no callback).
  void armHoldTimer();
  /// Now for the hold: ROS time and the steady clock's.
  static HoldClock holdClock();
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
  // GNSS/INS (an estimator with inertial states; doc/ros_interface.md "IMU")
  bool inertial() const;
  void setUpImu();
  void onImu(const sensor_msgs::Imu::ConstPtr& msg);
  /// ros.imu.extrinsics tf: the IMU's pose in base_link from TF, once; false while missing.
  bool resolveImuExtrinsics(const std::string& imu_frame);
  /// The estimator in use has inertial states (the registry's GnssInertial: it takes the readings).
  bool inertialActive() const;
  /// The IMU stopped after the start (the filter reports no readings): the epoch is not published.
  bool insStopped(const ppp::PppEpochRecord& rec) const;
  void fallBackToGnss(const ppp::GnssTime& time, const std::string& why);
  /// A new estimator of `name` (the lagged output handed over, the processor remade).
  void switchEstimator(const std::string& name);
  /// The odometry from the estimator's inertial state after an epoch (it needs the INS error covariance).
  void restartInsOdometry(const ppp::InertialState& state);
  void publishInsOdometry(const InsState& state);
  /// The attitude's alignment after an epoch as the estimator tells it (nullopt: no attitude yet).
  std::optional<ppp::AlignmentState> insAlignment(const ppp::PppEpochRecord& rec) const;
  /// The estimator's attitude is levelled but its heading not yet aligned (align_in_motion):
  /// odometry and TF come per epoch from the GNSS solution, without an orientation.
  bool insHeadingPending() const;
  /// PppStatus.ins_reason while the heading is pending: the alignment and what sets the heading.
  std::string headingPendingText() const;
  void fillInsStatus(ppp_bayes_tree::PppStatus& s, const ppp::GnssTime& time) const;
  void imuDiagnostics(diagnostic_updater::DiagnosticStatusWrapper& s) const;
  /// ppp/odometry/filtered never goes back in time with an IMU: false for a stamp not after the last.
  bool claimOdometryStamp(const ros::Time& stamp);

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

  // GNSS/INS: the IMU input and the odometry at the IMU rate (inertial() only)
  std::unique_ptr<NodeImuInput> imu_;
  ImuEpochHold<HeldEpoch> epoch_hold_;             // epochs waiting for the readings up to their time
  std::optional<double> hold_deadline_s_;          // the deadline hold_timer_ is set to (ROS time)
  ros::SteadyTimer hold_steady_timer_;             // every ros.imu.max_wait_s: the hold when the ROS clock stops
  std::unique_ptr<InsOdometry> ins_odometry_;
  std::optional<ImuExtrinsics> imu_extrinsics_;    // unknown while TF has none (ros.imu.extrinsics: tf)
  std::vector<ppp::ImuSample> epoch_imu_;          // the readings handed to the processor with the epoch
  std::string active_estimator_;                   // config_.ros.estimator, or the GNSS one after a fallback
  std::optional<std::string> ins_fallback_reason_;  // the IMU stopped: why
  std::optional<ppp::AlignmentState> ins_alignment_;  // after the newest epoch (insAlignment)
  std::optional<std::string> imu_extrinsics_problem_;  // the TF extrinsics refused for the start attitude
  std::optional<ppp::GnssTime> newest_gnss_time_;   // newest epoch received (the IMU time-base check)
  std::optional<ppp::GnssTime> last_gnss_update_;   // newest epoch solved
  std::optional<ros::Time> last_odometry_stamp_;    // ppp/odometry/filtered never goes back
  ros::Subscriber obs_sub_, corr_sub_, attitude_sub_, imu_sub_;
  std::vector<std::unique_ptr<GnssStreamSubscriber>> stream_subs_;  // live input
  ros::Publisher odom_pub_, fix_pub_, status_pub_, path_pub_;
  ros::Publisher smoothed_odom_pub_, smoothed_path_pub_;  // smoother node only
  ros::ServiceServer datum_srv_;
  ros::Timer timer_, path_timer_, smoothed_path_timer_, hold_timer_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  diagnostic_updater::Updater diagnostics_;
  std::unique_ptr<SimClockWatch> sim_clock_watch_;  // says so while /use_sim_time waits for /clock
};

}  // namespace ppp_ros
