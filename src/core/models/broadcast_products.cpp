#include "ppp_bayes_tree/models/broadcast_products.h"

#include <algorithm>

#include <iomanip>
#include <sstream>

#include "ppp_bayes_tree/io/transport/gnss_stream_decoder.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"
#include "ppp_bayes_tree/models/broadcast_ssr_ephemeris.h"
#include "ppp_bayes_tree/models/ssr_broadcast_fallback.h"
#include "ppp_bayes_tree/models/ssr_bias_provider.h"

namespace ppp {

namespace {

/// Adds the records of a stream to an ephemeris (store or SSR) with their reception times
/// (BeiDou records: to the store only, see loadBroadcastProducts).
template <class Target>
void addReceived(Target target, const ReceivedNavigation& nav) {
  for (const auto& r : nav.gps) target(r.record, r.received_at);
  for (const auto& r : nav.galileo) target(r.record, r.received_at);
  for (const auto& r : nav.glonass) target(r.record, r.received_at);
}

template <class Record>
const SatelliteId& satelliteOf(const Record& r) {
  return r.satellite;
}
template <class Record>
const SatelliteId& satelliteOf(const ReceivedRecord<Record>& r) {
  return r.record.satellite;
}

/// Adds the satellites of every record of a RINEX file (NavData) or a stream (ReceivedNavigation).
template <class Navigation>
void insertRecordSatellites(const Navigation& nav, std::set<SatelliteId>& out) {
  const auto insert = [&out](const auto& records) {
    for (const auto& r : records) out.insert(satelliteOf(r));
  };
  insert(nav.gps);
  insert(nav.galileo);
  insert(nav.glonass);
  insert(nav.beidou);
}

/// The satellites of decoded records: of RINEX files and of stream recordings.
std::set<SatelliteId> recordSatellites(const std::vector<NavData>& navs,
                                       const std::vector<StreamNavigationFile>& streams) {
  std::set<SatelliteId> out;
  for (const auto& n : navs) insertRecordSatellites(n, out);
  for (const auto& s : streams) insertRecordSatellites(s.navigation, out);
  return out;
}

}  // namespace

namespace {

/// A note when the corrections are too old at the first or last observation
/// epoch: the broadcast fallback serves there (and says how old they were).
void noteStaleCorrections(const SsrBroadcastFallback& fallback, const SsrCorrectionStore& store,
                          const std::string& stream, const std::optional<ObservationSpan>& span,
                          std::vector<std::string>& notes) {
  if (!span) return;
  std::string where;
  for (const GnssTime& t : {span->first, span->last}) {
    if (fallback.preciseAt(t)) continue;
    std::ostringstream os;
    os << (where.empty() ? "" : "; ") << "at " << t.toString(TimeSystem::GPS, 0) << " ";
    std::optional<GnssTime> newest;
    for (const auto& [sat, series] : store.orbits()) {
      auto it = series.upper_bound(t);
      if (it != series.begin() && (!newest || *newest < std::prev(it)->first)) newest = std::prev(it)->first;
    }
    if (newest) os << "the newest orbit correction is " << std::fixed << std::setprecision(0) << (t - *newest) << " s old";
    else os << "no orbit correction yet";
    where += os.str();
  }
  if (where.empty()) return;
  const BroadcastFallbackOptions& options = fallback.options();
  std::ostringstream sigmas;  // "2 m", or "3 m orbit, 2 m clock"
  if (options.orbit_sigma_m == options.clock_sigma_m) sigmas << options.orbit_sigma_m << " m";
  else sigmas << options.orbit_sigma_m << " m orbit, " << options.clock_sigma_m << " m clock";
  std::ostringstream os;
  os << "broadcast fallback: the SSR corrections of " << stream << " are missing or too old (orbit validity "
     << std::fixed << std::setprecision(0) << store.limits().orbit_max_age_s << " s) " << where
     << ": where fewer than " << options.min_ssr_satellites
     << " satellites have corrections in force, broadcast orbits and clocks serve (sigmas at least "
     << sigmas.str() << ") and the SSR code biases are not applied (codes as observed, as the broadcast clocks expect)";
  notes.push_back(os.str());
}

}  // namespace

namespace {

/// The navigation inputs: RINEX navigation files and receiver streams' navigation.
struct NavigationInputs {
  std::vector<NavData> navs;
  std::vector<StreamNavigationFile> streams;
  std::optional<GnssTime> reference_time;  // of the SSR stream: given, else the first record's
  std::string names;                       // the files' base names, comma separated
};

NavigationInputs readNavigationInputs(const std::vector<std::string>& nav,
                                      const std::optional<GnssTime>& stream_reference_time, BroadcastProducts& out) {
  NavigationInputs in;
  for (const auto& path : nav) {
    if (detectStreamFormatOfFile(path) != StreamFormat::Unknown) {
      in.streams.push_back(readStreamNavigation(path, stream_reference_time));
      const StreamNavigationFile& s = in.streams.back();
      if (!in.reference_time) in.reference_time = stream_reference_time ? stream_reference_time : s.first_time;
      out.notes.push_back("navigation records from the " + std::string(streamFormatName(s.format)) + " " +
                          fileBaseName(path) + ": " + std::to_string(s.navigation.size()) +
                          " record(s), each used from its reception in the stream on");
      if (s.counters.totalProblems() > 0) {
        std::string text = fileBaseName(path) + ": " + std::to_string(s.counters.totalProblems()) +
                           " problem(s) while decoding";
        if (!s.counters.problems.empty()) text += ", first: " + s.counters.problems.front().describe();
        out.problems.push_back(text);
      }
    } else {
      in.navs.push_back(readRinexNav(path));
      if (!in.reference_time) in.reference_time = in.navs.back().first_toc;
    }
    in.names += (in.names.empty() ? "" : ", ") + fileBaseName(path);
  }
  return in;
}

void fillGlonassChannels(const NavigationInputs& in, BroadcastProducts& out) {
  for (const auto& n : in.navs) out.glonass_channels.fillMissing(n.glonass_channels);
  for (const auto& s : in.streams)
    for (const auto& r : s.navigation.glonass)
      if (!out.glonass_channels.channel(r.record.satellite.prn))
        out.glonass_channels.set(r.record.satellite.prn, r.record.frequency_channel);
}

/// Every broadcast record, those of streams from their reception on.
std::shared_ptr<BroadcastEphemerisStore> broadcastStore(const NavigationInputs& in) {
  auto store = std::make_shared<BroadcastEphemerisStore>();
  for (const auto& n : in.navs) store->add(n);
  for (const auto& s : in.streams) {
    addReceived([&](const auto& record, const auto& received) { store->add(record, received); }, s.navigation);
    for (const auto& r : s.navigation.beidou) store->add(r.record, r.received_at);
  }
  return store;
}

/// The problems and notes of an SSR stream: decoding problems, repeated signals,
/// corrections without their broadcast record.
void noteSsrStream(const std::string& ssr_name, const SsrStreamFile& stream, const SsrCorrectionStore& store,
                   const BroadcastSsrEphemeris& eph, bool also_navigation, BroadcastProducts& out) {
  const auto describe = [&](const StreamCounters& c, const std::string& what) {
    if (c.totalProblems() == 0) return;
    std::string text = ssr_name + ": " + std::to_string(c.totalProblems()) + " " + what;
    if (!c.problems.empty()) text += ", first: " + c.problems.front().describe();
    out.problems.push_back(text);
  };
  describe(stream.counters, "problem(s) while decoding");
  if (!stream.receiver_messages_by_type.empty()) {
    std::uint64_t n = 0;
    std::string types;
    for (const auto& [type, count] : stream.receiver_messages_by_type) {
      n += count;
      types += (types.empty() ? "" : ", ") + std::to_string(type) + " x" + std::to_string(count);
    }
    out.notes.push_back(ssr_name + ": " + std::to_string(n) + " receiver message(s) beside the SSR ones (" + types +
                        (also_navigation ? "): its ephemerides are read as navigation input (--nav)"
                                         : "): not read from the SSR input; give the file as --nav too to use its "
                                           "ephemerides"));
  }
  if (stream.counters.repeated_signals > 0)
    out.notes.push_back(ssr_name + ": " + std::to_string(stream.counters.repeated_signals) +
                        " bias value(s) of a signal id sent twice for one satellite, the first of each kept; first: " +
                        stream.counters.first_repeated_signal);
  if (store.staleCodeBiasMessages() > 0)
    out.notes.push_back(ssr_name + ": " + std::to_string(store.staleCodeBiasMessages()) +
                        " code-bias message(s) sent with an epoch older than their validity, taken as re-sent and in "
                        "force from their arrival; first: " +
                        store.firstStaleCodeBiasMessage());
  describe(eph.consistency(), "SSR correction(s) without a broadcast record of their IOD");
}

/// The broadcast records corrected by the SSR stream `ssr`, with the broadcast
/// fallback where the corrections are missing or too old, and the SSR biases.
void addSsrCorrections(const std::string& ssr, const NavigationInputs& in,
                       std::optional<EphemerisReference> ssr_reference, SsrAgeLimits limits,
                       BroadcastFallbackOptions fallback_options,
                       const std::optional<ObservationSpan>& observation_span, bool ssr_in_nav,
                       BroadcastProducts& out) {
  const SsrStreamFile stream = readSsrStreamFile(ssr, in.reference_time);
  auto store = std::make_shared<SsrCorrectionStore>(limits);
  for (const auto& m : stream.messages) store->add(m);
  out.corrected_satellites = store->correctedSatellites();
  BroadcastSsrOptions options;
  const auto from_name = ssrReferenceFromStreamName(fileBaseName(ssr));
  options.reference = ssr_reference ? *ssr_reference : from_name.value_or(EphemerisReference::CentreOfMass);
  auto eph = std::make_shared<BroadcastSsrEphemeris>(in.navs, store, options);
  auto broadcast = std::make_shared<BroadcastEphemerisStore>();
  for (const auto& n : in.navs) broadcast->add(n);
  if (!in.streams.empty()) {
    for (const auto& s : in.streams) {
      addReceived([&](const auto& record, const auto& received) { eph->addRecord(record, received); }, s.navigation);
      addReceived([&](const auto& record, const auto& received) { broadcast->add(record, received); }, s.navigation);
      for (const auto& r : s.navigation.beidou) broadcast->add(r.record, r.received_at);
    }
    eph->checkConsistency();
  }
  auto fallback = std::make_shared<SsrBroadcastFallback>(eph, broadcast, fallback_options);
  out.notes.push_back("orbits and clocks: " + in.names + " corrected by SSR stream " + fileBaseName(ssr) + " (" +
                      std::to_string(stream.summary.messages) + " messages; orbits at the " +
                      std::string(ephemerisReferenceName(options.reference)) +
                      (ssr_reference ? ", as given" : from_name ? ", from the stream name" : ", by default") + ")");
  noteSsrStream(fileBaseName(ssr), stream, *store, *eph, ssr_in_nav, out);
  noteStaleCorrections(*fallback, *store, fileBaseName(ssr), observation_span, out.notes);
  if (store->codeBiasCount() > 0 || store->phaseBiasCount() > 0)
    out.ssr_biases = std::make_shared<SsrBiasProvider>(
        store, fileBaseName(ssr),
        [fallback](const SatelliteId& sat, const GnssTime& t) { return fallback->ssrInForce(sat, t); });
  out.ssr_phase_biases = store->phaseBiasCount() > 0;
  out.ephemeris = fallback;
  out.corrected = eph;
}

}  // namespace

BroadcastProducts loadBroadcastProducts(const std::vector<std::string>& nav, const std::optional<std::string>& ssr,
                                        std::optional<EphemerisReference> ssr_reference, SsrAgeLimits limits,
                                        BroadcastFallbackOptions fallback_options,
                                        std::optional<GnssTime> stream_reference_time,
                                        std::optional<ObservationSpan> observation_span) {
  BroadcastProducts out;
  // 1. The navigation records: RINEX navigation files and receiver streams.
  const NavigationInputs in = readNavigationInputs(nav, stream_reference_time, out);
  // 2. GLONASS channels and the satellites with records.
  fillGlonassChannels(in, out);
  out.record_satellites = recordSatellites(in.navs, in.streams);
  // 3. Without an SSR stream: the broadcast records alone.
  if (!ssr) {
    out.ephemeris = broadcastStore(in);
    out.notes.push_back("orbits and clocks: broadcast navigation records only (" + in.names +
                        "): metre-level accuracy, not precise products");
    return out;
  }
  // 4. With one: the records corrected by SSR, with the broadcast fallback.
  const bool ssr_in_nav = std::find(nav.begin(), nav.end(), *ssr) != nav.end();
  addSsrCorrections(*ssr, in, ssr_reference, limits, std::move(fallback_options), observation_span, ssr_in_nav, out);
  return out;
}

}  // namespace ppp
