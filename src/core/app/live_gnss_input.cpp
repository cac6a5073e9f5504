#include "ppp_bayes_tree/app/live_gnss_input.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <sstream>

#include "ppp_bayes_tree/io/epoch_time_screen.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_observation_source.h"
#include "ppp_bayes_tree/io/transport/gnss_stream_decoder.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"
#include "ppp_bayes_tree/models/ssr_bias_provider.h"

namespace ppp {

std::string_view liveProductModeName(LiveProductMode mode) {
  switch (mode) {
    case LiveProductMode::PreciseSsr: return "precise SSR";
    case LiveProductMode::BroadcastOnly: return "broadcast only";
  }
  return "unknown";
}

std::string_view streamStallName(StreamStall stall) {
  switch (stall) {
    case StreamStall::Ok: return "ok";
    case StreamStall::Warn: return "warn";
    case StreamStall::Error: return "error";
  }
  return "unknown";
}

namespace {

constexpr double kGpsEpochUnix_s = 315964800.0;  // 1980-01-06 00:00:00 UTC

/// Unix seconds (UTC) of a GPST instant.
double unixSeconds(const GnssTime& t) {
  return t.toGpsSecondsDouble() + t.offsetToSystem_s(TimeSystem::UTC) + kGpsEpochUnix_s;
}

/// The mode in force for queries from a released epoch's T - kMaxSignalTravel_s on.
struct ModeSpan {
  LiveProductMode mode = LiveProductMode::PreciseSsr;
  bool widened = false;  // broadcast answers with the fallback sigmas
};

struct HeldEpoch {
  StreamEpoch epoch;
  std::optional<double> arrival_s;
};

struct StreamState {
  std::unique_ptr<GnssStreamDecoder> decoder;
  LiveStreamStatus status;
  /// The epoch-time policy of the offline readers (io/epoch_time_screen.h).
  std::unique_ptr<EpochTimeScreen<HeldEpoch>> screen;
  std::optional<GnssTime> last_epoch;  // newest accepted observation time
  std::optional<GnssTime> last_ssr;    // newest SSR epoch of this stream
  std::size_t time_problems_reported = 0;  // of screen->counters().problems
  std::optional<GnssTime> first_epoch;     // first accepted observation time
};

}  // namespace

struct LiveGnssInput::Impl : public EphemerisSource {
  LiveInputOptions options;
  std::shared_ptr<SsrCorrectionStore> store;
  std::unique_ptr<BroadcastSsrEphemeris> corrected;
  BroadcastEphemerisStore broadcast;
  std::shared_ptr<SsrBiasProvider> bias_provider;
  bool reference_decided = false;

  std::map<std::string, StreamState> streams;
  std::vector<std::string> stream_order;
  std::optional<std::string> observation_stream;
  std::optional<GnssTime> reference;  // for week-less SSR times
  std::deque<HeldEpoch> held;
  static constexpr std::size_t kMaxTimeEvents = 100;  // until taken
  std::vector<std::string> time_events;               // takeTimeEvents()
  StreamSignalInventory inventory;
  RinexObsHeader header;
  std::string station_key;
  bool header_changed = false;

  std::map<GnssTime, ModeSpan> spans;  // key: T - kMaxSignalTravel_s of each released epoch
  ModeSpan last_span;
  bool any_released = false;
  std::optional<GnssTime> last_released;
  std::optional<GnssTime> last_pruned;
  std::map<LiveProductMode, std::uint64_t> released;
  std::uint64_t without_ephemeris = 0;
  std::optional<double> last_obs_arrival_s;
  std::optional<double> now_s;

  // ---- EphemerisSource: answers in the mode of the epoch being processed.
  ModeSpan spanAt(const GnssTime& t) const {
    if (spans.empty()) return currentDefault();
    auto it = spans.upper_bound(t);
    if (it == spans.begin()) return it->second;
    return std::prev(it)->second;
  }
  ModeSpan currentDefault() const {
    if (any_released) return last_span;
    if (!store->latestEpoch() && !options.expect_corrections) return {LiveProductMode::BroadcastOnly, false};
    return {LiveProductMode::PreciseSsr, false};
  }
  EphemerisAnswer<EphemerisClock> satelliteClock(const SatelliteId& sat, const GnssTime& t) const override {
    const ModeSpan span = spanAt(t);
    if (span.mode == LiveProductMode::PreciseSsr) return corrected->satelliteClock(sat, t);
    auto a = broadcast.satelliteClock(sat, t);
    if (span.widened) widenForFallback(a, options.fallback);
    return a;
  }
  EphemerisAnswer<EphemerisOrbit> satelliteOrbit(const SatelliteId& sat, const GnssTime& t) const override {
    const ModeSpan span = spanAt(t);
    if (span.mode == LiveProductMode::PreciseSsr) return corrected->satelliteOrbit(sat, t);
    auto a = broadcast.satelliteOrbit(sat, t);
    if (span.widened) widenForFallback(a, options.fallback);
    return a;
  }
  std::string describeSource() const override {
    return "live streams: " + corrected->describeSource() + ", broadcast-only fallback";
  }

  // ---- inputs
  void setReference(const GnssTime& t) {
    if (reference) return;
    reference = t;
    for (auto& [name, s] : streams) s.decoder->setSsrReferenceTime(t);
  }

  StreamState& stream(const StreamChunk& chunk) {
    auto it = streams.find(chunk.stream);
    if (it != streams.end()) return it->second;
    StreamFormat format = chunk.format;
    if (format == StreamFormat::Unknown)
      format = chunk.bytes.empty() ? StreamFormat::Rtcm3 : detectStreamFormat(chunk.bytes.data(), chunk.bytes.size());
    if (format == StreamFormat::Unknown) format = StreamFormat::Rtcm3;
    Rtcm3DecoderOptions rtcm;
    rtcm.reference_time = options.reference_time;
    rtcm.glonass_channels = options.glonass_channels;
    StreamState s;
    s.decoder = std::make_unique<GnssStreamDecoder>(format, rtcm);
    if (reference) s.decoder->setSsrReferenceTime(*reference);
    EpochTimeGuardOptions time_policy = streamEpochTimeOptions();
    time_policy.out_of_order_window_s = options.restart_jump_s;
    s.screen = std::make_unique<EpochTimeScreen<HeldEpoch>>(time_policy);
    s.status.stream = chunk.stream;
    s.status.format = format;
    stream_order.push_back(chunk.stream);
    return streams.emplace(chunk.stream, std::move(s)).first->second;
  }

  void refreshHeader(const GnssStreamDecoder& decoder) {
    RinexObsHeader h = header;
    fillStationHeader(decoder.station(), h);
    bool changed = false;
    const auto& channels = decoder.glonassChannels();
    for (int slot = 1; slot <= GlonassChannels::kMaxSlot; ++slot)
      if (const auto k = channels.channel(slot); k && !h.glonass_channels.channel(slot)) {
        h.glonass_channels.set(slot, *k);
        changed = true;
      }
    h.glonass_channel_entries = h.glonass_channels.size();
    std::ostringstream key;
    key << h.marker_name << '|' << h.antenna_type << '|' << h.antenna_radome << '|' << h.receiver_type;
    if (h.antenna_delta_hen_m) key << '|' << h.antenna_delta_hen_m->transpose();
    if (h.approx_position_ecef_m) key << '|' << h.approx_position_ecef_m->transpose();
    if (key.str() != station_key) {
      station_key = key.str();
      changed = true;
    }
    if (changed) {
      header = std::move(h);
      header_changed = true;
    }
  }

  /// An observation epoch through the stream's time policy: isolated bad times
  /// are dropped (counted by reason), a confirmed jump back is a receiver restart.
  void screenEpoch(StreamState& s, StreamEpoch&& e, const std::optional<double>& arrival_s) {
    const GnssTime t = e.time;
    const EpochOrigin origin{e.byte_offset, e.frame_index, 0};
    applyScreen(s, s.screen->push(t, origin, HeldEpoch{std::move(e), arrival_s}));
  }
  void applyScreen(StreamState& s, EpochTimeScreen<HeldEpoch>::Result&& r) {
    const EpochTimeScreen<HeldEpoch>& screen = *s.screen;
    s.status.time_backwards = screen.dropped(TimeDropReason::Duplicate) + screen.dropped(TimeDropReason::OutOfOrder);
    s.status.time_outliers = screen.dropped(TimeDropReason::UnconfirmedJump);
    s.status.restarts = screen.resets();
    s.status.forward_jumps = screen.forwardJumps();
    const auto& problems = screen.counters().problems;
    for (; s.time_problems_reported < problems.size(); ++s.time_problems_reported)
      if (time_events.size() < kMaxTimeEvents)
        time_events.push_back(s.status.stream + ": " + problems[s.time_problems_reported].describe());
    if (r.reset_step_s) {
      held.clear();  // receiver restart: what was held belongs to the old run
      if (time_events.size() < kMaxTimeEvents)
        time_events.push_back(s.status.stream + ": observation time went back by " +
                              std::to_string(static_cast<long long>(std::llround(-*r.reset_step_s))) +
                              " s, confirmed by the following epochs: receiver restart");
    }
    for (auto& kept : r.accepted) acceptEpoch(s, std::move(kept.payload.epoch), kept.payload.arrival_s);
  }

  /// A reference date given (options.reference_time) that the stream's own
  /// ephemeris weeks contradict: said once per stream (status and time events).
  void checkReferenceDate(StreamState& s) {
    if (!options.reference_time || !s.first_epoch || !s.last_epoch || !s.status.reference_date_warning.empty()) return;
    const BroadcastWeekEvidence* evidence = s.decoder->weekEvidence();
    if (!evidence) return;
    if (const auto why = referenceDateContradiction(*options.reference_time, *s.first_epoch, *s.last_epoch, *evidence)) {
      s.status.reference_date_warning = *why;
      if (time_events.size() < kMaxTimeEvents) time_events.push_back(s.status.stream + ": " + *why);
    }
  }

  void acceptEpoch(StreamState& s, StreamEpoch&& e, const std::optional<double>& arrival_s) {
    if (!s.first_epoch) s.first_epoch = e.time;
    s.last_epoch = e.time;
    ++s.status.observation_epochs;
    const auto before = inventory.signals;
    inventory.add(e);
    if (inventory.signals != before) {
      inventory.fillTypes(header);
      header_changed = true;
    }
    if (!header.time_of_first_obs)
      header.time_of_first_obs = RinexHeaderTime{e.time.toCalendar(TimeSystem::GPS), TimeSystem::GPS, e.time};
    setReference(e.time);
    if (arrival_s) last_obs_arrival_s = arrival_s;
    held.push_back(HeldEpoch{std::move(e), arrival_s});
  }

  void drain(StreamState& s, const std::optional<double>& arrival_s) {
    GnssStreamOutput& out = s.decoder->output();
    const auto& nav = out.navigation;
    for (const auto& r : nav.gps) {
      broadcast.add(r.record, r.received_at);
      corrected->addRecord(r.record, r.received_at);
    }
    for (const auto& r : nav.galileo) {
      broadcast.add(r.record, r.received_at);
      corrected->addRecord(r.record, r.received_at);
    }
    for (const auto& r : nav.glonass) {
      broadcast.add(r.record, r.received_at);
      corrected->addRecord(r.record, r.received_at);
    }
    // BeiDou: broadcast store only (the SSR-corrected ephemeris has no BeiDou model).
    for (const auto& r : nav.beidou) broadcast.add(r.record, r.received_at);
    s.status.ephemerides += nav.size();
    std::optional<GnssTime> newest_data;
    for (const auto& m : out.ssr) {
      ++s.status.ssr_messages;
      if (!m.header.epoch) continue;
      if (!reference_decided) {
        reference_decided = true;
        corrected->setReference(options.ssr_reference ? *options.ssr_reference
                                                      : ssrReferenceFromStreamName(s.status.stream)
                                                            .value_or(EphemerisReference::CentreOfMass));
      }
      const std::size_t resent_before = store->staleCodeBiasMessages();
      store->add(m);
      s.status.ssr_code_biases_resent += store->staleCodeBiasMessages() - resent_before;
      if (!s.last_ssr || *s.last_ssr < *m.header.epoch) s.last_ssr = *m.header.epoch;
      if (!newest_data || *newest_data < *m.header.epoch) newest_data = *m.header.epoch;
    }
    if (!bias_provider && (store->codeBiasCount() > 0 || store->phaseBiasCount() > 0))
      // The SSR biases belong to the SSR-corrected clocks: in the broadcast fallback
      // they do not apply (codes as observed, as the broadcast clocks expect).
      bias_provider = std::make_shared<SsrBiasProvider>(
          store, s.status.stream, [this](const SatelliteId&, const GnssTime& t) {
            return spanAt(t).mode == LiveProductMode::PreciseSsr;
          });
    if (!out.epochs.empty()) {
      if (!observation_stream) observation_stream = s.status.stream;
      for (auto& e : out.epochs) {
        if (!newest_data || *newest_data < e.time) newest_data = e.time;
        if (*observation_stream != s.status.stream) {
          ++s.status.ignored_epochs;
          continue;
        }
        screenEpoch(s, std::move(e), arrival_s);
      }
    }
    if (observation_stream && *observation_stream == s.status.stream) {
      refreshHeader(*s.decoder);
      checkReferenceDate(s);
    }
    if (newest_data) {
      if (!s.status.last_data_time || *s.status.last_data_time < *newest_data) s.status.last_data_time = *newest_data;
      if (arrival_s) s.status.latency_s = *arrival_s - unixSeconds(*newest_data);
    }
    out.clear();
  }

  // ---- release
  std::optional<GnssTime> newestObservation() const {
    if (!observation_stream) return std::nullopt;
    return streams.at(*observation_stream).last_epoch;
  }

  int satellitesWithSsr(const StreamEpoch& e) const {
    int n = 0;
    for (const auto& sat : e.satellites)
      if (corrected->correctedState(sat.satellite, e.time).ok()) ++n;
    return n;
  }

  ModeSpan modeFor(const StreamEpoch& e) const {
    if (!store->latestEpoch() && !options.expect_corrections) return {LiveProductMode::BroadcastOnly, false};
    if (chooseSsrOrBroadcast(satellitesWithSsr(e), options.fallback) == SsrOrbitClockChoice::Ssr)
      return {LiveProductMode::PreciseSsr, false};
    return {LiveProductMode::BroadcastOnly, true};
  }

  bool waitedForStation(const HeldEpoch& h) const {
    if (header.approx_position_ecef_m || options.station_wait_s <= 0.0 || !observation_stream) return true;
    if (streams.at(*observation_stream).status.format != StreamFormat::Rtcm3) return true;
    if (held.size() > options.max_held_epochs) return true;
    if (const auto newest = newestObservation(); newest && *newest - h.epoch.time > options.station_wait_s) return true;
    if (now_s && h.arrival_s && *now_s - *h.arrival_s > options.station_wait_s) return true;
    return false;
  }

  bool ready(const HeldEpoch& h, bool finishing) const {
    if (finishing) return true;
    const GnssTime& t = h.epoch.time;
    if (!waitedForStation(h)) return false;
    const auto latest_ssr = store->latestEpoch();
    if (latest_ssr && !(*latest_ssr < t)) return true;
    if (!latest_ssr && !options.expect_corrections) return true;
    if (held.size() > options.max_held_epochs) return true;
    if (const auto newest = newestObservation(); newest && *newest - t > options.correction_wait_s) return true;
    if (now_s && h.arrival_s && *now_s - *h.arrival_s > options.correction_wait_s) return true;
    return false;
  }

  std::vector<LiveReadyEpoch> release(bool finishing) {
    std::vector<LiveReadyEpoch> out;
    while (!held.empty() && ready(held.front(), finishing)) {
      HeldEpoch h = std::move(held.front());
      held.pop_front();
      const ModeSpan span = modeFor(h.epoch);
      spans[h.epoch.time - LiveGnssInput::kMaxSignalTravel_s] = span;
      last_span = span;
      any_released = true;
      last_released = h.epoch.time;
      ++released[span.mode];
      LiveReadyEpoch r;
      r.mode = span.mode;
      r.arrival_s = h.arrival_s;
      streamEpochToObsEpoch(h.epoch, header, r.epoch);
      for (const auto& sat : r.epoch.satellites) {
        if (!ssrBroadcastModelled(sat.satellite.system)) continue;
        if (!satelliteClock(sat.satellite, h.epoch.time - 0.075).ok()) ++without_ephemeris;
      }
      out.push_back(std::move(r));
    }
    if (!out.empty()) prune(out.front().epoch.time);
    return out;
  }

  /// Bounded memory: what no query for this or a later epoch can use.
  void prune(const GnssTime& oldest_released) {
    if (last_pruned && oldest_released - *last_pruned < 60.0) return;
    last_pruned = oldest_released;
    const GnssTime horizon = oldest_released - 1.0;
    store->dropSupersededBefore(horizon);  // keeps, per series, the newest entry at or before the horizon
    broadcast.dropOlderThan(oldest_released, options.keep_history_s);
    corrected->dropOlderThan(oldest_released, options.keep_history_s);
    while (spans.size() > 1 && spans.begin()->first < horizon - 600.0) spans.erase(spans.begin());
  }
};

LiveGnssInput::LiveGnssInput(LiveInputOptions options) : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.options = std::move(options);
  d.store = std::make_shared<SsrCorrectionStore>(d.options.ssr_age_limits);
  BroadcastSsrOptions ssr = d.options.ssr;
  ssr.reference = d.options.ssr_reference.value_or(EphemerisReference::CentreOfMass);
  d.corrected = std::make_unique<BroadcastSsrEphemeris>(d.store, ssr);
  if (d.options.ssr_reference) d.reference_decided = true;
  if (d.options.reference_time) d.reference = d.options.reference_time;
  for (const auto& path : d.options.navigation_files) {
    const NavData nav = readRinexNav(path);
    if (!d.reference && nav.first_toc) d.reference = nav.first_toc;
    d.broadcast.add(nav);
    for (const auto& e : nav.gps) d.corrected->addRecord(e);
    for (const auto& e : nav.galileo) d.corrected->addRecord(e);
    for (const auto& e : nav.glonass) d.corrected->addRecord(e);
  }
  d.header.version_text = "3.04";
  d.header.version = 3.04;
  d.header.major_version = 3;
  d.header.file_system = 'M';
  d.header.program = "ppp_bayes_tree";
  d.header.epoch_time_system = TimeSystem::GPS;
  d.header.glonass_channels = d.options.glonass_channels;
}

LiveGnssInput::~LiveGnssInput() = default;

void LiveGnssInput::feed(const StreamChunk& chunk) {
  Impl& d = *impl_;
  StreamState& s = d.stream(chunk);
  s.status.bytes += chunk.bytes.size();
  if (chunk.arrival_time_s) s.status.last_arrival_s = chunk.arrival_time_s;
  if (!chunk.bytes.empty()) s.decoder->feed(chunk.bytes.data(), chunk.bytes.size());
  d.drain(s, chunk.arrival_time_s);
}

std::vector<LiveReadyEpoch> LiveGnssInput::takeReadyEpochs(std::optional<double> now_s) {
  if (now_s) impl_->now_s = now_s;
  return impl_->release(false);
}

std::vector<LiveReadyEpoch> LiveGnssInput::finish() {
  Impl& d = *impl_;
  for (const auto& name : d.stream_order) {
    StreamState& s = d.streams.at(name);
    s.decoder->finish();
    d.drain(s, std::nullopt);
    d.applyScreen(s, s.screen->finish());  // what is still held on an unconfirmed time line: outliers
  }
  return d.release(true);
}

std::vector<std::string> LiveGnssInput::takeTimeEvents() {
  std::vector<std::string> out;
  out.swap(impl_->time_events);
  return out;
}

const EphemerisSource& LiveGnssInput::ephemeris() const { return *impl_; }

const BiasProvider* LiveGnssInput::biases() const { return impl_->bias_provider.get(); }

bool LiveGnssInput::hasPhaseBiases() const { return impl_->bias_provider && impl_->store->phaseBiasCount() > 0; }

const RinexObsHeader& LiveGnssInput::header() const { return impl_->header; }

bool LiveGnssInput::takeHeaderChanged() {
  const bool changed = impl_->header_changed;
  impl_->header_changed = false;
  return changed;
}

std::vector<LiveStreamStatus> LiveGnssInput::streams() const {
  const Impl& d = *impl_;
  std::vector<LiveStreamStatus> out;
  const auto newest_obs = d.newestObservation();
  for (const auto& name : d.stream_order) {
    const StreamState& s = d.streams.at(name);
    LiveStreamStatus st = s.status;
    st.problems = s.decoder->counters();
    for (const auto& p : s.screen->counters().problems) st.problems.add(p);
    const StreamCounters& ssr = s.decoder->ssrCounters();
    for (const auto& [kind, n] : ssr.problems_by_kind) st.problems.problems_by_kind[kind] += n;
    for (const auto& p : ssr.problems)
      if (st.problems.problems.size() < StreamCounters::kMaxKeptProblems) st.problems.problems.push_back(p);
    st.problems.repeated_signals = ssr.repeated_signals;
    st.problems.first_repeated_signal = ssr.first_repeated_signal;
    st.frames_by_type = st.problems.frames_by_type;
    if (s.last_ssr && newest_obs) st.ssr_age_s = *newest_obs - *s.last_ssr;
    if (d.observation_stream && *d.observation_stream == name && d.now_s && s.status.last_arrival_s) {
      const double quiet_s = *d.now_s - *s.status.last_arrival_s;
      st.stall = quiet_s > d.options.stall_error_s ? StreamStall::Error
                 : quiet_s > d.options.stall_warn_s ? StreamStall::Warn
                                                    : StreamStall::Ok;
    }
    out.push_back(std::move(st));
  }
  return out;
}

LiveProductMode LiveGnssInput::mode() const { return impl_->currentDefault().mode; }

std::uint64_t LiveGnssInput::releasedEpochs(LiveProductMode mode) const {
  const auto it = impl_->released.find(mode);
  return it == impl_->released.end() ? 0 : it->second;
}

std::uint64_t LiveGnssInput::satellitesWithoutEphemeris() const { return impl_->without_ephemeris; }

std::size_t LiveGnssInput::navigationRecords() const { return impl_->broadcast.size(); }

const SsrCorrectionStore& LiveGnssInput::corrections() const { return *impl_->store; }

}  // namespace ppp
