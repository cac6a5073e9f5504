#pragma once
// EpochTimeScreen: the one epoch-time policy of the receiver streams (RTCM 3
// MSM, u-blox RXM-RAWX), applied by the offline readers (ppp_solve --rtcm /
// --ubx) and the live input of the nodes alike, so that a recording gives the
// same epochs offline and live. It is EpochTimeGuard (io/epoch_time_guard.h)
// applied to decoded epoch times: duplicates and small steps back are dropped;
// any other jump is held until confirm_epochs epochs confirm it (a restart or an
// outage), else the held epochs are dropped as isolated outliers. Every dropped
// epoch is counted by reason and reported with its byte offset, frame index and
// time. The rules: doc/live_input.md, "The epoch-time policy".
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ppp_bayes_tree/io/stream_problem.h"
#include "ppp_bayes_tree/io/epoch_time_guard.h"
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
    if (!started_) return start(time, Item{origin, std::move(payload)});
    return take(guard_.push(time, Item{origin, std::move(payload)}));
  }
  /// End of the stream: a stream shorter than the start-up gives its longest
  /// time line; what is still held is dropped (unconfirmed); the screen starts afresh.
  Result finish() {
    Result r;
    if (!started_ && !lines_.empty()) {
      std::size_t longest = 0;
      for (std::size_t k = 1; k < lines_.size(); ++k)
        if (lines_[k].size() > lines_[longest].size()) longest = k;
      r = settle(longest);
    }
    const std::optional<GnssTime> last = guard_.lastAccepted();
    for (auto& e : guard_.clear())
      drop(TimeDropReason::UnconfirmedJump, e.time, last ? e.time - *last : 0.0, e.payload.origin);
    started_ = false;
    return r;
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

  struct Pending {
    GnssTime time;
    Item item;
  };
  static constexpr std::size_t kMaxStartLines = 8;

  /// Start-up: the first epoch is not believed alone. Epochs gather in
  /// candidate time lines (each epoch joins the line it follows); the first line
  /// of confirm_epochs epochs is the stream's time line, the others' epochs are
  /// dropped as unconfirmed. So a bad first epoch costs that epoch only too.
  Result start(const GnssTime& t, Item item) {
    const EpochTimeGuardOptions& o = guard_.options();
    for (std::size_t k = 0; k < lines_.size(); ++k) {
      const double step = t - lines_[k].back().time;
      if (step == 0.0) {
        drop(TimeDropReason::Duplicate, t, step, item.origin);
        return {};
      }
      if (step > 0.0 && step <= o.max_forward_step_s) {
        lines_[k].push_back(Pending{t, std::move(item)});
        return lines_[k].size() >= o.confirm_epochs ? settle(k) : Result{};
      }
    }
    if (!lines_.empty()) {
      const double step = t - lines_.back().back().time;
      if (o.drop_out_of_order && step < 0.0 && step >= -o.out_of_order_window_s) {
        drop(TimeDropReason::OutOfOrder, t, step, item.origin);
        return {};
      }
    }
    if (lines_.size() >= kMaxStartLines) {
      for (auto& e : lines_.front())
        drop(TimeDropReason::UnconfirmedJump, e.time, e.time - t, e.item.origin);
      lines_.erase(lines_.begin());
    }
    lines_.push_back({Pending{t, std::move(item)}});
    return lines_.back().size() >= o.confirm_epochs ? settle(lines_.size() - 1) : Result{};
  }
  /// Line `chosen` becomes the time line: its epochs are accepted, the others dropped.
  Result settle(std::size_t chosen) {
    started_ = true;
    std::vector<Pending> line = std::move(lines_[chosen]);
    for (std::size_t k = 0; k < lines_.size(); ++k)
      if (k != chosen)
        for (auto& e : lines_[k])
          drop(TimeDropReason::UnconfirmedJump, e.time, e.time - line.front().time, e.item.origin);
    lines_.clear();
    Result r;
    for (auto& e : line)
      for (auto& a : take(guard_.push(e.time, std::move(e.item))).accepted) r.accepted.push_back(std::move(a));
    return r;
  }

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
  bool started_ = false;                   // a time line is established
  std::vector<std::vector<Pending>> lines_;  // candidate time lines at start-up
  StreamCounters counters_;
  std::map<TimeDropReason, std::uint64_t> dropped_;
  std::uint64_t resets_ = 0, forward_jumps_ = 0;
};

}  // namespace ppp
