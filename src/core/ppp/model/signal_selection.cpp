#include "ppp_bayes_tree/ppp/model/signal_selection.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "ppp_bayes_tree/types/carrier_frequency.h"

namespace ppp {

// The signal table. Pairs and codes: RINEX 3.05 table A2 (tracking modes per band).
//  - GPS L1/L2 with the P(Y) codes first: the IGS clocks refer to the C1W/C2W IF
//    combination (Bias-SINEX: SATELLITE_CLOCK_REFERENCE_OBSERVABLES C1W C2W).
//  - GLONASS G1/G2 (FDMA) with the P codes first: the IGS and MGEX GLONASS clocks
//    refer to the C1P/C2P IF combination (WUM's Bias-SINEX: SATELLITE_CLOCK_
//    REFERENCE_OBSERVABLES R C1P C2P). The frequencies are per satellite (its
//    channel); the code is down-weighted by a factor of 3 for the receiver's
//    inter-frequency code biases (Cai & Gao 2013, GPS Solutions 17(2) 223-236;
//    Shi et al. 2013, GPS Solutions 17(4) 439-451). Automatic where the products
//    carry it and its channels are known (measured in doc/glonass.md).
//  - Galileo E1/E5a (C1C/C5Q or the pilot+data X modes), the IGS MGEX reference pair.
//  - BeiDou B1I/B3I (C2I/C6I): the broadcast clock refers to B3I and its TGD1 gives
//    the B1I/B3I IF combination (BDS-SIS-ICD-B1I 3.0, 5.2.4.10; the broadcast store
//    serves that combination's clock); the IGS MGEX BeiDou clocks refer to C2I/C6I
//    too. Not automatic: a run takes BeiDou only when the configuration lists it,
//    so that products which carry BeiDou (e.g. WHU's MGEX products) leave the
//    results of an existing `auto` configuration as they were.
const std::vector<SignalTableRow>& signalTable() {
  static const std::vector<SignalTableRow> table = {
      {GnssSystem::GPS, "gps", {'1', '2', {'W', 'C'}, {'W', 'L', 'X'}, {'C', 'W'}, {'W', 'L', 'X'}}, true, 'W', 'W'},
      {GnssSystem::GLONASS, "glonass", {'1', '2', {'P', 'C'}, {'P', 'C'}, {'P', 'C'}, {'P', 'C'}, 3.0}, true, 'P', 'P',
       true},
      {GnssSystem::Galileo, "galileo", {'1', '5', {'C', 'X'}, {'Q', 'X'}, {'C', 'X'}, {'Q', 'X'}}, true},
      {GnssSystem::BeiDou, "beidou", {'2', '6', {'I', 'X'}, {'I', 'X'}, {'I', 'X'}, {'I', 'X'}}, false},
  };
  return table;
}

const SignalTableRow* signalTableRow(GnssSystem system) {
  for (const auto& row : signalTable())
    if (row.system == system) return &row;
  return nullptr;
}

std::vector<GnssSystem> automaticSignalSystems() {
  std::vector<GnssSystem> out;
  for (const auto& row : signalTable())
    if (row.automatic) out.push_back(row.system);
  return out;
}

std::string signalTableSystemNames() {
  const auto& table = signalTable();
  std::string out;
  for (std::size_t k = 0; k < table.size(); ++k) {
    if (k > 0) out += k + 1 == table.size() ? " or " : ", ";
    out += systemName(table[k].system);
  }
  return out;
}

bool integerAmbiguitySystem(GnssSystem system) {
  const SignalTableRow* row = signalTableRow(system);
  return row != nullptr && !row->frequency_division;
}

SignalPriorities::SignalPriorities() {
  for (const auto& row : signalTable()) rows_[static_cast<int>(row.system)] = row.priority;
}

const SystemSignalPriority* SignalPriorities::find(GnssSystem system) const {
  const auto& row = rows_[static_cast<int>(system)];
  return row ? &*row : nullptr;
}

SystemSignalPriority& SignalPriorities::operator[](GnssSystem system) {
  auto& row = rows_[static_cast<int>(system)];
  if (!row) throw std::out_of_range(std::string(systemName(system)) + " has no row in the signal table");
  return *row;
}

const SystemSignalPriority& SignalPriorities::operator[](GnssSystem system) const {
  const SystemSignalPriority* row = find(system);
  if (row == nullptr) throw std::out_of_range(std::string(systemName(system)) + " has no row in the signal table");
  return *row;
}

namespace {

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
  glonass_channels_ = channelsHeaderFirst(header.glonass_channels, options_.glonass_channels);
  for (GnssSystem system : options_.systems) {
    auto& sc = systems_[static_cast<int>(system)];
    const SystemSignalPriority* p = options_.priorities.find(system);
    if (p == nullptr) {
      sc.missing = std::string(systemName(system)) + " is not supported for the IF model (" +
                   signalTableSystemNames() + " only)";
      sc.enabled = true;
      continue;
    }
    sc.enabled = true;
    if (const SignalTableRow* row = signalTableRow(system)) {
      sc.clock_reference1 = row->clock_reference1;
      sc.clock_reference2 = row->clock_reference2;
      sc.frequency_division = row->frequency_division;
    }
    sc.band1 = p->band1;
    sc.band2 = p->band2;
    sc.code_sigma_factor = p->code_sigma_factor;
    const auto& types = header.types(system);
    sc.code1 = columns(types, ObservableType::Pseudorange, p->band1, p->code1_attributes);
    sc.code2 = columns(types, ObservableType::Pseudorange, p->band2, p->code2_attributes);
    sc.phase1 = columns(types, ObservableType::CarrierPhase, p->band1, p->phase1_attributes);
    sc.phase2 = columns(types, ObservableType::CarrierPhase, p->band2, p->phase2_attributes);
    // FDMA: checked with channel 0; each satellite's come from its channel.
    const std::optional<int> channel = sc.frequency_division ? std::optional<int>(0) : std::nullopt;
    const auto f1 = carrierFrequency_hz(system, p->band1, channel);
    const auto f2 = carrierFrequency_hz(system, p->band2, channel);
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

bool SignalSelector::pairFrequencies_hz(const SystemColumns& sc, const SatelliteId& sat, double& f1_hz,
                                        double& f2_hz, std::string& why) const {
  if (!sc.frequency_division) {
    f1_hz = sc.frequency1_hz;
    f2_hz = sc.frequency2_hz;
    return true;
  }
  const std::optional<int> k = glonass_channels_.channel(sat.prn);
  const auto f1 = carrierFrequency_hz(sat.system, sc.band1, k);
  const auto f2 = carrierFrequency_hz(sat.system, sc.band2, k);
  if (!f1 || !f2) {
    why = "no GLONASS frequency channel (no GLONASS SLOT / FRQ # entry or navigation record for the slot)";
    return false;
  }
  f1_hz = *f1;
  f2_hz = *f2;
  return true;
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

namespace {

std::string missingSignals(const Observation* c1, const Observation* c2, const Observation* l1, const Observation* l2) {
  std::string why = "missing";
  if (c1 == nullptr) why += " code band 1";
  if (c2 == nullptr) why += " code band 2";
  if (l1 == nullptr) why += " phase band 1";
  if (l2 == nullptr) why += " phase band 2";
  return why;
}

/// The carrier-to-noise density of the band-1 phase's signal, when observed.
std::optional<double> cn0Of(const Observation* obs, std::uint32_t n, const ObservationCode& phase) {
  for (std::uint32_t k = 0; k < n; ++k) {
    const auto& o = obs[k];
    if (o.code.type == ObservableType::SignalStrength && o.code.band == phase.band &&
        o.code.attribute == phase.attribute && o.value) {
      return *o.value;
    }
  }
  return std::nullopt;
}

}  // namespace

void SignalSelector::select(const ObsEpoch& epoch, SignalSelectionResult& out) {
  out.clear();
  // Per system: satellites whose codes differ from the clock reference, no bias file.
  std::array<std::vector<SatelliteId>, kNumGnssSystems> unaligned;
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
    selectSatellite(epoch, i, sc, out, unaligned[static_cast<int>(sat.system)]);
  }
  for (int system = 0; system < kNumGnssSystems; ++system) {
    if (unaligned[system].empty()) continue;
    const SystemColumns& sc = systems_[system];
    const std::string reference = std::string("C") + sc.band1 + sc.clock_reference1 + "/C" + sc.band2 + sc.clock_reference2;
    SignalSelectionNote note;
    note.kind = SignalSelectionNoteKind::CodesWithoutBias;
    note.text = "no bias file: codes other than " + reference + " used with the IGS " + reference +
                " clock reference, their DCB (e.g. P1-C1) is not applied";
    note.satellites = unaligned[system];
    out.notes.push_back(std::move(note));
  }
}

void SignalSelector::selectSatellite(const ObsEpoch& epoch, std::size_t i, const SystemColumns& sc,
                                     SignalSelectionResult& out, std::vector<SatelliteId>& unaligned) {
  const SatelliteId sat = epoch.satellites[i].satellite;
  // 1. The pair's frequencies (FDMA: the satellite's channel).
  double f1_hz = 0.0, f2_hz = 0.0;
  if (std::string why; !pairFrequencies_hz(sc, sat, f1_hz, f2_hz, why)) {
    out.skipped.push_back({sat, std::move(why)});
    return;
  }
  // 2. The first present code and phase of each band, in the order of preference.
  const Observation* obs = epoch.begin(i);
  const std::uint32_t n = epoch.satellites[i].count;
  const Observation* c1 = firstPresent(obs, n, sc.code1);
  const Observation* c2 = firstPresent(obs, n, sc.code2);
  const Observation* l1 = firstPresent(obs, n, sc.phase1);
  const Observation* l2 = firstPresent(obs, n, sc.phase2);
  if (c1 == nullptr || c2 == nullptr || l1 == nullptr || l2 == nullptr) {
    out.skipped.push_back({sat, missingSignals(c1, c2, l1, l2)});
    return;
  }
  DualFrequencyObservation d;
  d.satellite = sat;
  d.time = epoch.time;
  d.code1 = c1->code;
  d.code2 = c2->code;
  d.phase1 = l1->code;
  d.phase2 = l2->code;
  d.frequency1_hz = f1_hz;
  d.frequency2_hz = f2_hz;
  d.code_sigma_factor = sc.code_sigma_factor;
  d.code1_m = *c1->value;
  d.code2_m = *c2->value;
  // 3. Code biases, or without a bias file the note of codes off the clock reference.
  if (biases_ != nullptr) {
    if (!correctCodeBiases(d, out)) return;
  } else if (sc.clock_reference1 != '\0' &&
             (d.code1.attribute != sc.clock_reference1 || d.code2.attribute != sc.clock_reference2)) {
    unaligned.push_back(sat);
  }
  // 4. Phases aligned within the band; lock flags; signal strength.
  d.phase1_cycles = *l1->value - phaseShift_cycles(sc, sat, d.phase1);
  d.phase2_cycles = *l2->value - phaseShift_cycles(sc, sat, d.phase2);
  // RINEX 3.05 sec. 5.3: LLI bit 0 = lost lock (cycle slip possible), bit 1 =
  // half-cycle ambiguity / slip possible.
  const std::uint8_t lli1 = l1->lli.value_or(0), lli2 = l2->lli.value_or(0);
  d.loss_of_lock1 = (lli1 & 1u) != 0;
  d.loss_of_lock2 = (lli2 & 1u) != 0;
  d.half_cycle_ambiguity = ((lli1 | lli2) & 2u) != 0;
  if (const auto cn0 = cn0Of(obs, n, d.phase1)) d.cn0_1_dbhz = *cn0;
  out.observations.push_back(d);
}

bool SignalSelector::correctCodeBiases(DualFrequencyObservation& d, SignalSelectionResult& out) {
  bool applies1 = true, applies2 = true;
  d.code1_osb_m = codeOsb_m(d.satellite, 0, d.code1, d.time, applies1);
  d.code2_osb_m = codeOsb_m(d.satellite, 1, d.code2, d.time, applies2);
  if (!applies1 || !applies2) {
    d.code1_osb_m.reset();  // the bias source has no say now (e.g. SSR too old: broadcast clocks)
    d.code2_osb_m.reset();
  } else if (options_.require_code_osb && (!d.code1_osb_m || !d.code2_osb_m)) {
    out.skipped.push_back({d.satellite, "no OSB in the bias file for " + (d.code1_osb_m ? d.code2 : d.code1).toString()});
    return false;
  }
  if (d.code1_osb_m) d.code1_m -= *d.code1_osb_m;  // Bias-SINEX 1.00: corrected = observed - OSB
  if (d.code2_osb_m) d.code2_m -= *d.code2_osb_m;
  return true;
}

std::string SignalSelectionNote::describe() const {
  std::string line = text;
  if (!satellites.empty()) line += ":";
  for (const SatelliteId& sat : satellites) line += " " + sat.toString();
  return line;
}

SignalSelectionResult selectDualFrequency(const ObsEpoch& epoch, const RinexObsHeader& header,
                                          const SignalSelectionOptions& options, const BiasProvider* biases) {
  SignalSelector selector(header, options, biases);
  return selector.select(epoch);
}

}  // namespace ppp
