#include "ppp_bayes_tree/models/sinex_bias_provider.h"

namespace ppp {

BiasAnswer SinexBiasProvider::osb(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const {
  BiasAnswer out;
  const auto v = file_.osb(sat, code, t);
  const BiasRecord* used = nullptr;
  if (v && v->unit == BiasValueUnit::Metres) {
    out.value_m = v->value;
    for (const auto& r : file_.records) {
      if (r.line == v->line) {
        used = &r;
        break;
      }
    }
  }
  if (used == nullptr) {  // absent: holds for this instant only
    out.valid_from = t;
    out.valid_until = t;
    return out;
  }
  // The interval over which the same row stays the answer: its own validity,
  // cut where another row of the same satellite and code starts.
  out.valid_from = used->start;
  out.valid_until = used->end;
  for (const auto& r : file_.records) {
    if (&r == used || r.type != BiasType::OSB || !r.satellite || *r.satellite != sat || r.obs1 != code) continue;
    if (r.start && t < *r.start && (!out.valid_until || *r.start < *out.valid_until))
      out.valid_until = *r.start - 1e-6;
  }
  return out;
}

BiasAnswer SinexBiasProvider::codeBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const {
  return osb(sat, code, t);
}

BiasAnswer SinexBiasProvider::phaseBias(const SatelliteId& sat, const ObservationCode& code,
                                        const GnssTime& t) const {
  return osb(sat, code, t);  // phase OSB rows carry the phase observation code (L1C, ...)
}

}  // namespace ppp
