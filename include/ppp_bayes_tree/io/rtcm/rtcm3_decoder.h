#pragma once
// Rtcm3Decoder: decodes an RTCM 3 byte stream (fed in chunks of any size) into
// observation epochs (MSM4-7 of GPS, GLONASS, Galileo, SBAS, QZSS, BeiDou),
// station data (1005-1008, 1033) and broadcast ephemerides (1019, 1020, 1042,
// 1044, 1045, 1046). An epoch is assembled from the MSM messages of all systems
// with the same time. The week of MSM times comes from context (a reference
// date, or a Galileo / BeiDou ephemeris week); until it is known, epochs are
// counted as UnresolvedTime. Bad input (CRC, truncation, garbage, short or
// inconsistent messages, unknown types) is counted with byte offset and frame
// index; a bad satellite is left out, the rest of the epoch goes on.
// Messages, loss-of-lock flags, GLONASS channels and time placement:
// doc/rtcm_decoding.md.
// References: RTCM 10403.3 "Differential GNSS Services - Version 3" (3.5.10-3.5.14
// ephemerides, 3.5.16 MSM); RINEX 3.05 sec. 5.3 (LLI).
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/stream_epoch.h"
#include "ppp_bayes_tree/io/stream_problem.h"
#include "ppp_bayes_tree/types/beidou_ephemeris.h"
#include "ppp_bayes_tree/types/glonass_channels.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/navigation_records.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// Station description from 1005/1006/1007/1008/1033.
struct RtcmStationInfo {
  std::optional<int> station_id;
  std::optional<Eigen::Vector3d> arp_ecef_m;   // antenna reference point (1005/1006)
  std::optional<double> antenna_height_m;      // 1006: ARP height above the marker
  std::optional<int> itrf_realization_year;    // DF021
  std::string antenna_descriptor;              // e.g. "LEIAR25.R3      NONE" (IGS name)
  std::string antenna_serial;
  int antenna_setup_id = 0;
  std::string receiver_type, receiver_firmware, receiver_serial;
};

struct Rtcm3DecoderOptions {
  /// Approximate time of the data (any instant within half a week of it).
  std::optional<GnssTime> reference_time;
  /// GLONASS channels known beforehand (used when the stream gives none).
  GlonassChannels glonass_channels;
};

/// Everything decoded since the caller last took it.
struct Rtcm3Output {
  std::vector<StreamEpoch> epochs;
  std::vector<GpsLnavEphemeris> gps;  // GPS and QZSS LNAV
  std::vector<GalileoEphemeris> galileo;
  std::vector<GlonassEphemeris> glonass;
  std::vector<BeidouEphemeris> beidou;
  void clear() {
    epochs.clear();
    gps.clear();
    galileo.clear();
    glonass.clear();
    beidou.clear();
  }
};

/// What the broadcast weeks of the GPS/QZSS, Galileo and BeiDou ephemerides say
/// about the stream's time (placed by a reference date, or by the stream): a
/// record agrees when its toe, in the week it was sent with, lies within a day
/// of the stream's time (a toe early in its week may come with the week before,
/// that of transmission: the nearer reading counts).
struct BroadcastWeekEvidence {
  std::size_t records = 0;             // records counted (agreeing or not)
  std::vector<double> disagreement_s;  // toe as sent minus the stream's time, of those not agreeing [s]
};

struct MsmFields;  // the fields of one MSM message, as read (rtcm3_decoder.cpp)
struct NonMsmMessage;  // a non-MSM message type and its decoding step (rtcm3_decoder.cpp)

class Rtcm3Decoder {
 public:
  /// A handler for frames of types this decoder does not read (e.g. SSR);
  /// returns true when it consumed the frame (otherwise: UnknownMessage).
  using ForeignFrameHandler = std::function<bool(const Rtcm3Frame&)>;

  explicit Rtcm3Decoder(Rtcm3DecoderOptions options = {});

  /// True for the message types decodeFrame() reads or knowingly skips
  /// (observations, ephemerides, station and antenna messages, 1013, 1230).
  static bool readsMessageType(int message_type);

  void setForeignFrameHandler(ForeignFrameHandler handler) { foreign_ = std::move(handler); }
  /// Called after each frame fed has been decoded, and at the end of finish()
  /// (callers that stamp results with the stream time, io/transport/gnss_stream_decoder.h).
  void setFrameDecodedHandler(std::function<void()> handler) { after_frame_ = std::move(handler); }

  /// Feeds bytes (any chunking); decoded results accumulate in output().
  void feed(const std::uint8_t* data, std::size_t size);
  /// End of stream: reports a truncated last frame and closes a pending epoch.
  void finish();
  /// Decodes one well-framed message (used by feed; public for callers that frame themselves).
  void decodeFrame(const Rtcm3Frame& frame);

  Rtcm3Output& output() { return output_; }
  const StreamCounters& counters() const { return framer_.counters(); }
  /// The ephemerides' broadcast weeks against the stream's time (a wrong reference date shows here).
  const BroadcastWeekEvidence& weekEvidence() const { return week_evidence_; }
  const RtcmStationInfo& station() const { return station_; }
  const GlonassChannels& glonassChannels() const { return channels_; }
  /// Messages decoded per type (a subset of counters().frames_by_type).
  const std::map<int, std::uint64_t>& decodedByType() const { return decoded_by_type_; }
  /// Frames of known but unused types (e.g. 1230 GLONASS biases), per type.
  const std::map<int, std::uint64_t>& ignoredByType() const { return ignored_by_type_; }
  /// BeiDou MSM messages whose time was GPST instead of BDT (see the .cpp), taken into the open epoch.
  std::uint64_t beidouGpstMessages() const { return beidou_gpst_messages_; }
  /// The latest resolved time (nullopt while the week is unknown).
  const std::optional<GnssTime>& currentTime() const { return time_; }

 private:
  void noteWeekEvidence(const GnssTime& toe_as_sent, double toe_sow);
  BroadcastWeekEvidence week_evidence_;
  struct PendingGps {
    GpsLnavEphemeris eph;
    int week10 = 0;
    std::uint64_t byte_offset = 0, frame_index = 0;
    int type = 0;
  };

  void problem(StreamProblemKind kind, const Rtcm3Frame& frame, std::string detail);
  void decodeMsm(const Rtcm3Frame& frame, GnssSystem system, int msm);
  std::optional<GnssTime> msmEpochTime(const Rtcm3Frame& frame, GnssSystem system, const MsmFields& m);
  void takeStreamTime(const GnssTime& t);
  void openEpoch(const Rtcm3Frame& frame, const GnssTime& t);
  StreamSatellite msmSatellite(GnssSystem system, int msm, const MsmFields& m, std::size_t i, std::size_t& cell);
  void addToOpenEpoch(StreamSatellite satellite);
  /// The non-MSM message of this type the decoder reads or skips; nullptr for another type.
  static const NonMsmMessage* nonMsmMessage(int message_type);
  void decodeStation(const Rtcm3Frame& frame);
  void decodeAntennaReceiver(const Rtcm3Frame& frame);
  void decodeGpsQzss(const Rtcm3Frame& frame);
  void decodeGlonassEph(const Rtcm3Frame& frame);
  void decodeGalileo(const Rtcm3Frame& frame);
  void decodeBeidou(const Rtcm3Frame& frame);
  void setTimeFromEphemeris(const GnssTime& toe);
  void resolveGpsWeek(PendingGps& pending);
  void flushPendingEpoch();
  std::optional<int> glonassChannel(int slot) const;

  Rtcm3DecoderOptions options_;
  Rtcm3Framer framer_;
  ForeignFrameHandler foreign_;
  std::function<void()> after_frame_;
  Rtcm3Output output_;
  RtcmStationInfo station_;
  GlonassChannels channels_;            // from the stream (MSM5/7 or 1020)
  std::optional<GnssTime> time_;
  std::optional<StreamEpoch> pending_;
  std::map<std::pair<int, int>, std::uint32_t> lock_ms_;  // (satellite index, signal id)
  std::vector<PendingGps> pending_gps_;
  std::map<int, std::uint64_t> decoded_by_type_;
  std::map<int, std::uint64_t> ignored_by_type_;
  std::uint64_t beidou_gpst_messages_ = 0;
  bool time_from_stream_ = false;  // time_ set from the stream, not only the reference date
  bool finishing_ = false;
  std::vector<Rtcm3Frame> deferred_glonass_;  // GLONASS MSM waiting for the day (see .cpp)
};

/// MSM signal id (1..32, RTCM 10403.3 tables 3.5-91/96/99/102/105/108) to the RINEX
/// band and attribute ("1C"); nullopt for a reserved id.
std::optional<std::pair<char, char>> msmSignalCode(GnssSystem system, int signal_id);
/// The inverse: MSM signal id of a RINEX band/attribute, nullopt when MSM has none.
std::optional<int> msmSignalId(GnssSystem system, char band, char attribute);
/// Minimum lock time [ms] of the MSM lock-time indicators DF402 (4 bits) and DF407 (10 bits).
std::uint32_t msmLockTimeDf402_ms(unsigned indicator);
std::uint32_t msmLockTimeDf407_ms(unsigned indicator);
/// The RTCM message type's system and MSM number (4..7) for 1071..1137; nullopt otherwise.
std::optional<std::pair<GnssSystem, int>> msmTypeInfo(int message_type);
/// The inverse: the message type of a system's MSM1..7 (1077 = GPS MSM7), nullopt
/// for a system whose signals are not tabled here (NavIC) or another MSM number.
std::optional<int> msmMessageType(GnssSystem system, int msm);
/// The MSM satellite id (DF394 bit 1..64) of a satellite: the PRN; SBAS PRN - 119 (S20 = PRN 120 -> 1).
int msmSatelliteId(const SatelliteId& sat);

}  // namespace ppp
