#include "ppp_bayes_tree/app/stream_inspection.h"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "ppp_bayes_tree/evaluation/json_text.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/io/stream_pump.h"
#include "ppp_bayes_tree/io/ubx/ubx_observation_source.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

template <typename Sats>
void noteEphemeris(StreamInspection& s, const Sats& records) {
  for (const auto& r : records) {
    ++s.ephemeris_records[r.satellite.system];
    s.ephemeris_satellites[r.satellite.system].insert(r.satellite);
  }
}

std::string satList(const std::set<SatelliteId>& sats) {
  std::string out;
  for (const auto& s : sats) out += (out.empty() ? "" : " ") + s.toString();
  return out;
}

/// Epoch times in the order received: span, spacing, gaps, epochs not after the previous.
class EpochTiming {
 public:
  void note(StreamInspection& s, const GnssTime& t) {
    ++s.epochs;
    if (!s.first_epoch || t < *s.first_epoch) s.first_epoch = t;
    if (!s.last_epoch || t > *s.last_epoch) s.last_epoch = t;
    if (previous_) {
      const double dt = t - *previous_;
      if (dt <= 0.0) {
        ++s.backwards;
      } else {
        ++spacing_ms_[std::llround(dt * 1000.0)];
        dts_.push_back(dt);
      }
    }
    if (!previous_ || t > *previous_) previous_ = t;
  }
  void finish(StreamInspection& s) const {
    if (spacing_ms_.empty()) return;
    const auto mode = std::max_element(spacing_ms_.begin(), spacing_ms_.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    s.interval_s = mode->first * 1e-3;
    GnssTime t = *s.first_epoch;
    for (double dt : dts_) {
      if (dt > 1.5 * *s.interval_s) {
        ++s.gap_count;
        if (s.gaps.size() < 20) s.gaps.push_back(StreamGap{t, dt});
      }
      t += dt;
    }
  }

 private:
  std::map<long long, std::size_t> spacing_ms_;
  std::optional<GnssTime> previous_;
  std::vector<double> dts_;
};

/// A u-blox recording: RXM-RAWX epochs and RXM-SFRBX ephemerides (io/ubx/ubx_observation_source.h).
StreamInspection inspectUbxFile(const std::string& path) {
  StreamInspection s;
  s.path = path;
  s.format = StreamFormat::Ubx;
  UbxObservationSource source(path);
  EpochTiming timing;
  ObsEpoch epoch;
  while (source.next(epoch) == ObservationRead::Epoch) {
    timing.note(s, epoch.time);
    for (std::size_t i = 0; i < epoch.satellites.size(); ++i) {
      const SatelliteId sat = epoch.satellites[i].satellite;
      s.satellites[sat.system].insert(sat);
      for (const Observation* o = epoch.begin(i); o != epoch.end(i); ++o)
        if (o->value) s.signals[sat.system].insert(o->code.signal());
    }
  }
  timing.finish(s);
  noteEphemeris(s, source.navigation().gps);
  noteEphemeris(s, source.navigation().galileo);
  noteEphemeris(s, source.navigation().glonass);
  noteEphemeris(s, source.navigation().beidou);
  s.counters = source.counters();
  return s;
}

}  // namespace

StreamInspection inspectStreamFile(const std::string& path, const Rtcm3DecoderOptions& options) {
  StreamInspection s;
  s.path = path;
  s.format = detectStreamFormatOfFile(path);
  if (s.format == StreamFormat::Ubx) return inspectUbxFile(path);
  if (s.format != StreamFormat::Rtcm3)
    throw std::runtime_error(path + ": not an RTCM 3 or UBX stream (no frame with a good checksum found)");
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw FileOpenError("cannot open " + path);
  Rtcm3Decoder decoder(options);
  // SSR messages (1057-1068, 1240-1270, 4076) are the SSR decoder's.
  RtcmSsrDecoder ssr(options.reference_time);
  decoder.setForeignFrameHandler([&ssr](const Rtcm3Frame& frame) {
    const bool decoded = ssr.decode(frame);
    ssr.takeMessages();
    return decoded;
  });
  EpochTiming timing;
  auto drain = [&]() {
    auto& out = decoder.output();
    for (const auto& e : out.epochs) {
      timing.note(s, e.time);
      for (const auto& sat : e.satellites) {
        s.satellites[sat.satellite.system].insert(sat.satellite);
        for (const auto& sig : sat.signals) s.signals[sat.satellite.system].insert(std::string{sig.band, sig.attribute});
      }
    }
    noteEphemeris(s, out.gps);
    noteEphemeris(s, out.galileo);
    noteEphemeris(s, out.glonass);
    noteEphemeris(s, out.beidou);
    out.clear();
  };
  StreamPump(f.get(), path).run({[&](const std::uint8_t* data, std::size_t size) { decoder.feed(data, size); },
                                 [&]() { decoder.finish(); }, drain});
  timing.finish(s);
  s.counters = decoder.counters();
  for (const auto& [kind, count] : ssr.counters().problems_by_kind) s.counters.problems_by_kind[kind] += count;
  for (const auto& p : ssr.counters().problems)
    if (s.counters.problems.size() < StreamCounters::kMaxKeptProblems) s.counters.problems.push_back(p);
  s.counters.repeated_signals = ssr.counters().repeated_signals;
  s.counters.first_repeated_signal = ssr.counters().first_repeated_signal;
  if (ssr.summary().messages > 0) {
    std::istringstream lines(ssr.summary().format());
    for (std::string line; std::getline(lines, line);) s.ssr.push_back(line);
  }
  s.decoded_by_type = decoder.decodedByType();
  s.ignored_by_type = decoder.ignoredByType();
  s.station = decoder.station();
  s.glonass_channels = decoder.glonassChannels();
  s.beidou_gpst_messages = decoder.beidouGpstMessages();
  return s;
}

std::string formatStreamInspection(const StreamInspection& s) {
  std::ostringstream os;
  os << "== " << s.path << "\n";
  os << "  type      " << streamFormatName(s.format) << "\n";
  os << "  bytes     " << s.counters.bytes << ", frames " << s.counters.frames << " with a good CRC\n";
  os << "  frames per type:";
  for (const auto& [type, n] : s.counters.frames_by_type) {
    os << " " << type << "x" << n;
    if (s.ignored_by_type.count(type)) os << "(not used)";
  }
  os << "\n";
  os << "  epochs    " << s.epochs;
  if (s.first_epoch)
    os << ", " << s.first_epoch->toString(TimeSystem::GPS, 1) << " .. " << s.last_epoch->toString(TimeSystem::GPS, 1)
       << " (" << (*s.last_epoch - *s.first_epoch) << " s)";
  os << "\n";
  if (s.interval_s) {
    os << format("  rate      %.3f s (%.2f Hz), %zu gap(s), %zu epoch(s) not after the previous\n", *s.interval_s,
                 1.0 / *s.interval_s, s.gap_count, s.backwards);
    for (const auto& g : s.gaps) os << "    gap of " << g.length_s << " s after " << g.after.toString(TimeSystem::GPS, 1) << "\n";
  }
  for (const auto& [sys, sats] : s.satellites) {
    os << "  " << systemName(sys) << ": " << sats.size() << " satellites (" << satList(sats) << "); signals";
    for (const auto& sig : s.signals.at(sys)) os << " " << sig;
    os << "\n";
  }
  for (const auto& [sys, n] : s.ephemeris_records)
    os << "  ephemerides " << systemName(sys) << ": " << n << " records, " << s.ephemeris_satellites.at(sys).size()
       << " satellites\n";
  if (s.station.station_id) os << "  station   id " << *s.station.station_id << "\n";
  if (s.station.arp_ecef_m) {
    os << format("  ARP       %.4f %.4f %.4f m ECEF", s.station.arp_ecef_m->x(), s.station.arp_ecef_m->y(),
                 s.station.arp_ecef_m->z());
    if (s.station.antenna_height_m) os << ", antenna height " << *s.station.antenna_height_m << " m";
    os << "\n";
  }
  if (!s.station.antenna_descriptor.empty()) os << "  antenna   " << s.station.antenna_descriptor << "\n";
  if (!s.station.receiver_type.empty())
    os << "  receiver  " << s.station.receiver_type << " " << s.station.receiver_firmware << "\n";
  if (s.glonass_channels.size() > 0) os << "  GLONASS channels known for " << s.glonass_channels.size() << " slots\n";
  if (s.beidou_gpst_messages > 0)
    os << "  note: " << s.beidou_gpst_messages << " BeiDou MSM carried GPST instead of BDT (RTCM 3.2 draft encoder)\n";
  for (const auto& line : s.ssr) os << "  " << line << "\n";
  os << "  problems  " << s.counters.totalProblems();
  if (s.counters.count(StreamProblemKind::ChecksumError) == 0) os << " (no CRC errors)";
  os << "\n";
  for (const auto& [kind, n] : s.counters.problems_by_kind) os << "    " << n << " x " << streamProblemKindName(kind) << "\n";
  for (std::size_t i = 0; i < s.counters.problems.size() && i < 10; ++i)
    os << "    " << s.counters.problems[i].describe() << "\n";
  if (s.counters.repeated_signals > 0)
    os << "  note: " << s.counters.repeated_signals
       << " SSR bias value(s) of a signal id sent twice for one satellite, the first of each kept; first: "
       << s.counters.first_repeated_signal << "\n";
  if (s.counters.count(StreamProblemKind::UnresolvedTime) > 0)
    os << "  the week of the MSM epochs is unknown: give --ref-date YYYY/MM/DD\n";
  os << "\n";
  return os.str();
}

std::string streamInspectionJson(const StreamInspection& s) {
  std::ostringstream os;
  os << "{\n  \"path\": " << jsonString(s.path) << ",\n  \"format\": " << jsonString(streamFormatName(s.format))
     << ",\n  \"bytes\": " << s.counters.bytes << ",\n  \"frames\": " << s.counters.frames << ",\n  \"frames_by_type\": {";
  bool first = true;
  for (const auto& [type, n] : s.counters.frames_by_type) {
    os << (first ? "" : ", ") << "\"" << type << "\": " << n;
    first = false;
  }
  os << "},\n  \"crc_errors\": " << s.counters.count(StreamProblemKind::ChecksumError) << ",\n  \"problems\": {";
  first = true;
  for (const auto& [kind, n] : s.counters.problems_by_kind) {
    os << (first ? "" : ", ") << jsonString(streamProblemKindName(kind)) << ": " << n;
    first = false;
  }
  os << "},\n  \"epochs\": " << s.epochs;
  if (s.first_epoch) {
    os << ",\n  \"first_epoch\": " << jsonString(s.first_epoch->toString(TimeSystem::GPS, 3))
       << ",\n  \"last_epoch\": " << jsonString(s.last_epoch->toString(TimeSystem::GPS, 3))
       << ",\n  \"span_s\": " << jsonNumber(*s.last_epoch - *s.first_epoch);
  }
  if (s.interval_s) os << ",\n  \"interval_s\": " << jsonNumber(*s.interval_s) << ",\n  \"gaps\": " << s.gap_count;
  os << ",\n  \"systems\": {";
  first = true;
  for (const auto& [sys, sats] : s.satellites) {
    os << (first ? "" : ",") << "\n    " << jsonString(systemName(sys)) << ": {\"satellites\": [";
    bool f2 = true;
    for (const auto& sat : sats) {
      os << (f2 ? "" : ", ") << jsonString(sat.toString());
      f2 = false;
    }
    os << "], \"signals\": [";
    f2 = true;
    for (const auto& sig : s.signals.at(sys)) {
      os << (f2 ? "" : ", ") << jsonString(sig);
      f2 = false;
    }
    os << "]}";
    first = false;
  }
  os << "\n  },\n  \"ephemerides\": {";
  first = true;
  for (const auto& [sys, n] : s.ephemeris_records) {
    os << (first ? "" : ", ") << jsonString(systemName(sys)) << ": {\"records\": " << n
       << ", \"satellites\": " << s.ephemeris_satellites.at(sys).size() << "}";
    first = false;
  }
  os << "},\n  \"ssr\": [";
  first = true;
  for (const auto& line : s.ssr) {
    os << (first ? "" : ", ") << jsonString(line);
    first = false;
  }
  os << "]\n}\n";
  return os.str();
}

FileSummary summarizeStreamFile(const std::string& path) {
  const StreamInspection s = inspectStreamFile(path);
  FileSummary f;
  f.path = path;
  f.type = std::string(streamFormatName(s.format));
  f.first_epoch = s.first_epoch;
  f.last_epoch = s.last_epoch;
  f.interval_s = s.interval_s;
  f.epoch_count = s.epochs;
  f.satellites = s.satellites;
  for (const auto& [sys, sigs] : s.signals)
    for (const auto& sig : sigs) f.signals[sys].insert(sig);
  f.facts.push_back(std::to_string(s.counters.frames) + " frames, " +
                    std::to_string(s.counters.count(StreamProblemKind::ChecksumError)) + " CRC errors");
  for (const auto& [sys, n] : s.ephemeris_records)
    f.facts.push_back(std::string(systemName(sys)) + " ephemerides: " + std::to_string(n));
  if (!s.station.antenna_descriptor.empty()) f.facts.push_back("antenna " + s.station.antenna_descriptor);
  if (!s.station.receiver_type.empty()) f.facts.push_back("receiver " + s.station.receiver_type);
  for (const auto& p : s.counters.problems) f.report.addProblem(0, p.describe());
  if (s.counters.count(StreamProblemKind::UnresolvedTime) > 0)
    f.facts.push_back("MSM week unknown: ppp_stream_inspect --ref-date gives the epochs");
  return f;
}

}  // namespace ppp
