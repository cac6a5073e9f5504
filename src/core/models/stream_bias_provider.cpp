#include "ppp_bayes_tree/models/stream_bias_provider.h"

#include <cmath>

namespace ppp {

SatelliteBiasBatch sampleBiases(const BiasProvider& provider, const GnssTime& t, const RinexObsHeader& header,
                                const std::vector<SatelliteId>& satellites) {
  SatelliteBiasBatch batch;
  batch.time = t;
  batch.source = provider.describeSource();
  for (const SatelliteId& sat : satellites) {
    std::vector<ObservableBias> biases;
    for (const ObservationCode& code : header.types(sat.system)) {
      BiasAnswer a;
      if (code.type == ObservableType::Pseudorange) a = provider.codeBias(sat, code, t);
      else if (code.type == ObservableType::CarrierPhase) a = provider.phaseBias(sat, code, t);
      if (a.value_m) biases.push_back({code, *a.value_m});
    }
    if (!biases.empty()) batch.biases[sat] = std::move(biases);
  }
  return batch;
}

void StreamBiasProvider::add(const SatelliteBiasBatch& batch) {
  if (batch.biases.empty()) return;
  for (auto& [key, series] : series_) series.erase(batch.time);  // a repeated epoch replaces the held one
  for (const auto& [sat, biases] : batch.biases)
    for (const ObservableBias& b : biases) series_[{sat, b.code}][batch.time] = b.bias_m;
  batch_times_.insert(batch.time);
  if (*batch_times_.rbegin() == batch.time) source_ = batch.source;
  prune();
}

void StreamBiasProvider::prune() {
  if (!std::isfinite(history_s_)) return;  // an infinite history keeps every batch
  const GnssTime oldest_kept = *batch_times_.rbegin() - history_s_;
  while (!batch_times_.empty() && *batch_times_.begin() < oldest_kept) batch_times_.erase(batch_times_.begin());
  for (auto it = series_.begin(); it != series_.end();) {
    auto& series = it->second;
    series.erase(series.begin(), series.lower_bound(oldest_kept));
    it = series.empty() ? series_.erase(it) : std::next(it);
  }
}

void StreamBiasProvider::clear() {
  series_.clear();
  batch_times_.clear();
  source_.clear();
}

BiasAnswer StreamBiasProvider::lookup(const Key& key, const GnssTime& t) const {
  BiasAnswer a;
  a.valid_from = a.valid_until = t;
  const auto s = series_.find(key);
  if (s == series_.end()) return a;
  auto it = s->second.upper_bound(t);
  if (it == s->second.begin()) return a;
  a.value_m = std::prev(it)->second;
  return a;
}

BiasAnswer StreamBiasProvider::codeBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const {
  return lookup({sat, code}, t);
}

BiasAnswer StreamBiasProvider::phaseBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const {
  return lookup({sat, code}, t);
}

std::string StreamBiasProvider::describeSource() const {
  return "correction stream biases: " + (source_.empty() ? std::string("none yet") : source_);
}

}  // namespace ppp
