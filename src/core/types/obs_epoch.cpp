#include "ppp_bayes_tree/types/obs_epoch.h"

namespace ppp {

const Observation* ObsEpoch::find(const SatelliteId& satellite, const ObservationCode& code) const {
  const auto i = indexOf(satellite);
  if (!i) return nullptr;
  for (const Observation* o = begin(*i); o != end(*i); ++o) {
    if (o->code == code) return o;
  }
  return nullptr;
}

std::optional<std::size_t> ObsEpoch::indexOf(const SatelliteId& satellite) const {
  for (std::size_t i = 0; i < satellites.size(); ++i) {
    if (satellites[i].satellite == satellite) return i;
  }
  return std::nullopt;
}

}  // namespace ppp
