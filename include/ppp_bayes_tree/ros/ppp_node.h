#pragma once
// PppNode: the ROS adapter around one EpochEstimator (ppp_ekf_node: "ekf";
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
//             `ros:`), loaded strictly at start-up (loadNodeConfig).
#include <array>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Geometry>
#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/Pose.h>
#include <nav_msgs/Path.h>
#include <nav_msgs/Odometry.h>
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
#include "ppp_bayes_tree/app/live_gnss_input.h"
#include "ppp_bayes_tree/io/bias_sinex_reader.h"
#include "ppp_bayes_tree/evaluation/lagged_trajectory_output.h"
#include "ppp_bayes_tree/ppp/correction_gate.h"
#include "ppp_bayes_tree/ppp/product_assembly.h"
#include "ppp_bayes_tree/models/correction_buffer.h"
#include "ppp_bayes_tree/models/stream_bias_provider.h"
#include "ppp_bayes_tree/ppp/epoch_estimator.h"
#include "ppp_bayes_tree/io/epoch_time_guard.h"
#include "ppp_bayes_tree/ppp/ppp_config.h"
#include "ppp_bayes_tree/ppp/ppp_epoch_processor.h"
#include "ppp_bayes_tree/ros/gnss_stream_subscriber.h"
#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/ros/node_options.h"
#include "ppp_bayes_tree/ros/sim_clock_watch.h"

namespace ppp_ros {

/// The node's configuration: the private namespace through the core loader
/// plus the `ros:` section. Throws ppp::ConfigError with the key path.
struct NodeConfig {
  ppp::PppConfig ppp;
  RosNodeOptions ros;
};
NodeConfig loadNodeConfig(const ros::NodeHandle& private_nh);

/// Solution state of one epoch from the position sigmas (ENU) and thresholds.
std::uint8_t solutionState(bool solved, const Eigen::Vector3d& sigma_enu_m, const RosNodeOptions& options);
std::string solutionStateText(std::uint8_t state);

class PppNode {
 public:
  /// Throws std::runtime_error / ppp::ConfigError with a clear message on a
  /// missing or invalid parameter or product file.
  PppNode(ros::NodeHandle nh, ros::NodeHandle private_nh, const std::string& estimator);
  /// Fixed lag: hands the rest of the window to the trajectory output (CSV).
  ~PppNode();

 private:
  struct Attitude {
    ros::Time stamp;
    Eigen::Quaterniond q_map_base = Eigen::Quaterniond::Identity();
    std::array<double, 9> covariance{};  // orientation covariance of the Imu message [rad^2]
  };
  /// base_link pose in the map frame for an antenna position (ENU) at `stamp`.
  struct BodyPose {
    Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q_map_base = Eigen::Quaterniond::Identity();
    const Attitude* attitude = nullptr;  // the attitude applied, if any
    geometry_msgs::Pose toMsg() const;
  };
  /// A correction batch and its satellite biases for ambiguity resolution (one message).
  struct CorrectionInput {
    ppp::CorrectionBatch batch;
    ppp::SatelliteBiasBatch biases;
  };
  /// Where the phase information for ambiguity resolution comes from (provider
  /// nullptr: none, with the reason in `source`).
  struct PhaseBiasChoice {
    const ppp::BiasProvider* provider = nullptr;
    std::string source;
  };
  struct Pending {
    ppp_bayes_tree::GnssObservations::ConstPtr msg;
    ppp::GnssTime time;
    ros::Time arrival;
  };
  void onObservations(const ros::MessageEvent<ppp_bayes_tree::GnssObservations const>& event);
  void onCorrections(const ros::MessageEvent<ppp_bayes_tree::PreciseCorrections const>& event);
  /// An observation epoch whose stamp the time guard accepted: to the correction gate.
  void acceptObservation(Pending p);
  /// A correction batch whose stamp the time guard accepted: to the buffer.
  void acceptCorrections(CorrectionInput input);
  /// Clears the buffer on a confirmed jump back, then adds the released batches.
  void applyCorrectionOutcome(ppp::EpochTimeGuard<CorrectionInput>::Outcome& outcome);
  /// Observations ahead of the corrections [s] (data time or ROS arrival time, the larger).
  std::optional<double> correctionsStale_s() const;
  void onAttitude(const sensor_msgs::Imu::ConstPtr& msg);
  void onTimer(const ros::TimerEvent&);
  void onPathTimer(const ros::TimerEvent&);
  void onSmoothedPathTimer(const ros::TimerEvent&);
  bool onSetDatum(ppp_bayes_tree::SetDatum::Request& req, ppp_bayes_tree::SetDatum::Response& res);
  void drain();
  void processEpoch(const Pending& p);
  /// One epoch through the processor and out (both inputs).
  void processObsEpoch(const ppp::ObsEpoch& epoch);
  // live input (ros.live)
  void startLiveInput();
  void onStreamChunk(ppp::StreamChunk&& chunk);
  void drainLive();
  void processLiveEpoch(const ppp::LiveReadyEpoch& ready);
  void diagnoseLive(diagnostic_updater::DiagnosticStatusWrapper& s);
  void publishSolution(const ppp::PppEpochRecord& rec, const ppp_bayes_tree::PppStatus& status);
  void publishSmoothedOdometry(const ppp::GnssTime& newest);
  void attachAttitude(const ros::Time& stamp);
  BodyPose bodyPose(const Eigen::Vector3d& antenna_enu_m, const ros::Time& stamp) const;
  nav_msgs::Odometry odometry(const ros::Time& stamp, const BodyPose& pose, const Eigen::Matrix3d& cov_enu_m2) const;
  /// The smoothed trajectory when the estimator smooths (nullptr for the EKF).
  const ppp::SmoothedTrajectoryProvider* smoother() const { return estimator_->smoothing(); }
  void setDatum(const Eigen::Vector3d& position_ecef_m);
  void resetEstimator(const std::string& why);
  /// At start (smoother node): full smoother = warn what it costs; fixed lag = where the states go.
  void announceSmootherCost() const;
  /// Hands the live feed's SSR phase biases to the product assembly's PPP-AR gate;
  /// true when the processor must get the new phaseBiases().
  bool acceptLivePhaseBiases();
  void startProcessor();
  void warn(const std::string& category, const std::string& text);
  void diagnoseInputs(diagnostic_updater::DiagnosticStatusWrapper& s);
  void diagnoseCorrections(diagnostic_updater::DiagnosticStatusWrapper& s);
  void diagnoseSolution(diagnostic_updater::DiagnosticStatusWrapper& s);
  // ambiguity resolution (ambiguity_resolution.enabled)
  PhaseBiasChoice choosePhaseBiases();
  /// At the first correction batch: its systems, clock centre and antenna model to the assembly.
  void declareStreamedProducts(const ppp_bayes_tree::PreciseCorrections& msg, const ppp::CorrectionBatch& batch);
  bool arEnabled() const { return products_.arGate().mode != ppp::AmbiguityResolutionMode::Off; }
  /// Hands the processor the phase information of this epoch; logs when it changes.
  void updatePhaseBiases();
  /// The fix state fields of the status from the epoch's record.
  void setFixState(const ppp::PppEpochRecord& rec, bool solved, ppp_bayes_tree::PppStatus& s);
  void diagnoseAmbiguities(diagnostic_updater::DiagnosticStatusWrapper& s);

  ros::NodeHandle nh_, pnh_;
  NodeConfig config_;
  ppp::ProductAssembly products_;  // ANTEX, Bias-SINEX, BLQ, the systems and the PPP-AR gate (core)
  std::optional<ppp::OceanLoadingCoefficients> ocean_;
  ppp::CorrectionBuffer corrections_;
  std::unique_ptr<ppp::EpochEstimator> estimator_;
  std::unique_ptr<ppp::PppEpochProcessor> processor_;
  ppp::RinexObsHeader layout_;
  bool layout_changed_ = false;
  ppp::CorrectionGate<Pending> gate_;  // epochs waiting for covering corrections
  // Time stamps (epoch_time_guard.h): an isolated bad stamp is dropped, a sustained jump back resets.
  ppp::EpochTimeGuard<Pending> obs_guard_;
  ppp::EpochTimeGuard<CorrectionInput> corr_guard_;
  std::optional<ppp::GnssTime> last_output_time_;  // newest epoch published (outputs never go back)
  std::string last_time_drop_;                     // the last stamp dropped, with the reason (diagnostics)
  // Messages lost before the node: gaps in header.seq, per publisher (roscpp numbers each
  // publication's messages; a subscriber or publisher queue overflow leaves a gap).
  std::map<std::string, std::uint32_t> obs_seq_, corr_seq_;
  std::optional<ros::Time> last_obs_arrival_, last_corr_arrival_;
  std::optional<ppp::GnssTime> last_received_;  // newest observation epoch received

  // datum of the map frame
  std::optional<Eigen::Vector3d> datum_ecef_m_;
  Eigen::Matrix3d ecef_to_enu_ = Eigen::Matrix3d::Identity();

  ros::Subscriber obs_sub_, corr_sub_, attitude_sub_;
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
  nav_msgs::Path path_;

  // attitude (lever arm): the newest message, and the one applied to each epoch (by stamp)
  std::optional<Attitude> attitude_;
  std::map<ros::Time, Attitude> attitude_of_epoch_;
  bool lever_arm_note_logged_ = false;
  std::size_t attitude_received_ = 0, attitude_invalid_ = 0, epochs_without_attitude_ = 0;

  // smoother outputs
  std::optional<std::uint32_t> last_smoothed_index_;  // newest state published on ppp/odometry/smoothed
  bool smoothed_path_stale_ = false;                   // epochs processed since the last path re-read
  std::optional<ppp::SmootherEpochDiagnostics> last_smoother_;  // of the last processed epoch
  std::size_t estimator_restarts_ = 0;                 // after a failed update (the core restarts; counted here)
  double smoothed_path_read_s_ = 0.0, smoothed_path_read_max_s_ = 0.0;
  std::size_t smoothed_path_poses_ = 0;
  // Fixed lag (bounded memory): the states past the lag go to this output
  // (ros.smoothed.trajectory_csv, and the newest path_max_poses for ppp/path/smoothed);
  // the smoother keeps only its window.
  std::unique_ptr<ppp::LaggedTrajectoryOutput> lagged_output_;
  /// The lagged output's smoother (nullptr: not a fixed-lag smoother).
  ppp::PppSmoother* laggedSmoother();
  void attachLaggedOutput();

  // counters and figures
  ppp_bayes_tree::PppStatus counters_;  // the counter fields only
  ppp_bayes_tree::PppStatus last_status_;
  bool have_status_ = false;
  std::size_t obs_received_ = 0, corr_received_ = 0, obs_at_last_diag_ = 0, corr_at_last_diag_ = 0;
  std::size_t lost_at_last_diag_ = 0;  // messages lost (both topics) at the last inputs diagnostic
  ros::WallTime last_diag_time_;
  double last_correction_age_s_ = std::numeric_limits<double>::quiet_NaN();
  ConversionIssues issues_;
  std::map<std::string, ros::WallTime> last_warning_;

  // ambiguity resolution: the corrections' satellite biases, the phase information in
  // use (its source text), and the fix figures since the start or the last reset
  ppp::StreamBiasProvider stream_biases_;
  ppp::PhaseInformation stream_bias_kind_ = ppp::PhaseInformation::None;  // what the batches declare
  bool streamed_declared_ = false;
  PhaseBiasChoice phase_biases_;
  bool phase_bias_logged_ = false;
  std::uint32_t epochs_fixed_ = 0, ambiguity_releases_ = 0;
  std::optional<ppp::GnssTime> first_solved_, first_fixed_;

  // live input (ros.live): the subscribers feed live_; its ephemeris replaces corrections_
  std::unique_ptr<ppp::LiveGnssInput> live_;
  std::vector<std::unique_ptr<GnssStreamSubscriber>> stream_subs_;
  std::uint8_t product_mode_ = ppp_bayes_tree::PppStatus::PRODUCTS_PRECISE;  // of the epoch being processed
  std::string product_mode_text_ = "precise products";
  const ppp::BiasProvider* processor_biases_ = nullptr;  // the bias provider the processor was made with
  std::size_t live_receiver_restarts_ = 0;  // resets after the observation time went back
  // Cost figures of the live path (diagnostics "live streams"; scripts/bench_live_realtime.sh):
  // thread CPU time in LiveGnssInput (feed: framing + decoding; takeReadyEpochs: release),
  // in the estimator (PppEpochProcessor::process, every input), and the in-node latency
  // (subscriber callback of the chunk completing an epoch -> its solution published, ROS
  // clock; time waiting in the subscriber queue is not in it) of the last kLatencyWindow
  // epochs (bounded).
  static constexpr std::size_t kLatencyWindow = 1000;
  double live_decode_cpu_s_ = 0.0, estimator_cpu_s_ = 0.0;
  std::deque<double> live_latency_s_;
};

}  // namespace ppp_ros
