#pragma once
// RtcmSsrDecoder: decodes the SSR messages of an RTCM 3 stream, one frame at a
// time (frames come from Rtcm3Framer or from the observation decoder's hook for
// types it does not read):
//   - RTCM 10403.3 SSR: 1057-1068 (GPS, GLONASS), 1240-1263 (Galileo, QZSS,
//     SBAS, BeiDou), 1264 (VTEC), 1265-1270 (phase biases);
//   - IGS-SSR v1.00 (message 4076, all sub-types of section 5).
// Values into SsrMessage (types/ssr_corrections.h).
//
// Epoch times carry no week (GLONASS messages: no day). They are placed in
// GPST next to a reference time from the context (the navigation file, the
// observations, or the previous SSR epoch): the week (day) that puts the epoch
// nearest the reference. Galileo epoch times are GST (aligned with GPST),
// BeiDou ones BDT (= GPST - 14 s), RTCM GLONASS ones GLONASS time of day
// (UTC(SU) + 3 h). Without a reference the epoch stays unresolved (counted as
// UnresolvedTime; the values are still decoded).
//
// A message shorter than its fields, or with a satellite id outside the
// system's range, is counted as MalformedMessage with byte offset and frame
// index; the rest of the stream goes on.
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/stream_problem.h"
#include "ppp_bayes_tree/types/ssr_corrections.h"

namespace ppp {

/// What an SSR stream holds, for ppp_stream_inspect.
struct SsrStreamSummary {
  struct Source {
    int provider_id = 0;
    int solution_id = 0;
    friend bool operator<(const Source& a, const Source& b) {
      return a.provider_id != b.provider_id ? a.provider_id < b.provider_id : a.solution_id < b.solution_id;
    }
  };
  std::set<Source> sources;                    // provider / solution ids seen
  std::map<int, std::uint64_t> messages_by_type;  // 4076 counted as 4076000 + sub-type
  std::map<std::string, std::set<double>> update_intervals_s;  // "<system> <kind>" -> intervals
  std::set<int> iod_ssr;
  std::uint64_t datum_itrf_messages = 0, datum_regional_messages = 0;  // DF375 of orbit messages
  std::map<GnssSystem, std::set<SatelliteId>> satellites;
  std::optional<GnssTime> first_epoch, last_epoch;  // resolved epochs only
  /// First and last resolved epochs of the code-bias messages and of the others.
  std::pair<std::optional<GnssTime>, std::optional<GnssTime>> code_bias_epochs, other_epochs;
  std::uint64_t messages = 0;
  std::uint64_t orbit_corrections = 0, clock_corrections = 0, code_biases = 0, phase_biases = 0,
                high_rate_clocks = 0, uras = 0, vtec_messages = 0;
  /// BeiDou orbit / combined messages that fit only the RTKLIB layout (toe
  /// modulo + 24-bit IODCRC) instead of the IGS one (toe modulo + 8-bit IOD).
  std::uint64_t beidou_rtklib_layout_messages = 0;
  /// Readable lines (no trailing newline).
  std::string format() const;
};

class RtcmSsrDecoder {
 public:
  explicit RtcmSsrDecoder(std::optional<GnssTime> reference_time = std::nullopt);

  /// True for the types decode() reads: RTCM SSR types and 4076.
  static bool isSsrMessageType(int message_type);

  /// Sets (or moves) the time next to which week-less epochs are placed.
  void setReferenceTime(const GnssTime& t) { reference_ = t; }

  /// Decodes one frame. false: not an SSR type (nothing counted). true: the
  /// frame was an SSR message (decoded and queued, or counted as a problem).
  bool decode(const Rtcm3Frame& frame);

  /// The messages decoded since the last call (moves them out).
  std::vector<SsrMessage> takeMessages();
  const std::vector<SsrMessage>& pendingMessages() const { return messages_; }

  /// Frames decoded per type and problems (MalformedMessage, UnresolvedTime).
  const StreamCounters& counters() const { return counters_; }
  const SsrStreamSummary& summary() const { return summary_; }

 private:
  void problem(StreamProblemKind kind, const Rtcm3Frame& frame, std::string detail);
  /// Drops the code and phase biases beyond their bounds (io/bias_bounds.h), each a problem.
  void refuseImplausibleBiases(const Rtcm3Frame& frame, SsrMessage& m);
  /// Keeps the first bias of a signal id that a satellite's block sends more
  /// than once and drops the later ones, each counted. Seen on SSRA03IGS0
  /// (2026-07-07): GPS satellites with L5 send signal id 0 (C1C) twice; the
  /// first value agrees with CODE's C1C OSB (negated), the second is near the
  /// satellite's C5Q bias and is no C1C bias. Counted apart from the problems
  /// (StreamCounters::repeated_signals): it says nothing against the stream.
  void refuseRepeatedSignals(const Rtcm3Frame& frame, SsrMessage& m);
  std::optional<GnssTime> resolveEpoch(const SsrHeader& header, bool igs) const;

  std::optional<GnssTime> reference_;
  std::vector<SsrMessage> messages_;
  StreamCounters counters_;
  SsrStreamSummary summary_;
};

/// A whole SSR stream file: its messages, the framer's and the decoder's
/// counters together (frames of other types are counted as UnknownMessage).
struct SsrStreamFile {
  std::vector<SsrMessage> messages;
  StreamCounters counters;
  SsrStreamSummary summary;
  /// Receiver messages beside the SSR ones (ephemerides, observations, station:
  /// types a receiver stream's decoder reads), per type: not used here, not problems.
  std::map<int, std::uint64_t> receiver_messages_by_type;
};
/// Reads a file (throws FileOpenError when it cannot be opened).
SsrStreamFile readSsrStreamFile(const std::string& path, std::optional<GnssTime> reference_time);
/// The same from bytes in memory (fuzzing, tests).
SsrStreamFile decodeSsrStream(const std::uint8_t* data, std::size_t size, std::optional<GnssTime> reference_time);

}  // namespace ppp
