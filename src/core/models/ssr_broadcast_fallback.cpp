#include "ppp_bayes_tree/models/ssr_broadcast_fallback.h"

namespace ppp {

SsrBroadcastFallback::SsrBroadcastFallback(std::shared_ptr<const BroadcastSsrEphemeris> corrected,
                                           std::shared_ptr<const BroadcastEphemerisStore> broadcast,
                                           BroadcastFallbackOptions options)
    : corrected_(std::move(corrected)), broadcast_(std::move(broadcast)), options_(options) {
  const SsrCorrectionStore& store = corrected_->store();
  for (const auto& [sat, series] : store.orbits()) {
    if (series.empty()) continue;
    if (!first_correction_ || series.begin()->first < *first_correction_) first_correction_ = series.begin()->first;
    for (const auto& [t0, entry] : series) {
      const GnssTime end = t0 + SsrCorrectionStore::validity_s(store.limits().orbit_max_age_s, entry.update_interval_s);
      if (!last_in_force_ || *last_in_force_ < end) last_in_force_ = end;
    }
  }
}

bool SsrBroadcastFallback::correctionsInForce(const SatelliteId& sat, const GnssTime& t) const {
  const SsrCorrectionStore& store = corrected_->store();
  return store.orbit(sat, t) && store.clock(sat, t);
}

int SsrBroadcastFallback::satellitesInForce(const GnssTime& t) const {
  if (!first_correction_) return 0;  // a stream without orbit corrections
  if (t < *first_correction_ || *last_in_force_ < t) return 0;  // none yet, or every one has aged out
  int n = 0;
  for (const auto& entry : corrected_->store().orbits())
    if (correctionsInForce(entry.first, t) && ++n >= options_.min_ssr_satellites) break;
  return n;
}

bool SsrBroadcastFallback::preciseAt(const GnssTime& t) const {
  const double wait_s = corrected_->store().limits().orbit_max_age_s;
  if (first_correction_ && t < *first_correction_ && *first_correction_ - t <= wait_s) return true;  // starting: wait
  return chooseSsrOrBroadcast(satellitesInForce(t), options_) == SsrOrbitClockChoice::Ssr;
}

bool SsrBroadcastFallback::ssrInForce(const SatelliteId& sat, const GnssTime& t) const {
  return preciseAt(t) && correctionsInForce(sat, t);
}

EphemerisAnswer<EphemerisClock> SsrBroadcastFallback::satelliteClock(const SatelliteId& sat, const GnssTime& t) const {
  if (preciseAt(t)) return corrected_->satelliteClock(sat, t);
  auto a = broadcast_->satelliteClock(sat, t);
  widenForFallback(a, options_);
  return a;
}

EphemerisAnswer<EphemerisOrbit> SsrBroadcastFallback::satelliteOrbit(const SatelliteId& sat, const GnssTime& t) const {
  if (preciseAt(t)) return corrected_->satelliteOrbit(sat, t);
  auto a = broadcast_->satelliteOrbit(sat, t);
  widenForFallback(a, options_);
  return a;
}

std::string SsrBroadcastFallback::describeSource() const {
  return corrected_->describeSource() + ", broadcast records where the corrections are too old";
}

}  // namespace ppp
