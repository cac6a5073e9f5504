#include "ppp_bayes_tree/io/rinex/stream_epoch_layout.h"

namespace ppp {
namespace {

std::optional<double> observable(const StreamSignal& s, ObservableType type) {
  switch (type) {
    case ObservableType::Pseudorange: return s.pseudorange_m;
    case ObservableType::CarrierPhase: return s.carrier_phase_cycles;
    case ObservableType::Doppler: return s.doppler_hz;
    case ObservableType::SignalStrength: return s.cnr_dbhz;
    default: return std::nullopt;
  }
}

}  // namespace

void StreamSignalInventory::add(const StreamEpoch& epoch) {
  for (const auto& sat : epoch.satellites) {
    auto& map = signals[static_cast<int>(sat.satellite.system)];
    for (const auto& s : sat.signals) {
      int& bits = map[{s.band, s.attribute}];
      if (s.pseudorange_m) bits |= 1;
      if (s.carrier_phase_cycles) bits |= 2;
      if (s.doppler_hz) bits |= 4;
      if (s.cnr_dbhz) bits |= 8;
    }
  }
}

void StreamSignalInventory::fillTypes(RinexObsHeader& header) const {
  static const ObservableType kOrder[] = {ObservableType::Pseudorange, ObservableType::CarrierPhase,
                                          ObservableType::Doppler, ObservableType::SignalStrength};
  for (int s = 0; s < kNumGnssSystems; ++s) {
    auto& types = header.obs_types[s];
    types.clear();
    for (const auto& [signal, bits] : signals[s]) {  // std::map: sorted by band, then attribute
      for (int k = 0; k < 4; ++k) {
        if (!(bits & (1 << k))) continue;
        ObservationCode code;
        code.type = kOrder[k];
        code.band = signal.first;
        code.attribute = signal.second;
        types.push_back(code);
      }
    }
    header.scale_factors[s].assign(types.size(), 1.0);
  }
}

void streamEpochToObsEpoch(const StreamEpoch& in, const RinexObsHeader& header, ObsEpoch& out) {
  out.clear();
  out.time = in.time;
  for (const auto& sat : in.satellites) {
    const auto& types = header.types(sat.satellite.system);
    if (types.empty()) continue;
    SatelliteObservations so;
    so.satellite = sat.satellite;
    so.first = static_cast<std::uint32_t>(out.observations.size());
    so.count = static_cast<std::uint32_t>(types.size());
    bool any = false;
    for (const auto& code : types) {
      Observation obs;
      obs.code = code;
      for (const auto& s : sat.signals) {
        if (s.band != code.band || s.attribute != code.attribute) continue;
        obs.value = observable(s, code.type);
        if (code.type == ObservableType::CarrierPhase && obs.value && s.lli != 0) obs.lli = s.lli;
        break;
      }
      any = any || obs.value.has_value();
      out.observations.push_back(obs);
    }
    if (!any) {
      out.observations.resize(so.first);
      continue;
    }
    out.satellites.push_back(so);
  }
}

}  // namespace ppp
