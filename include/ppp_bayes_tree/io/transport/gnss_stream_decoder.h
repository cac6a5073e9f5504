#pragma once
// GnssStreamDecoder: one receiver or correction byte stream (RTCM 3 or UBX),
// fed in chunks of any size, decoded to what a PPP run takes from it:
// observation epochs (as StreamEpoch for both formats), broadcast navigation
// records stamped with their RECEPTION time, SSR messages (RTCM) and the
// station description. Used by the live input (app/live_gnss_input.h) and by
// ppp_solve --nav on a stream file (models/broadcast_products.h), so that both
// stamp records identically.
//
// Reception time of a record: the stream's time when the frame that completed
// the record was decoded (RTCM: the decoder's latest resolved time, i.e. of the
// newest MSM or ephemeris; UBX: the newest RXM-RAWX epoch); nullopt before the
// stream has a time. It depends only on the byte order, never on the chunking.
//
// SSR frames (RTCM) are decoded by an RtcmSsrDecoder whose reference time is
// the reference given, else the stream's own time; frames met before any time
// is known are held (at most kMaxHeldSsrFrames, then counted UnresolvedTime).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "ppp_bayes_tree/io/rtcm/rtcm3_decoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/io/stream_problem.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"
#include "ppp_bayes_tree/io/ubx/ubx_decoder.h"
#include "ppp_bayes_tree/types/beidou_ephemeris.h"
#include "ppp_bayes_tree/types/navigation_records.h"

namespace ppp {

/// A decoded record and when it was received (stream time; nullopt: unknown).
template <class Record>
struct ReceivedRecord {
  Record record;
  std::optional<GnssTime> received_at;
};

/// Navigation records of a stream in the order decoded.
struct ReceivedNavigation {
  std::vector<ReceivedRecord<GpsLnavEphemeris>> gps;  // GPS and QZSS LNAV
  std::vector<ReceivedRecord<GalileoEphemeris>> galileo;
  std::vector<ReceivedRecord<GlonassEphemeris>> glonass;
  std::vector<ReceivedRecord<BeidouEphemeris>> beidou;
  std::size_t size() const { return gps.size() + galileo.size() + glonass.size() + beidou.size(); }
  void clear() {
    gps.clear();
    galileo.clear();
    glonass.clear();
    beidou.clear();
  }
};

/// What was decoded since the caller last took it.
struct GnssStreamOutput {
  std::vector<StreamEpoch> epochs;
  ReceivedNavigation navigation;
  std::vector<SsrMessage> ssr;
  /// GLONASS channels of UBX measurements (RTCM: in the decoder's channels).
  GlonassChannels glonass_channels;
  void clear() {
    epochs.clear();
    navigation.clear();
    ssr.clear();
  }
};

class GnssStreamDecoder {
 public:
  static constexpr std::size_t kMaxHeldSsrFrames = 20000;

  GnssStreamDecoder(StreamFormat format, Rtcm3DecoderOptions rtcm_options = {}, UbxDecoderOptions ubx_options = {});
  ~GnssStreamDecoder();
  GnssStreamDecoder(const GnssStreamDecoder&) = delete;
  GnssStreamDecoder& operator=(const GnssStreamDecoder&) = delete;

  StreamFormat format() const { return format_; }
  void feed(const std::uint8_t* data, std::size_t size);
  /// End of stream (truncated last frame, pending epoch).
  void finish();
  /// Time next to which week-less SSR epochs are placed (before the stream has one).
  void setSsrReferenceTime(const GnssTime& t);

  GnssStreamOutput& output() { return output_; }
  /// Framing and decoding problems and frame counts (observation decoder).
  const StreamCounters& counters() const;
  /// The SSR decoder's counters (RTCM with SSR; empty otherwise).
  const StreamCounters& ssrCounters() const { return ssr_.counters(); }
  const SsrStreamSummary& ssrSummary() const { return ssr_.summary(); }
  const RtcmStationInfo& station() const;
  const GlonassChannels& glonassChannels() const;
  /// The stream's latest time (nullopt while unknown).
  std::optional<GnssTime> currentTime() const;
  /// RTCM: what the ephemerides' broadcast weeks say about the stream's time
  /// (Rtcm3Decoder::weekEvidence); nullptr for UBX (RXM-RAWX carries the week).
  const BroadcastWeekEvidence* weekEvidence() const { return rtcm_ ? &rtcm_->weekEvidence() : nullptr; }

 private:
  void afterRtcmFrame();
  bool ssrFrame(const Rtcm3Frame& frame);
  void drainSsr();

  StreamFormat format_;
  std::optional<Rtcm3Decoder> rtcm_;
  std::optional<UbxDecoder> ubx_;
  UbxDecoder::Handlers ubx_handlers_;
  RtcmSsrDecoder ssr_;
  std::optional<GnssTime> ssr_reference_;
  std::vector<Rtcm3Frame> held_ssr_;
  std::optional<GnssTime> ubx_time_;
  GnssStreamOutput output_;
  StreamCounters empty_;
  RtcmStationInfo no_station_;
};

/// Every navigation record of a stream file with its reception time (throws
/// FileOpenError when it cannot be read). Problems are in `counters`.
struct StreamNavigationFile {
  StreamFormat format = StreamFormat::Unknown;
  ReceivedNavigation navigation;
  StreamCounters counters;
  std::optional<GnssTime> first_time;  // the stream's first resolved time
};
StreamNavigationFile readStreamNavigation(const std::string& path, std::optional<GnssTime> reference_time);

}  // namespace ppp
