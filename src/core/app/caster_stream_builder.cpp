#include "ppp_bayes_tree/app/caster_stream_builder.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "ppp_bayes_tree/io/bit_writer.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_ephemeris_encoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_msm_encoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp {
namespace {

const GnssSystem kMsmSystems[] = {GnssSystem::GPS,  GnssSystem::GLONASS, GnssSystem::Galileo,
                                  GnssSystem::SBAS, GnssSystem::QZSS,    GnssSystem::BeiDou};

void putText(BitWriter& w, const std::string& text) {
  const std::string s = text.substr(0, 31);  // DF228-DF232: up to 31 characters
  w.putUnsigned(s.size(), 8);
  for (char c : s) w.putUnsigned(static_cast<unsigned char>(c), 8);
}

}  // namespace

StreamEpoch streamEpochFromRinex(const ObsEpoch& in, std::map<std::pair<SatelliteId, std::string>, GnssTime>& arc_start,
                                 const std::set<GnssSystem>& systems) {
  StreamEpoch out;
  out.time = in.time;
  for (std::size_t i = 0; i < in.satellites.size(); ++i) {
    const SatelliteId sat = in.satellites[i].satellite;
    if (!systems.empty() && !systems.count(sat.system)) continue;
    StreamSatellite s{sat, {}};
    for (const Observation* o = in.begin(i); o != in.end(i); ++o) {
      if (!o->value) continue;
      StreamSignal* sig = nullptr;
      for (auto& x : s.signals)
        if (x.band == o->code.band && x.attribute == o->code.attribute) sig = &x;
      if (sig == nullptr) {
        StreamSignal x;
        x.band = o->code.band;
        x.attribute = o->code.attribute;
        s.signals.push_back(x);
        sig = &s.signals.back();
      }
      switch (o->code.type) {
        case ObservableType::Pseudorange: sig->pseudorange_m = o->value; break;
        case ObservableType::CarrierPhase:
          sig->carrier_phase_cycles = o->value;
          sig->lli = o->lli.value_or(0);
          break;
        case ObservableType::Doppler: sig->doppler_hz = o->value; break;
        case ObservableType::SignalStrength: sig->cnr_dbhz = o->value; break;
        default: break;
      }
    }
    for (auto& x : s.signals) {
      const auto key = std::make_pair(sat, std::string{x.band, x.attribute});
      auto it = arc_start.find(key);
      if (it == arc_start.end() || (x.lli & 1) || !x.carrier_phase_cycles)
        it = arc_start.insert_or_assign(key, in.time).first;
      x.lock_time_s = in.time - it->second;
    }
    if (!s.signals.empty()) out.satellites.push_back(std::move(s));
  }
  return out;
}

std::vector<std::vector<std::uint8_t>> stationFrames(const RinexObsHeader& header, int station_id) {
  if (!header.approx_position_ecef_m)
    throw std::invalid_argument("station frames: the RINEX header has no APPROX POSITION XYZ");
  const Eigen::Vector3d delta_hen = header.antenna_delta_hen_m.value_or(Eigen::Vector3d::Zero());
  // RTCM 1006 gives the ARP and its height above the marker (DF028); RINEX the
  // marker and the ARP's height/east/north offsets from it.
  const Eigen::Vector3d arp = enuToEcef(Eigen::Vector3d(delta_hen[1], delta_hen[2], delta_hen[0]),
                                        *header.approx_position_ecef_m);
  std::vector<std::vector<std::uint8_t>> frames;
  {
    BitWriter w;  // RTCM 10403.3 3.5.3, DF025-DF028 in 0.1 mm
    w.putUnsigned(1006, 12);
    w.putUnsigned(static_cast<std::uint64_t>(station_id), 12);
    w.putUnsigned(0, 6);       // ITRF realisation year: not given
    w.putUnsigned(0b1110, 4);  // GPS, GLONASS, Galileo; not a reference-station indicator
    w.putSigned(std::llround(arp.x() * 1e4), 38);
    w.putUnsigned(0, 2);  // single receiver oscillator, reserved
    w.putSigned(std::llround(arp.y() * 1e4), 38);
    w.putUnsigned(0, 2);  // quarter cycle indicator
    w.putSigned(std::llround(arp.z() * 1e4), 38);
    w.putUnsigned(static_cast<std::uint64_t>(std::llround(std::max(0.0, delta_hen[0]) * 1e4)), 16);
    frames.push_back(encodeRtcm3Frame(w.bytes()));
  }
  if (!header.antenna_type.empty() || !header.receiver_type.empty()) {
    BitWriter w;  // 1033 (3.5.6): antenna descriptor "TYPE(16) RADOME(4)" as IGS names it
    std::string descriptor = header.antenna_type;
    descriptor.resize(16, ' ');
    descriptor += header.radomeOrNone();
    w.putUnsigned(1033, 12);
    w.putUnsigned(static_cast<std::uint64_t>(station_id), 12);
    putText(w, descriptor);
    w.putUnsigned(0, 8);  // antenna setup id
    putText(w, header.antenna_number);
    putText(w, header.receiver_type);
    putText(w, header.receiver_version);
    putText(w, header.receiver_number);
    frames.push_back(encodeRtcm3Frame(w.bytes()));
  }
  return frames;
}

CasterStreamBuilder::CasterStreamBuilder(CasterStreamOptions options) : options_(std::move(options)) {}

void CasterStreamBuilder::setStation(const RinexObsHeader& header) {
  station_ = header;
  for (int slot = 1; slot <= GlonassChannels::kMaxSlot; ++slot)
    if (const auto k = header.glonass_channels.channel(slot)) channels_.set(slot, *k);
}

void CasterStreamBuilder::addEpoch(const ObsEpoch& epoch) {
  if (epoch.flag != EpochFlag::Ok && epoch.flag != EpochFlag::PowerFailure) return;
  const StreamEpoch e = streamEpochFromRinex(epoch, arc_start_, options_.systems);
  if (!first_) first_ = e.time;
  last_ = e.time;
  ++epochs_;
  std::vector<GnssSystem> present;
  for (const GnssSystem system : kMsmSystems)
    for (const auto& s : e.satellites)
      if (s.satellite.system == system) {
        present.push_back(system);
        break;
      }
  MsmEncodeOptions enc;
  enc.station_id = options_.station_id;
  enc.glonass_channels = channels_;
  for (std::size_t i = 0; i < present.size(); ++i) {
    enc.more_messages_follow = i + 1 < present.size();
    for (const auto& payload : encodeMsm7(e, present[i], enc)) {
      const int type = static_cast<int>((payload[0] << 4) | (payload[1] >> 4));
      msm_.push_back({e.time.toGpsSecondsDouble() + options_.observation_latency_s, encodeRtcm3Frame(payload), e.time,
                      type});
    }
  }
}

void CasterStreamBuilder::addNavigation(const NavData& nav) {
  for (int slot = 1; slot <= GlonassChannels::kMaxSlot; ++slot)
    if (const auto k = nav.glonass_channels.channel(slot); k && !channels_.channel(slot)) channels_.set(slot, *k);
  auto add = [&](const auto& eph, const GnssTime& reference, const GnssTime& transmission, int rank) {
    Record r;
    try {
      r.frame = encodeRtcm3Frame(encodeEphemerisPayload(eph));
    } catch (const std::exception& e) {
      counters_.add(StreamProblem{StreamProblemKind::MalformedMessage, 0, 0, ephemerisMessageType(eph),
                                  eph.satellite.toString() + " record at " + reference.toString() +
                                      " cannot be encoded: " + e.what()});
      return;
    }
    r.transmission = transmission;
    r.reference = reference;
    r.message_type = ephemerisMessageType(eph);
    r.key = eph.satellite.toString() + "/" + std::to_string(r.message_type);
    r.preamble_rank = rank;
    records_.push_back(std::move(r));
  };
  for (const auto& e : nav.galileo) add(e, e.orbit.toe, transmissionTime(e).value_or(e.orbit.toe), 0);
  for (const auto& g : nav.glonass) add(g, g.tb, transmissionTime(g), 1);
  for (const auto& e : nav.gps) add(e, e.orbit.toe, transmissionTime(e).value_or(e.orbit.toe), 2);
}

void CasterStreamBuilder::addSsrStream(const std::vector<std::uint8_t>& bytes, std::optional<GnssTime> reference) {
  if (!reference) reference = first_;
  RtcmSsrDecoder decoder(reference);
  Rtcm3Framer framer;
  framer.feed(bytes.data(), bytes.size(), [&](const Rtcm3Frame& frame) {
    const bool ssr = decoder.decode(frame);
    std::vector<SsrMessage> messages = decoder.takeMessages();
    if (!ssr || messages.empty() || !messages.front().header.epoch) {
      counters_.add(StreamProblem{ssr ? StreamProblemKind::UnresolvedTime : StreamProblemKind::UnknownMessage,
                                  frame.byte_offset, frame.frame_index, frame.message_type,
                                  ssr ? "SSR frame without a resolvable epoch, left out"
                                      : "not an SSR message, left out of the correction stream"});
      return;
    }
    const GnssTime epoch = *messages.front().header.epoch;
    ssr_.push_back({epoch.toGpsSecondsDouble() + options_.ssr_latency_s, encodeRtcm3Frame(frame.payload), epoch,
                    frame.message_type});
  });
  framer.finish();
  for (const auto& p : framer.counters().problems) counters_.add(p);
}

std::vector<TimedFrame> CasterStreamBuilder::navigationFrames() const {
  std::vector<TimedFrame> out;
  if (!first_ || !last_) return out;
  const double start_s = first_->toGpsSecondsDouble() + options_.observation_latency_s;
  const double end_s = last_->toGpsSecondsDouble() + options_.observation_latency_s;
  // Per satellite and message type, the records in order of transmission.
  std::map<std::string, std::vector<const Record*>> by_key;
  for (const auto& r : records_) by_key[r.key].push_back(&r);
  struct Send {
    double at_s;
    int rank;  // ahead of the first epoch: preamble order
    const Record* record;
  };
  std::vector<Send> sends;
  for (auto& [key, list] : by_key) {
    std::stable_sort(list.begin(), list.end(), [](const Record* a, const Record* b) {
      return a->transmission < b->transmission || (a->transmission == b->transmission && a->reference < b->reference);
    });
    for (std::size_t i = 0; i < list.size(); ++i) {
      const Record& r = *list[i];
      const double tx_s = r.transmission.toGpsSecondsDouble();
      if (tx_s > end_s) break;
      const double next_s = i + 1 < list.size() ? list[i + 1]->transmission.toGpsSecondsDouble() : end_s + 1.0;
      double first_send_s = tx_s;
      if (tx_s < start_s) {
        // Transmitted before the stream starts: sent ahead of the first epoch when still of use.
        if (first_->toGpsSecondsDouble() - r.reference.toGpsSecondsDouble() > options_.max_record_age_s) continue;
        first_send_s = start_s - 1.0;
        sends.push_back({first_send_s, r.preamble_rank, &r});
      } else {
        sends.push_back({tx_s, 3, &r});
      }
      // Repeats until the next record of the key is transmitted (or the stream ends).
      if (options_.ephemeris_repeat_s > 0.0)
        for (double t = first_send_s + options_.ephemeris_repeat_s; t < next_s && t <= end_s;
             t += options_.ephemeris_repeat_s)
          sends.push_back({t, 3, &r});
    }
  }
  std::stable_sort(sends.begin(), sends.end(), [](const Send& a, const Send& b) {
    return a.at_s < b.at_s || (a.at_s == b.at_s && a.rank < b.rank);
  });
  for (const auto& s : sends) out.push_back({s.at_s, s.record->frame, s.record->reference, s.record->message_type});
  return out;
}

std::vector<TimedFrame> CasterStreamBuilder::observationFrames() const { return observationFrames(navigationFrames()); }

std::vector<TimedFrame> CasterStreamBuilder::observationFrames(const std::vector<TimedFrame>& nav) const {
  std::vector<TimedFrame> out;
  if (!first_) return out;
  // Station: ahead of everything, then every station_repeat_s.
  std::vector<TimedFrame> station;
  if (station_ && station_->approx_position_ecef_m) {
    const auto frames = stationFrames(*station_, options_.station_id);
    const double start_s = first_->toGpsSecondsDouble() + options_.observation_latency_s;
    const double end_s = last_->toGpsSecondsDouble() + options_.observation_latency_s;
    for (double t = start_s - 1.0; t <= end_s; t += options_.station_repeat_s > 0 ? options_.station_repeat_s : 1e300) {
      for (const auto& f : frames) {
        const int type = static_cast<int>((f[3] << 4) | (f[4] >> 4));
        station.push_back({t, f, *first_ + (t - start_s), type});
      }
    }
  }
  out = station;
  out.insert(out.end(), nav.begin(), nav.end());
  out.insert(out.end(), msm_.begin(), msm_.end());
  std::stable_sort(out.begin(), out.end(), [](const TimedFrame& a, const TimedFrame& b) { return a.arrival_s < b.arrival_s; });
  return out;
}

std::vector<TimedFrame> CasterStreamBuilder::ssrFrames() const {
  std::vector<TimedFrame> out;
  for (const auto& f : ssr_)
    if (!first_ || (!(f.data_time < *first_ - options_.ssr_margin_s) && !(*last_ + options_.ssr_margin_s < f.data_time)))
      out.push_back(f);
  std::stable_sort(out.begin(), out.end(), [](const TimedFrame& a, const TimedFrame& b) { return a.arrival_s < b.arrival_s; });
  return out;
}

CasterStream CasterStreamBuilder::build() const {
  const std::vector<TimedFrame> nav = navigationFrames();
  CasterStream stream;
  stream.frames = observationFrames(nav);
  const auto ssr = ssrFrames();
  stream.frames.insert(stream.frames.end(), ssr.begin(), ssr.end());
  std::stable_sort(stream.frames.begin(), stream.frames.end(),
                   [](const TimedFrame& a, const TimedFrame& b) { return a.arrival_s < b.arrival_s; });
  for (const auto& f : stream.frames) ++stream.frames_by_type[f.message_type];
  std::set<std::vector<std::uint8_t>> records;
  for (const auto& f : nav) records.insert(f.bytes);
  stream.records_sent = records.size();
  return stream;
}

void writeFrames(const std::string& path, const std::vector<TimedFrame>& frames) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw FileOpenError("cannot write " + path);
  for (const auto& f : frames) out.write(reinterpret_cast<const char*>(f.bytes.data()), static_cast<std::streamsize>(f.bytes.size()));
  if (!out) throw FileOpenError("error writing " + path);
}

}  // namespace ppp
