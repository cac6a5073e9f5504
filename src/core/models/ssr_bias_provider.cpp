#include "ppp_bayes_tree/models/ssr_bias_provider.h"

#include <algorithm>

namespace ppp {

namespace {
/// GPS P(Y) code tracked as P, Z-tracking (W) or Y: one signal at the satellite.
bool gpsPyCode(char attribute) { return attribute == 'P' || attribute == 'W' || attribute == 'Y'; }

/// The bias of the stream's signal for `code`: its own, else, for a GPS P(Y)
/// code with `py_family`, the one the stream sends for another tracking of the
/// P(Y) code on that band (the Galileo HAS stream sends "L2 P" where receivers
/// track C2W; the satellite delays the P(Y) code the same however it is tracked).
template <class Signal>
const Signal* signalFor(const std::vector<Signal>& biases, const ObservationCode& code, bool py_family) {
  for (const auto& b : biases)
    if (b.code && b.code->band == code.band && b.code->attribute == code.attribute) return &b;
  if (!py_family || !gpsPyCode(code.attribute)) return nullptr;
  for (const auto& b : biases)
    if (b.code && b.code->band == code.band && gpsPyCode(b.code->attribute)) return &b;
  return nullptr;
}

template <class Pick, class NextEpoch>
BiasAnswer answer(const Pick& pick, const ObservationCode& code, const GnssTime& t, double max_age_s,
                  const NextEpoch& next, bool py_family) {
  BiasAnswer out;
  if (!pick) {
    out.valid_from = out.valid_until = t;
    return out;
  }
  if (const auto* b = signalFor(pick.entry->value.biases, code, py_family)) {
    out.value_m = -b->bias_m;  // SSR: added to the measurement; OSB: subtracted
    out.valid_from = pick.entry->in_force_from;
    GnssTime until =
        pick.entry->in_force_from + SsrCorrectionStore::validity_s(max_age_s, pick.entry->update_interval_s);
    if (const auto n = next(pick.entry->in_force_from)) until = std::min(until, *n - 1e-3);
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
                        [&](const GnssTime& from) { return ssr_->nextCodeBiasEpoch(sat, from); },
                        sat.system == GnssSystem::GPS),
                 t);
}

BiasAnswer SsrBiasProvider::phaseBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const {
  if (in_force_ && !in_force_(sat, t)) return notInForce(t);
  return bounded(answer(ssr_->phaseBias(sat, t), code, t, ssr_->limits().bias_max_age_s,
                        [&](const GnssTime& from) { return ssr_->nextPhaseBiasEpoch(sat, from); }, false),
                 t);
}

}  // namespace ppp
