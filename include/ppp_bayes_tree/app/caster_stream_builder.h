#pragma once
// CasterStreamBuilder: one RTCM 3 stream as an NTRIP caster would send it for a
// processed day, made from RINEX files (ppp_stream_make; the ESBC live tests):
// the station (1006, 1033), each observation epoch as MSM7, each broadcast record
// from its transmission time, repeated, and the SSR frames of a correction
// stream, each at its arrival time (epoch + latency). Frames are ordered by
// arrival time; at equal times the order of adding is kept.
// What each part carries and when: doc/offline_tools.md, "How ppp_stream_make
// builds a caster stream".
// Reference: RTCM 10403.3 (1006, 1033, MSM7 3.5.16, ephemerides 3.5.10-3.5.14).
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_decoder.h"
#include "ppp_bayes_tree/io/stream_problem.h"
#include "ppp_bayes_tree/types/obs_epoch.h"

namespace ppp {

/// One frame of a made stream and when the caster sends it.
struct TimedFrame {
  double arrival_s = 0.0;  // GPST seconds (GnssTime::toGpsSecondsDouble)
  std::vector<std::uint8_t> bytes;
  GnssTime data_time;  // the epoch (or record reference time) it belongs to
  int message_type = 0;
};

/// A made stream: its frames in arrival order and what they hold.
struct CasterStream {
  std::vector<TimedFrame> frames;
  std::map<int, std::size_t> frames_by_type;
  std::size_t records_sent = 0;  // broadcast records sent (first sends, not repeats)
};

struct CasterStreamOptions {
  int station_id = 1;
  double observation_latency_s = 0.5;
  double ssr_latency_s = 2.0;
  /// SSR frames are sent for epochs from this long before the first observation
  /// epoch to this long after the last (the corrections a user needs at the ends).
  double ssr_margin_s = 60.0;
  double ephemeris_repeat_s = 60.0;
  double station_repeat_s = 300.0;
  /// Records of a satellite older than this at the first epoch are not sent.
  double max_record_age_s = 4.0 * 3600.0;
  /// Systems sent as MSM7 (empty: every system MSM carries).
  std::set<GnssSystem> systems;
};

/// A RINEX epoch as a decoded stream epoch (systems in `systems`, all when
/// empty): per signal C/L/D/S, the LLI of the phase, and a lock time counted
/// from the start of the signal's arc (kept in `arc_start` across epochs).
StreamEpoch streamEpochFromRinex(const ObsEpoch& epoch,
                                 std::map<std::pair<SatelliteId, std::string>, GnssTime>& arc_start,
                                 const std::set<GnssSystem>& systems = {});

/// 1006 (ARP and antenna height) and, when the header names an antenna or a
/// receiver, 1033, framed. Throws std::invalid_argument without APPROX POSITION.
std::vector<std::vector<std::uint8_t>> stationFrames(const RinexObsHeader& header, int station_id);

class CasterStreamBuilder {
 public:
  explicit CasterStreamBuilder(CasterStreamOptions options = {});

  /// The station description (RINEX observation header) and its GLONASS channels.
  void setStation(const RinexObsHeader& header);
  /// One observation epoch (in time order).
  void addEpoch(const ObsEpoch& epoch);
  /// Broadcast records (sent by frames(), once the epochs' span is known).
  void addNavigation(const NavData& nav);
  /// The frames of an RTCM SSR stream (e.g. ppp_ssr_encode's), placed by their
  /// epochs, resolved next to `reference` (default: the first epoch). Frames that
  /// are not SSR, or whose time cannot be resolved, are counted and left out.
  void addSsrStream(const std::vector<std::uint8_t>& bytes, std::optional<GnssTime> reference = std::nullopt);

  /// The receiver's stream: station, MSM and records, in arrival order.
  std::vector<TimedFrame> observationFrames() const;
  /// The correction stream: the SSR frames, in arrival order.
  std::vector<TimedFrame> ssrFrames() const;
  /// Both merged in arrival order (one caster stream), with its figures.
  CasterStream build() const;

  std::size_t epochs() const { return epochs_; }
  std::optional<GnssTime> firstEpoch() const { return first_; }
  std::optional<GnssTime> lastEpoch() const { return last_; }
  /// Problems met (SSR frames left out, records that could not be encoded).
  const StreamCounters& counters() const { return counters_; }

 private:
  struct Record {
    GnssTime transmission;
    GnssTime reference;  // toe / tb
    std::string key;     // satellite + message type: a newer record supersedes
    int message_type = 0;
    int preamble_rank = 0;  // order ahead of the first epoch: Galileo, GLONASS, GPS/QZSS
    std::vector<std::uint8_t> frame;
  };
  std::vector<TimedFrame> navigationFrames() const;
  /// observationFrames() around the navigation frames given.
  std::vector<TimedFrame> observationFrames(const std::vector<TimedFrame>& navigation) const;

  CasterStreamOptions options_;
  std::optional<RinexObsHeader> station_;
  GlonassChannels channels_;
  std::map<std::pair<SatelliteId, std::string>, GnssTime> arc_start_;
  std::vector<TimedFrame> msm_, ssr_;
  std::vector<Record> records_;
  std::optional<GnssTime> first_, last_;
  std::size_t epochs_ = 0;
  StreamCounters counters_;
};

/// Writes the frames' bytes in order (throws FileOpenError when it cannot).
void writeFrames(const std::string& path, const std::vector<TimedFrame>& frames);

}  // namespace ppp
