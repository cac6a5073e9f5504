#include "ppp_bayes_tree/ros/ppp_node.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/NavSatFix.h>

#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/types/constants.h"
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
  setUpImu();  // an estimator with inertial states: the IMU's options go into its configuration
  std::string why;
  estimator_ = ppp::makeEstimator(config_.ros.estimator, config_.ppp, &why);
  if (!estimator_) throw std::runtime_error("estimator '" + config_.ros.estimator + "' is not available: " + why);
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
  // TCP_NODELAY: without it Nagle's algorithm held readings back behind the GNSS epoch they
  // precede (a 0.125 s "gap" before an epoch of the u-blox walk bag, the INS stopped).
  if (imu_)
    imu_sub_ = nh_.subscribe(o.imu.topic, 2000, &PppNode::onImu, this, ros::TransportHints().tcpNoDelay());
  // The epochs held for the IMU also go on by the steady clock when the ROS clock stands
  // still (a bag's /clock stopped: no ROS timer fires, no reading comes; imu_epoch_hold.h).
  if (imu_ && o.imu.max_wait_s > 0.0)
    hold_steady_timer_ =
        nh_.createSteadyTimer(ros::WallDuration(o.imu.max_wait_s), [this](const ros::SteadyTimerEvent&) {
          if (!epoch_hold_.empty()) releaseAndDiagnose();
        });
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
  if (imu_) diagnostics_.add("imu", [this](DiagnosticStatusWrapper& s) { imuDiagnostics(s); });
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
  switchEstimator(config_.ros.estimator);  // the file continues (rows not after the last one are refused and counted)
  outputs_.resetTrajectory();
  last_output_time_.reset();
  ins_fallback_reason_.reset();
  ins_alignment_.reset();
  last_gnss_update_.reset();
  last_odometry_stamp_.reset();
  if (imu_) {
    imu_->reset();
    ins_odometry_->stop();
  }
}

void PppNode::switchEstimator(const std::string& name) {
  outputs_.finishLaggedOutput(*estimator_);
  std::string why;
  std::unique_ptr<ppp::PppEstimator> made = ppp::makeEstimator(name, config_.ppp, &why);
  if (!made) throw std::runtime_error("estimator '" + name + "' is not available: " + why);  // registered names only
  estimator_ = std::move(made);
  outputs_.attachLaggedOutput(*estimator_);
  processor_.reset();
  active_estimator_ = name;
}

void PppNode::onObservations(const ros::MessageEvent<ppp_bayes_tree::GnssObservations const>& event) {
  ObservationIntake intake = inputs_.receiveObservations(event.getMessage(), event.getPublisherName(), ros::Time::now());
  if (imu_) {  // the newest epoch received: the IMU's time base is compared with it
    const ppp::GnssTime t = fromUtcStamp(event.getMessage()->header.stamp);
    if (!newest_gnss_time_ || t - *newest_gnss_time_ > 0.0 || intake.reset_why) newest_gnss_time_ = t;
  }
  if (intake.reset_why) {
    releaseHeldEpochs(true);  // the epochs before the jump go on first, in order
    resetEstimator(*intake.reset_why);
  }
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
    while (std::optional<PendingObservation> ready = inputs_.nextReady(now_s)) {
      const ppp::GnssTime time = ready->time;
      admitEpoch(std::move(*ready), time, now_s);
    }
  }
  releaseAndDiagnose();
}

void PppNode::releaseAndDiagnose() {
  releaseHeldEpochs();
  diagnostics_.update();
}

void PppNode::drainLive() {
  const double now_s = ros::Time::now().toSec();
  for (ppp::LiveReadyEpoch& ready : inputs_.takeLiveReady(now_s)) {
    const ppp::GnssTime time = ready.epoch.time;
    // The newest epoch received (the IMU's time base is compared with it), also while it waits.
    if (!newest_gnss_time_ || time - *newest_gnss_time_ > 0.0) newest_gnss_time_ = time;
    admitEpoch(std::move(ready), time, now_s);
  }
}

bool PppNode::waitsForImu() const { return imu_ && inertialActive(); }

void PppNode::admitEpoch(HeldEpoch epoch, const ppp::GnssTime& time, double now_s) {
  if (epoch_hold_.empty() && !waitsForImu()) {  // GNSS only: at once, as it comes
    processHeld(epoch);
    return;
  }
  epoch_hold_.hold(std::move(epoch), time, HoldClock{now_s, ros::SteadyTime::now().toSec()});
}

HoldClock PppNode::holdClock() { return {ros::Time::now().toSec(), ros::SteadyTime::now().toSec()}; }

void PppNode::releaseHeldEpochs(bool all) {
  if (epoch_hold_.empty()) return;
  while (std::optional<ReleasedEpoch<HeldEpoch>> r =
             epoch_hold_.release(holdClock(), imu_ ? imu_->progress() : ImuProgress{}, !all && waitsForImu())) {
    const ImuWaitOutcome outcome = r->decision.outcome;
    if (outcome == ImuWaitOutcome::WaitedOut || outcome == ImuWaitOutcome::ClockStopped)
      warnings_.warn("imu:" + imuWaitOutcomeText(outcome),
                     "ppp: " + imuWaitedOutText(r->time, r->waited_s, r->decision, nh_.resolveName(imu_->topic()),
                                                epoch_hold_.maxWait_s()));
    processHeld(r->epoch);
  }
  armHoldTimer();
}

void PppNode::processHeld(HeldEpoch& epoch) {
  if (auto* live = std::get_if<ppp::LiveReadyEpoch>(&epoch)) {
    processLiveEpoch(*live);
  } else if (std::optional<ppp::ObsEpoch> obs = inputs_.toEpoch(std::get<PendingObservation>(epoch))) {
    processObsEpoch(*obs);
  }
}

void PppNode::armHoldTimer() {
  const std::optional<double> deadline_s = epoch_hold_.deadline_s();
  if (deadline_s == hold_deadline_s_) return;
  hold_deadline_s_ = deadline_s;
  if (!deadline_s) {
    hold_timer_.stop();
    return;
  }
  // Just after the deadline (a timer fires at or after its time).
  const double in_s = std::max(*deadline_s - ros::Time::now().toSec(), 0.0) + 1e-3;
  hold_timer_ = nh_.createTimer(
      ros::Duration(in_s),
      [this](const ros::TimerEvent&) {
        hold_deadline_s_.reset();
        releaseAndDiagnose();
      },
      true);
}

void PppNode::processLiveEpoch(const ppp::LiveReadyEpoch& ready) {
  if (auto why = inputs_.liveRestart(ready, last_output_time_, ros::Time::now())) resetEstimator(*why);
  if (!inputs_.admitLiveEpoch(ready)) return;
  processObsEpoch(ready.epoch);
  if (ready.arrival_s) inputs_.recordLiveLatency(ros::Time::now().toSec() - *ready.arrival_s);
}

void PppNode::publishEmptyEpoch(const ppp::GnssTime& time) {
  ppp_bayes_tree::PppStatus s = outputs_.emptyEpochStatus(
      time, inputs_.counters(), inputs_.correctionsStale_s().value_or(kNaN), phase_biases_, arEnabled());
  fillInsStatus(s, time);
  status_pub_.publish(s);
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
  if (imu_) {  // the readings up to the epoch, as ppp_solve hands them on (none to a GNSS-only estimator)
    epoch_imu_ = imu_->takeUpTo(epoch.time);
    processor_->setImu(inertialActive() ? &epoch_imu_ : nullptr);
  }
  const auto start = std::chrono::steady_clock::now();
  const double cpu0_s = ppp::threadCpu_s();
  const ppp::PppEpochRecord rec = processor_->process(epoch, *estimator_);
  estimator_cpu_s_ += ppp::threadCpu_s() - cpu0_s;
  const double update_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (rec.refused) {  // cannot happen after the time checks above, kept as a guard
    warnings_.warn("refused", "ppp: epoch refused: " + rec.reason);
    return;
  }
  if (insStopped(rec)) {  // the epoch again through the GNSS-only estimator
    fallBackToGnss(epoch.time, rec.reason);
    processObsEpoch(epoch);
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
  if (solved) last_gnss_update_ = epoch.time;
  ins_alignment_ = insAlignment(rec);
  ppp_bayes_tree::PppStatus s =
      outputs_.epochStatus(epoch.time, rec, inputs_.counters(),
                           epochFigures(inputs_, *estimator_, epoch, rec, update_s, processor_->receiverAntennaWarnings()),
                           phase_biases_, arEnabled());
  fillInsStatus(s, epoch.time);
  if (publishable) {
    last_output_time_ = epoch.time;
    if (solved) publishSolution(epoch.time, rec, s);
    status_pub_.publish(s);
  }
  if (const std::optional<ppp::InertialState> state = estimator_->inertialState()) restartInsOdometry(*state);
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
  // With the GNSS/INS filter the odometry and TF come at the IMU rate (publishInsOdometry).
  // Before the heading is aligned in motion they come per epoch, without an orientation.
  if ((!inertialActive() || insHeadingPending()) && claimOdometryStamp(out.odometry.header.stamp)) {
    odom_pub_.publish(out.odometry);
    if (out.tf) tf_.sendTransform(*out.tf);
  }
  fix_pub_.publish(out.fix);
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

// ---- GNSS/INS -----------------------------------------------------------------

bool PppNode::inertial() const {
  const ppp::EstimatorEntry* entry = ppp::findEstimator(config_.ros.estimator);
  return entry && entry->state == ppp::EstimatedState::GnssInertial;
}

void PppNode::setUpImu() {
  active_estimator_ = config_.ros.estimator;
  if (!inertial()) return;
  const RosImuOptions& o = config_.ros.imu;
  if (!o.extrinsics_from_tf) imu_extrinsics_ = parameterExtrinsics(o);
  config_.ppp.ins = insOptions(config_.ros, imu_extrinsics_.value_or(ImuExtrinsics{}), config_.ppp.ins);
  imu_ = std::make_unique<NodeImuInput>(config_.ros, warnings_.sink());
  epoch_hold_ = ImuEpochHold<HeldEpoch>(o.max_wait_s);
  ins_odometry_ = std::make_unique<InsOdometry>(config_.ppp.ins);
  ROS_INFO_STREAM("ppp: " << config_.ros.estimator << " with the IMU on " << nh_.resolveName(o.topic) << " ("
                          << o.grade << "; extrinsics from " << (o.extrinsics_from_tf ? "TF" : "ros.imu parameters")
                          << "; start attitude " << startAttitudeName(o.initial_attitude)
                          << "; an epoch waits for its readings at most " << o.max_wait_s << " s)");
}

void PppNode::onImu(const sensor_msgs::Imu::ConstPtr& msg) {
  const bool known = imu_extrinsics_ || (!imu_extrinsics_problem_ && resolveImuExtrinsics(msg->header.frame_id));
  const std::optional<Eigen::Matrix3d> body_from_imu =
      known ? std::optional<Eigen::Matrix3d>(bodyFromImu(*imu_extrinsics_)) : std::nullopt;
  const std::vector<ppp::ImuSample> accepted =
      imu_->receive(*msg, newest_gnss_time_, body_from_imu, ros::Time::now().toSec());
  // An epoch the new readings cover goes on now (before the odometry steps them: it restarts from the epoch).
  releaseHeldEpochs();
  if (ins_fallback_reason_) return;
  for (const ppp::ImuSample& r : accepted)
    if (const std::optional<InsState> state = ins_odometry_->step(r)) publishInsOdometry(*state);
}

bool PppNode::resolveImuExtrinsics(const std::string& imu_frame) {
  const std::string& base = config_.ros.base_frame;
  if (imu_frame.empty() || !tf_buffer_.canTransform(base, imu_frame, ros::Time(0))) return false;
  const geometry_msgs::Transform t = tf_buffer_.lookupTransform(base, imu_frame, ros::Time(0)).transform;
  ImuExtrinsics e;  // the IMU's pose in base_link: points of the IMU frame into base_link
  e.translation_m = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  e.rotation_base_imu = Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).toRotationMatrix();
  try {
    config_.ppp.ins = insOptions(config_.ros, e, config_.ppp.ins);
  } catch (const std::invalid_argument& refused) {  // the IMU's axes do not fit ros.imu.initial_attitude
    imu_extrinsics_problem_ = std::string("IMU extrinsics from TF ") + base + " -> " + imu_frame + " refused: " +
                              refused.what() + "; the IMU is not used";
    ROS_ERROR_STREAM("ppp: " << *imu_extrinsics_problem_);
    return false;
  }
  imu_extrinsics_ = e;
  ins_odometry_ = std::make_unique<InsOdometry>(config_.ppp.ins);
  ROS_INFO_STREAM("ppp: IMU extrinsics from TF " << base << " -> " << imu_frame << ": translation ["
                                                 << e.translation_m.transpose() << "] m; the GNSS/INS filter starts with them");
  switchEstimator(config_.ros.estimator);  // its lever arm is in the body frame at the IMU
  return true;
}

bool PppNode::inertialActive() const {
  const ppp::EstimatorEntry* entry = ppp::findEstimator(estimator_->name());
  return entry && entry->state == ppp::EstimatedState::GnssInertial;
}

bool PppNode::insStopped(const ppp::PppEpochRecord& rec) const {
  return estimator_->inertialState() && rec.no_solution_reason == ppp::NoSolutionReason::NoImuReadings;
}

void PppNode::fallBackToGnss(const ppp::GnssTime& time, const std::string& why) {
  // The registered estimator of the GNSS receiver state that gives the same solutions.
  const ppp::EstimatorEntry* own = ppp::findEstimator(config_.ros.estimator);
  std::string gnss;
  for (const ppp::EstimatorEntry& e : ppp::kEstimators)
    if (gnss.empty() && e.state == ppp::EstimatedState::GnssReceiver && own && e.solutions == own->solutions)
      gnss = std::string(e.name);
  ins_fallback_reason_ = "the IMU stopped before " + time.toString() + ": " + why;
  warnings_.warn("ins_fallback", "ppp: " + *ins_fallback_reason_ + "; GNSS only (estimator " + gnss +
                                     ", started afresh) from this epoch on, until an estimator reset");
  ins_odometry_->stop();
  switchEstimator(gnss);
}

void PppNode::restartInsOdometry(const ppp::InertialState& inertial) {
  if (!inertial.error_covariance) return;
  InsState state;
  state.time = inertial.time;
  state.nav = inertial.nav;
  state.bias = inertial.bias;
  state.covariance = *inertial.error_covariance;
  ins_odometry_->restart(state, imu_->lastTaken(), imu_->pending());
  if (const std::optional<InsState>& now = ins_odometry_->current()) publishInsOdometry(*now);
}

bool PppNode::claimOdometryStamp(const ros::Time& stamp) {
  if (!imu_) return true;
  if (last_odometry_stamp_ && stamp <= *last_odometry_stamp_) return false;
  last_odometry_stamp_ = stamp;
  return true;
}

std::optional<ppp::AlignmentState> PppNode::insAlignment(const ppp::PppEpochRecord& rec) const {
  if (!imu_ || !inertialActive()) return std::nullopt;
  // ekf_ins keeps the attitude's quality; smoother_ins has a NavState only once aligned.
  if (const std::optional<ppp::InertialState> ins = estimator_->inertialState())
    return ins->attitude_quality ? ins->attitude_quality->state : ppp::AlignmentState::Aligned;
  // smoother_ins solves GNSS only between the levelling and the course's heading.
  if (config_.ros.imu.initial_attitude == RosImuOptions::StartAttitude::AlignInMotion && solvedEpoch(rec))
    return ppp::AlignmentState::LevelOnly;
  return std::nullopt;
}

bool PppNode::insHeadingPending() const {
  return ins_alignment_ && *ins_alignment_ != ppp::AlignmentState::Aligned;
}

void PppNode::publishInsOdometry(const InsState& state) {
  if (!outputs_.hasDatum() || !imu_extrinsics_ || insHeadingPending()) return;
  const ros::Time stamp = utcStamp(state.time);
  if (!claimOdometryStamp(stamp)) return;
  const RosNodeOptions& o = config_.ros;
  const OdometryFrame frame{o.map_frame, o.base_frame, outputs_.datumEcef(), outputs_.enuFromEcef()};
  const ImuExtrinsics body = filterBodyExtrinsics(*imu_extrinsics_);  // the filter's frame in base_link
  odom_pub_.publish(insOdometryMessage(state, body, frame));
  if (!o.publish_tf) return;
  std::optional<geometry_msgs::TransformStamped> odom_to_base;
  if (tf_buffer_.canTransform(o.odom_frame, o.base_frame, ros::Time(0)))
    odom_to_base = tf_buffer_.lookupTransform(o.odom_frame, o.base_frame, ros::Time(0));
  const BasePose pose = basePose(state, body, frame);
  if (auto tf = outputs_.mapTransform(stamp, pose.position_m, Eigen::Quaterniond(pose.rotation_map_base), odom_to_base))
    tf_.sendTransform(*tf);
}

void PppNode::fillInsStatus(ppp_bayes_tree::PppStatus& s, const ppp::GnssTime& time) const {
  using S = ppp_bayes_tree::PppStatus;
  s.accel_bias_mps2 = s.gyro_bias_radps = {kNaN, kNaN, kNaN};
  s.seconds_since_gnss_update = last_gnss_update_ ? time - *last_gnss_update_ : kNaN;
  s.ins_state = S::INS_NOT_CONFIGURED;
  s.ins_state_text = "not configured";
  if (!imu_) return;
  s.estimator = active_estimator_;
  s.imu_readings_used = static_cast<std::uint32_t>(imu_->counters().used);
  s.imu_readings_rejected = static_cast<std::uint32_t>(imu_->counters().rejected);
  const std::optional<ppp::InertialState> ins = estimator_->inertialState();
  if (ins_fallback_reason_) {
    s.ins_state = S::INS_FALLEN_BACK;
    s.ins_state_text = "fallen back to GNSS";
    s.ins_reason = *ins_fallback_reason_;
  } else if (!ins) {
    s.ins_state = S::INS_WAITING;
    s.ins_state_text = "waiting";
    s.ins_reason = imu_extrinsics_problem_ ? *imu_extrinsics_problem_
                   : imu_extrinsics_       ? s.reason
                                           : "IMU extrinsics missing: no TF " + config_.ros.base_frame + " -> the IMU frame";
    if (insHeadingPending()) s.ins_reason = headingPendingText();
  } else {
    s.ins_state = S::INS_RUNNING;
    s.ins_state_text = "running";
    for (int i = 0; i < 3; ++i) {
      s.accel_bias_mps2[i] = ins->bias.accel_mps2[i];
      s.gyro_bias_radps[i] = ins->bias.gyro_radps[i];
    }
    if (ins->error_covariance) {
      InsState state;
      state.covariance = *ins->error_covariance;
      s.ins_attitude_valid = !insHeadingPending() &&
                             attitudeSigma_rad(state) < config_.ros.imu.attitude_sigma_valid_deg * ppp::kDegToRad;
    }
    if (insHeadingPending()) s.ins_reason = headingPendingText();
  }
}

std::string PppNode::headingPendingText() const {
  std::ostringstream t;
  t << "attitude " << ppp::alignmentStateText(*ins_alignment_) << ": the heading comes from the course over ground once "
    << "base_link moves forward faster than " << config_.ros.imu.heading_speed_mps
    << " m/s (ros.imu.initial_attitude align_in_motion); odometry and TF per epoch without orientation until then";
  return t.str();
}

void PppNode::imuDiagnostics(diagnostic_updater::DiagnosticStatusWrapper& s) const {
  using diagnostic_msgs::DiagnosticStatus;
  const ImuInputCounters& c = imu_->counters();
  const ImuWaitCounters& w = epoch_hold_.counters();
  const bool missing = !imu_extrinsics_ && c.received > 0;
  if (imu_extrinsics_problem_)
    s.summary(DiagnosticStatus::ERROR, *imu_extrinsics_problem_);
  else if (missing)
    s.summary(DiagnosticStatus::ERROR, "IMU extrinsics missing: no TF " + config_.ros.base_frame + " -> the IMU frame");
  else if (ins_fallback_reason_)
    s.summary(DiagnosticStatus::WARN, "GNSS only: " + *ins_fallback_reason_);
  else if (c.rejected > 0)
    s.summary(DiagnosticStatus::WARN, std::to_string(c.rejected) + " IMU message(s) not used");
  else if (w.waited_out > 0)
    s.summary(DiagnosticStatus::WARN, std::to_string(w.waited_out) + " epoch(s) processed before the IMU caught up "
                                      "(ros.imu.max_wait_s)");
  else
    s.summary(DiagnosticStatus::OK, c.received > 0 ? "IMU readings in use" : "no IMU message yet");
  s.add("topic", nh_.resolveName(imu_->topic()));
  s.add("estimator", active_estimator_);
  s.add("messages received", c.received);
  s.add("readings used", c.used);
  s.add("messages not used", c.rejected);
  s.add("readings dropped (buffer full)", c.dropped_old);
  s.add("problems", imu_->problemSummary());
  s.add("epochs waiting for the IMU now", epoch_hold_.size());
  s.add("epochs that waited for the IMU", w.held);
  s.add("epochs released by a reading at their time", w.covered);
  s.add("epochs released by ros.imu.max_wait_s", w.waited_out);
  s.add("of them while the ROS clock stood still", w.clock_stopped);
  s.add("largest IMU lag at release [s]", w.largest_lag_s);
  s.add("longest wait [s]", w.longest_wait_s);
  s.add("epochs not held (IMU silent)", w.silent);
  s.add("extrinsics", imu_extrinsics_problem_ ? *imu_extrinsics_problem_
                      : imu_extrinsics_      ? (config_.ros.imu.extrinsics_from_tf ? "from TF" : "from ros.imu")
                                             : "missing");
  s.add("start attitude", startAttitudeName(config_.ros.imu.initial_attitude));
  s.add("alignment", ins_alignment_ ? ppp::alignmentStateText(*ins_alignment_) : "no attitude yet");
}

}  // namespace ppp_ros
