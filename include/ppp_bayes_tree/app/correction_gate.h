#pragma once
// CorrectionGate: real-time observation epochs wait for the corrections that
// cover them. An epoch leaves the gate (in arrival order) when the correction
// buffer covers its time (a batch after it is held: CorrectionBuffer::covers),
// or when waiting is over: it arrived more than `wait_s` ago (wall or replay
// clock), the newest epoch received is more than `wait_s` after it, or more
// than `max_pending` epochs wait. An epoch released uncovered is processed
// anyway: its satellites without corrections are rejected with the reason.
// The payload is whatever the caller keeps per epoch (the ROS node: the message).
#include <cstddef>
#include <deque>
#include <optional>

#include "ppp_bayes_tree/models/correction_buffer.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

struct CorrectionGateOptions {
  double wait_s = 2.0;            // longest wait for covering corrections [s]
  std::size_t max_pending = 100;  // more waiting epochs release the oldest
};

template <class Payload>
class CorrectionGate {
 public:
  struct Entry {
    GnssTime time;     // epoch time (GPST)
    double arrival_s;  // caller's clock at arrival [s]
    Payload payload;
  };

  explicit CorrectionGate(CorrectionGateOptions options = {}) : options_(options) {}

  void push(const GnssTime& time, double arrival_s, Payload payload) {
    pending_.push_back(Entry{time, arrival_s, std::move(payload)});
  }
  /// The oldest epoch when it may be processed at `now_s`, else nullopt (it waits).
  /// `newest_received`: the newest epoch time received (nullopt: none).
  std::optional<Entry> pop(double now_s, const CorrectionBuffer& corrections,
                           const std::optional<GnssTime>& newest_received) {
    if (pending_.empty()) return std::nullopt;
    const Entry& e = pending_.front();
    const bool covered = corrections.covers(e.time);
    const bool waited = now_s - e.arrival_s > options_.wait_s ||
                        (newest_received && *newest_received - e.time > options_.wait_s) ||
                        pending_.size() > options_.max_pending;
    if (!covered && !waited) return std::nullopt;
    Entry out = std::move(pending_.front());
    pending_.pop_front();
    return out;
  }
  std::size_t size() const { return pending_.size(); }
  bool empty() const { return pending_.empty(); }
  void clear() { pending_.clear(); }
  const CorrectionGateOptions& options() const { return options_; }

 private:
  CorrectionGateOptions options_;
  std::deque<Entry> pending_;
};

}  // namespace ppp
