#include "ppp_bayes_tree/io/transport/gnss_stream_decoder.h"

#include <cstdio>
#include <memory>

#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/stream_pump.h"
#include "ppp_bayes_tree/io/ubx/ubx_observation_source.h"  // toStreamEpoch: the one UBX epoch conversion

namespace ppp {

GnssStreamDecoder::GnssStreamDecoder(StreamFormat format, Rtcm3DecoderOptions rtcm_options,
                                     UbxDecoderOptions ubx_options)
    : format_(format) {
  if (rtcm_options.reference_time) ssr_reference_ = rtcm_options.reference_time;
  if (format_ == StreamFormat::Ubx) {
    ubx_.emplace(ubx_options);
    ubx_handlers_.on_epoch = [this](const UbxObservationEpoch& e) {
      ubx_time_ = e.time;
      for (const auto& m : e.measurements)
        if (m.glonass_channel && m.satellite.system == GnssSystem::GLONASS)
          output_.glonass_channels.set(m.satellite.prn, *m.glonass_channel);
      output_.epochs.push_back(toStreamEpoch(e));
    };
    ubx_handlers_.on_gps = [this](const GpsLnavEphemeris& e) { output_.navigation.gps.push_back({e, ubx_time_}); };
    ubx_handlers_.on_galileo = [this](const GalileoEphemeris& e) {
      output_.navigation.galileo.push_back({e, ubx_time_});
    };
    ubx_handlers_.on_glonass = [this](const GlonassEphemeris& e) {
      output_.navigation.glonass.push_back({e, ubx_time_});
    };
    ubx_handlers_.on_beidou = [this](const BeidouEphemeris& e) { output_.navigation.beidou.push_back({e, ubx_time_}); };
  } else {
    rtcm_.emplace(std::move(rtcm_options));
    rtcm_->setForeignFrameHandler([this](const Rtcm3Frame& f) { return ssrFrame(f); });
    rtcm_->setFrameDecodedHandler([this]() { afterRtcmFrame(); });
  }
}

GnssStreamDecoder::~GnssStreamDecoder() = default;

void GnssStreamDecoder::feed(const std::uint8_t* data, std::size_t size) {
  if (ubx_) ubx_->feed(data, size, ubx_handlers_);
  if (rtcm_) rtcm_->feed(data, size);
}

void GnssStreamDecoder::finish() {
  if (ubx_) ubx_->finish();
  if (rtcm_) rtcm_->finish();
}

void GnssStreamDecoder::setSsrReferenceTime(const GnssTime& t) {
  if (!ssr_reference_) ssr_reference_ = t;
  drainSsr();
}

const StreamCounters& GnssStreamDecoder::counters() const {
  if (rtcm_) return rtcm_->counters();
  if (ubx_) return ubx_->counters();
  return empty_;
}

const RtcmStationInfo& GnssStreamDecoder::station() const { return rtcm_ ? rtcm_->station() : no_station_; }

const GlonassChannels& GnssStreamDecoder::glonassChannels() const {
  return rtcm_ ? rtcm_->glonassChannels() : output_.glonass_channels;
}

std::optional<GnssTime> GnssStreamDecoder::currentTime() const { return rtcm_ ? rtcm_->currentTime() : ubx_time_; }

void GnssStreamDecoder::afterRtcmFrame() {
  Rtcm3Output& out = rtcm_->output();
  const std::optional<GnssTime> now = rtcm_->currentTime();
  for (auto& e : out.epochs) output_.epochs.push_back(std::move(e));
  for (const auto& e : out.gps) output_.navigation.gps.push_back({e, now});
  for (const auto& e : out.galileo) output_.navigation.galileo.push_back({e, now});
  for (const auto& e : out.glonass) output_.navigation.glonass.push_back({e, now});
  for (const auto& e : out.beidou) output_.navigation.beidou.push_back({e, now});
  out.clear();
  if (!held_ssr_.empty() && now) drainSsr();
}

bool GnssStreamDecoder::ssrFrame(const Rtcm3Frame& frame) {
  if (!RtcmSsrDecoder::isSsrMessageType(frame.message_type)) return false;
  if (!ssr_reference_ && rtcm_->currentTime()) ssr_reference_ = rtcm_->currentTime();
  if (!ssr_reference_) {
    if (held_ssr_.size() < kMaxHeldSsrFrames) {
      held_ssr_.push_back(frame);
      return true;
    }
    // Too many without a time: decoded unresolved (counted by the SSR decoder).
  } else {
    drainSsr();
    ssr_.setReferenceTime(*ssr_reference_);
  }
  ssr_.decode(frame);
  auto messages = ssr_.takeMessages();
  for (auto& m : messages) output_.ssr.push_back(std::move(m));
  return true;
}

void GnssStreamDecoder::drainSsr() {
  if (held_ssr_.empty()) return;
  if (!ssr_reference_ && rtcm_ && rtcm_->currentTime()) ssr_reference_ = rtcm_->currentTime();
  if (!ssr_reference_) return;
  ssr_.setReferenceTime(*ssr_reference_);
  std::vector<Rtcm3Frame> held;
  held.swap(held_ssr_);
  for (const auto& f : held) ssr_.decode(f);
  auto messages = ssr_.takeMessages();
  for (auto& m : messages) output_.ssr.push_back(std::move(m));
}

StreamNavigationFile readStreamNavigation(const std::string& path, std::optional<GnssTime> reference_time) {
  StreamNavigationFile out;
  out.format = detectStreamFormatOfFile(path);
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw FileOpenError("cannot open stream file " + path);
  Rtcm3DecoderOptions options;
  options.reference_time = reference_time;
  GnssStreamDecoder decoder(out.format == StreamFormat::Ubx ? StreamFormat::Ubx : StreamFormat::Rtcm3, options);
  auto drain = [&]() {
    auto& o = decoder.output();
    if (!out.first_time && decoder.currentTime()) out.first_time = decoder.currentTime();
    auto& n = o.navigation;
    out.navigation.gps.insert(out.navigation.gps.end(), n.gps.begin(), n.gps.end());
    out.navigation.galileo.insert(out.navigation.galileo.end(), n.galileo.begin(), n.galileo.end());
    out.navigation.glonass.insert(out.navigation.glonass.end(), n.glonass.begin(), n.glonass.end());
    out.navigation.beidou.insert(out.navigation.beidou.end(), n.beidou.begin(), n.beidou.end());
    o.clear();
  };
  StreamPump(f.get(), path).run({[&](const std::uint8_t* data, std::size_t size) { decoder.feed(data, size); },
                                 [&]() { decoder.finish(); }, drain});
  out.counters = decoder.counters();
  return out;
}

}  // namespace ppp
