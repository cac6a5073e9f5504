#pragma once
// The ROS node's inputs (ppp_node.h): observation and correction messages to core
// types, their time stamps through the epoch time guard (an isolated bad stamp is
// dropped, a sustained jump back resets the estimator), the correction gate (an
// epoch waits until corrections cover it), messages lost before the node (header.seq
// gaps per publisher) and the live input path (raw streams through ppp::LiveGnssInput).
// What the inputs meet is counted here (counters()); the outputs count theirs
// (node_outputs.h), and the status and diagnostics read both. Times come
// in as arguments (arrival, now): no ROS master or clock is needed.
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <ros/time.h>

#include "ppp_bayes_tree/GnssObservations.h"
#include "ppp_bayes_tree/PppStatus.h"
#include "ppp_bayes_tree/PreciseCorrections.h"
#include "ppp_bayes_tree/app/correction_gate.h"
#include "ppp_bayes_tree/app/live_gnss_input.h"
#include "ppp_bayes_tree/io/epoch_time_guard.h"
#include "ppp_bayes_tree/models/correction_buffer.h"
#include "ppp_bayes_tree/models/stream_bias_provider.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"
#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/ros/node_options.h"
#include "ppp_bayes_tree/ros/phase_bias_choice.h"
#include "ppp_bayes_tree/ros/throttled_warnings.h"

namespace ppp_ros {

/// An observation message whose stamp the time guard accepted, waiting for corrections.
struct PendingObservation {
  ppp_bayes_tree::GnssObservations::ConstPtr msg;
  ppp::GnssTime time;
  ros::Time arrival;
};

/// A correction batch and its satellite biases for ambiguity resolution (one message).
struct CorrectionInput {
  ppp::CorrectionBatch batch;
  ppp::SatelliteBiasBatch biases;
};

/// Messages lost before the node: gaps in header.seq, per publisher (roscpp numbers each
/// publication's messages consecutively; a subscriber or publisher queue overflow leaves a
/// gap). A seq not above the last one (a publisher that restarted, or one that leaves seq 0)
/// starts counting afresh: no loss counted.
class SequenceGapCounter {
 public:
  /// The messages missing between the last seq of `publisher` and `seq`.
  std::uint32_t gap(const std::string& publisher, std::uint32_t seq);

 private:
  std::map<std::string, std::uint32_t> last_seq_;
};

/// An observation message through the time guard.
struct ObservationIntake {
  ppp::EpochTimeGuard<PendingObservation>::Outcome outcome;
  /// Time went back for good: the estimator is reset (with this reason) before the accepted epochs.
  std::optional<std::string> reset_why;
  ros::Time arrival;  // of the message
};

class NodeInputs {
 public:
  NodeInputs(const RosNodeOptions& options, WarningSink warn);

  // --- GnssObservations / PreciseCorrections topics ---
  /// Counts the message and its header.seq gap, converts its time and passes it through
  /// the time guard (dropped stamps counted and named). A time that cannot be converted:
  /// counted as invalid, nothing accepted.
  ObservationIntake receiveObservations(const ppp_bayes_tree::GnssObservations::ConstPtr& msg,
                                        const std::string& publisher, const ros::Time& arrival);
  /// After the node's reset (intake.reset_why): the held correction batches the loop vouches
  /// for, then the accepted epochs to the correction gate. An epoch without satellites is
  /// counted and handed to `on_empty` (the node publishes its status) instead.
  void admitObservations(ObservationIntake& intake, const std::function<void(const ppp::GnssTime&)>& on_empty);
  /// Counts the message and its header.seq gap, converts it (problems counted); nullopt when
  /// it is dropped (unconvertible, or no usable satellite).
  std::optional<CorrectionInput> receiveCorrections(const ppp_bayes_tree::PreciseCorrections& msg,
                                                    const std::string& publisher);
  /// A converted batch through the time guard to the buffer (`now`: its age at arrival).
  void admitCorrections(const ppp_bayes_tree::PreciseCorrections& msg, CorrectionInput input, const ros::Time& now);
  /// The oldest waiting epoch when the gate releases it at `now_s` (ROS time).
  std::optional<PendingObservation> nextReady(double now_s);
  /// A released epoch in core types (the layout follows the message); problems counted.
  std::optional<ppp::ObsEpoch> toEpoch(const PendingObservation& p);

  // --- phase information for ambiguity resolution ---
  /// Once, at the first usable batch (topic input): the clock centre and antenna model of
  /// the stream's orbits and clocks to the product assembly; true when it took them (the
  /// satellite antennas and the PPP-AR gate may have changed).
  bool declareStreamedProducts(ppp::ProductAssembly& products, const ppp_bayes_tree::PreciseCorrections& msg,
                               const ppp::CorrectionBatch& batch);
  /// The streamed phase information (the live feed's SSR phase biases, RTCM 1265-1270 and
  /// IGS-SSR, or the biases the correction batches carry) through the assembly's PPP-AR
  /// gate, which decides as for ppp_solve; then the phase information in use.
  PhaseBiasChoice choosePhaseBiases(ppp::ProductAssembly& products);

  // --- live input (ros.live) ---
  /// Throws on an unreadable navigation file (ppp::LiveGnssInput).
  void startLive(const ppp::LiveInputOptions& options);
  bool isLive() const { return live_ != nullptr; }
  ppp::LiveGnssInput* live() { return live_.get(); }
  const ppp::LiveGnssInput* live() const { return live_.get(); }
  /// Bytes of one stream to the decoder (its thread CPU time counted).
  void feed(const ppp::StreamChunk& chunk);
  /// The epochs ready at `now_s`; the time events logged, the layout taken when it changed.
  std::vector<ppp::LiveReadyEpoch> takeLiveReady(double now_s);
  /// A ready epoch not after the last output is a receiver restart: counted, the reset reason returned.
  std::optional<std::string> liveRestart(const ppp::LiveReadyEpoch& ready,
                                         const std::optional<ppp::GnssTime>& last_output_time, const ros::Time& now);
  /// Takes the epoch's product mode; false for an epoch without satellites (counted).
  bool admitLiveEpoch(const ppp::LiveReadyEpoch& ready);
  /// In-node latency of a live epoch (chunk callback -> solution published), the last kLatencyWindow.
  void recordLiveLatency(double latency_s);
  static constexpr std::size_t kLatencyWindow = 1000;

  // --- the processor's products ---
  /// Orbits and clocks: the live input's (broadcast + SSR), else the correction batches'.
  const ppp::EphemerisSource& ephemeris() const;
  /// Code biases: the products' (Bias-SINEX), else the live input's SSR biases (nullptr
  /// until they arrive; then stable), else none.
  const ppp::BiasProvider* codeBiases(const ppp::ProductAssembly& products) const;

  // --- the estimator's side ---
  /// The estimator is reset: the epochs waiting for corrections are discarded (counted); returns how many.
  std::size_t resetForEstimator();
  /// The observation layout, and whether it changed since the last call (once).
  const ppp::RinexObsHeader& layout() const { return layout_; }
  bool takeLayoutChanged();

  // --- state and counters (status, diagnostics) ---
  /// The counter fields of PppStatus the inputs count (the outputs': NodeOutputs::counters()).
  const ppp_bayes_tree::PppStatus& counters() const { return counters_; }
  const ppp::CorrectionBuffer& corrections() const { return corrections_; }
  const ppp::StreamBiasProvider& streamBiases() const { return stream_biases_; }
  ppp::PhaseInformation streamBiasKind() const { return stream_bias_kind_; }
  /// Observations ahead of the corrections [s] (data time or ROS arrival time, the larger).
  std::optional<double> correctionsStale_s() const;
  std::size_t observationMessages() const { return obs_received_; }
  std::size_t correctionMessages() const { return corr_received_; }
  std::size_t pendingEpochs() const { return gate_.size(); }
  std::size_t epochsHeld() const { return obs_guard_.held(); }
  /// The last stamp dropped, with its reason ("" = none).
  const std::string& lastTimeDrop() const { return last_time_drop_; }
  const ConversionIssues& issues() const { return issues_; }
  double lastCorrectionAge_s() const { return last_correction_age_s_; }
  std::uint8_t productMode() const { return product_mode_; }
  const std::string& productModeText() const { return product_mode_text_; }
  std::size_t liveReceiverRestarts() const { return live_receiver_restarts_; }
  double liveDecodeCpu_s() const { return live_decode_cpu_s_; }
  const std::deque<double>& liveLatencies_s() const { return live_latency_s_; }

 private:
  void countObservationDrops(const ppp::EpochTimeGuard<PendingObservation>::Outcome& outcome);
  /// Clears the buffer on a confirmed jump back, then adds the released batches.
  void applyCorrectionOutcome(ppp::EpochTimeGuard<CorrectionInput>::Outcome& outcome, const ros::Time& now);
  void acceptCorrections(CorrectionInput input, const ros::Time& now);
  void acceptObservation(PendingObservation p, const std::function<void(const ppp::GnssTime&)>& on_empty);

  RosNodeOptions options_;
  WarningSink warn_;
  ppp::CorrectionBuffer corrections_;
  ppp::StreamBiasProvider stream_biases_;
  ppp::PhaseInformation stream_bias_kind_ = ppp::PhaseInformation::None;  // what the batches declare
  bool streamed_declared_ = false;
  ppp::CorrectionGate<PendingObservation> gate_;  // epochs waiting for covering corrections
  ppp::EpochTimeGuard<PendingObservation> obs_guard_;
  ppp::EpochTimeGuard<CorrectionInput> corr_guard_;
  SequenceGapCounter obs_seq_, corr_seq_;
  std::optional<ros::Time> last_obs_arrival_, last_corr_arrival_;
  std::optional<ppp::GnssTime> last_received_;  // newest observation epoch received
  ppp::RinexObsHeader layout_;
  bool layout_changed_ = false;
  ppp_bayes_tree::PppStatus counters_;  // the inputs' counter fields only
  std::size_t obs_received_ = 0, corr_received_ = 0;
  double last_correction_age_s_;
  std::string last_time_drop_;
  ConversionIssues issues_;
  // live input: its ephemeris replaces corrections_
  std::unique_ptr<ppp::LiveGnssInput> live_;
  std::uint8_t product_mode_ = ppp_bayes_tree::PppStatus::PRODUCTS_PRECISE;  // of the epoch being processed
  std::string product_mode_text_ = "precise products";
  std::size_t live_receiver_restarts_ = 0;  // resets after the observation time went back
  // Cost figures of the live path (diagnostics "live streams"; scripts/bench_live_realtime.sh):
  // thread CPU time in LiveGnssInput (feed: framing + decoding; takeReadyEpochs: release)
  // and the in-node latency of the last kLatencyWindow epochs (bounded).
  double live_decode_cpu_s_ = 0.0;
  std::deque<double> live_latency_s_;
};

/// A signed step in seconds as the logs write it ("+1.000 s").
std::string secondsText(double s);

/// The node's products through the core's one assembly (as ppp_solve): the ANTEX,
/// Bias-SINEX and BLQ files of ros.products; orbits and clocks streamed (the
/// corrections topic, or the live input: a live SSR feed when ros.live lists
/// correction topics, whose satellite antenna model is the configuration's
/// ssr.antenna_model; product_sources.h). They resolve the systems and the PPP-AR
/// gate: the estimator is made from their config(). Throws std::runtime_error when
/// the antenna corrections need ANTEX files and none is given, and on unreadable files.
ppp::ProductAssembly assembleNodeProducts(const ppp::PppConfig& config, const RosNodeOptions& options);

/// One subscription of the live input: a topic and the stream it feeds.
struct LiveSubscription {
  LiveStreamTopic topic;
  std::string stream;  // "" = a stream of its own (the topic's)
};
/// The observation topics are one receiver's (ublox_gps: RXM-RAWX and RXM-SFRBX on
/// two topics): one stream, named by their resolved names joined by "+", so that one
/// decoder sees them all (the SFRBX GPS week comes from RAWX). Each correction topic
/// is a stream of its own. `resolve`: the node handle's name resolution.
std::vector<LiveSubscription> liveSubscriptions(const RosNodeOptions& options,
                                                const std::function<std::string(const std::string&)>& resolve);

}  // namespace ppp_ros
