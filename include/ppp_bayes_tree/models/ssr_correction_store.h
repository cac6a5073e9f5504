#pragma once
// SsrCorrectionStore: the SSR corrections of a stream by satellite and epoch,
// and the choice of the correction to apply at an instant: the newest one
// whose epoch t0 is not after the instant (as a real-time user has it), if it
// is not older than its validity.
//
// Validity (age limit) of a correction of update interval U [s]:
//   max(max_age_s, 2 U)  -- the configured age limit, but never less than two
// update intervals (a correction sent every 10800 s stays current between two).
// Age limits after RTKLIB (MAXAGESSR 90 s, MAXAGESSR_HRCLK 10 s); config keys
// under `ssr:` (ppp_config): orbit_max_age_s, clock_max_age_s,
// high_rate_clock_max_age_s, bias_max_age_s.
//
// Code biases re-sent with the epoch of their issue. A service may send its
// code biases again and again with the epoch at which the set was issued,
// hours before: the Galileo HAS internet data distribution (RTCM 1059/1242,
// provider 270) repeats a set every 10 s with the epoch of the previous
// afternoon. Such a message arrives older than its validity. It is taken as in
// force from its arrival: the newest SSR epoch of the stream before it (stream
// order is arrival order, in files as live). The stream then says the set is
// still current each time it repeats it, and the age counts from the last
// repetition. Counted (staleCodeBiasMessages). Phase biases are not treated so:
// a phase bias older than its validity stays unused, as a fix must not rest on it.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"
#include "ppp_bayes_tree/types/ssr_corrections.h"

namespace ppp {

struct SsrAgeLimits {
  double orbit_max_age_s = 90.0;            // age of an orbit correction [s]
  double clock_max_age_s = 90.0;            // age of a clock correction [s]
  double high_rate_clock_max_age_s = 10.0;  // age of a high-rate clock [s]
  double bias_max_age_s = 3600.0;           // age of a code / phase bias [s] (biases change slowly)
};

/// A stored correction with what is needed to judge and place it.
template <class T>
struct SsrTimed {
  T value;
  GnssTime t0;                 // SSR epoch (GPST), as sent
  GnssTime in_force_from;      // t0, or the arrival of a code bias re-sent older than its validity
  double update_interval_s = 0.0;
  int iod_ssr = 0;
  int provider_id = 0, solution_id = 0;
  std::uint64_t byte_offset = 0, frame_index = 0;
};

/// A correction found for an instant, or why there is none.
template <class T>
struct SsrPick {
  const SsrTimed<T>* entry = nullptr;
  bool too_old = false;   // there is one, but older than its validity
  std::string reason;     // for people when entry is null
  explicit operator bool() const { return entry != nullptr; }
};

class SsrCorrectionStore {
 public:
  explicit SsrCorrectionStore(SsrAgeLimits limits = {}) : limits_(limits) {}

  /// Adds the values of one message, in stream order; false (nothing added)
  /// when its epoch is unresolved.
  bool add(const SsrMessage& message);

  SsrPick<SsrOrbitCorrection> orbit(const SatelliteId& sat, const GnssTime& t) const;
  SsrPick<SsrClockCorrection> clock(const SatelliteId& sat, const GnssTime& t) const;
  SsrPick<SsrHighRateClock> highRateClock(const SatelliteId& sat, const GnssTime& t) const;
  SsrPick<SsrCodeBias> codeBias(const SatelliteId& sat, const GnssTime& t) const;
  SsrPick<SsrPhaseBias> phaseBias(const SatelliteId& sat, const GnssTime& t) const;
  /// When the next code bias of the satellite comes in force after `from` (for validity intervals).
  std::optional<GnssTime> nextCodeBiasEpoch(const SatelliteId& sat, const GnssTime& from) const;
  std::optional<GnssTime> nextPhaseBiasEpoch(const SatelliteId& sat, const GnssTime& from) const;

  /// Every orbit correction (for consistency checks against the broadcast records).
  const std::map<SatelliteId, std::map<GnssTime, SsrTimed<SsrOrbitCorrection>>>& orbits() const { return orbits_; }
  /// Drops the corrections no query at or after `t` can pick: per satellite and
  /// kind, those older than the newest one with t0 <= t (bounded memory in live
  /// operation). Returns how many were dropped.
  std::size_t dropSupersededBefore(const GnssTime& t);
  /// The newest SSR epoch stored (nullopt when empty).
  std::optional<GnssTime> latestEpoch() const { return latest_; }
  /// The satellites with both orbit and clock corrections (the ones the stream corrects).
  std::set<SatelliteId> correctedSatellites() const;
  std::size_t orbitCount() const;
  std::size_t clockCount() const;
  std::size_t codeBiasCount() const;
  std::size_t phaseBiasCount() const;
  std::size_t unresolvedMessages() const { return unresolved_; }
  /// Code-bias messages that arrived older than their validity and were taken
  /// from their arrival (see the header), and the first of them, described.
  std::size_t staleCodeBiasMessages() const { return stale_code_bias_messages_; }
  const std::string& firstStaleCodeBiasMessage() const { return first_stale_code_bias_message_; }
  const SsrAgeLimits& limits() const { return limits_; }
  /// The validity of a correction of this update interval and age limit [s].
  static double validity_s(double max_age_s, double update_interval_s);

 private:
  template <class T>
  using Series = std::map<SatelliteId, std::map<GnssTime, SsrTimed<T>>>;
  /// When the code biases of `m` come in force: their epoch, or their arrival
  /// when they arrive older than their validity (counted).
  GnssTime codeBiasInForceFrom(const SsrMessage& m);
  template <class T>
  SsrPick<T> pick(const Series<T>& series, const SatelliteId& sat, const GnssTime& t, double max_age_s,
                  const char* what) const;

  SsrAgeLimits limits_;
  Series<SsrOrbitCorrection> orbits_;
  Series<SsrClockCorrection> clocks_;
  Series<SsrHighRateClock> high_rate_clocks_;
  Series<SsrCodeBias> code_biases_;
  Series<SsrPhaseBias> phase_biases_;
  std::size_t unresolved_ = 0;
  std::size_t stale_code_bias_messages_ = 0;
  std::string first_stale_code_bias_message_;
  std::optional<GnssTime> latest_;
};

}  // namespace ppp
