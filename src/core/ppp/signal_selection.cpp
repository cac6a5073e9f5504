#include "ppp_bayes_tree/ppp/signal_selection.h"

#include <algorithm>
#include <cmath>

#include "ppp_bayes_tree/types/carrier_frequency.h"

namespace ppp {
namespace {

const SystemSignalPriority* priorityOf(const SignalSelectionOptions& o, GnssSystem system) {
  if (system == GnssSystem::GPS) return &o.gps;
  if (system == GnssSystem::Galileo) return &o.galileo;
  return nullptr;
}

std::vector<int> columns(const std::vector<ObservationCode>& types, ObservableType type, char band,
                         const std::vector<char>& attributes) {
  std::vector<int> out;
  for (char a : attributes) {
    for (std::size_t k = 0; k < types.size(); ++k) {
      if (types[k].type == type && types[k].band == band && types[k].attribute == a) out.push_back(static_cast<int>(k));
    }
  }
  return out;
}

/// First column of the priority list holding a value in this satellite's slice.
const Observation* firstPresent(const Observation* obs, std::uint32_t count, const std::vector<int>& cols) {
  for (int c : cols) {
    if (static_cast<std::uint32_t>(c) < count && obs[c].value && std::isfinite(*obs[c].value)) return &obs[c];
  }
  return nullptr;
}

std::string signalList(char type, char band, const std::vector<char>& attributes) {
  std::string s;
  for (char a : attributes) {
    if (!s.empty()) s += '/';
    s += type;
    s += band;
    s += a;
  }
  return s;
}

}  // namespace

SignalSelector::SignalSelector(const RinexObsHeader& header, SignalSelectionOptions options,
                               const BiasProvider* biases)
    : options_(std::move(options)), biases_(biases), osb_cache_(static_cast<std::size_t>(kNumGnssSystems) * 100 * 2) {
  for (int s = 0; s < kNumGnssSystems; ++s) types_[s] = header.obs_types[s];
  for (GnssSystem system : options_.systems) {
    auto& sc = systems_[static_cast<int>(system)];
    const SystemSignalPriority* p = priorityOf(options_, system);
    if (p == nullptr) {
      sc.missing = std::string(systemName(system)) + " is not supported for the IF model (GPS and Galileo only)";
      sc.enabled = true;
      continue;
    }
    sc.enabled = true;
    const auto& types = header.types(system);
    sc.code1 = columns(types, ObservableType::Pseudorange, p->band1, p->code1_attributes);
    sc.code2 = columns(types, ObservableType::Pseudorange, p->band2, p->code2_attributes);
    sc.phase1 = columns(types, ObservableType::CarrierPhase, p->band1, p->phase1_attributes);
    sc.phase2 = columns(types, ObservableType::CarrierPhase, p->band2, p->phase2_attributes);
    const auto f1 = carrierFrequency_hz(system, p->band1);
    const auto f2 = carrierFrequency_hz(system, p->band2);
    if (!f1 || !f2) {
      sc.missing = "no carrier frequency for the configured bands";
    } else {
      sc.frequency1_hz = *f1;
      sc.frequency2_hz = *f2;
    }
    const auto need = [&](const std::vector<int>& c, char type, char band, const std::vector<char>& attrs) {
      if (c.empty() && sc.missing.empty()) sc.missing = "the file has none of " + signalList(type, band, attrs);
    };
    need(sc.code1, 'C', p->band1, p->code1_attributes);
    need(sc.code2, 'C', p->band2, p->code2_attributes);
    need(sc.phase1, 'L', p->band1, p->phase1_attributes);
    need(sc.phase2, 'L', p->band2, p->phase2_attributes);
    for (const auto& ps : header.phase_shifts) {
      if (ps.system != system || !ps.shift_cycles) continue;
      if (ps.satellites.empty()) {
        sc.phase_shifts.emplace_back(ps.code, *ps.shift_cycles);
      } else {
        sc.satellite_phase_shifts.push_back(ps);
      }
    }
  }
}

double SignalSelector::phaseShift_cycles(const SystemColumns& sc, const SatelliteId& sat,
                                         const ObservationCode& code) const {
  if (options_.phase_shift == PhaseShiftHandling::AsWritten) return 0.0;
  for (const auto& ps : sc.satellite_phase_shifts) {
    if (ps.code == code && std::find(ps.satellites.begin(), ps.satellites.end(), sat) != ps.satellites.end()) {
      return *ps.shift_cycles;
    }
  }
  for (const auto& [c, shift] : sc.phase_shifts) {
    if (c == code) return shift;
  }
  return 0.0;
}

std::optional<double> SignalSelector::codeOsb_m(const SatelliteId& sat, int slot, const ObservationCode& code,
                                                const GnssTime& t, bool& applies) {
  applies = true;
  if (biases_ == nullptr) return std::nullopt;
  OsbCache& c = osb_cache_[static_cast<std::size_t>(sat.index()) * 2 + static_cast<std::size_t>(slot)];
  if (c.valid && c.code == code && (!c.from || !(t < *c.from)) && (!c.until || !(*c.until < t))) {
    applies = c.applies;
    return c.value_m;
  }
  const BiasAnswer a = biases_->codeBias(sat, code, t);
  c = OsbCache{};
  c.valid = true;
  c.code = code;
  c.value_m = a.applies ? a.value_m : std::nullopt;
  c.applies = a.applies;
  c.from = a.valid_from;
  c.until = a.valid_until;
  applies = c.applies;
  return c.value_m;
}

void SignalSelector::select(const ObsEpoch& epoch, SignalSelectionResult& out) {
  out.clear();
  std::string unaligned;  // satellites whose codes differ from the clock reference, no bias file
  for (std::size_t i = 0; i < epoch.satellites.size(); ++i) {
    const SatelliteId sat = epoch.satellites[i].satellite;
    const auto& sc = systems_[static_cast<int>(sat.system)];
    if (!sc.enabled) {
      out.skipped.push_back({sat, std::string(systemName(sat.system)) + " not enabled"});
      continue;
    }
    if (!sc.missing.empty()) {
      out.skipped.push_back({sat, sc.missing});
      continue;
    }
    const Observation* obs = epoch.begin(i);
    const std::uint32_t n = epoch.satellites[i].count;
    const Observation* c1 = firstPresent(obs, n, sc.code1);
    const Observation* c2 = firstPresent(obs, n, sc.code2);
    const Observation* l1 = firstPresent(obs, n, sc.phase1);
    const Observation* l2 = firstPresent(obs, n, sc.phase2);
    if (c1 == nullptr || c2 == nullptr || l1 == nullptr || l2 == nullptr) {
      std::string why = "missing";
      if (c1 == nullptr) why += " code band 1";
      if (c2 == nullptr) why += " code band 2";
      if (l1 == nullptr) why += " phase band 1";
      if (l2 == nullptr) why += " phase band 2";
      out.skipped.push_back({sat, why});
      continue;
    }
    DualFrequencyObservation d;
    d.satellite = sat;
    d.time = epoch.time;
    d.code1 = c1->code;
    d.code2 = c2->code;
    d.phase1 = l1->code;
    d.phase2 = l2->code;
    d.frequency1_hz = sc.frequency1_hz;
    d.frequency2_hz = sc.frequency2_hz;
    d.code1_m = *c1->value;
    d.code2_m = *c2->value;
    if (biases_ != nullptr) {
      bool applies1 = true, applies2 = true;
      d.code1_osb_m = codeOsb_m(sat, 0, d.code1, epoch.time, applies1);
      d.code2_osb_m = codeOsb_m(sat, 1, d.code2, epoch.time, applies2);
      if (!applies1 || !applies2) {
        d.code1_osb_m.reset();  // the bias source has no say now (e.g. SSR too old: broadcast clocks)
        d.code2_osb_m.reset();
      } else if (options_.require_code_osb && (!d.code1_osb_m || !d.code2_osb_m)) {
        out.skipped.push_back({sat, "no OSB in the bias file for " + (d.code1_osb_m ? d.code2 : d.code1).toString()});
        continue;
      }
      if (d.code1_osb_m) d.code1_m -= *d.code1_osb_m;  // Bias-SINEX 1.00: corrected = observed - OSB
      if (d.code2_osb_m) d.code2_m -= *d.code2_osb_m;
    } else if (sat.system == GnssSystem::GPS && (d.code1.attribute != 'W' || d.code2.attribute != 'W')) {
      unaligned += ' ';
      unaligned += sat.toString();
    }
    d.phase1_cycles = *l1->value - phaseShift_cycles(sc, sat, d.phase1);
    d.phase2_cycles = *l2->value - phaseShift_cycles(sc, sat, d.phase2);
    // RINEX 3.05 sec. 5.3: LLI bit 0 = lost lock (cycle slip possible), bit 1 =
    // half-cycle ambiguity / slip possible.
    const std::uint8_t lli1 = l1->lli.value_or(0), lli2 = l2->lli.value_or(0);
    d.loss_of_lock1 = (lli1 & 1u) != 0;
    d.loss_of_lock2 = (lli2 & 1u) != 0;
    d.half_cycle_ambiguity = ((lli1 | lli2) & 2u) != 0;
    for (std::uint32_t k = 0; k < n; ++k) {
      const auto& o = obs[k];
      if (o.code.type == ObservableType::SignalStrength && o.code.band == d.phase1.band &&
          o.code.attribute == d.phase1.attribute && o.value) {
        d.cn0_1_dbhz = *o.value;
        break;
      }
    }
    out.observations.push_back(d);
  }
  if (!unaligned.empty()) {
    out.notes.push_back("no bias file: codes other than C1W/C2W used with the IGS C1W/C2W clock reference, their "
                        "DCB (e.g. P1-C1) is not applied:" + unaligned);
  }
}

SignalSelectionResult selectDualFrequency(const ObsEpoch& epoch, const RinexObsHeader& header,
                                          const SignalSelectionOptions& options, const BiasProvider* biases) {
  SignalSelector selector(header, options, biases);
  return selector.select(epoch);
}

}  // namespace ppp
