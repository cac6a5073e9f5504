#pragma once
// Signal selection for the ionosphere-free (IF) PPP model: picks, per satellite
// of an ObsEpoch, the two codes and two phases of the configured frequency pair
// (GPS L1/L2, GLONASS G1/G2, Galileo E1/E5a, BeiDou B1I/B3I) by a configurable
// tracking-mode priority, aligns the codes to the clock product's code reference
// (corrected = observed - OSB) and fills DualFrequencyObservation. The frequency
// pair and the priorities of each system are one row of the signal table
// (signalTable()); adding a system = adding its row. GLONASS rows are
// frequency-division: the frequencies come per satellite from its channel.
// The code alignment, the phase shifts and GLONASS channels: doc/measurement_model.md,
// "Signal selection".
// References: Bias-SINEX 1.00 (Schaer 2016) sec. 3.3 / 4.3 (OSB); RINEX 3.05
// sec. 5.2 and table A2 (phase shifts); GLONASS ICD 5.1 sec. 3.3.1.4; RTKLIB 2.4.3
// (Takasu 2013) for the form of the priority table.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/models/bias_provider.h"
#include "ppp_bayes_tree/ppp/model/dual_frequency_observation.h"
#include "ppp_bayes_tree/types/glonass_channels.h"
#include "ppp_bayes_tree/types/obs_epoch.h"

namespace ppp {

/// Frequency pair and tracking-mode priorities (RINEX 3 attribute letters,
/// first = preferred) of one system.
struct SystemSignalPriority {
  char band1 = '1';
  char band2 = '2';
  std::vector<char> code1_attributes;
  std::vector<char> code2_attributes;
  std::vector<char> phase1_attributes;
  std::vector<char> phase2_attributes;
  /// Factor on the code sigma of this system's IF code (1 = the common
  /// weighting). GLONASS: its receiver code biases differ per frequency channel
  /// (inter-frequency biases, Shi et al. 2013, GPS Solutions 17(4)), which the
  /// common receiver clock cannot absorb; the code is down-weighted instead
  /// (Cai & Gao 2013, GPS Solutions 17(2): GLONASS code weighted lower than GPS).
  double code_sigma_factor = 1.0;
};

/// One row of the signal table: a system that has an ionosphere-free pair here.
struct SignalTableRow {
  GnssSystem system = GnssSystem::GPS;
  /// Its section under measurement_model.signals (config/ppp.yaml).
  const char* config_key = "";
  /// The default pair and priorities (the configuration may change the priorities).
  SystemSignalPriority priority;
  /// Processed by `signals.systems: auto` when the products and antennas cover it;
  /// false: only when listed in `signals.systems`.
  bool automatic = false;
  /// Tracking modes of the band-1 / band-2 codes the usual clock products refer
  /// to (GPS: C1W/C2W, the IGS convention), '\0' when the row states none. Other
  /// codes used without a bias file are reported in the epoch notes.
  char clock_reference1 = '\0';
  char clock_reference2 = '\0';
  /// FDMA (GLONASS): the frequencies are per satellite, from its frequency
  /// channel, and the ambiguities have no integer property with undifferenced
  /// products (each satellite's phase has its own wavelength; the receiver's
  /// inter-channel phase biases do not cancel between satellites), so ambiguity
  /// resolution never fixes them: their arcs stay float.
  bool frequency_division = false;
};

/// The signal table, in the order of GnssSystem (rows: GPS, GLONASS, Galileo, BeiDou).
const std::vector<SignalTableRow>& signalTable();
/// The row of `system`, nullptr when the system has no IF pair here.
const SignalTableRow* signalTableRow(GnssSystem system);
/// The systems of the table whose row is `automatic`, in table order.
std::vector<GnssSystem> automaticSignalSystems();
/// The table's systems as a list for messages: "GPS, GLONASS, Galileo or BeiDou".
std::string signalTableSystemNames();
/// Whether the IF ambiguities of `system` may be fixed to integers: a system of
/// the table that is not frequency_division (GLONASS FDMA never is).
bool integerAmbiguitySystem(GnssSystem system);

/// Per system priorities (index: GnssSystem), from the table's defaults; a
/// system without a row has none.
class SignalPriorities {
 public:
  SignalPriorities();
  /// nullptr when the system has no row in the signal table.
  const SystemSignalPriority* find(GnssSystem system) const;
  /// The row of a system of the table (std::out_of_range otherwise).
  SystemSignalPriority& operator[](GnssSystem system);
  const SystemSignalPriority& operator[](GnssSystem system) const;

 private:
  std::array<std::optional<SystemSignalPriority>, kNumGnssSystems> rows_;
};

enum class PhaseShiftHandling {
  AsWritten,        // RINEX 3.01+: the file values are already aligned (default)
  RestoreOriginal,  // subtract the reported correction: original phase
};

struct SignalSelectionOptions {
  /// Frequency pair and priorities per system (defaults: signalTable()).
  SignalPriorities priorities;
  /// Systems processed; others are skipped with a reason.
  std::vector<GnssSystem> systems{GnssSystem::GPS};
  /// true (default; no `signals.systems` key): the product assembly
  /// (product_assembly.h) processes every automatic system of the table
  /// (GPS | GLONASS | Galileo) that the products and the satellite antennas cover and
  /// writes them into `systems` (which holds GPS for code that runs without
  /// the assembly). false: exactly `systems`.
  bool systems_from_products = true;
  /// With a bias file: skip a satellite when an OSB of a selected code is
  /// missing (true), or use the code uncorrected and say so (false).
  bool require_code_osb = true;
  PhaseShiftHandling phase_shift = PhaseShiftHandling::AsWritten;
  /// GLONASS frequency channels known besides the observation header (e.g. from
  /// navigation records); the header's GLONASS SLOT / FRQ # entries come first.
  GlonassChannels glonass_channels;
};

/// A satellite of the epoch that got no dual-frequency observation, with why.
struct SkippedSignal {
  SatelliteId satellite;
  std::string reason;
};

/// What a signal-selection note is about.
enum class SignalSelectionNoteKind {
  CodesWithoutBias,  // codes other than the clock reference used without a bias file: their DCB is not applied
};

/// A note of the signal selection on one epoch: its text and the satellites it
/// concerns (kept apart, so that notes of many epochs merge by text).
struct SignalSelectionNote {
  SignalSelectionNoteKind kind = SignalSelectionNoteKind::CodesWithoutBias;
  /// "no bias file: codes other than C1W/C2W used with the IGS C1W/C2W clock
  /// reference, their DCB (e.g. P1-C1) is not applied"
  std::string text;
  std::vector<SatelliteId> satellites;  // in the epoch's order

  /// The note as one line: the text, then ":" and the satellites when there are any.
  std::string describe() const;
};

struct SignalSelectionResult {
  std::vector<DualFrequencyObservation> observations;
  std::vector<SkippedSignal> skipped;
  /// Per epoch notes on the code reference.
  std::vector<SignalSelectionNote> notes;

  void clear() {
    observations.clear();
    skipped.clear();
    notes.clear();
  }
};

/// Selects signals for whole epochs. Built once per observation file: the
/// column of each code in the header's type list is resolved at construction,
/// and OSB values are cached with their validity, so that select() performs
/// no allocation once the output vectors have grown (except for skip reasons).
class SignalSelector {
 public:
  /// `biases` may be nullptr (no bias file); it must outlive the selector.
  SignalSelector(const RinexObsHeader& header, SignalSelectionOptions options, const BiasProvider* biases);

  void select(const ObsEpoch& epoch, SignalSelectionResult& out);
  SignalSelectionResult select(const ObsEpoch& epoch) {
    SignalSelectionResult r;
    select(epoch, r);
    return r;
  }
  const SignalSelectionOptions& options() const { return options_; }

 private:
  struct SystemColumns {
    bool enabled = false;
    std::string missing;  // why the system cannot be used with this header ("" = usable)
    std::vector<int> code1, code2, phase1, phase2;  // columns in priority order
    double frequency1_hz = 0.0, frequency2_hz = 0.0;
    char band1 = '1', band2 = '2';
    bool frequency_division = false;  // per-satellite frequencies from the channel
    double code_sigma_factor = 1.0;
    char clock_reference1 = '\0', clock_reference2 = '\0';  // SignalTableRow
    std::vector<std::pair<ObservationCode, double>> phase_shifts;  // all-satellite records
    std::vector<PhaseShift> satellite_phase_shifts;               // per-satellite records
  };
  struct OsbCache {
    bool valid = false;
    ObservationCode code;
    std::optional<double> value_m;
    bool applies = true;  // BiasAnswer::applies
    std::optional<GnssTime> from, until;
  };

  /// The code OSB of a signal, nullopt when the provider has none; `applies` is
  /// set false when the provider has no say at `t` (BiasAnswer::applies).
  std::optional<double> codeOsb_m(const SatelliteId& sat, int slot, const ObservationCode& code, const GnssTime& t,
                                  bool& applies);
  double phaseShift_cycles(const SystemColumns& sc, const SatelliteId& sat, const ObservationCode& code) const;
  /// The pair's frequencies of `sat`: the system's, or for FDMA those of its
  /// channel (false, with `why`, when the channel is unknown).
  bool pairFrequencies_hz(const SystemColumns& sc, const SatelliteId& sat, double& f1_hz, double& f2_hz,
                          std::string& why) const;
  /// Satellite i of the epoch: its observation, or the reason it is skipped; a code
  /// off the clock reference without a bias file is added to `unaligned`.
  void selectSatellite(const ObsEpoch& epoch, std::size_t i, const SystemColumns& sc, SignalSelectionResult& out,
                       std::vector<SatelliteId>& unaligned);
  /// Corrects the codes by their OSBs; false (skipped, in `out`) when an OSB is required and missing.
  bool correctCodeBiases(DualFrequencyObservation& d, SignalSelectionResult& out);

  SignalSelectionOptions options_;
  const BiasProvider* biases_;
  std::array<SystemColumns, kNumGnssSystems> systems_;
  std::array<std::vector<ObservationCode>, kNumGnssSystems> types_;
  GlonassChannels glonass_channels_;  // header entries, then options_.glonass_channels
  std::vector<OsbCache> osb_cache_;  // index: satellite index * 2 + slot
};

/// Convenience for one epoch (builds a selector each call: prefer SignalSelector in loops).
SignalSelectionResult selectDualFrequency(const ObsEpoch& epoch, const RinexObsHeader& header,
                                          const SignalSelectionOptions& options, const BiasProvider* biases);

}  // namespace ppp
