#pragma once
// EpochTimeScreen: the one epoch-time policy of the receiver streams (RTCM 3
// MSM, u-blox RXM-RAWX). The offline readers (ppp_solve --rtcm / --ubx:
// RtcmObservationSource, UbxObservationSource) and the live input of the nodes
// (app/live_gnss_input.h) screen their decoded epochs through it, so that a
// recording gives the same epochs offline and live.
//
// It is EpochTimeGuard (ppp/epoch_time_guard.h, the rule the nodes apply to
// message stamps) applied to decoded epoch times, with the options of
// streamEpochTimeOptions():
//  - an epoch after the last accepted one by at most max_forward_step_s: accepted;
//  - the same time again: dropped (Duplicate); a step back within
//    out_of_order_window_s: dropped (OutOfOrder);
//  - any other step (a time of week days ahead, a week one too high, a jump
//    back): HELD as a candidate time line. confirm_epochs consecutive epochs on
//    it confirm it: a jump back is then a receiver restart (or a looping
//    recording), reported as a reset; a jump forward is an outage. When an epoch
//    follows the accepted time line first, the held epochs were isolated
//    outliers, each dropped (UnconfirmedJump). One bad epoch therefore costs
//    that epoch only, never the rest of the stream.
//  - finish(): epochs still held at the end of the stream are dropped as unconfirmed.
// Every dropped epoch is counted by reason and reported as a StreamProblem of
// kind EpochTimeRefused that names its byte offset, frame index, its time and
// the accepted time it departs from (counters()).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ppp_bayes_tree/io/stream_problem.h"
#include "ppp_bayes_tree/ppp/epoch_time_guard.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

/// The options both stream paths use: a forward step up to 600 s is normal, a
/// step back up to 60 s is out of order (LiveInputOptions::restart_jump_s), a
/// jump is believed after 3 consecutive epochs on its time line.
EpochTimeGuardOptions streamEpochTimeOptions();

/// Where an epoch came from in its stream (for the problem text).
struct EpochOrigin {
  std::uint64_t byte_offset = 0;
  std::uint64_t frame_index = 0;
  int message_type = 0;  // RTCM type of the epoch's first message, UBX class<<8|id
};

/// The problem reported for a dropped epoch: "epoch T is S s after the accepted
/// epoch U: <reason>: dropped".
StreamProblem epochTimeProblem(TimeDropReason reason, const GnssTime& time, double step_s, const EpochOrigin& origin);

template <class Payload>
class EpochTimeScreen {
 public:
  struct Released {
    GnssTime time;
    Payload payload;
  };
  struct Result {
    std::vector<Released> accepted;      // in time order
    std::optional<double> reset_step_s;  // a confirmed jump back [s]: restart before `accepted`
    std::optional<double> forward_jump_s;  // a confirmed jump forward [s]
  };

  explicit EpochTimeScreen(EpochTimeGuardOptions options = streamEpochTimeOptions()) : guard_(options) {}

  Result push(const GnssTime& time, const EpochOrigin& origin, Payload payload) {
    return take(guard_.push(time, Item{origin, std::move(payload)}));
  }
  /// End of the stream: what is still held is dropped (unconfirmed); the screen starts afresh.
  void finish() {
    const std::optional<GnssTime> last = guard_.lastAccepted();
    for (auto& e : guard_.clear())
      drop(TimeDropReason::UnconfirmedJump, e.time, last ? e.time - *last : 0.0, e.payload.origin);
  }

  /// EpochTimeRefused problems, one per dropped epoch (with byte offsets).
  const StreamCounters& counters() const { return counters_; }
  std::uint64_t dropped(TimeDropReason reason) const {
    const auto it = dropped_.find(reason);
    return it == dropped_.end() ? 0 : it->second;
  }
  std::uint64_t resets() const { return resets_; }
  std::uint64_t forwardJumps() const { return forward_jumps_; }
  std::size_t held() const { return guard_.held(); }
  const EpochTimeGuardOptions& options() const { return guard_.options(); }

 private:
  struct Item {
    EpochOrigin origin;
    Payload payload{};
  };
  using Guard = EpochTimeGuard<Item>;

  Result take(typename Guard::Outcome&& out) {
    Result r;
    for (auto& d : out.dropped) drop(d.reason, d.time, d.step_s, d.payload.origin);
    if (out.reset_step_s) ++resets_;
    if (out.forward_jump_s) ++forward_jumps_;
    r.reset_step_s = out.reset_step_s;
    r.forward_jump_s = out.forward_jump_s;
    for (auto& e : out.accepted) r.accepted.push_back(Released{e.time, std::move(e.payload.payload)});
    return r;
  }
  void drop(TimeDropReason reason, const GnssTime& time, double step_s, const EpochOrigin& origin) {
    ++dropped_[reason];
    counters_.add(epochTimeProblem(reason, time, step_s, origin));
  }

  Guard guard_;
  StreamCounters counters_;
  std::map<TimeDropReason, std::uint64_t> dropped_;
  std::uint64_t resets_ = 0, forward_jumps_ = 0;
};

}  // namespace ppp
