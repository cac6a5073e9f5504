#include "ppp_bayes_tree/ros/ppp_node.h"

#include <chrono>
#include <limits>

#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/NavSatFix.h>

#include "ppp_bayes_tree/types/thread_cpu_time.h"

namespace ppp_ros {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

PppNode::PppNode(ros::NodeHandle nh, ros::NodeHandle pnh, const std::string& estimator)
    : nh_(nh),
      pnh_(pnh),
      config_(loadNodeConfig(pnh, estimator)),
      inputs_(config_.ros, warnings_.sink()),
      outputs_(config_.ros, warnings_.sink()),
      diagnosis_(config_.ros, ros::WallTime::now()),
      tf_listener_(tf_buffer_),
      diagnostics_(nh, pnh) {
  // The products resolve the systems and the PPP-AR gate: the estimator is made from their config.
  products_ = assembleNodeProducts(config_.ppp, config_.ros);
  config_.ppp = products_.config();
  for (const auto& n : products_.notes()) ROS_INFO_STREAM("ppp_" << estimator << "_node: " << n);
  std::string why;
  estimator_ = ppp::makeEstimator(estimator, config_.ppp, &why);
  if (!estimator_) throw std::runtime_error("estimator '" + estimator + "' is not available: " + why);
  if (const auto datum = configuredDatum(config_.ros)) setDatum(*datum);
  outputs_.attachLaggedOutput(*estimator_);
  if (smoother()) logNote(smootherCostNote(config_.ppp.smoother.fixed_lag_s, config_.ros.smoothed_trajectory_csv));
  subscribe();
  advertise();
  addDiagnostics();
  sim_clock_watch_ = std::make_unique<SimClockWatch>(nh_, "ppp_" + estimator + "_node");
  logStart();
}

void PppNode::subscribe() {
  // Queues as configured (observations: at least what the correction wait buffers);
  // whatever is lost before the node anyway is counted from header.seq.
  const RosNodeOptions& o = config_.ros;
  if (o.live()) {
    startLiveInput();
  } else {
    obs_sub_ = nh_.subscribe(o.observations_topic, static_cast<std::uint32_t>(o.observation_queue_size),
                             &PppNode::onObservations, this);
    corr_sub_ = nh_.subscribe(o.corrections_topic, static_cast<std::uint32_t>(o.correction_queue_size),
                              &PppNode::onCorrections, this);
  }
  if (!o.attitude_topic.empty())
    attitude_sub_ = nh_.subscribe<sensor_msgs::Imu>(
        o.attitude_topic, 200, [this](const sensor_msgs::Imu::ConstPtr& msg) { outputs_.receiveAttitude(*msg); });
}

void PppNode::advertise() {
  const RosNodeOptions& o = config_.ros;
  odom_pub_ = nh_.advertise<nav_msgs::Odometry>("ppp/odometry/filtered", 100);
  fix_pub_ = nh_.advertise<sensor_msgs::NavSatFix>("ppp/fix", 100);
  status_pub_ = nh_.advertise<ppp_bayes_tree::PppStatus>("ppp/status", 100);
  path_pub_ = nh_.advertise<nav_msgs::Path>("ppp/path/filtered", 2, true);
  if (smoother()) {  // the EKF node does not advertise the smoothed topics
    smoothed_odom_pub_ = nh_.advertise<nav_msgs::Odometry>("ppp/odometry/smoothed", 100);
    smoothed_path_pub_ = nh_.advertise<nav_msgs::Path>("ppp/path/smoothed", 2, true);
    smoothed_path_timer_ =
        nh_.createTimer(ros::Duration(1.0 / o.smoothed_path_publish_rate_hz), &PppNode::onSmoothedPathTimer, this);
  }
  static_tf_.sendTransform(outputs_.leverArmTransform());  // base_link -> gnss_antenna
  datum_srv_ = nh_.advertiseService("set_datum", &PppNode::onSetDatum, this);
  timer_ = nh_.createTimer(ros::Duration(0.1), &PppNode::onTimer, this);
  path_timer_ = nh_.createTimer(ros::Duration(1.0 / o.path_publish_rate_hz), &PppNode::onPathTimer, this);
}

void PppNode::addDiagnostics() {
  using diagnostic_updater::DiagnosticStatusWrapper;
  diagnosis_ = NodeDiagnostics(config_.ros, ros::WallTime::now());  // rates from the end of the set-up
  diagnostics_.setHardwareID("ppp_" + config_.ros.estimator);
  diagnostics_.add("inputs", [this](DiagnosticStatusWrapper& s) {
    diagnosis_.inputs(s, inputs_, outputs_, ros::WallTime::now());
  });
  if (inputs_.isLive())
    diagnostics_.add("live streams", [this](DiagnosticStatusWrapper& s) {
      diagnosis_.live(s, inputs_, outputs_, stream_subs_, estimator_cpu_s_, ros::Time::now().toSec());
    });
  else
    diagnostics_.add("corrections",
                     [this](DiagnosticStatusWrapper& s) { diagnosis_.corrections(s, inputs_, outputs_); });
  diagnostics_.add("solution", [this](DiagnosticStatusWrapper& s) {
    diagnosis_.solution(s, inputs_, outputs_, smoother(), estimator_restarts_);
  });
  diagnostics_.add("ambiguity resolution", [this](DiagnosticStatusWrapper& s) {
    diagnosis_.ambiguities(s, arEnabled(), phase_biases_, outputs_);
  });
}

void PppNode::logStart() const {
  std::vector<std::string> live_topics;
  for (const auto& sub : stream_subs_) live_topics.push_back(sub->topic());
  const auto resolve = [this](const std::string& topic) { return nh_.resolveName(topic); };
  logNote(startSummary(config_.ros, config_.ppp.source_name, products_.antexFiles(), live_topics, resolve));
}

void PppNode::startLiveInput() {
  const RosNodeOptions& o = config_.ros;
  inputs_.startLive(o.live_input);  // throws on an unreadable navigation file
  const auto resolve = [this](const std::string& topic) { return nh_.resolveName(topic); };
  for (const LiveSubscription& sub : liveSubscriptions(o, resolve))
    stream_subs_.push_back(std::make_unique<GnssStreamSubscriber>(
        nh_, sub.topic.topic, sub.topic.format, static_cast<std::uint32_t>(o.live_queue_size),
        [this](ppp::StreamChunk&& chunk) { onStreamChunk(std::move(chunk)); }, sub.stream));
}

void PppNode::logNote(const StartNote& note) const {
  if (note.warning) ROS_WARN_STREAM(note.text);
  else ROS_INFO_STREAM(note.text);
}

PppNode::~PppNode() { outputs_.finishLaggedOutput(*estimator_); }

void PppNode::setDatum(const Eigen::Vector3d& p) { static_tf_.sendTransform(outputs_.setDatum(p)); }

bool PppNode::onSetDatum(ppp_bayes_tree::SetDatum::Request& req, ppp_bayes_tree::SetDatum::Response& res) {
  const DatumRequest datum = datumRequest(req.latitude_deg, req.longitude_deg, req.height_m);
  res.success = datum.position_ecef_m.has_value();
  res.message = datum.message;
  if (res.success) {
    setDatum(*datum.position_ecef_m);
    outputs_.clearPathsForDatum();
  }
  return true;
}

void PppNode::resetEstimator(const std::string& why) {
  const std::size_t discarded = inputs_.resetForEstimator();
  warnings_.warn("reset", "ppp: estimator reset: " + why + "; " + std::to_string(discarded) +
                              " epoch(s) waiting for corrections discarded (counted)");
  outputs_.finishLaggedOutput(*estimator_);
  std::string unused;
  estimator_ = ppp::makeEstimator(config_.ros.estimator, config_.ppp, &unused);
  outputs_.attachLaggedOutput(*estimator_);  // the file continues (rows not after the last one are refused and counted)
  processor_.reset();
  outputs_.resetTrajectory();
  last_output_time_.reset();
}

void PppNode::onObservations(const ros::MessageEvent<ppp_bayes_tree::GnssObservations const>& event) {
  ObservationIntake intake = inputs_.receiveObservations(event.getMessage(), event.getPublisherName(), ros::Time::now());
  if (intake.reset_why) resetEstimator(*intake.reset_why);
  inputs_.admitObservations(intake, [this](const ppp::GnssTime& time) { publishEmptyEpoch(time); });
  drain();
}

void PppNode::onCorrections(const ros::MessageEvent<ppp_bayes_tree::PreciseCorrections const>& event) {
  const ppp_bayes_tree::PreciseCorrections& msg = *event.getMessage();
  std::optional<CorrectionInput> input = inputs_.receiveCorrections(msg, event.getPublisherName());
  if (!input) return;
  // The first batch declares the stream's clock centre and antenna model: the antennas may change.
  if (inputs_.declareStreamedProducts(products_, msg, input->batch) && processor_) startProcessor();
  inputs_.admitCorrections(msg, std::move(*input), ros::Time::now());
  drain();
}

void PppNode::onStreamChunk(ppp::StreamChunk&& chunk) {
  inputs_.feed(chunk);
  drain();
}

void PppNode::onTimer(const ros::TimerEvent&) {
  // A ros::Timer runs on the ROS clock: under sim time only once /clock has come, so
  // the live chunks held for a valid clock go on from here too (gnss_stream_subscriber.h).
  for (auto& sub : stream_subs_) sub->releaseHeld();
  drain();
}

void PppNode::drain() {
  if (inputs_.isLive()) {
    drainLive();
  } else {
    const double now_s = ros::Time::now().toSec();
    while (std::optional<PendingObservation> ready = inputs_.nextReady(now_s))
      if (std::optional<ppp::ObsEpoch> epoch = inputs_.toEpoch(*ready)) processObsEpoch(*epoch);
  }
  diagnostics_.update();
}

void PppNode::drainLive() {
  for (const ppp::LiveReadyEpoch& ready : inputs_.takeLiveReady(ros::Time::now().toSec())) processLiveEpoch(ready);
}

void PppNode::processLiveEpoch(const ppp::LiveReadyEpoch& ready) {
  if (auto why = inputs_.liveRestart(ready, last_output_time_, ros::Time::now())) resetEstimator(*why);
  if (!inputs_.admitLiveEpoch(ready)) return;
  processObsEpoch(ready.epoch);
  if (ready.arrival_s) inputs_.recordLiveLatency(ros::Time::now().toSec() - *ready.arrival_s);
}

void PppNode::publishEmptyEpoch(const ppp::GnssTime& time) {
  status_pub_.publish(outputs_.emptyEpochStatus(time, inputs_.counters(), inputs_.correctionsStale_s().value_or(kNaN),
                                                phase_biases_, arEnabled()));
}

void PppNode::startProcessor() {
  const ppp::RinexObsHeader& layout = inputs_.layout();
  const ppp::OceanLoadingLookup ocean = products_.oceanLoading(layout.marker_name);
  if (!ocean.note.empty() && !ocean.coefficients) warnings_.warn("blq", "ppp: " + ocean.note);
  processor_biases_ = inputs_.codeBiases(products_);
  processor_ = std::make_unique<ppp::PppEpochProcessor>(layout, config_.ppp, inputs_.ephemeris(), products_.antennas(),
                                                         processor_biases_, ocean.coefficients);
  for (const auto& w : processor_->receiverAntennaWarnings()) warnings_.warn("antenna:" + w, "ppp: " + w);
  phase_biases_ = {};  // the new processor gets the phase information at its first epoch
  if (layout.approx_position_ecef_m) estimator_->setApproximatePosition(*layout.approx_position_ecef_m);
  inputs_.takeLayoutChanged();
}

void PppNode::processObsEpoch(const ppp::ObsEpoch& epoch) {
  // Live SSR biases arrive after the start: the processor is remade with them (once: then stable).
  if (!processor_ || inputs_.codeBiases(products_) != processor_biases_) startProcessor();
  else if (inputs_.takeLayoutChanged()) processor_->setObservationTypes(inputs_.layout());
  updatePhaseBiases();  // the live SSR phase biases and the batches' biases through the assembly's gate
  const auto start = std::chrono::steady_clock::now();
  const double cpu0_s = ppp::threadCpu_s();
  const ppp::PppEpochRecord rec = processor_->process(epoch, *estimator_);
  estimator_cpu_s_ += ppp::threadCpu_s() - cpu0_s;
  const double update_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (rec.refused) {  // cannot happen after the time checks above, kept as a guard
    warnings_.warn("refused", "ppp: epoch refused: " + rec.reason);
    return;
  }
  // Outputs never go back in time, one stamp one fix (the time guard and the FIFO gate
  // ensure it; kept as a guard).
  const bool publishable = !last_output_time_ || epoch.time > *last_output_time_;
  if (!publishable) {
    outputs_.countNotPublished();
    warnings_.warn("output_order", "ppp: solution at " + epoch.time.toString() +
                                       " not after the last published one: not published");
  }
  const bool solved = solvedEpoch(rec);
  if (solved && !outputs_.hasDatum()) setDatum(*rec.solution.position_ecef_m);
  const ppp_bayes_tree::PppStatus s =
      outputs_.epochStatus(epoch.time, rec, inputs_.counters(),
                           epochFigures(inputs_, *estimator_, epoch, rec, update_s, processor_->receiverAntennaWarnings()),
                           phase_biases_, arEnabled());
  if (publishable) {
    last_output_time_ = epoch.time;
    if (solved) publishSolution(epoch.time, rec, s);
    status_pub_.publish(s);
  }
  if (rec.estimator_reset) {
    // The core restarted the estimator from its last good state (as offline in
    // ppp_solve); the node only counts and reports it.
    ++estimator_restarts_;
    warnings_.warn("restart", "ppp: estimator restarted from its last good state at " + epoch.time.toString() + ": " +
                                  rec.reason);
  }
}

void PppNode::publishSolution(const ppp::GnssTime& time, const ppp::PppEpochRecord& rec,
                              const ppp_bayes_tree::PppStatus& status) {
  const RosNodeOptions& o = config_.ros;
  // map -> base_link, or map -> odom when another node publishes odom -> base_link.
  std::optional<geometry_msgs::TransformStamped> odom_to_base;
  std::string err;
  if (o.publish_tf && tf_buffer_.canTransform(o.odom_frame, o.base_frame, ros::Time(0), &err))
    odom_to_base = tf_buffer_.lookupTransform(o.odom_frame, o.base_frame, ros::Time(0));
  const SolutionMessages out = outputs_.solution(rec, status, odom_to_base);
  odom_pub_.publish(out.odometry);
  fix_pub_.publish(out.fix);
  if (out.tf) tf_.sendTransform(*out.tf);
  if (const ppp::SmoothedTrajectoryProvider* sm = smoother())
    if (auto odom = outputs_.smoothedOdometry(*sm, time)) smoothed_odom_pub_.publish(*odom);
  outputs_.markSmoothedStale();
}

void PppNode::onPathTimer(const ros::TimerEvent&) {
  if (const nav_msgs::Path* path = outputs_.filteredPath()) path_pub_.publish(*path);
}

void PppNode::onSmoothedPathTimer(const ros::TimerEvent&) {
  if (const ppp::SmoothedTrajectoryProvider* sm = smoother())
    if (auto path = outputs_.smoothedPath(*sm)) smoothed_path_pub_.publish(*path);
}

void PppNode::updatePhaseBiases() {
  PhaseBiasChoice choice = inputs_.choosePhaseBiases(products_);
  const bool changed = choice.provider != phase_biases_.provider || choice.source != phase_biases_.source;
  phase_biases_ = std::move(choice);
  if (!changed && phase_bias_logged_) return;
  processor_->setPhaseBiases(phase_biases_.provider);
  if (!arEnabled()) return;
  if (phase_biases_.provider)
    ROS_INFO_STREAM("ppp: ambiguity resolution with " << phase_biases_.source);
  else if (!phase_bias_logged_)  // once: the status and diagnostics carry it per epoch
    ROS_WARN_STREAM("ppp: " << phase_biases_.source);
  phase_bias_logged_ = true;
}

}  // namespace ppp_ros
