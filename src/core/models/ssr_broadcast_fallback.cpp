#include "ppp_bayes_tree/models/ssr_broadcast_fallback.h"

#include <algorithm>

namespace ppp {

SsrBroadcastFallback::SsrBroadcastFallback(std::shared_ptr<const BroadcastSsrEphemeris> corrected,
                                           std::shared_ptr<const BroadcastEphemerisStore> broadcast,
                                           SsrFallbackOptions options)
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

bool SsrBroadcastFallback::preciseAt(const GnssTime& t) const {
  const SsrCorrectionStore& store = corrected_->store();
  if (!first_correction_) return false;  // a stream without orbit corrections
  if (t < *first_correction_) return *first_correction_ - t <= store.limits().orbit_max_age_s;  // starting: wait
  if (*last_in_force_ < t) return false;  // every correction has aged out
  int n = 0;
  for (const auto& entry : store.orbits())
    if (correctionsInForce(entry.first, t) && ++n >= options_.min_ssr_satellites) return true;
  return false;
}

bool SsrBroadcastFallback::ssrInForce(const SatelliteId& sat, const GnssTime& t) const {
  return preciseAt(t) && correctionsInForce(sat, t);
}

EphemerisAnswer<EphemerisClock> SsrBroadcastFallback::satelliteClock(const SatelliteId& sat, const GnssTime& t) const {
  if (preciseAt(t)) return corrected_->satelliteClock(sat, t);
  auto a = broadcast_->satelliteClock(sat, t);
  if (a.ok()) a.value->clock_sigma_m = std::max(a.value->clock_sigma_m.value_or(0.0), options_.broadcast_clock_sigma_m);
  return a;
}

EphemerisAnswer<EphemerisOrbit> SsrBroadcastFallback::satelliteOrbit(const SatelliteId& sat, const GnssTime& t) const {
  if (preciseAt(t)) return corrected_->satelliteOrbit(sat, t);
  auto a = broadcast_->satelliteOrbit(sat, t);
  if (a.ok())
    a.value->position_sigma_m = std::max(a.value->position_sigma_m.value_or(0.0), options_.broadcast_orbit_sigma_m);
  return a;
}

std::string SsrBroadcastFallback::describeSource() const {
  return corrected_->describeSource() + ", broadcast records where the corrections are too old";
}

}  // namespace ppp
