#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/products/product_antenna_model.h"
#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/record_filter.h"
#include "ppp_bayes_tree/models/clock_wide_lane_bias_provider.h"
#include "ppp_bayes_tree/ppp/pipeline/product_sources.h"

namespace ppp {

namespace {

std::string systemList(const std::vector<GnssSystem>& systems) {
  std::string out;
  for (auto s : systems) out += (out.empty() ? "" : ", ") + std::string(systemName(s));
  return out.empty() ? std::string("none") : out;
}

/// Whether the orbits and clocks are SSR corrections (a recording or a live feed),
/// whose satellite antenna model the configuration states (ssr.antenna_model).
bool fromSsr(const ProductAssemblyInputs& in) { return selectProductSource(in).ssr_antenna_model; }

/// The satellite antenna models the products name (SP3 and clock headers, or the
/// stream's declaration). An SSR recording's model is the one the configuration
/// states (ssr.antenna_model).
std::vector<std::string> productAntennaModels(const ProductAssemblyInputs& in,
                                              const std::vector<RinexClockHeader>& clock_headers,
                                              const std::string& ssr_antenna_model) {
  std::vector<std::string> models;
  for (const auto& f : in.sp3) {
    try {
      models.push_back(productAntennaModel(f));
    } catch (const std::exception&) {  // unreadable products are reported by their readers
    }
  }
  for (const auto& h : clock_headers) models.push_back(h.pcvs_applied);
  if (in.streamedOrbitsAndClocks() && !in.streamed.antenna_model.empty()) models.push_back(in.streamed.antenna_model);
  else if (fromSsr(in) && !ssr_antenna_model.empty()) models.push_back(ssr_antenna_model);
  return models;
}

/// Why the gate knows no satellite antenna model of the products.
std::string unknownAntennaModelDetail(const ProductAssemblyInputs& in, const std::string& ssr_antenna_model) {
  if (fromSsr(in) && ssr_antenna_model.empty())
    return "SSR streams name no satellite antenna model: set ssr.antenna_model to the provider's (IGS20 for the "
           "IGS real-time service's streams)";
  return "the products name no satellite antenna model";
}

/// The one family the named models share ("" when none is named or they differ).
std::string commonFamily(const std::vector<std::string>& models) {
  std::set<std::string> families;
  for (const auto& m : models)
    if (!antennaModelFamily(m).empty()) families.insert(antennaModelFamily(m));
  return families.size() == 1 ? *families.begin() : std::string();
}

/// Whether the ANTEX files hold a satellite block of `system` for one of `satellites`
/// (any satellite of the system when the list is empty).
bool antennasCover(const AntexCalibrations& antex, GnssSystem system, const std::set<SatelliteId>& satellites) {
  for (const auto& f : antex.files())
    for (const auto& a : f.file.antennas) {
      if (!a.satellite || a.satellite->system != system) continue;
      if (satellites.empty() || satellites.count(*a.satellite)) return true;
    }
  return false;
}

/// The satellites whose antennas the run uses: those the products carry, else
/// every satellite of the systems that the ANTEX files hold.
std::vector<SatelliteId> satellitesInUse(const OrbitClockProducts& products, const AntexCalibrations& antex,
                                         const std::vector<GnssSystem>& systems) {
  std::set<SatelliteId> out;
  const auto processed = [&](const SatelliteId& s) {
    return std::find(systems.begin(), systems.end(), s.system) != systems.end();
  };
  if (products.satellites_known) {
    for (const auto& s : products.satellites)
      if (processed(s)) out.insert(s);
  } else {
    for (const auto& f : antex.files())
      for (const auto& a : f.file.antennas)
        if (a.satellite && processed(*a.satellite)) out.insert(*a.satellite);
  }
  return {out.begin(), out.end()};
}

/// The satellites of the Bias-SINEX file's code OSB rows.
std::set<SatelliteId> codeOsbSatellites(const BiasSinexFile& file) {
  std::set<SatelliteId> out;
  for (const BiasRecord& r : file.records)
    if (r.type == BiasType::OSB && r.satellite && r.obs1.type == ObservableType::Pseudorange) out.insert(*r.satellite);
  return out;
}

/// "a.SP3, a.CLK": the orbit and clock files (precise or broadcast, with the SSR recording).
std::string orbitClockFileNames(const OrbitClockFiles& in) {
  std::vector<std::string> paths = in.sp3;
  paths.insert(paths.end(), in.clk.begin(), in.clk.end());
  paths.insert(paths.end(), in.nav.begin(), in.nav.end());
  if (in.ssr) paths.push_back(*in.ssr);
  std::string out;
  for (const auto& p : paths) out += (out.empty() ? "" : ", ") + fileBaseName(p);
  return out;
}

/// The satellites the orbits and clocks can serve: those the source carries; with an
/// SSR recording and its broadcast fallback, every satellite with navigation records
/// (the fallback serves uncorrected satellites too).
const std::set<SatelliteId>& servedSatellites(const OrbitClockProducts& products, const OrbitClockFiles& in,
                                              const PppConfig& config) {
  const bool fallback = products.from_navigation_records && in.ssr && config.ssr.fallback.enabled;
  return fallback ? products.record_satellites : products.satellites;
}

bool hasPhaseOsb(const BiasSinexFile* file) {
  if (file == nullptr) return false;
  return std::any_of(file->records.begin(), file->records.end(), [](const BiasRecord& r) {
    return r.type == BiasType::OSB && r.obs1.type == ObservableType::CarrierPhase;
  });
}

/// Whether the satellite antennas let the gate fix in `mode`.
bool antennasAllowFixing(const std::optional<AntennaModelCheck>& check, AmbiguityResolutionMode mode,
                         bool allow_mismatch, ArGateReason& reason) {
  const AntennaModelConsistency v = check ? check->verdict : AntennaModelConsistency::Unknown;
  if (v == AntennaModelConsistency::Consistent || allow_mismatch) return true;
  if (v == AntennaModelConsistency::Different) {
    reason = ArGateReason::AntennaModelDifferent;
    return false;
  }
  if (mode == AmbiguityResolutionMode::On) return true;  // true: only a known difference refuses
  reason = ArGateReason::AntennaModelUnknown;
  return false;
}

}  // namespace

std::string toString(PhaseInformation p) {
  switch (p) {
    case PhaseInformation::None: return "no phase information";
    case PhaseInformation::AnalysisCentreOsb: return "phase OSBs of the clocks' analysis centre";
    case PhaseInformation::IntegerRecoveryClocks: return "integer-recovery clocks";
    case PhaseInformation::SsrPhaseBiases: return "SSR phase biases";
  }
  return "unknown";
}

std::string toString(ArGateReason r) {
  switch (r) {
    case ArGateReason::Fixing: return "fixing";
    case ArGateReason::Disabled: return "disabled";
    case ArGateReason::NoConsistentPhaseBiases: return "no consistent phase biases";
    case ArGateReason::AntennaModelDifferent: return "satellite antenna model differs from the products'";
    case ArGateReason::AntennaModelUnknown: return "satellite antenna model of the products not known";
    case ArGateReason::PhaseInformationRefused: return "phase information refused as implausible";
  }
  return "unknown";
}

std::string ArGateVerdict::text() const {
  std::string out = "ambiguity resolution: " + std::string(fix ? "fixing" : "float") + " (enabled: " +
                    toString(mode) + "): ";
  out += fix ? toString(phase) : toString(reason);
  if (!detail.empty()) out += " (" + detail + ")";
  return out;
}

bool ProductAssemblyInputs::streamedOrbitsAndClocks() const {
  const ProductSource* source = findProductSource(productInputsGiven(*this));
  return source && source->streamed;
}

ProductAssembly ProductAssembly::assemble(const ProductAssemblyInputs& in, const PppConfig& config) {
  ProductAssembly a;
  a.inputs_ = in;
  a.config_ = config;
  const AmbiguityResolutionOptions& ar = config.ambiguity_resolution;
  a.configured_ar_mode_ = ar.enabled ? AmbiguityResolutionMode::On : ar.mode;
  const ProductSource& source = selectProductSource(in);  // throws for inputs of no source
  const std::vector<GnssSystem> candidates =
      config.signals.systems_from_products ? automaticSignalSystems() : config.signals.systems;

  // Orbits and clocks, for the candidate systems and the observations' span.
  RecordFilter filter;
  filter.systems = candidates;
  filter.first = in.first;
  filter.last = in.last;
  const OrbitClockProducts orbit_clock = source.load(in, config, filter, a.notes_, a.problems_);
  a.ephemeris_ = orbit_clock.ephemeris;
  // GLONASS channels of the navigation records, where the observation header has none.
  a.config_.signals.glonass_channels.fillMissing(orbit_clock.glonass_channels);
  a.checkGlonassChannels(in, orbit_clock);

  // ANTEX (satellites of the products' family first), Bias-SINEX, BLQ.
  for (const auto& f : in.clk) a.clock_headers_.push_back(readRinexClockHeader(f));  // read once
  const std::vector<std::string> product_models =
      productAntennaModels(in, a.clock_headers_, config.ssr.antenna_model);
  ProductFiles files;
  files.atx = in.atx;
  files.bias = in.bias;
  files.blq = in.blq;
  files.systems = candidates;
  files.satellite_family = commonFamily(product_models);
  a.set_ = std::make_shared<ProductSet>(ProductSet::load(files));
  a.antennas_ = a.set_->antennas();
  a.notes_.insert(a.notes_.end(), a.set_->notes().begin(), a.set_->notes().end());
  a.problems_.insert(a.problems_.end(), a.set_->problems().begin(), a.set_->problems().end());

  a.checkCoverage(in, orbit_clock);
  if (config.signals.systems_from_products) a.resolveSystems(in, candidates, orbit_clock);
  a.checkObservedSatellites(in, orbit_clock);
  a.decision_notes_begin_ = a.notes_.size();
  if (a.antennas() && !product_models.empty()) a.checkSatelliteAntennas(in, product_models, orbit_clock);

  // Code biases: the Bias-SINEX file's, else the SSR recording's.
  if (a.set_->biases() != nullptr) {
    a.code_biases_ = std::shared_ptr<const BiasProvider>(a.set_, a.set_->biases());
  } else if (orbit_clock.ssr_biases) {
    a.code_biases_ = orbit_clock.ssr_biases;
    a.notes_.push_back("code biases: " + orbit_clock.ssr_biases->describeSource());
  }
  a.decideArGate(in, orbit_clock);
  return a;
}

void ProductAssembly::resolveSystems(const ProductAssemblyInputs& in, const std::vector<GnssSystem>& candidates,
                                     const OrbitClockProducts& orbit_clock) {
  // Every candidate that the products and the satellite antennas cover.
  std::vector<GnssSystem> systems;
  for (GnssSystem s : candidates) {
    const std::string why = whyNotCovered(in, s, orbit_clock);
    if (why.empty()) systems.push_back(s);
    else notes_.push_back("systems: " + std::string(systemName(s)) + " skipped: " + why);
  }
  if (systems.empty()) {
    notes_.push_back("systems: none covered by the products and the antennas; processing " +
                     systemList(config_.signals.systems) + " as configured");
    return;
  }
  config_.signals.systems = systems;
  notes_.push_back("systems: " + systemList(systems) + " (every system of " + systemList(automaticSignalSystems()) +
                   " that the products and the satellite antennas cover)");
}

std::string ProductAssembly::whyNotCovered(const ProductAssemblyInputs& in, GnssSystem system,
                                           const OrbitClockProducts& orbit_clock) const {
  std::set<SatelliteId> carried;
  for (const auto& sat : orbit_clock.satellites)
    if (sat.system == system) carried.insert(sat);
  const auto& declared = in.streamed.systems;
  const SignalTableRow* row = signalTableRow(system);
  const bool frequency_division = row != nullptr && row->frequency_division;
  const ProductSource& source = selectProductSource(in);
  const auto antex = antennas();
  if (orbit_clock.satellites_known && carried.empty()) return orbit_clock.missingReason(system);
  const bool declared_elsewhere =
      !declared.empty() && std::find(declared.begin(), declared.end(), system) == declared.end();
  if (in.streamedOrbitsAndClocks() && declared_elsewhere) return "not carried by the product stream";
  if (frequency_division && !source.auto_frequency_division)
    return "a live SSR feed shows which systems it corrects only as it streams, after the receiver state is made; "
           "list it in signals.systems to process it";
  if (frequency_division && in.observation_glonass_channels && in.observation_glonass_channels->size() == 0 &&
      config_.signals.glonass_channels.size() == 0)
    return "no frequency channels (no GLONASS SLOT / FRQ # in the observation header, no navigation records)";
  if (config_.model.satellite_antenna && antex && !antennasCover(*antex, system, carried))
    return "no satellite antenna calibrations in the ANTEX files";
  return {};
}

void ProductAssembly::checkGlonassChannels(const ProductAssemblyInputs& in, const OrbitClockProducts& orbit_clock) {
  if (!in.observation_glonass_channels) return;
  const auto signed_text = [](int k) { return (k > 0 ? "+" : "") + std::to_string(k); };
  for (int slot = 1; slot <= GlonassChannels::kMaxSlot; ++slot) {
    const std::optional<int> header = in.observation_glonass_channels->channel(slot);
    const std::optional<int> nav = orbit_clock.glonass_channels.channel(slot);
    if (!header || !nav || *header == *nav) continue;
    problems_.push_back("GLONASS " + SatelliteId{GnssSystem::GLONASS, slot}.toString() + ": channel " +
                        signed_text(*header) + " in the observation header (GLONASS SLOT / FRQ #), " +
                        signed_text(*nav) + " in the navigation records: the channels conflict (the header's is used)");
  }
}

void ProductAssembly::checkCoverage(const ProductAssemblyInputs& in, const OrbitClockProducts& orbit_clock) {
  if (!in.first || !in.last) return;  // the observations' span is not known (streamed)
  std::vector<ProductTimeSpan> spans = orbit_clock.spans;
  if (const BiasSinexFile* bias = set_->biasFile(); bias != nullptr && in.bias) {
    ProductTimeSpan span{"biases", fileBaseName(*in.bias), bias->header.data_start, bias->header.data_end, true};
    if (span.first && span.last) spans.push_back(span);  // a header without a validity states none
  }
  for (const ProductTimeSpan& span : spans) applyCoverageFinding(checkProductCoverage(span, *in.first, *in.last), notes_);
}

void ProductAssembly::checkObservedSatellites(const ProductAssemblyInputs& in, const OrbitClockProducts& orbit_clock) {
  if (!in.observed_satellites) return;  // not known before the run (streamed observations)
  const std::vector<GnssSystem>& systems = config_.signals.systems;
  std::set<SatelliteId> observed;
  for (const auto& s : *in.observed_satellites)
    if (std::find(systems.begin(), systems.end(), s.system) != systems.end()) observed.insert(s);
  std::vector<ProductSatellites> kinds;
  if (orbit_clock.satellites_known)
    kinds.push_back({"orbits/clocks", orbitClockFileNames(in), servedSatellites(orbit_clock, in, config_)});
  const BiasSinexFile* bias = set_->biasFile();
  if (bias != nullptr && in.bias && config_.signals.require_code_osb) {
    const std::set<SatelliteId> with_osb = codeOsbSatellites(*bias);
    if (!with_osb.empty()) kinds.push_back({"biases", fileBaseName(*in.bias), with_osb});  // none: DSBs only
  }
  for (const ProductSatellites& kind : kinds) applyCoverageFinding(checkSatelliteCoverage(kind, observed), notes_);
}

void ProductAssembly::checkSatelliteAntennas(const ProductAssemblyInputs& in,
                                             const std::vector<std::string>& product_models,
                                             const OrbitClockProducts& orbit_clock) {
  // The satellite antennas in use against the products' model.
  const auto antex = antennas();
  const std::vector<SatelliteId> in_use = satellitesInUse(orbit_clock, *antex, config_.signals.systems);
  antenna_check_ = checkAntennaModelConsistency(product_models, usedSatelliteAntennaModels(*antex, in_use, in.first));
  if (antex->files().size() > 1 && !antex->satelliteFamily().empty()) {
    std::map<std::string, std::size_t> by_file;
    for (const auto& sat : in_use)
      if (const auto found = antex->satelliteBlock(sat, in.first); found.calibration) ++by_file[found.source];
    std::string from;
    for (const auto& [name, n] : by_file) from += (from.empty() ? "" : ", ") + std::to_string(n) + " from " + name;
    notes_.push_back("satellite antennas: the products' family " + antex->satelliteFamily() + " taken first of " +
                     std::to_string(antex->files().size()) + " ANTEX files (" +
                     (from.empty() ? std::string("no satellite in use") : from) + ")");
  }
  notes_.push_back((antenna_check_->different() ? "warning: " : "") + antenna_check_->text());
}

void ProductAssembly::decideArGate(const ProductAssemblyInputs& in, const OrbitClockProducts& orbit_clock) {
  const AmbiguityResolutionOptions& ar = config_.ambiguity_resolution;
  ArGateVerdict& v = verdict_;
  v.mode = configured_ar_mode_;  // config_'s `enabled` is the resolved one after a first decision
  if (v.mode == AmbiguityResolutionMode::Off) {
    v.reason = ArGateReason::Disabled;
    config_.ambiguity_resolution.enabled = false;
    return;
  }
  ArGateReason antenna_reason = ArGateReason::Fixing;
  const bool antennas_ok = antennasAllowFixing(antenna_check_, v.mode, ar.allow_antenna_model_mismatch, antenna_reason);
  if (!antennas_ok) {
    v.reason = antenna_reason;
    v.detail = antenna_check_ ? antenna_check_->models() : unknownAntennaModelDetail(in, config_.ssr.antenna_model);
    if (v.mode == AmbiguityResolutionMode::On)
      v.detail += "; ambiguity_resolution.allow_antenna_model_mismatch: true to fix anyway";
  } else {
    if (antenna_check_ && antenna_check_->verdict != AntennaModelConsistency::Consistent)
      notes_.push_back("ambiguity resolution: antenna model mismatch allowed (allow_antenna_model_mismatch)");
    const bool refused = findPhaseInformation(in, orbit_clock);
    v.fix = v.phase != PhaseInformation::None;
    v.reason = v.fix ? ArGateReason::Fixing
                     : (refused ? ArGateReason::PhaseInformationRefused : ArGateReason::NoConsistentPhaseBiases);
  }
  // The resolver runs: always with `true` (as before `auto`); with auto when the
  // gate fixes, or when the stream may still let it (its declarations and phase
  // biases come later; without phase biases the resolver leaves the float as it is).
  config_.ambiguity_resolution.enabled =
      v.mode == AmbiguityResolutionMode::On || v.fix || in.streamedOrbitsAndClocks();
  notes_.push_back(v.text());
}

namespace {

/// "<n> phase rows of <file> refused (first: line L: ...)"; "" when none was.
std::string refusedPhaseRows(const BiasSinexFile* file, const std::string& path) {
  if (file == nullptr || file->refused.phase_rows == 0) return {};
  std::string out = std::to_string(file->refused.phase_rows) + " phase bias rows of " + fileBaseName(path) +
                    " refused as implausible";
  if (file->refused.first_phase_line > 0)
    out += " (first: line " + std::to_string(file->refused.first_phase_line) + ": " + file->refused.first_phase_reason + ")";
  return out;
}

}  // namespace

bool ProductAssembly::findPhaseInformation(const ProductAssemblyInputs& in, const OrbitClockProducts& orbit_clock) {
  // In order: OSBs of the clocks' centre, integer-recovery clocks, SSR phase biases.
  const BiasSinexFile* bias_file = set_->biasFile();
  switch (selectProductSource(in).phase) {
    case SourcePhaseInformation::ClockProducts:
      return phaseFromClockProducts(in, bias_file, in.bias ? refusedPhaseRows(bias_file, *in.bias) : std::string());
    case SourcePhaseInformation::SsrRecording:
      phaseFromSsr(in, orbit_clock);
      return false;
    case SourcePhaseInformation::Stream:  // else the stream's own biases later
      phaseFromStreamCentre(in, bias_file);
      return false;
  }
  return false;
}

bool ProductAssembly::phaseFromClockProducts(const ProductAssemblyInputs& in, const BiasSinexFile* bias_file,
                                             const std::string& refused_rows) {
  ArGateVerdict& v = verdict_;
  std::vector<ProductOrigin> clocks;
  for (std::size_t i = 0; i < in.clk.size(); ++i) clocks.push_back({in.clk[i], clockHeaderCentre(clock_headers_[i])});
  std::optional<ProductOrigin> bias;
  if (in.bias) bias = ProductOrigin{*in.bias, bias_file ? bias_file->header.file_agency : ""};
  const PhaseBiasCheck check = checkPhaseBiasConsistency(clocks, bias, hasPhaseOsb(bias_file));
  IntegerRecoveryClockBiases wl = readIntegerRecoveryClockBiases(clock_headers_, in.clk);
  if (check.consistent()) {
    v.phase = PhaseInformation::AnalysisCentreOsb;
    phase_biases_ = set_->biases();
    v.detail = check.clock_centre + (check.from_headers ? ", from the headers" : ", from the file names");
    notes_.push_back("ambiguity resolution: " + check.text());
    if (!refused_rows.empty()) notes_.push_back("ambiguity resolution: " + refused_rows + "; not fixed where missing");
    return false;
  }
  problems_.insert(problems_.end(), wl.problems.begin(), wl.problems.end());
  if (wl.provider) {
    v.phase = PhaseInformation::IntegerRecoveryClocks;
    v.detail = std::to_string(wl.provider->size()) + " wide-lane satellite biases in the clock header";
    notes_.push_back("ambiguity resolution: integer-recovery clocks with " + v.detail);
    if (wl.refused > 0)
      notes_.push_back("ambiguity resolution: " + std::to_string(wl.refused) + " of " + std::to_string(wl.lines) +
                       " wide-lane lines of the clock header refused; their satellites are not fixed");
    phase_biases_ = wl.provider.get();
    owned_phase_biases_ = std::move(wl.provider);
    return false;
  }
  // Nothing usable: say why, the refused inputs first.
  if (check.verdict == PhaseBiasConsistency::NoPhaseBiases && !refused_rows.empty()) {
    v.detail = refused_rows;
    return true;
  }
  if (!wl.whyNone().empty()) {
    v.detail = wl.whyNone();
    return true;
  }
  v.detail = check.why();
  return false;
}

void ProductAssembly::phaseFromSsr(const ProductAssemblyInputs& in, const OrbitClockProducts& orbit_clock) {
  ArGateVerdict& v = verdict_;
  if (orbit_clock.ssr_phase_biases) {
    v.phase = PhaseInformation::SsrPhaseBiases;
    phase_biases_ = orbit_clock.ssr_biases.get();
    v.detail = orbit_clock.ssr_biases->describeSource();
  } else {
    v.detail = in.ssr ? "the SSR stream carries no phase biases" : "broadcast orbits and clocks without SSR";
  }
}

void ProductAssembly::phaseFromStreamCentre(const ProductAssemblyInputs& in, const BiasSinexFile* bias_file) {
  ArGateVerdict& v = verdict_;
  const std::string agency = bias_file ? bias_file->header.file_agency : "";
  if (hasPhaseOsb(bias_file) && !agency.empty() && agency == in.streamed.clock_centre) {
    v.phase = PhaseInformation::AnalysisCentreOsb;
    phase_biases_ = set_->biases();
    v.detail = agency + ", the stream's clock centre";
  } else {
    v.detail = "no phase biases from the stream yet";
  }
}

bool ProductAssembly::acceptStreamedPhaseBiases(const BiasProvider* provider, PhaseInformation kind) {
  ArGateVerdict& v = verdict_;
  if (v.mode == AmbiguityResolutionMode::Off || provider == nullptr || kind == PhaseInformation::None) return false;
  streamed_phase_biases_ = provider;  // kept for declareStreamedProducts, even when refused now
  streamed_phase_kind_ = kind;
  if (v.reason == ArGateReason::AntennaModelDifferent || v.reason == ArGateReason::AntennaModelUnknown) return false;
  if (v.fix && phase_biases_ == provider) return false;
  if (v.fix && v.phase != PhaseInformation::SsrPhaseBiases && kind == PhaseInformation::SsrPhaseBiases)
    return false;  // a consistent Bias-SINEX file stays
  phase_biases_ = provider;
  v.phase = kind;
  v.fix = true;
  v.reason = ArGateReason::Fixing;
  v.detail = provider->describeSource();
  config_.ambiguity_resolution.enabled = true;
  notes_.push_back(v.text());
  return true;
}

bool ProductAssembly::declareStreamedProducts(const StreamedProductInfo& info) {
  if (!inputs_.streamedOrbitsAndClocks()) return false;
  if (info.clock_centre == inputs_.streamed.clock_centre && info.antenna_model == inputs_.streamed.antenna_model)
    return false;
  inputs_.streamed.clock_centre = info.clock_centre;
  inputs_.streamed.antenna_model = info.antenna_model;
  const std::vector<std::string> models = productAntennaModels(inputs_, clock_headers_, config_.ssr.antenna_model);
  const std::string family = commonFamily(models);
  if (antennas_ && family != antennas_->satelliteFamily())
    antennas_ = std::make_shared<const AntexCalibrations>(antennas_->files(), family);
  const OrbitClockProducts streamed;  // orbits and clocks not known before the run
  // The earlier decision's notes were made without the declaration: replaced
  // (streamed orbits and clocks bring no code-bias note between them).
  notes_.resize(std::min(decision_notes_begin_, notes_.size()));
  notes_.push_back("the product stream declares " +
                   (info.clock_centre.empty() ? std::string("no clock centre") : "clocks of " + info.clock_centre) +
                   " and " +
                   (info.antenna_model.empty() ? std::string("no satellite antenna model")
                                               : "the satellite antenna model " + info.antenna_model));
  antenna_check_.reset();
  if (antennas_ && !models.empty()) checkSatelliteAntennas(inputs_, models, streamed);
  verdict_ = ArGateVerdict{};
  phase_biases_ = nullptr;
  decideArGate(inputs_, streamed);
  if (streamed_phase_biases_) acceptStreamedPhaseBiases(streamed_phase_biases_, streamed_phase_kind_);
  return true;
}

OceanLoadingLookup ProductAssembly::oceanLoading(const std::string& station) const {
  return set_ ? set_->oceanLoading(station) : OceanLoadingLookup{};
}

PppProducts ProductAssembly::products(const std::string& station) const {
  PppProducts p;
  p.ephemeris = ephemeris_;
  p.antennas = antennas();
  p.biases = code_biases_;
  const OceanLoadingLookup ocean = oceanLoading(station);
  if (ocean.coefficients) p.ocean = *ocean.coefficients;
  p.notes = notes_;
  if (!ocean.note.empty()) p.notes.push_back(ocean.note);
  return p;
}

}  // namespace ppp
