#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "ppp_bayes_tree/io/bit_reader.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_decoder.h"
#include "ppp_bayes_tree/io/bias_bounds.h"
#include "rtcm_ssr_layout.h"

namespace ppp {

namespace {
constexpr double kWeek_s = 604800.0;
constexpr double kDay_s = 86400.0;

std::string kindKey(const SsrHeader& h) {
  return std::string(systemName(h.system)) + " " + std::string(ssrMessageKindName(h.kind));
}
}  // namespace

RtcmSsrDecoder::RtcmSsrDecoder(std::optional<GnssTime> reference_time) : reference_(reference_time) {}

bool RtcmSsrDecoder::isSsrMessageType(int message_type) {
  return message_type == 4076 || ssr_layout::rtcmTypeInfo(message_type).has_value();
}

void RtcmSsrDecoder::problem(StreamProblemKind kind, const Rtcm3Frame& frame, std::string detail) {
  StreamProblem p;
  p.kind = kind;
  p.byte_offset = frame.byte_offset;
  p.frame_index = frame.frame_index;
  p.message_type = frame.message_type;
  p.detail = std::move(detail);
  counters_.add(std::move(p));
}

void RtcmSsrDecoder::refuseImplausibleBiases(const Rtcm3Frame& frame, SsrMessage& m) {
  const auto refuse = [&](auto& satellites, BiasKind kind) {
    for (auto& sat : satellites) {
      auto& biases = sat.biases;
      for (auto it = biases.begin(); it != biases.end();) {
        const auto beyond = biasBeyondBound_m(kind, it->bias_m);
        if (!beyond) {
          ++it;
          continue;
        }
        problem(StreamProblemKind::ImplausibleValue, frame,
                sat.satellite.toString() + " signal " + std::to_string(it->signal_id) + ": " + *beyond +
                    ": bias not used");
        it = biases.erase(it);
      }
    }
  };
  refuse(m.code_biases, BiasKind::Code);
  refuse(m.phase_biases, BiasKind::Phase);
}

void RtcmSsrDecoder::refuseRepeatedSignals(const Rtcm3Frame& frame, SsrMessage& m) {
  const auto refuse = [&](auto& satellites, const char* what) {
    for (auto& sat : satellites) {
      auto& biases = sat.biases;
      for (std::size_t k = 1; k < biases.size();) {
        const auto first = std::find_if(biases.begin(), biases.begin() + static_cast<std::ptrdiff_t>(k),
                                        [&](const auto& b) { return b.signal_id == biases[k].signal_id; });
        if (first == biases.begin() + static_cast<std::ptrdiff_t>(k)) {
          ++k;
          continue;
        }
        std::ostringstream o;
        o << sat.satellite.toString() << " " << what << " signal " << biases[k].signal_id
          << (first->code ? " (" + first->code->toString() + ")" : std::string()) << " sent again in the message: the first value "
          << first->bias_m << " m kept, the repeated value " << biases[k].bias_m << " m dropped";
        if (counters_.repeated_signals++ == 0)
          counters_.first_repeated_signal =
              streamPlace(frame.byte_offset, frame.frame_index, frame.message_type) + ": " + o.str();
        biases.erase(biases.begin() + static_cast<std::ptrdiff_t>(k));
      }
    }
  };
  refuse(m.code_biases, "code bias");
  refuse(m.phase_biases, "phase bias");
}

std::optional<GnssTime> RtcmSsrDecoder::resolveEpoch(const SsrHeader& h, bool igs) const {
  if (!reference_) return std::nullopt;
  const GnssTime& ref = *reference_;
  if (!igs && h.system == GnssSystem::GLONASS && h.kind != SsrMessageKind::Vtec) {
    // GLONASS time of day: place it in the GLONASS day nearest the reference.
    const double offset_s = ref.offsetToSystem_s(TimeSystem::GLONASS);  // GLONASST - GPST
    const double ref_glo_s = ref.toGpsSecondsDouble() + offset_s;
    const double day_start = std::floor(ref_glo_s / kDay_s) * kDay_s;
    double t_glo = day_start + h.epoch_time_s;
    if (t_glo - ref_glo_s > kDay_s / 2) t_glo -= kDay_s;
    if (ref_glo_s - t_glo > kDay_s / 2) t_glo += kDay_s;
    return GnssTime::fromGpsSeconds(static_cast<std::int64_t>(std::llround(t_glo - offset_s)));
  }
  double sow = h.epoch_time_s;
  sow += gpstMinusWeekTime_s(h.system).value_or(0.0);  // BDT -> GPST
  const GpsWeekTime w = ref.gpsWeek();
  double t = static_cast<double>(w.week) * kWeek_s + sow;
  const double ref_s = ref.toGpsSecondsDouble();
  if (t - ref_s > kWeek_s / 2) t -= kWeek_s;
  if (ref_s - t > kWeek_s / 2) t += kWeek_s;
  return GnssTime::fromGpsSeconds(static_cast<std::int64_t>(std::llround(t)));
}

namespace {

/// The type of an SSR message: its layout and the key it is counted under (IGS-SSR:
/// 4076000 + sub-type), or the problem that leaves it without one.
struct SsrType {
  std::optional<ssr_layout::TypeInfo> info;
  int summary_key = 0;
  StreamProblemKind problem_kind = StreamProblemKind::MalformedMessage;
  std::string problem;
};

/// Reads the IGS-SSR version and sub-type (IDF001, IDF002) into m's header; the RTCM
/// types have their layout from the message type alone.
SsrType readSsrType(BitReader& r, const Rtcm3Frame& frame, SsrMessage& m) {
  SsrType type;
  type.summary_key = frame.message_type;
  if (frame.message_type != 4076) {
    type.info = ssr_layout::rtcmTypeInfo(frame.message_type);
    return type;
  }
  m.header.igs_version = static_cast<int>(r.u(3));   // IDF001
  m.header.igs_subtype = static_cast<int>(r.u(8));   // IDF002
  if (!r.ok()) {
    type.problem = "IGS-SSR message shorter than its header";
    return type;
  }
  type.info = ssr_layout::igsTypeInfo(m.header.igs_subtype);
  type.summary_key = 4076000 + m.header.igs_subtype;
  if (!type.info) {
    type.problem_kind = StreamProblemKind::UnknownMessage;
    type.problem = "IGS-SSR sub-type " + std::to_string(m.header.igs_subtype) + " not defined by IGS-SSR v1.00";
  }
  return type;
}

/// Parses the header fields and the satellite blocks (or the VTEC block) that follow
/// the type. A BeiDou orbit message that the IGS layout does not fit exactly is read
/// again with the RTKLIB one (see satelliteFieldBits); true when that one fits.
bool parseSsrBody(BitReader& r, SsrMessage& m, bool igs, std::vector<ssr_layout::BadSatellite>& bad) {
  const SsrHeader start = m.header;
  const auto parse = [&](BitReader& reader, bool bds_rtklib) {
    m = SsrMessage{};
    m.header = start;
    bad.clear();
    ssr_layout::Reader io(reader);
    ssr_layout::header(io, m, igs);
    if (m.header.kind == SsrMessageKind::Vtec) ssr_layout::vtecBlock(io, m);
    else ssr_layout::satelliteBlocks(io, m, igs, bad, bds_rtklib);
  };
  const BitReader after_type = r;
  parse(r, false);
  if (igs || m.header.system != GnssSystem::BeiDou ||
      !(m.header.kind == SsrMessageKind::Orbit || m.header.kind == SsrMessageKind::Combined) ||
      (r.ok() && r.remainingBits() < 8))
    return false;
  BitReader retry = after_type;
  parse(retry, true);
  r = retry;
  return retry.ok() && retry.remainingBits() < 8;
}

void addToSummary(SsrStreamSummary& s, const SsrMessage& m, int summary_key) {
  s.messages += 1;
  s.messages_by_type[summary_key] += 1;
  s.sources.insert({m.header.provider_id, m.header.solution_id});
  s.update_intervals_s[kindKey(m.header)].insert(m.header.update_interval_s);
  s.iod_ssr.insert(m.header.iod_ssr);
  if (m.header.datum_regional) (*m.header.datum_regional ? s.datum_regional_messages : s.datum_itrf_messages) += 1;
  if (m.header.epoch) {
    if (!s.first_epoch || *m.header.epoch < *s.first_epoch) s.first_epoch = m.header.epoch;
    if (!s.last_epoch || *s.last_epoch < *m.header.epoch) s.last_epoch = m.header.epoch;
    auto& [first, last] = m.header.kind == SsrMessageKind::CodeBias ? s.code_bias_epochs : s.other_epochs;
    if (!first || *m.header.epoch < *first) first = m.header.epoch;
    if (!last || *last < *m.header.epoch) last = m.header.epoch;
  }
  auto sats = [&](const auto& list) { for (const auto& x : list) s.satellites[m.header.system].insert(x.satellite); };
  sats(m.orbits); sats(m.clocks); sats(m.code_biases); sats(m.phase_biases); sats(m.high_rate_clocks); sats(m.uras);
  s.orbit_corrections += m.orbits.size();
  s.clock_corrections += m.clocks.size();
  for (const auto& b : m.code_biases) s.code_biases += b.biases.size();
  for (const auto& b : m.phase_biases) s.phase_biases += b.biases.size();
  s.high_rate_clocks += m.high_rate_clocks.size();
  s.uras += m.uras.size();
  if (m.vtec) s.vtec_messages += 1;
}

}  // namespace

bool RtcmSsrDecoder::decode(const Rtcm3Frame& frame) {
  if (!isSsrMessageType(frame.message_type)) return false;
  counters_.frames += 1;
  counters_.frames_by_type[frame.message_type] += 1;
  // 1. The message type (IGS-SSR: version and sub-type) and its layout.
  BitReader r(frame.payload.data(), frame.payload.size());
  r.skip(12);
  SsrMessage m;
  const bool igs = frame.message_type == 4076;
  const SsrType type = readSsrType(r, frame, m);
  if (!type.info) {
    problem(type.problem_kind, frame, type.problem);
    return true;
  }
  m.header.message_type = frame.message_type;
  m.header.system = type.info->system;
  m.header.kind = type.info->kind;
  m.header.byte_offset = frame.byte_offset;
  m.header.frame_index = frame.frame_index;
  // 2. Header and blocks, which must fill the message.
  std::vector<ssr_layout::BadSatellite> bad;
  if (parseSsrBody(r, m, igs, bad)) summary_.beidou_rtklib_layout_messages += 1;
  if (!r.ok()) {
    problem(StreamProblemKind::MalformedMessage, frame,
            std::string(ssrMessageKindName(m.header.kind)) + " message of " + std::to_string(frame.payload.size()) +
                " bytes is shorter than its fields (satellite count or bias counts too large): message dropped");
    return true;
  }
  if (r.remainingBits() >= 8) {
    problem(StreamProblemKind::MalformedMessage, frame,
            std::to_string(r.remainingBits()) + " bits left after the last field: layout mismatch, message dropped");
    return true;
  }
  for (const auto& b : bad)
    problem(StreamProblemKind::MalformedMessage, frame,
            "satellite id " + std::to_string(b.raw_id) + " outside the " + std::string(systemName(m.header.system)) +
                " range: satellite skipped");
  // 3. Values not used: biases beyond their bounds, signals sent twice.
  refuseImplausibleBiases(frame, m);
  refuseRepeatedSignals(frame, m);
  // 4. The epoch, placed by the reference time, which then follows the stream.
  m.header.epoch = resolveEpoch(m.header, igs);
  if (!m.header.epoch) {
    problem(StreamProblemKind::UnresolvedTime, frame,
            "SSR epoch time " + std::to_string(m.header.epoch_time_s) +
                " s has no week (no reference time): values kept, epoch unresolved");
  } else {
    reference_ = m.header.epoch;  // follow the stream across week / day boundaries
  }
  // 5. The summary.
  addToSummary(summary_, m, type.summary_key);
  messages_.push_back(std::move(m));
  return true;
}

std::vector<SsrMessage> RtcmSsrDecoder::takeMessages() {
  std::vector<SsrMessage> out;
  out.swap(messages_);
  return out;
}

std::string SsrStreamSummary::format() const {
  std::ostringstream o;
  o << "SSR messages: " << messages << "\n";
  o << "  by type:";
  for (const auto& [type, n] : messages_by_type) {
    if (type >= 4076000) o << " 4076/" << (type - 4076000) << ":" << n;
    else o << " " << type << ":" << n;
  }
  o << "\n  providers/solutions:";
  for (const auto& src : sources) o << " " << src.provider_id << "/" << src.solution_id;
  o << "\n  IOD SSR:";
  for (int i : iod_ssr) o << " " << i;
  o << "\n  reference datum (orbit messages): ITRF " << datum_itrf_messages << ", regional " << datum_regional_messages;
  o << "\n  update intervals:";
  for (const auto& [key, set] : update_intervals_s) {
    o << " [" << key << ":";
    for (double v : set) o << " " << v << " s";
    o << "]";
  }
  o << "\n  values: orbit " << orbit_corrections << ", clock " << clock_corrections << ", high-rate clock "
    << high_rate_clocks << ", URA " << uras << ", code bias " << code_biases << ", phase bias " << phase_biases
    << ", VTEC " << vtec_messages;
  if (beidou_rtklib_layout_messages > 0)
    o << "\n  BeiDou orbit messages in the RTKLIB layout (24-bit IODCRC): " << beidou_rtklib_layout_messages;
  o << "\n  satellites:";
  for (const auto& [sys, set] : satellites) o << " " << systemName(sys) << " " << set.size();
  if (first_epoch && last_epoch)
    o << "\n  epochs: " << first_epoch->toString(TimeSystem::GPS, 0) << " to " << last_epoch->toString(TimeSystem::GPS, 0)
      << " GPST";
  const auto& [bias_first, bias_last] = code_bias_epochs;
  const auto& [other_first, other_last] = other_epochs;
  constexpr double kApart_s = 3600.0;  // a code-bias set an hour or more apart from the rest is said
  if (bias_first && other_first && (*other_first - *bias_first > kApart_s || *bias_last - *other_last > kApart_s))
    o << "\n  code-bias epochs " << bias_first->toString(TimeSystem::GPS, 0) << " to "
      << bias_last->toString(TimeSystem::GPS, 0) << ", other messages " << other_first->toString(TimeSystem::GPS, 0)
      << " to " << other_last->toString(TimeSystem::GPS, 0)
      << " (code biases older than their validity on arrival are taken as re-sent, in force from their arrival)";
  if (!(first_epoch && last_epoch)) o << "\n  epochs: not placed in time (no week known)";
  return o.str();
}

SsrStreamFile decodeSsrStream(const std::uint8_t* data, std::size_t size, std::optional<GnssTime> reference_time) {
  SsrStreamFile out;
  Rtcm3Framer framer;
  RtcmSsrDecoder decoder(reference_time);
  StreamCounters unknown;
  const auto on_frame = [&](const Rtcm3Frame& f) {
    if (decoder.decode(f)) return;
    if (Rtcm3Decoder::readsMessageType(f.message_type)) {
      ++out.receiver_messages_by_type[f.message_type];
    } else {
      StreamProblem p;
      p.kind = StreamProblemKind::UnknownMessage;
      p.byte_offset = f.byte_offset;
      p.frame_index = f.frame_index;
      p.message_type = f.message_type;
      p.detail = "message type " + std::to_string(f.message_type) + " is not an SSR message: skipped";
      unknown.add(std::move(p));
    }
  };
  constexpr std::size_t kChunk = 4096;
  for (std::size_t i = 0; i < size; i += kChunk) framer.feed(data + i, std::min(kChunk, size - i), on_frame);
  framer.finish();
  out.counters = framer.counters();
  for (const auto& p : decoder.counters().problems) out.counters.add(p);
  for (const auto& p : unknown.problems) out.counters.add(p);
  // Problems beyond the kept ones still count.
  for (const StreamCounters* c : {&decoder.counters(), static_cast<const StreamCounters*>(&unknown)})
    for (const auto& [kind, n] : c->problems_by_kind) {
      std::uint64_t kept = 0;
      for (const auto& p : c->problems) kept += p.kind == kind ? 1 : 0;
      out.counters.problems_by_kind[kind] += n - kept;
    }
  out.counters.repeated_signals = decoder.counters().repeated_signals;
  out.counters.first_repeated_signal = decoder.counters().first_repeated_signal;
  out.messages = decoder.takeMessages();
  out.summary = decoder.summary();
  return out;
}

SsrStreamFile readSsrStreamFile(const std::string& path, std::optional<GnssTime> reference_time) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileOpenError("cannot open SSR stream file " + path);
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return decodeSsrStream(bytes.data(), bytes.size(), reference_time);
}

}  // namespace ppp
