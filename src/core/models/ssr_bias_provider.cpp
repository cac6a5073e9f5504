#include "ppp_bayes_tree/models/ssr_bias_provider.h"

#include <algorithm>

namespace ppp {

namespace {
template <class Pick, class NextEpoch>
BiasAnswer answer(const Pick& pick, const ObservationCode& code, const GnssTime& t, double max_age_s,
                  const NextEpoch& next) {
  BiasAnswer out;
  if (!pick) {
    out.valid_from = out.valid_until = t;
    return out;
  }
  for (const auto& b : pick.entry->value.biases) {
    if (!b.code || b.code->band != code.band || b.code->attribute != code.attribute) continue;
    out.value_m = -b.bias_m;  // SSR: added to the measurement; OSB: subtracted
    out.valid_from = pick.entry->t0;
    GnssTime until = pick.entry->t0 + SsrCorrectionStore::validity_s(max_age_s, pick.entry->update_interval_s);
    if (const auto n = next(pick.entry->t0)) until = std::min(until, *n - 1e-3);
    out.valid_until = until;
    return out;
  }
  out.valid_from = out.valid_until = t;
  return out;
}

/// "No say" at `t` (the broadcast fallback is in force there).
BiasAnswer notInForce(const GnssTime& t) {
  BiasAnswer out;
  out.applies = false;
  out.valid_from = out.valid_until = t;
  return out;
}
}  // namespace

BiasAnswer SsrBiasProvider::bounded(BiasAnswer a, const GnssTime& t) const {
  // With a fallback the mode may change at any epoch: the answer holds for `t` only.
  if (in_force_) a.valid_from = a.valid_until = t;
  return a;
}

BiasAnswer SsrBiasProvider::codeBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const {
  if (in_force_ && !in_force_(sat, t)) return notInForce(t);
  return bounded(answer(ssr_->codeBias(sat, t), code, t, ssr_->limits().bias_max_age_s,
                [&](const GnssTime& t0) { return ssr_->nextCodeBiasEpoch(sat, t0); }), t);
}

BiasAnswer SsrBiasProvider::phaseBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const {
  if (in_force_ && !in_force_(sat, t)) return notInForce(t);
  return bounded(answer(ssr_->phaseBias(sat, t), code, t, ssr_->limits().bias_max_age_s,
                [&](const GnssTime& t0) { return ssr_->nextPhaseBiasEpoch(sat, t0); }), t);
}

}  // namespace ppp
