#include "ppp_bayes_tree/models/ssr_correction_store.h"

#include <algorithm>
#include <iterator>

#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {

namespace {
template <class T>
SsrTimed<T> timed(const T& value, const SsrHeader& h, const GnssTime& in_force_from) {
  SsrTimed<T> e{value,         *h.epoch,      in_force_from, h.update_interval_s, h.iod_ssr,
                h.provider_id, h.solution_id, h.byte_offset, h.frame_index};
  return e;
}
template <class T>
SsrTimed<T> timed(const T& value, const SsrHeader& h) {
  return timed(value, h, *h.epoch);
}
template <class Map>
std::size_t countAll(const Map& m) {
  std::size_t n = 0;
  for (const auto& [sat, series] : m) n += series.size();
  return n;
}
template <class Map>
std::optional<GnssTime> nextEpoch(const Map& m, const SatelliteId& sat, const GnssTime& t0) {
  const auto it = m.find(sat);
  if (it == m.end()) return std::nullopt;
  const auto next = it->second.upper_bound(t0);
  if (next == it->second.end()) return std::nullopt;
  return next->first;
}
}  // namespace

double SsrCorrectionStore::validity_s(double max_age_s, double update_interval_s) {
  return std::max(max_age_s, 2.0 * update_interval_s);
}

bool SsrCorrectionStore::add(const SsrMessage& m) {
  if (!m.header.epoch) {
    ++unresolved_;
    return false;
  }
  const SsrHeader& h = m.header;
  const GnssTime code_bias_from = codeBiasInForceFrom(m);
  if (!latest_ || *latest_ < *h.epoch) latest_ = *h.epoch;
  for (const auto& o : m.orbits) orbits_[o.satellite][*h.epoch] = timed(o, h);
  for (const auto& c : m.clocks) clocks_[c.satellite][*h.epoch] = timed(c, h);
  for (const auto& c : m.high_rate_clocks) high_rate_clocks_[c.satellite][*h.epoch] = timed(c, h);
  for (const auto& b : m.code_biases) code_biases_[b.satellite][code_bias_from] = timed(b, h, code_bias_from);
  for (const auto& b : m.phase_biases) phase_biases_[b.satellite][*h.epoch] = timed(b, h);
  return true;
}

GnssTime SsrCorrectionStore::codeBiasInForceFrom(const SsrMessage& m) {
  const SsrHeader& h = m.header;
  if (m.code_biases.empty() || !latest_) return *h.epoch;
  const double age_on_arrival_s = *latest_ - *h.epoch;
  if (age_on_arrival_s <= validity_s(limits_.bias_max_age_s, h.update_interval_s)) return *h.epoch;
  if (stale_code_bias_messages_++ == 0)
    first_stale_code_bias_message_ =
        format("code biases of %s (provider %d) with epoch %s arrived at %s, %.0f s later: in force from their arrival",
               std::string(systemName(h.system)).c_str(), h.provider_id, h.epoch->toString(TimeSystem::GPS, 0).c_str(),
               latest_->toString(TimeSystem::GPS, 0).c_str(), age_on_arrival_s);
  return *latest_;
}

template <class T>
SsrPick<T> SsrCorrectionStore::pick(const Series<T>& series, const SatelliteId& sat, const GnssTime& t,
                                    double max_age_s, const char* what) const {
  SsrPick<T> out;
  const auto it = series.find(sat);
  if (it == series.end() || it->second.empty()) {
    out.reason = std::string("no SSR ") + what + " for " + sat.toString();
    return out;
  }
  auto after = it->second.upper_bound(t);  // first epoch > t
  if (after == it->second.begin()) {
    out.reason = std::string("no SSR ") + what + " for " + sat.toString() + " at or before " + t.toString(TimeSystem::GPS, 1);
    return out;
  }
  const SsrTimed<T>& e = std::prev(after)->second;
  const double age = t - e.in_force_from;
  const double validity = validity_s(max_age_s, e.update_interval_s);
  if (age > validity) {
    out.reason = format("SSR %s for %s is %.0f s old, older than its validity %.0f s", what, sat.toString().c_str(),
                        age, validity);
    out.too_old = true;
    return out;
  }
  out.entry = &e;
  return out;
}

SsrPick<SsrOrbitCorrection> SsrCorrectionStore::orbit(const SatelliteId& sat, const GnssTime& t) const {
  return pick(orbits_, sat, t, limits_.orbit_max_age_s, "orbit correction");
}
SsrPick<SsrClockCorrection> SsrCorrectionStore::clock(const SatelliteId& sat, const GnssTime& t) const {
  return pick(clocks_, sat, t, limits_.clock_max_age_s, "clock correction");
}
SsrPick<SsrHighRateClock> SsrCorrectionStore::highRateClock(const SatelliteId& sat, const GnssTime& t) const {
  return pick(high_rate_clocks_, sat, t, limits_.high_rate_clock_max_age_s, "high-rate clock");
}
SsrPick<SsrCodeBias> SsrCorrectionStore::codeBias(const SatelliteId& sat, const GnssTime& t) const {
  return pick(code_biases_, sat, t, limits_.bias_max_age_s, "code bias");
}
SsrPick<SsrPhaseBias> SsrCorrectionStore::phaseBias(const SatelliteId& sat, const GnssTime& t) const {
  return pick(phase_biases_, sat, t, limits_.bias_max_age_s, "phase bias");
}
std::optional<GnssTime> SsrCorrectionStore::nextCodeBiasEpoch(const SatelliteId& sat, const GnssTime& from) const {
  return nextEpoch(code_biases_, sat, from);
}
std::optional<GnssTime> SsrCorrectionStore::nextPhaseBiasEpoch(const SatelliteId& sat, const GnssTime& from) const {
  return nextEpoch(phase_biases_, sat, from);
}
namespace {
template <class Series>
std::size_t dropSuperseded(Series& series, const GnssTime& t) {
  std::size_t n = 0;
  for (auto& [sat, by_time] : series) {
    auto keep = by_time.upper_bound(t);  // first entry after t
    if (keep == by_time.begin()) continue;
    --keep;  // the newest entry with t0 <= t: kept
    n += static_cast<std::size_t>(std::distance(by_time.begin(), keep));
    by_time.erase(by_time.begin(), keep);
  }
  return n;
}
}  // namespace

std::size_t SsrCorrectionStore::dropSupersededBefore(const GnssTime& t) {
  return dropSuperseded(orbits_, t) + dropSuperseded(clocks_, t) + dropSuperseded(high_rate_clocks_, t) +
         dropSuperseded(code_biases_, t) + dropSuperseded(phase_biases_, t);
}

std::set<SatelliteId> SsrCorrectionStore::correctedSatellites() const {
  std::set<SatelliteId> out;
  for (const auto& [sat, series] : orbits_) {
    const auto clock = clocks_.find(sat);
    if (!series.empty() && clock != clocks_.end() && !clock->second.empty()) out.insert(sat);
  }
  return out;
}

std::size_t SsrCorrectionStore::orbitCount() const { return countAll(orbits_); }
std::size_t SsrCorrectionStore::clockCount() const { return countAll(clocks_); }
std::size_t SsrCorrectionStore::codeBiasCount() const { return countAll(code_biases_); }
std::size_t SsrCorrectionStore::phaseBiasCount() const { return countAll(phase_biases_); }

}  // namespace ppp
