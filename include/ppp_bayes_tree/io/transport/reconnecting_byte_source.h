#pragma once
// ReconnectingByteSource: keeps a live input going. It makes a source through
// a factory, reads through it, and when the source fails or closes, drops it and
// makes a new one after a back-off that doubles from min to max per failed
// attempt (reset by data). Permanent errors (authentication refused, unknown
// mountpoint, bad spec: io/transport/byte_source.h) are reported and retried only at
// the max back-off. Every error reaches the caller once as an Error result
// (then Timeout while waiting), so that a node can log and count it.
#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "ppp_bayes_tree/io/transport/byte_source.h"

namespace ppp {

class ReconnectingByteSource : public ByteSource {
 public:
  using Factory = std::function<std::unique_ptr<ByteSource>()>;

  ReconnectingByteSource(Factory factory, std::chrono::milliseconds backoff_min,
                         std::chrono::milliseconds backoff_max);

  ByteSourceRead read(std::uint8_t* buffer, std::size_t capacity,
                      std::chrono::milliseconds timeout) override;
  std::string describe() const override;
  void close() override;

  /// The wait before the next attempt after the latest failure.
  std::chrono::milliseconds currentBackoff() const { return backoff_; }
  /// A source is made and not dropped (after a Timeout from read(): connected).
  bool hasSource() const { return source_ != nullptr; }

 private:
  void absorbCounters();   // adds the current source's counters to closed_counters_, drops it
  void refreshCounters();  // counters_ = closed_counters_ + the current source's

  Factory factory_;
  std::chrono::milliseconds backoff_min_, backoff_max_, backoff_;
  std::unique_ptr<ByteSource> source_;
  std::string description_;
  bool had_data_ = false;
  std::uint64_t opened_ = 0;  // sources made
  std::chrono::steady_clock::time_point next_attempt_{};
  ByteSourceCounters closed_counters_;  // summed over dropped sources
};

}  // namespace ppp
