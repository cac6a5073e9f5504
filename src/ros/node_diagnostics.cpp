#include "ppp_bayes_tree/ros/node_diagnostics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "ppp_bayes_tree/evaluation/quantile.h"

namespace ppp_ros {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using diagnostic_msgs::DiagnosticStatus;

/// The summary of a task that several checks may raise: the first of the worst level.
class WorstSummary {
 public:
  void raise(std::uint8_t level, const std::string& text) {
    if (level > level_ || text_.empty()) {
      text_ = text;
      level_ = std::max(level_, level);
    }
  }
  bool empty() const { return text_.empty(); }
  void fill(diagnostic_updater::DiagnosticStatusWrapper& s, const std::string& otherwise) const {
    s.summary(level_, text_.empty() ? otherwise : text_);
  }

 private:
  std::uint8_t level_ = DiagnosticStatus::OK;
  std::string text_;
};

void addSubscriber(diagnostic_updater::DiagnosticStatusWrapper& s, const GnssStreamSubscriber& sub, WorstSummary& summary) {
  const GnssStreamSubscriber::Counters& c = sub.counters();
  const std::string p = sub.topic() + ": ";
  s.add(p + "messages (type)", std::to_string(c.messages) + " (" + (c.type.empty() ? "none yet" : c.type) + ")");
  s.add(p + "messages lost before the node (header.seq gaps)", c.lost);
  s.add(p + "messages held until the ROS clock was valid (sim time before /clock)", c.held_for_clock);
  if (c.lost > 0)
    summary.raise(DiagnosticStatus::WARN, sub.topic() + ": " + std::to_string(c.lost) +
                                              " message(s) lost before the node (a queue overflowed)");
  s.add(p + "messages of a wrong type/MD5 / malformed (dropped)",
        std::to_string(c.wrong_type) + " / " + std::to_string(c.malformed));
  if (!c.last_error.empty()) s.add(p + "last error", c.last_error);
  s.add(p + "reconnects", "not known on a topic (see the transport node's diagnostics)");
  if (c.wrong_type + c.malformed > 0)
    summary.raise(DiagnosticStatus::WARN, sub.topic() + ": messages dropped (" + c.last_error + ")");
}

void addStream(diagnostic_updater::DiagnosticStatusWrapper& s, const ppp::LiveStreamStatus& st, double now_s,
               const ppp::LiveInputOptions& o, WorstSummary& summary) {
  const std::string p = st.stream + ": ";
  std::uint64_t frames = 0;
  for (const auto& [type, n] : st.frames_by_type) frames += n;
  s.add(p + "format", std::string(ppp::streamFormatName(st.format)));
  s.add(p + "bytes / frames", std::to_string(st.bytes) + " / " + std::to_string(frames));
  s.add(p + "CRC/checksum errors", st.problems.count(ppp::StreamProblemKind::ChecksumError));
  s.add(p + "problems (all kinds)", st.problems.totalProblems());
  s.add(p + "SSR bias signal ids sent twice (first kept)", st.problems.repeated_signals);
  s.add(p + "SSR code biases re-sent with an old epoch (in force from arrival)", st.ssr_code_biases_resent);
  s.add(p + "observation epochs decoded / ignored", std::to_string(st.observation_epochs) + " / " +
                                                        std::to_string(st.ignored_epochs));
  s.add(p + "epochs back in time dropped / receiver restarts",
        std::to_string(st.time_backwards) + " / " + std::to_string(st.restarts));
  s.add(p + "epoch time outliers dropped / forward jumps",
        std::to_string(st.time_outliers) + " / " + std::to_string(st.forward_jumps));
  if (!st.reference_date_warning.empty()) summary.raise(DiagnosticStatus::WARN, p + st.reference_date_warning);
  s.add(p + "ephemerides decoded", st.ephemerides);
  s.add(p + "SSR messages", st.ssr_messages);
  s.add(p + "SSR age [s]", st.ssr_age_s.value_or(kNaN));
  s.add(p + "latency [s]", st.latency_s.value_or(kNaN));
  s.add(p + "since the last chunk [s]", st.last_arrival_s ? now_s - *st.last_arrival_s : kNaN);
  s.add(p + "stall", std::string(ppp::streamStallName(st.stall)));
  if (st.stall == ppp::StreamStall::Error)
    summary.raise(DiagnosticStatus::ERROR, "observation stream " + st.stream + " stalled (ERROR threshold " +
                                               std::to_string(o.stall_error_s) + " s)");
  else if (st.stall == ppp::StreamStall::Warn)
    summary.raise(DiagnosticStatus::WARN, "observation stream " + st.stream + " stalled (WARN threshold " +
                                              std::to_string(o.stall_warn_s) + " s)");
}

}  // namespace

StartNote startSummary(const RosNodeOptions& o, const std::string& config_source, std::size_t antex_files,
                       const std::vector<std::string>& live_topics,
                       const std::function<std::string(const std::string&)>& resolve) {
  std::string inputs = resolve(o.observations_topic) + " and " + resolve(o.corrections_topic);
  if (o.live()) {
    inputs = "the live streams";
    for (const auto& topic : live_topics) inputs += " " + topic;
  }
  const std::string node = "ppp_" + (o.node_estimator.empty() ? o.estimator : o.node_estimator) + "_node";
  return {false, node + ": config from " + config_source + ", " + std::to_string(antex_files) +
                     " ANTEX file(s), bias " + (o.bias.empty() ? "none" : o.bias) + ", waiting for " + inputs +
                     (o.attitude_topic.empty() ? std::string(", no attitude source")
                                               : ", attitude from " + resolve(o.attitude_topic))};
}

StartNote smootherCostNote(double fixed_lag_s, const std::string& trajectory_csv) {
  if (fixed_lag_s <= 0.0)
    // Measured with scripts/bench_live_node.sh (simulated loiter, ~9 satellites, 1 Hz at 30x).
    return {true,
            "ppp_smoother_node: full smoother (smoother/fixed_lag_s 0): every state stays in memory, about 25 KB "
            "per epoch, and the update time grows with the trajectory (1 h at 1 Hz: RSS 125 MB, update p99 8.8 ms; "
            "15 min at 10 Hz: 285 MB, p99 39 ms, past a 10 Hz budget). For long bags and live use a fixed lag: "
            "config/live.yaml (launch files: smoother_memory:=bounded; 15 min at 10 Hz: 49 MB, p99 6.2 ms) writes "
            "each state leaving the lag to ros/smoothed/trajectory_csv"};
  std::ostringstream text;
  text << "ppp_smoother_node: fixed-lag smoother, lag " << fixed_lag_s << " s: memory and update time bounded; "
       << (trajectory_csv.empty() ? std::string("states leaving the lag are not written (ros/smoothed/trajectory_csv \"\")")
                                  : "states leaving the lag written to " + trajectory_csv);
  return {false, text.str()};
}

NodeDiagnostics::NodeDiagnostics(const RosNodeOptions& options, ros::WallTime start)
    : options_(options), last_diag_time_(start) {}

void NodeDiagnostics::inputs(diagnostic_updater::DiagnosticStatusWrapper& s, const NodeInputs& in,
                             const NodeOutputs& out, ros::WallTime now) {
  const ppp_bayes_tree::PppStatus& c = in.counters();
  const AttitudeCounters& attitude = out.attitudeCounters();
  const std::size_t obs_received = in.observationMessages(), corr_received = in.correctionMessages();
  const double dt = std::max(1e-3, (now - last_diag_time_).toSec());
  const double obs_rate = (obs_received - obs_at_last_diag_) / dt, corr_rate = (corr_received - corr_at_last_diag_) / dt;
  obs_at_last_diag_ = obs_received;
  corr_at_last_diag_ = corr_received;
  last_diag_time_ = now;
  s.add("observation messages", obs_received);
  s.add("observation rate [Hz, wall]", obs_rate);
  s.add("correction messages", corr_received);
  s.add("correction rate [Hz, wall]", corr_rate);
  s.add("pending epochs", in.pendingEpochs());
  s.add("duplicate epochs dropped", c.epochs_duplicate);
  s.add("out-of-order epochs dropped", c.epochs_out_of_order + out.counters().epochs_not_published);
  s.add("isolated bad stamps dropped (time jump not confirmed)", c.epochs_time_jump_dropped);
  s.add("epochs held as a candidate time jump", in.epochsHeld());
  s.add("estimator resets (sustained jump back in time)", c.estimator_resets);
  s.add("epochs discarded at resets", c.epochs_discarded_at_reset);
  s.add("observation messages lost before the node (header.seq gaps)", c.observations_lost);
  s.add("correction messages lost before the node (header.seq gaps)", c.corrections_lost);
  s.add("correction batches dropped (isolated bad stamps)", c.corrections_time_jump_dropped);
  s.add("last stamp dropped", in.lastTimeDrop().empty() ? std::string("none") : in.lastTimeDrop());
  s.add("empty epochs", c.empty_epochs);
  s.add("invalid observations excluded", c.observations_invalid);
  if (!options_.attitude_topic.empty()) {
    s.add("attitude messages", attitude.received);
    s.add("attitude messages invalid (ignored)", attitude.invalid);
    s.add("solved epochs without a current attitude (at the antenna)", attitude.epochs_without);
  }
  for (const auto& [reason, n] : in.issues().counts) s.add(reason, n);
  const std::size_t lost = std::size_t{c.observations_lost} + c.corrections_lost;
  if (obs_received == 0) s.summary(DiagnosticStatus::WARN, "no observations received yet");
  else if (lost > lost_at_last_diag_)
    s.summary(DiagnosticStatus::WARN,
              std::to_string(lost - lost_at_last_diag_) + " message(s) lost before the node since the last report");
  else if (options_.expected_observation_rate_hz > 0 && obs_rate < 0.5 * options_.expected_observation_rate_hz)
    s.summary(DiagnosticStatus::WARN, "observation rate below half the expected rate");
  else s.summary(DiagnosticStatus::OK, "receiving");
  lost_at_last_diag_ = lost;
}

void NodeDiagnostics::corrections(diagnostic_updater::DiagnosticStatusWrapper& s, const NodeInputs& in,
                                  const NodeOutputs& out) const {
  const ppp_bayes_tree::PppStatus& c = in.counters();
  const ppp::CorrectionBuffer& buffer = in.corrections();
  s.add("batches held", buffer.size());
  s.add("newest batch", buffer.newest() ? buffer.newest()->toString() : std::string("none"));
  s.add("age of the last batch at arrival [s]", in.lastCorrectionAge_s());
  s.add("satellite-epochs without corrections", out.counters().corrections_late);
  s.add("corrections for unknown satellites", c.corrections_unknown_satellites);
  s.add("correction messages lost before the node (header.seq gaps)", c.corrections_lost);
  s.add("correction batches dropped (isolated bad stamps)", c.corrections_time_jump_dropped);
  const std::optional<double> stale = in.correctionsStale_s();
  s.add("observations ahead of the corrections [s]", stale.value_or(kNaN));
  s.add("stale thresholds WARN / ERROR [s]", std::to_string(options_.corrections_stale_warn_s) + " / " +
                                                 std::to_string(options_.corrections_stale_error_s));
  const double age_s = in.lastCorrectionAge_s();
  if (buffer.size() == 0) s.summary(DiagnosticStatus::WARN, "no corrections received yet");
  else if (stale && *stale > options_.corrections_stale_error_s)
    s.summary(DiagnosticStatus::ERROR, "corrections stopped: observations " + std::to_string(static_cast<long>(*stale)) +
                                           " s ahead of the newest batch " + buffer.newest()->toString());
  else if (stale && *stale > options_.corrections_stale_warn_s)
    s.summary(DiagnosticStatus::WARN, "corrections stale: observations " + std::to_string(static_cast<long>(*stale)) +
                                          " s ahead of the newest batch");
  else if (std::isfinite(age_s) && age_s > options_.max_correction_latency_s)
    s.summary(DiagnosticStatus::WARN, "corrections arrive late");
  else s.summary(DiagnosticStatus::OK, "corrections current");
}

void NodeDiagnostics::solution(diagnostic_updater::DiagnosticStatusWrapper& s, const NodeInputs& in,
                               const NodeOutputs& out, const ppp::SmoothedTrajectoryProvider* smoother,
                               std::size_t estimator_restarts) const {
  s.add("estimator", options_.estimator);
  s.add("epochs processed", out.counters().epochs_processed);
  if (!out.lastStatus()) {
    s.summary(DiagnosticStatus::WARN, "no epoch processed yet");
    return;
  }
  const ppp_bayes_tree::PppStatus& last = *out.lastStatus();
  s.add("solution state", last.solution_state_text);
  for (const auto& w : last.warnings) s.add("warning", w);
  s.add("satellites used", last.satellites_used);
  s.add("update time [s]", last.update_time_s);
  s.add("sigma east/north/up [m]", std::to_string(last.sigma_east_m) + " " + std::to_string(last.sigma_north_m) + " " +
                                       std::to_string(last.sigma_up_m));
  s.add("estimator restarts after a failed update", estimator_restarts);
  if (smoother) {
    const ppp::SmootherEpochDiagnostics r = out.lastSmoother().value_or(ppp::SmootherEpochDiagnostics{});
    s.add("smoother: fixed lag [s] (0: full)", smoother->fixedLag_s());
    s.add("smoother: variables re-eliminated", r.variables_reeliminated);
    s.add("smoother: variables relinearized", r.variables_relinearized);
    s.add("smoother: cliques touched", r.cliques_touched);
    s.add("smoother: variables marginalized", r.variables_marginalized);
    s.add("smoother: iSAM2 update time [s]", r.update_time_s);
    s.add("smoothed path: poses", out.smoothedPathPoses());
    if (const ppp::LaggedTrajectoryOutput* lagged = out.laggedOutput()) {
      s.add("smoothed trajectory: states past the lag", lagged->statesHandedOut());
      if (const ppp::SmoothedTrajectoryWriter* w = lagged->writer())
        s.add("smoothed trajectory: " + w->path() + " rows written / refused",
              std::to_string(w->rowsWritten()) + " / " + std::to_string(w->rowsRefused()));
    }
    s.add("smoothed path: last / max re-read time [s]",
          std::to_string(out.smoothedPathRead_s()) + " / " + std::to_string(out.smoothedPathReadMax_s()));
  }
  if (last.solution_state == ppp_bayes_tree::PppStatus::NO_SOLUTION)
    s.summary(DiagnosticStatus::WARN, "no solution: " + last.reason);
  else if (!last.warnings.empty()) s.summary(DiagnosticStatus::WARN, last.solution_state_text + "; " + last.warnings[0]);
  else s.summary(DiagnosticStatus::OK, last.solution_state_text);
}

void NodeDiagnostics::live(diagnostic_updater::DiagnosticStatusWrapper& s, const NodeInputs& in,
                           const NodeOutputs& out,
                           const std::vector<std::unique_ptr<GnssStreamSubscriber>>& subscribers,
                           double estimator_cpu_s, double now_s) const {
  const ppp::LiveGnssInput& live = *in.live();
  WorstSummary summary;
  const bool broadcast = live.mode() == ppp::LiveProductMode::BroadcastOnly;
  s.add("product mode", std::string(ppp::liveProductModeName(live.mode())));
  s.add("epochs released precise SSR", live.releasedEpochs(ppp::LiveProductMode::PreciseSsr));
  s.add("epochs released broadcast only", live.releasedEpochs(ppp::LiveProductMode::BroadcastOnly));
  s.add("satellites without an ephemeris at their epoch (waiting)", live.satellitesWithoutEphemeris());
  s.add("navigation records held", live.navigationRecords());
  s.add("estimator resets at receiver restarts", in.liveReceiverRestarts());
  // Cost figures (thread CPU time, so meaningful on a loaded machine) and latency.
  const std::vector<ppp::LiveStreamStatus> streams = live.streams();
  std::uint64_t decoded_epochs = 0;
  for (const ppp::LiveStreamStatus& st : streams) decoded_epochs += st.observation_epochs;
  double conversion_cpu_s = 0.0;
  for (const auto& sub : subscribers) conversion_cpu_s += sub->counters().conversion_cpu_s;
  const auto per_epoch_ms = [](double cpu_s, std::uint64_t n) { return n > 0 ? 1e3 * cpu_s / static_cast<double>(n) : kNaN; };
  s.add("input CPU: message conversion [s]", conversion_cpu_s);
  s.add("input CPU: decoding and release (LiveGnssInput) [s]", in.liveDecodeCpu_s());
  s.add("input CPU per decoded epoch [ms]", per_epoch_ms(conversion_cpu_s + in.liveDecodeCpu_s(), decoded_epochs));
  s.add("estimator CPU [s]", estimator_cpu_s);
  s.add("estimator CPU per processed epoch [ms]", per_epoch_ms(estimator_cpu_s, out.counters().epochs_processed));
  std::vector<double> latency(in.liveLatencies_s().begin(), in.liveLatencies_s().end());
  std::sort(latency.begin(), latency.end());
  s.add("latency epochs (callback of the epoch's last chunk -> solution published, the last " +
            std::to_string(NodeInputs::kLatencyWindow) + " at most)",
        latency.size());
  s.add("latency median [s]", ppp::quantileOfSorted(latency, 0.5));
  s.add("latency p99 [s]", ppp::quantileOfSorted(latency, 0.99));
  s.add("latency max [s]", ppp::quantileOfSorted(latency, 1.0));
  for (const auto& sub : subscribers) addSubscriber(s, *sub, summary);
  bool have_observations = false;
  for (const ppp::LiveStreamStatus& st : streams) {
    addStream(s, st, now_s, options_.live_input, summary);
    if (st.observation_epochs > 0) have_observations = true;
  }
  if (!have_observations) summary.raise(DiagnosticStatus::WARN, "no observation epoch decoded yet");
  // Broadcast only is the configured operation without a correction stream (OK), a fallback otherwise (WARN).
  if (broadcast && options_.live_input.expect_corrections)
    summary.raise(DiagnosticStatus::WARN, "broadcast only: corrections stopped or too old (widened sigmas)");
  summary.fill(s, broadcast ? "receiving, broadcast only (no correction stream configured)" : "receiving, precise SSR");
}

void NodeDiagnostics::ambiguities(diagnostic_updater::DiagnosticStatusWrapper& s, bool enabled,
                                  const PhaseBiasChoice& phase, const NodeOutputs& out) const {
  const std::optional<ppp_bayes_tree::PppStatus>& last = out.lastStatus();
  s.add("enabled", enabled);
  s.add("phase information", phase.provider ? phase.source : std::string("none"));
  s.add("epochs fixed", out.epochsFixed());
  s.add("held integers released (float departed, wide lane changed)", out.ambiguityReleases());
  s.add("time to first fix [s]", out.timeToFirstFix_s());
  s.add("first fix", out.firstFixed() ? out.firstFixed()->toString() : std::string("none yet"));
  if (last) {
    s.add("fix state", last->fix_state_text);
    s.add("float reason", last->float_reason);
    s.add("ambiguities held", last->ambiguities_fixed);
    s.add("wide lanes fixed", last->wide_lanes_fixed);
    s.add("ratio", last->ratio);
  }
  if (!enabled) s.summary(DiagnosticStatus::OK, "off (float)");
  else if (!last) s.summary(DiagnosticStatus::OK, "on, no epoch processed yet");
  else if (!phase.provider) s.summary(DiagnosticStatus::WARN, phase.source);
  else if (last->fix_state == ppp_bayes_tree::PppStatus::FIX_FIXED)
    s.summary(DiagnosticStatus::OK, "fixed (" + std::to_string(last->ambiguities_fixed) + " held)");
  else s.summary(DiagnosticStatus::OK, "float: " + last->float_reason);
}

}  // namespace ppp_ros
