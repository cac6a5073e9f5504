#include "ppp_bayes_tree/io/transport/reconnecting_byte_source.h"

#include <algorithm>
#include <thread>

namespace ppp {
namespace {
using Clock = std::chrono::steady_clock;

void addCounters(ByteSourceCounters& total, const ByteSourceCounters& part) {
  total.bytes += part.bytes;
  total.connects += part.connects;
  total.stalls += part.stalls;
  total.gga_sent += part.gga_sent;
  for (const auto& [kind, count] : part.errors_by_kind) total.errors_by_kind[kind] += count;
}
}  // namespace

ReconnectingByteSource::ReconnectingByteSource(Factory factory, std::chrono::milliseconds backoff_min,
                                               std::chrono::milliseconds backoff_max)
    : factory_(std::move(factory)),
      backoff_min_(std::max(backoff_min, std::chrono::milliseconds(1))),
      backoff_max_(std::max(backoff_max, backoff_min_)),
      backoff_(backoff_min_) {
  if (auto probe = factory_()) description_ = probe->describe();
}

std::string ReconnectingByteSource::describe() const { return description_ + " (reconnecting)"; }

void ReconnectingByteSource::close() {
  absorbCounters();
  refreshCounters();
}

void ReconnectingByteSource::absorbCounters() {
  if (!source_) return;
  addCounters(closed_counters_, source_->counters());
  source_.reset();
}

void ReconnectingByteSource::refreshCounters() {
  ByteSourceCounters total = closed_counters_;
  if (source_) addCounters(total, source_->counters());
  counters_ = total;
}

ByteSourceRead ReconnectingByteSource::read(std::uint8_t* buffer, std::size_t capacity,
                                            std::chrono::milliseconds timeout) {
  const auto now = Clock::now();
  if (!source_) {
    if (now < next_attempt_) {
      std::this_thread::sleep_for(std::min<Clock::duration>(timeout, next_attempt_ - now));
      return ByteSourceRead::timeout();
    }
    source_ = factory_();
    had_data_ = false;
    if (opened_ > 0) ++closed_counters_.reconnects;
    ++opened_;
  }
  ByteSourceRead result = source_->read(buffer, capacity, timeout);
  if (result.status == ByteSourceStatus::Data || result.status == ByteSourceStatus::Timeout) {
    if (result.status == ByteSourceStatus::Data) {
      had_data_ = true;
      backoff_ = backoff_min_;
    }
    refreshCounters();
    return result;
  }
  // Closed or failed: drop it, wait the back-off, then make a new one.
  ByteSourceError error = result.error ? *result.error
                                       : ByteSourceError{ByteSourceErrorKind::ConnectionLost,
                                                         source_->describe() + ": the stream ended"};
  absorbCounters();
  if (!result.error) ++closed_counters_.errors_by_kind[error.kind];
  const bool permanent = isPermanentByteSourceError(error.kind);
  const auto wait = permanent ? backoff_max_ : backoff_;
  next_attempt_ = Clock::now() + wait;
  backoff_ = permanent ? backoff_max_ : std::min(backoff_ * 2, backoff_max_);
  error.detail += " (retry in " + std::to_string(wait.count() / 1000.0).substr(0, 6) + " s" +
                  (permanent ? ", a permanent error: check the spec/account" : "") + ")";
  closed_counters_.last_error = error;
  refreshCounters();
  return ByteSourceRead{ByteSourceStatus::Error, 0, error};
}

}  // namespace ppp
