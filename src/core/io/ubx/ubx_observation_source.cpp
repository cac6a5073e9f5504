#include "ppp_bayes_tree/io/ubx/ubx_observation_source.h"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <set>

#include "ppp_bayes_tree/io/epoch_time_screen.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rinex/stream_epoch_layout.h"
#include "ppp_bayes_tree/io/stream_pump.h"

namespace ppp {
namespace {

constexpr int kUbxRawxType = 0x0215;  // RXM-RAWX, class << 8 | id

constexpr ObservableType kTypes[4] = {ObservableType::Pseudorange, ObservableType::CarrierPhase,
                                      ObservableType::Doppler, ObservableType::SignalStrength};

}  // namespace

RinexObsHeader ubxObservationHeader(const std::vector<UbxObservationEpoch>& epochs, const std::string& file_name) {
  RinexObsHeader header;
  header.version_text = "3.04";
  header.version = 3.04;
  header.major_version = 3;
  header.file_system = 'M';
  header.program = "ppp_bayes_tree UBX";
  header.comments.push_back("format: u-blox UBX");
  header.comments.push_back("log: " + file_name);
  std::array<std::set<std::pair<char, char>>, kNumGnssSystems> signals;
  for (const auto& epoch : epochs) {
    for (const auto& m : epoch.measurements) {
      signals[static_cast<int>(m.satellite.system)].insert({m.signal.band, m.signal.attribute});
      if (m.glonass_channel && !header.glonass_channels.channel(m.satellite.prn)) {
        if (header.glonass_channels.set(m.satellite.prn, *m.glonass_channel)) ++header.glonass_channel_entries;
      }
    }
  }
  for (int s = 0; s < kNumGnssSystems; ++s) {
    for (const auto& [band, attribute] : signals[s]) {
      for (ObservableType type : kTypes) header.obs_types[s].push_back(ObservationCode{type, band, attribute});
    }
    header.scale_factors[s].assign(header.obs_types[s].size(), 1.0);
  }
  header.epoch_time_system = TimeSystem::GPS;
  header.signal_strength_unit = "DBHZ";
  if (!epochs.empty()) {
    RinexHeaderTime first;
    first.time = epochs.front().time;
    first.calendar = first.time.toCalendar();
    header.time_of_first_obs = first;
    RinexHeaderTime last;
    last.time = epochs.back().time;
    last.calendar = last.time.toCalendar();
    header.time_of_last_obs = last;
    for (const auto& e : epochs) {
      if (e.leap_seconds) {
        header.leap_seconds = *e.leap_seconds;
        break;
      }
    }
  }
  return header;
}

StreamEpoch toStreamEpoch(const UbxObservationEpoch& in) {
  StreamEpoch out;
  out.time = in.time;
  out.byte_offset = in.byte_offset;
  out.frame_index = in.frame_index;
  for (const auto& m : in.measurements) {
    StreamSatellite* sat = nullptr;
    for (auto& s : out.satellites)
      if (s.satellite == m.satellite) sat = &s;
    if (sat == nullptr) {
      out.satellites.push_back(StreamSatellite{m.satellite, {}});
      sat = &out.satellites.back();
    }
    StreamSignal s;
    s.band = m.signal.band;
    s.attribute = m.signal.attribute;
    s.pseudorange_m = m.pseudorange_m;
    s.carrier_phase_cycles = m.carrier_phase_cycles;
    s.doppler_hz = m.doppler_hz;
    s.cnr_dbhz = m.cn0_dbhz;
    s.lli = m.lli;
    s.lock_time_s = m.lock_time_s;
    sat->signals.push_back(s);
  }
  return out;
}

void toObsEpoch(const UbxObservationEpoch& in, const RinexObsHeader& header, ObsEpoch& out) {
  streamEpochToObsEpoch(toStreamEpoch(in), header, out);
  out.line = 0;
}

UbxObservationSource::UbxObservationSource(const std::string& path, UbxDecoderOptions options)
    : path_(path), name_(fileBaseName(path)) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> in(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!in) throw FileOpenError("cannot open UBX file " + path);
  UbxDecoder decoder(options);
  UbxDecoder::Handlers handlers;
  handlers.on_epoch = [&](const UbxObservationEpoch& e) { epochs_.push_back(e); };
  handlers.on_gps = [&](const GpsLnavEphemeris& e) { navigation_.gps.push_back(e); };
  handlers.on_galileo = [&](const GalileoEphemeris& e) { navigation_.galileo.push_back(e); };
  handlers.on_glonass = [&](const GlonassEphemeris& e) { navigation_.glonass.push_back(e); };
  handlers.on_beidou = [&](const BeidouEphemeris& e) { navigation_.beidou.push_back(e); };
  StreamPump(in.get(), path).run(
      {[&](const std::uint8_t* data, std::size_t size) { decoder.feed(data, size, handlers); },
       [&]() { decoder.finish(); }, nullptr});  // the handlers take what is decoded
  counters_ = decoder.counters();
  screenEpochTimes();
  statistics_ = decoder.statistics();
  header_ = ubxObservationHeader(epochs_, name_);
}

void UbxObservationSource::screenEpochTimes() {
  EpochTimeScreen<std::size_t> screen;
  std::vector<UbxObservationEpoch> kept;
  kept.reserve(epochs_.size());
  auto take = [&](EpochTimeScreen<std::size_t>::Result&& r) {
    for (const auto& e : r.accepted) kept.push_back(std::move(epochs_[e.payload]));
  };
  for (std::size_t i = 0; i < epochs_.size(); ++i) {
    const UbxObservationEpoch& e = epochs_[i];
    take(screen.push(e.time, EpochOrigin{e.byte_offset, e.frame_index, kUbxRawxType}, i));
  }
  take(screen.finish());
  epochs_ = std::move(kept);
  time_screen_ = screen.counters();
  for (const auto& p : time_screen_.problems) counters_.add(p);
}

ObservationRead UbxObservationSource::next(ObsEpoch& epoch) {
  if (next_ >= epochs_.size()) return ObservationRead::End;
  toObsEpoch(epochs_[next_++], header_, epoch);
  return ObservationRead::Epoch;
}

std::vector<ObservationProblem> UbxObservationSource::problems() const {
  std::vector<ObservationProblem> out;
  for (const auto& p : counters_.problems) out.push_back(ObservationProblem{name_, 0, p.describe()});
  return out;
}

double UbxObservationSource::progress() const {
  return epochs_.empty() ? 1.0 : static_cast<double>(next_) / static_cast<double>(epochs_.size());
}

}  // namespace ppp
