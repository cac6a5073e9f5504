#pragma once
// LiveGnssInput: the live input engine of the PPP nodes. Raw receiver and
// correction streams go in as byte chunks (StreamChunk: a serial read, an NTRIP
// read, an rtcm_msgs/Message, a ublox_msgs message re-framed as UBX); out come
// observation epochs ready for PppEpochProcessor, and ONE EphemerisSource
// (broadcast records corrected by SSR) that is updated as navigation records
// and SSR messages arrive.
//
// The nodes decode through this one class with the same code as ppp_solve
// --rtcm/--ubx --nav --ssr (models/broadcast_ssr_ephemeris.h,
// models/broadcast_fallback.h, io/epoch_time_screen.h), so that a node's
// solution equals ppp_solve's on the same recording. Bad bytes never throw:
// they are counted per stream (LiveStreamStatus::problems).
//
// Streams, record choice, epoch readiness (SSR, the correction wait, the
// broadcast fallback), time jumps and bad bytes: doc/live_input.md, "How the
// nodes decode live streams".
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/io/stream_problem.h"
#include "ppp_bayes_tree/io/transport/stream_chunk.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"
#include "ppp_bayes_tree/models/bias_provider.h"
#include "ppp_bayes_tree/models/broadcast_fallback.h"
#include "ppp_bayes_tree/models/broadcast_ssr_ephemeris.h"
#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/models/ssr_correction_store.h"
#include "ppp_bayes_tree/types/glonass_channels.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/obs_epoch.h"

namespace ppp {

struct LiveInputOptions {
  /// Approximate time of the data (within half a week) for MSM and SSR times
  /// without a week (as ppp_solve --ref-date). nullopt: from the streams
  /// (Galileo/BeiDou ephemerides, UBX week) or the first preloaded navigation file.
  /// Checked against the observation stream's ephemeris weeks: a contradiction
  /// is reported (LiveStreamStatus::reference_date_warning), where ppp_solve refuses.
  std::optional<GnssTime> reference_time;
  /// SSR evaluation: high-rate clocks (default on), unhealthy records (default off).
  /// Its `reference` is replaced by `ssr_reference` below.
  BroadcastSsrOptions ssr;
  /// The point the SSR orbits refer to. nullopt (default): from the name of the
  /// first stream that carries SSR ("SSRA..." antenna phase centre, "SSRC..."
  /// centre of mass), else centre of mass (as ppp_solve --ssr).
  std::optional<EphemerisReference> ssr_reference;
  /// Age limits of SSR corrections [s] (defaults: orbit 90, clock 90, high-rate 10, bias 3600).
  SsrAgeLimits ssr_age_limits;
  /// How long an observation epoch waits for the corrections covering it [s]
  /// (default 10 s: IGS SSR latency is 2-6 s).
  double correction_wait_s = 10.0;
  /// An RTCM observation stream's epochs wait for the station position
  /// (1005/1006 ARP: the run's approximate position, which ppp_solve's scan of a
  /// recording knows from the start) at most this long [s] (default 30 s;
  /// stations send it every 5-30 s). 0: no wait. UBX streams never wait.
  double station_wait_s = 30.0;
  /// Hold epochs for corrections even before any SSR message arrived (default
  /// true: a correction stream is configured). false: without SSR, epochs go
  /// out at once as BroadcastOnly.
  bool expect_corrections = true;
  /// The broadcast fallback, the rule of the offline run too (models/broadcast_fallback.h;
  /// config `ssr:`): with SSR orbit+clock in force for fewer than min_ssr_satellites
  /// of the epoch's satellites, the epoch goes out as BroadcastOnly with the sigmas
  /// widened; with the fallback off, as PreciseSsr (satellites without corrections
  /// are rejected).
  BroadcastFallbackOptions fallback;
  /// Observation stream stalled: no new epoch for this long on the arrival
  /// clock [s] -> Warn (default 2 s), Error (default 10 s).
  double stall_warn_s = 2.0;
  double stall_error_s = 10.0;
  /// An observation time this far [s] before the previous one is a jump back,
  /// a receiver restart once confirmed (default 60 s); smaller steps back are
  /// counted and dropped.
  double restart_jump_s = 60.0;
  /// At most this many epochs are held waiting (default 600); the oldest go
  /// out (as if their wait had passed) when more arrive.
  std::size_t max_held_epochs = 600;
  /// SSR corrections and broadcast records older than this before the newest
  /// released epoch are dropped (bounded memory) [s] (default 6 h).
  double keep_history_s = 6.0 * 3600.0;
  /// RINEX navigation files loaded before any stream (records serve from the start).
  std::vector<std::string> navigation_files;
  /// GLONASS channels known beforehand (used when the stream gives none).
  GlonassChannels glonass_channels;
};

enum class LiveProductMode { PreciseSsr, BroadcastOnly };
std::string_view liveProductModeName(LiveProductMode mode);  // "precise SSR", "broadcast only"

/// Observation stream health from arrival times (Ok without arrival times).
enum class StreamStall { Ok, Warn, Error };
std::string_view streamStallName(StreamStall stall);

struct LiveReadyEpoch {
  ObsEpoch epoch;  // laid out by header() as it is when takeReadyEpochs returns
  LiveProductMode mode = LiveProductMode::PreciseSsr;
  /// Arrival time of the chunk that completed the epoch (StreamChunk::arrival_time_s,
  /// same clock); nullopt without arrival times. The node's end-to-end latency is
  /// measured from it (time published minus this).
  std::optional<double> arrival_s;
};

struct LiveStreamStatus {
  std::string stream;
  StreamFormat format = StreamFormat::Rtcm3;
  std::uint64_t bytes = 0;
  std::map<int, std::uint64_t> frames_by_type;  // RTCM type / UBX class<<8|id
  StreamCounters problems;                      // framing + decoding (+ SSR) problems
  std::uint64_t observation_epochs = 0;         // decoded
  std::uint64_t ignored_epochs = 0;             // from a stream that is not the observation stream
  std::uint64_t time_backwards = 0;             // observation epochs not after the previous one (dropped)
  std::uint64_t restarts = 0;                   // confirmed observation time jumps back > restart_jump_s
  std::uint64_t time_outliers = 0;              // isolated time jumps not confirmed (dropped)
  std::uint64_t forward_jumps = 0;              // confirmed jumps forward (an outage beyond 600 s)
  std::size_t ephemerides = 0;                  // navigation records decoded
  std::uint64_t ssr_messages = 0;
  /// Code-bias messages sent with an epoch older than their validity, taken as
  /// re-sent and in force from their arrival (models/ssr_correction_store.h).
  std::uint64_t ssr_code_biases_resent = 0;
  std::optional<GnssTime> last_data_time;       // newest observation or SSR epoch decoded
  /// Newest observation time minus this stream's newest SSR epoch [s] (SSR streams).
  std::optional<double> ssr_age_s;
  std::optional<double> last_arrival_s;
  /// Arrival minus the data's own time (GPST converted to UTC, unix seconds) of
  /// the last chunk that completed an epoch or SSR message [s].
  std::optional<double> latency_s;
  StreamStall stall = StreamStall::Ok;          // observation stream only
  /// Non-empty when LiveInputOptions::reference_time is contradicted by the
  /// stream's own ephemeris weeks (io/rtcm/rtcm_observation_source.h,
  /// referenceDateContradiction: the date, the epochs' times, the evidence);
  /// also given once by takeTimeEvents().
  std::string reference_date_warning;
};

class LiveGnssInput {
 public:
  /// Throws FileOpenError / ParseError when a navigation file cannot be read.
  explicit LiveGnssInput(LiveInputOptions options = {});
  ~LiveGnssInput();
  LiveGnssInput(const LiveGnssInput&) = delete;
  LiveGnssInput& operator=(const LiveGnssInput&) = delete;

  /// Feeds bytes of one stream; never throws on bad bytes: counted per stream.
  void feed(const StreamChunk& chunk);
  /// The epochs ready now, in time order. `now_s`: the arrival clock (same
  /// clock as StreamChunk::arrival_time_s) for the wait limit and the stall state.
  std::vector<LiveReadyEpoch> takeReadyEpochs(std::optional<double> now_s = std::nullopt);
  /// End of data: every held epoch, with its mode as the corrections known allow.
  std::vector<LiveReadyEpoch> finish();

  /// Stable for the object's life; updated as records and corrections arrive.
  const EphemerisSource& ephemeris() const;
  /// SSR code/phase biases, nullptr while no SSR bias has arrived (then stable).
  const BiasProvider* biases() const;
  /// True once the streams carried SSR phase biases (then biases() serves them:
  /// the product assembly decides whether they are used for PPP-AR).
  bool hasPhaseBiases() const;
  /// Types seen so far, station/antenna (1005/1006/1033), GLONASS channels.
  const RinexObsHeader& header() const;
  /// True once after the observation types (or the station) changed.
  bool takeHeaderChanged();
  std::vector<LiveStreamStatus> streams() const;
  /// What the epoch-time policy did since the last call, one sentence each (an
  /// epoch dropped, with its stream, byte offset, time and reason; a confirmed
  /// receiver restart), for the log; at most 100 are kept between calls.
  std::vector<std::string> takeTimeEvents();
  /// The mode of the last released epoch (PreciseSsr before any).
  LiveProductMode mode() const;

  /// Epochs released per mode, satellites of released epochs without any
  /// ephemeris at their epoch (counted), epochs dropped (time backwards, restart).
  std::uint64_t releasedEpochs(LiveProductMode mode) const;
  std::uint64_t satellitesWithoutEphemeris() const;
  /// Navigation records and SSR corrections held (bounded by keep_history_s).
  std::size_t navigationRecords() const;
  const SsrCorrectionStore& corrections() const;

  /// Queries for epoch T are at emission times > T - kMaxSignalTravel_s.
  static constexpr double kMaxSignalTravel_s = 0.11;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ppp
