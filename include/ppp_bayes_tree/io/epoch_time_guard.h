#pragma once
// EpochTimeGuard: decides, for a real-time stream of time-stamped epochs
// (observation epochs, correction batches), which stamps are believed. One bad
// stamp (GPS week 0 or 65535, a clock +1 h or +1 day off, an epoch re-sent
// minutes late) must not restart an estimator: only a SUSTAINED jump does.
//
//   step = t - (last accepted time)
//   0 < step <= max_forward_step_s          accepted (the normal case)
//   step == 0                               dropped: duplicate (one stamp, one fix)
//   -out_of_order_window_s <= step < 0      dropped: out of order (or passed on, see below)
//   otherwise (a jump)                      HELD: the epoch waits for confirmation
//
// Held epochs form a candidate time line: each next epoch that follows the last
// held one as the normal case above joins it. When `confirm_epochs` epochs are
// held the jump is confirmed: they are all released in time order, and a jump
// BACK (a rosbag loop) is reported as a reset (the caller restarts its
// estimator before processing them); a jump forward (a long outage) is not.
// When an epoch follows the accepted time line again before that, the held
// epochs were isolated bad stamps: dropped, each with its reason. Nothing held
// is lost silently: every epoch pushed comes out once, accepted or dropped.
// The payload is whatever the caller keeps per epoch (the ROS node: the message).
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

struct EpochTimeGuardOptions {
  double max_forward_step_s = 600.0;     // a larger step forward is a jump (held) [s]
  double out_of_order_window_s = 60.0;   // a step back up to this is out of order; more: a jump [s]
  std::size_t confirm_epochs = 3;        // consecutive epochs that confirm a jump (>= 1; 1: at once)
  /// false: duplicates and out-of-order stamps within the window are passed on
  /// as accepted (the caller orders them itself, e.g. a correction buffer) and
  /// do not move the accepted time line back.
  bool drop_out_of_order = true;
};

enum class TimeDropReason {
  Duplicate,          // the stamp of the last accepted epoch again
  OutOfOrder,         // older than the last accepted epoch, within the window
  UnconfirmedJump,    // a jump not followed by enough consistent epochs (an isolated bad stamp)
};
std::string text(TimeDropReason reason);

template <class Payload>
class EpochTimeGuard {
 public:
  struct Entry {
    GnssTime time;
    Payload payload;
  };
  struct Dropped {
    GnssTime time;
    TimeDropReason reason;
    double step_s;  // its time minus the last accepted time [s]
    Payload payload;
  };
  struct Outcome {
    std::vector<Entry> accepted;   // to be processed now, in time order
    std::vector<Dropped> dropped;  // each with the reason
    /// A sustained jump back was confirmed: the step [s] (< 0) from the old
    /// time line to the first accepted epoch; the caller resets before `accepted`.
    std::optional<double> reset_step_s;
    /// A sustained jump forward was confirmed (no reset): its step [s].
    std::optional<double> forward_jump_s;
  };

  explicit EpochTimeGuard(EpochTimeGuardOptions options = {}) : options_(options) {
    if (options_.confirm_epochs == 0) options_.confirm_epochs = 1;
  }

  Outcome push(const GnssTime& time, Payload payload) {
    Outcome out;
    if (!last_) {
      last_ = time;
      out.accepted.push_back(Entry{time, std::move(payload)});
      return out;
    }
    const double step = time - *last_;
    if (follows(step)) {
      dropHeld(out);  // the accepted time line goes on: whatever was held was isolated
      last_ = time;
      out.accepted.push_back(Entry{time, std::move(payload)});
      return out;
    }
    if (step <= 0.0 && step >= -options_.out_of_order_window_s) {
      if (!options_.drop_out_of_order) {
        out.accepted.push_back(Entry{time, std::move(payload)});
        return out;
      }
      out.dropped.push_back(
          Dropped{time, step == 0.0 ? TimeDropReason::Duplicate : TimeDropReason::OutOfOrder, step, std::move(payload)});
      return out;
    }
    // A jump: joins the held candidates when it follows them, else starts new ones.
    if (!held_.empty() && !follows(time - held_.back().time)) dropHeld(out);
    held_.push_back(Entry{time, std::move(payload)});
    if (held_.size() >= options_.confirm_epochs) confirm(out);
    return out;
  }

  /// Confirms the held epochs now (another stream's confirmed jump vouches for them,
  /// e.g. the observations of a rosbag loop for its correction batches).
  Outcome confirmHeld() {
    Outcome out;
    if (!held_.empty()) confirm(out);
    return out;
  }

  /// The newest accepted time (nullopt before the first epoch).
  const std::optional<GnssTime>& lastAccepted() const { return last_; }
  /// Epochs held as a candidate jump, and the time of the first (nullopt: none).
  std::size_t held() const { return held_.size(); }
  std::optional<GnssTime> firstHeld() const {
    return held_.empty() ? std::nullopt : std::optional<GnssTime>(held_.front().time);
  }
  const EpochTimeGuardOptions& options() const { return options_; }
  /// Forgets everything (held epochs are returned, for counting).
  std::vector<Entry> clear() {
    last_.reset();
    std::vector<Entry> held = std::move(held_);
    held_.clear();
    return held;
  }

 private:
  void confirm(Outcome& out) {
    const double jump = held_.front().time - *last_;
    if (jump < 0.0) out.reset_step_s = jump;
    else out.forward_jump_s = jump;
    last_ = held_.back().time;
    for (auto& e : held_) out.accepted.push_back(std::move(e));
    held_.clear();
  }
  bool follows(double step_s) const { return step_s > 0.0 && step_s <= options_.max_forward_step_s; }
  void dropHeld(Outcome& out) {
    for (auto& e : held_)
      out.dropped.push_back(Dropped{e.time, TimeDropReason::UnconfirmedJump, e.time - *last_, std::move(e.payload)});
    held_.clear();
  }

  EpochTimeGuardOptions options_;
  std::optional<GnssTime> last_;
  std::vector<Entry> held_;
};

}  // namespace ppp
