#include "ppp_bayes_tree/ros/node_inputs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <ros/console.h>

#include "ppp_bayes_tree/types/text_format.h"
#include "ppp_bayes_tree/types/thread_cpu_time.h"

namespace ppp_ros {
namespace {

ppp::EpochTimeGuardOptions observationGuardOptions(const RosNodeOptions& o) {
  ppp::EpochTimeGuardOptions g;
  g.max_forward_step_s = o.max_forward_step_s;
  g.out_of_order_window_s = o.reset_backwards_threshold_s;
  g.confirm_epochs = o.time_jump_confirm_epochs;
  return g;
}

ppp::EpochTimeGuardOptions correctionGuardOptions(const RosNodeOptions& o) {
  // Correction batches: farther apart than the history cannot be interpolated anyway;
  // out-of-order batches go to the buffer, which orders them and drops duplicates.
  ppp::EpochTimeGuardOptions g = observationGuardOptions(o);
  g.max_forward_step_s = o.correction_history_s;
  g.drop_out_of_order = false;
  return g;
}

ppp::CorrectionBufferOptions bufferOptions(const RosNodeOptions& o) {
  ppp::CorrectionBufferOptions b;
  b.history_s = o.correction_history_s;
  return b;
}

}  // namespace

std::string secondsText(double s) { return ppp::format("%+.3f s", s); }

std::uint32_t SequenceGapCounter::gap(const std::string& publisher, std::uint32_t seq) {
  const auto it = last_seq_.find(publisher);
  if (it == last_seq_.end()) {
    last_seq_[publisher] = seq;
    return 0;
  }
  const std::uint32_t previous = it->second;
  it->second = seq;
  return seq > previous ? seq - previous - 1 : 0;
}

NodeInputs::NodeInputs(const RosNodeOptions& options, WarningSink warn)
    : options_(options),
      warn_(std::move(warn)),
      corrections_(bufferOptions(options)),
      stream_biases_(options.correction_history_s),
      gate_({options.correction_wait_s, options.max_pending_epochs}),
      obs_guard_(observationGuardOptions(options)),
      corr_guard_(correctionGuardOptions(options)),
      last_correction_age_s_(std::numeric_limits<double>::quiet_NaN()) {
  counters_.estimator = options.estimator;
}

ObservationIntake NodeInputs::receiveObservations(const ppp_bayes_tree::GnssObservations::ConstPtr& msg,
                                                  const std::string& publisher, const ros::Time& arrival) {
  ++obs_received_;
  if (const std::uint32_t lost = obs_seq_.gap(publisher, msg->header.seq)) {
    counters_.observations_lost += lost;
    warn_("obs_lost", "ppp: " + std::to_string(lost) + " observation message(s) lost before the node (header.seq gap "
                      "from " + publisher + "; queue ros.input.observation_queue_size " +
                      std::to_string(options_.observation_queue_size) + "): counted");
  }
  ObservationIntake intake;
  intake.arrival = arrival;
  PendingObservation p;
  p.msg = msg;
  p.arrival = arrival;
  last_obs_arrival_ = arrival;
  try {
    p.time = fromMessageTime(msg->week, msg->seconds_of_week, msg->time_system);
  } catch (const std::exception& e) {
    ++counters_.observations_invalid;
    warn_("obs_time", std::string("ppp: observation epoch dropped: ") + e.what());
    return intake;
  }
  const ppp::GnssTime time = p.time;
  intake.outcome = obs_guard_.push(time, std::move(p));
  countObservationDrops(intake.outcome);
  if (intake.outcome.reset_step_s)
    intake.reset_why = "time went back by " + secondsText(*intake.outcome.reset_step_s) + " (beyond " +
                       std::to_string(options_.reset_backwards_threshold_s) + " s), confirmed by " +
                       std::to_string(intake.outcome.accepted.size()) + " consecutive epochs";
  return intake;
}

void NodeInputs::countObservationDrops(const ppp::EpochTimeGuard<PendingObservation>::Outcome& outcome) {
  for (const auto& d : outcome.dropped) {
    last_time_drop_ = "observation epoch " + d.time.toString() + " (" + secondsText(d.step_s) + "): " + ppp::text(d.reason);
    switch (d.reason) {
      case ppp::TimeDropReason::Duplicate: ++counters_.epochs_duplicate; break;
      case ppp::TimeDropReason::OutOfOrder: ++counters_.epochs_out_of_order; break;
      case ppp::TimeDropReason::UnconfirmedJump: ++counters_.epochs_time_jump_dropped; break;
    }
    warn_("obs_drop:" + ppp::text(d.reason), "ppp: " + last_time_drop_ + ": dropped (counted)");
  }
}

void NodeInputs::admitObservations(ObservationIntake& intake,
                                   const std::function<void(const ppp::GnssTime&)>& on_empty) {
  auto& outcome = intake.outcome;
  if (outcome.reset_step_s) {
    // The observations' confirmed loop vouches for correction batches held as a jump back
    // to the new time line (within the correction history of its first epoch).
    const std::optional<ppp::GnssTime> held = corr_guard_.firstHeld();
    const std::optional<ppp::GnssTime>& last = corr_guard_.lastAccepted();
    if (held && last && *held < *last && !outcome.accepted.empty() &&
        std::abs(*held - outcome.accepted.front().time) <= options_.correction_history_s) {
      auto corrections = corr_guard_.confirmHeld();
      applyCorrectionOutcome(corrections, intake.arrival);
    }
  }
  if (outcome.forward_jump_s)
    warn_("forward_jump", "ppp: time went forward by " + secondsText(*outcome.forward_jump_s) + ", confirmed by " +
                              std::to_string(outcome.accepted.size()) + " consecutive epochs: accepted");
  for (auto& e : outcome.accepted) acceptObservation(std::move(e.payload), on_empty);
  outcome.accepted.clear();
}

void NodeInputs::acceptObservation(PendingObservation p, const std::function<void(const ppp::GnssTime&)>& on_empty) {
  last_received_ = p.time;
  if (p.msg->satellites.empty()) {
    ++counters_.empty_epochs;
    warn_("empty", "ppp: empty epoch " + p.time.toString() + " (no satellites): no solution");
    on_empty(p.time);
    return;
  }
  const ppp::GnssTime time = p.time;
  const double arrival_s = p.arrival.toSec();
  gate_.push(time, arrival_s, std::move(p));
}

std::optional<CorrectionInput> NodeInputs::receiveCorrections(const ppp_bayes_tree::PreciseCorrections& msg,
                                                              const std::string& publisher) {
  ++corr_received_;
  if (const std::uint32_t lost = corr_seq_.gap(publisher, msg.header.seq)) {
    counters_.corrections_lost += lost;
    warn_("corr_lost", "ppp: " + std::to_string(lost) + " correction message(s) lost before the node (header.seq gap "
                       "from " + publisher + "; queue ros.input.correction_queue_size " +
                       std::to_string(options_.correction_queue_size) + "): counted");
  }
  ConversionIssues issues;
  CorrectionInput input;
  try {
    input.batch = fromMessage(msg, issues);
    input.biases = biasesFromMessage(msg, issues);
  } catch (const std::exception& e) {
    issues_.add(std::string("correction batch dropped: ") + e.what());
    warn_("corrections_time", std::string("ppp: correction batch dropped: ") + e.what());
    return std::nullopt;
  }
  for (const auto& [reason, n] : issues.counts) {
    if (reason.find("unknown satellite") != std::string::npos) counters_.corrections_unknown_satellites += n;
    issues_.counts[reason] += n;
    warn_("corr:" + reason.substr(0, 20), "ppp: corrections: " + reason);
  }
  if (input.batch.satellites.empty()) {
    warn_("corr_empty", "ppp: correction batch without a usable satellite ignored");
    return std::nullopt;
  }
  return input;
}

void NodeInputs::admitCorrections(const ppp_bayes_tree::PreciseCorrections& msg, CorrectionInput input,
                                  const ros::Time& now) {
  if (!input.biases.biases.empty()) stream_bias_kind_ = phaseInformation(msg.ar_bias_kind);
  last_correction_age_s_ = (now - msg.header.stamp).toSec();
  const ppp::GnssTime time = input.batch.time;
  auto outcome = corr_guard_.push(time, std::move(input));
  for (const auto& d : outcome.dropped) {
    ++counters_.corrections_time_jump_dropped;
    last_time_drop_ = "correction batch " + d.time.toString() + " (" + secondsText(d.step_s) + "): " + ppp::text(d.reason);
    warn_("corr_jump", "ppp: " + last_time_drop_ + ": dropped (counted)");
  }
  applyCorrectionOutcome(outcome, now);
}

void NodeInputs::applyCorrectionOutcome(ppp::EpochTimeGuard<CorrectionInput>::Outcome& outcome, const ros::Time& now) {
  if (outcome.reset_step_s) {
    warn_("corrections_back", "ppp: correction time went back by " + secondsText(*outcome.reset_step_s) +
                                  ", confirmed (" + std::to_string(outcome.accepted.size()) + " batches): buffer of " +
                                  std::to_string(corrections_.size()) + " batches cleared");
    corrections_.clear();
    stream_biases_.clear();
  }
  for (auto& e : outcome.accepted) acceptCorrections(std::move(e.payload), now);
}

void NodeInputs::acceptCorrections(CorrectionInput input, const ros::Time& now) {
  const ppp::BatchAddResult r = corrections_.add(std::move(input.batch));
  if (r == ppp::BatchAddResult::Added) stream_biases_.add(input.biases);
  if (r == ppp::BatchAddResult::Duplicate) warn_("corr_dup", "ppp: duplicate correction batch ignored");
  if (r == ppp::BatchAddResult::TooOld) warn_("corr_old", "ppp: correction batch older than the history ignored");
  if (r != ppp::BatchAddResult::Duplicate && r != ppp::BatchAddResult::TooOld) last_corr_arrival_ = now;
}

bool NodeInputs::declareStreamedProducts(ppp::ProductAssembly& products, const ppp_bayes_tree::PreciseCorrections& msg,
                                         const ppp::CorrectionBatch& batch) {
  if (streamed_declared_ || live_) return false;
  streamed_declared_ = true;
  const ppp::StreamedProductInfo info = streamedProductInfo(msg, batch);
  if (!products.declareStreamedProducts(info)) return false;
  ROS_INFO_STREAM("ppp: the correction stream declares "
                  << (info.clock_centre.empty() ? "no clock centre" : "clocks of " + info.clock_centre) << " and "
                  << (info.antenna_model.empty() ? "no antenna model" : "antenna model " + info.antenna_model) << ": "
                  << products.arGate().text());
  return true;
}

PhaseBiasChoice NodeInputs::choosePhaseBiases(ppp::ProductAssembly& products) {
  if (live_) {
    if (live_->hasPhaseBiases() &&
        products.acceptStreamedPhaseBiases(live_->biases(), ppp::PhaseInformation::SsrPhaseBiases))
      ROS_INFO_STREAM("ppp: " << products.arGate().text());
  } else if (!stream_biases_.empty() && stream_bias_kind_ != ppp::PhaseInformation::None &&
             products.acceptStreamedPhaseBiases(&stream_biases_, stream_bias_kind_)) {
    ROS_INFO_STREAM("ppp: " << products.arGate().text());
  }
  if (const ppp::BiasProvider* p = products.phaseBiases()) return {p, p->describeSource()};
  if (products.arGate().mode == ppp::AmbiguityResolutionMode::Off) return {nullptr, "ambiguity resolution off"};
  return {nullptr, products.arGate().text()};
}

std::optional<PendingObservation> NodeInputs::nextReady(double now_s) {
  auto ready = gate_.pop(now_s, corrections_, last_received_);
  if (!ready) return std::nullopt;
  return std::move(ready->payload);
}

std::optional<ppp::ObsEpoch> NodeInputs::toEpoch(const PendingObservation& p) {
  ppp::ObsEpoch epoch;
  ConversionIssues issues;
  try {
    layout_changed_ |= fromMessage(*p.msg, layout_, epoch, issues);
  } catch (const std::exception& e) {
    ++counters_.observations_invalid;
    warn_("obs_convert", std::string("ppp: observation epoch dropped: ") + e.what());
    return std::nullopt;
  }
  for (const auto& [reason, n] : issues.counts) {
    counters_.observations_invalid += n;
    issues_.counts[reason] += n;
    warn_("obs:" + reason.substr(0, 24), "ppp: observations: " + reason + " (excluded, counted)");
  }
  return epoch;
}

std::optional<double> NodeInputs::correctionsStale_s() const {
  std::optional<double> stale;
  if (last_received_ && corrections_.newest()) stale = *last_received_ - *corrections_.newest();
  if (last_obs_arrival_ && last_corr_arrival_) {
    const double by_arrival = (*last_obs_arrival_ - *last_corr_arrival_).toSec();
    stale = stale ? std::max(*stale, by_arrival) : by_arrival;
  }
  return stale;
}

std::size_t NodeInputs::resetForEstimator() {
  const std::size_t discarded = gate_.size();
  ++counters_.estimator_resets;
  counters_.epochs_discarded_at_reset += static_cast<std::uint32_t>(discarded);
  gate_.clear();
  last_received_.reset();
  return discarded;
}

bool NodeInputs::takeLayoutChanged() {
  const bool changed = layout_changed_;
  layout_changed_ = false;
  return changed;
}

void NodeInputs::startLive(const ppp::LiveInputOptions& options) {
  live_ = std::make_unique<ppp::LiveGnssInput>(options);
}

void NodeInputs::feed(const ppp::StreamChunk& chunk) {
  const double cpu0_s = ppp::threadCpu_s();
  live_->feed(chunk);
  live_decode_cpu_s_ += ppp::threadCpu_s() - cpu0_s;
}

std::vector<ppp::LiveReadyEpoch> NodeInputs::takeLiveReady(double now_s) {
  const double cpu0_s = ppp::threadCpu_s();
  std::vector<ppp::LiveReadyEpoch> ready = live_->takeReadyEpochs(now_s);
  live_decode_cpu_s_ += ppp::threadCpu_s() - cpu0_s;
  for (const std::string& event : live_->takeTimeEvents()) warn_("epoch_time", "ppp: " + event);
  if (ready.empty()) return ready;
  // The epochs are laid out by the header as it is now.
  if (live_->takeHeaderChanged()) {
    layout_ = live_->header();
    layout_changed_ = true;
  }
  return ready;
}

std::optional<std::string> NodeInputs::liveRestart(const ppp::LiveReadyEpoch& ready,
                                                   const std::optional<ppp::GnssTime>& last_output_time,
                                                   const ros::Time& now) {
  ++obs_received_;
  last_obs_arrival_ = now;
  // LiveGnssInput drops small steps back; what still goes back is a receiver restart
  // (a jump beyond ros.live.restart_jump_s): reset as on a bag loop.
  if (!last_output_time || ready.epoch.time > *last_output_time) return std::nullopt;
  ++live_receiver_restarts_;
  return "receiver restart: observation time went back by " + secondsText(ready.epoch.time - *last_output_time) +
         " (live input)";
}

bool NodeInputs::admitLiveEpoch(const ppp::LiveReadyEpoch& ready) {
  const ppp::ObsEpoch& epoch = ready.epoch;
  last_received_ = epoch.time;
  const bool broadcast = ready.mode == ppp::LiveProductMode::BroadcastOnly;
  product_mode_ = broadcast ? ppp_bayes_tree::PppStatus::PRODUCTS_BROADCAST_ONLY
                            : ppp_bayes_tree::PppStatus::PRODUCTS_PRECISE;
  product_mode_text_ = std::string(ppp::liveProductModeName(ready.mode));
  if (broadcast && options_.live_input.expect_corrections)
    warn_("broadcast_only", "ppp: corrections missing or too old at " + epoch.time.toString() +
                                ": broadcast orbits and clocks only (widened sigmas)");
  if (epoch.satellites.empty()) {
    ++counters_.empty_epochs;
    warn_("empty", "ppp: empty epoch " + epoch.time.toString() + " (no satellites): no solution");
    return false;
  }
  return true;
}

void NodeInputs::recordLiveLatency(double latency_s) {
  live_latency_s_.push_back(latency_s);
  if (live_latency_s_.size() > kLatencyWindow) live_latency_s_.pop_front();
}

const ppp::EphemerisSource& NodeInputs::ephemeris() const {
  if (live_) return live_->ephemeris();
  return corrections_;
}

const ppp::BiasProvider* NodeInputs::codeBiases(const ppp::ProductAssembly& products) const {
  if (const ppp::BiasProvider* b = products.codeBiases().get()) return b;
  return live_ ? live_->biases() : nullptr;
}

ppp::ProductAssembly assembleNodeProducts(const ppp::PppConfig& config, const RosNodeOptions& o) {
  if (o.atx.empty() &&
      (config.model.satellite_antenna || config.model.receiver_antenna == ppp::ReceiverAntennaPolicy::Required))
    throw std::runtime_error("parameter ros/products/atx is empty, but measurement_model/corrections/"
                             "satellite_antenna is on or receiver_antenna is required: give the ANTEX file(s) or "
                             "turn them off");
  ppp::ProductAssemblyInputs in;  // no orbit and clock files: streamed (the first batch declares its products)
  in.atx = o.atx;
  if (!o.bias.empty()) in.bias = o.bias;
  if (!o.blq.empty()) in.blq = o.blq;
  in.live_ssr = o.live() && !o.live_correction_topics.empty();
  return ppp::ProductAssembly::assemble(in, config);
}

std::vector<LiveSubscription> liveSubscriptions(const RosNodeOptions& o,
                                                const std::function<std::string(const std::string&)>& resolve) {
  std::string receiver;
  for (const auto& t : o.live_observation_topics) receiver += (receiver.empty() ? "" : "+") + resolve(t.topic);
  std::vector<LiveSubscription> out;
  for (const auto& t : o.live_observation_topics) out.push_back({t, receiver});
  for (const auto& t : o.live_correction_topics) out.push_back({t, ""});
  return out;
}

}  // namespace ppp_ros
