#pragma once
// ProductAssembly: the one place that turns a run's product inputs into what the
// epoch processor and the estimator need. ppp_solve (PppPipeline), the ROS nodes
// (PppNode) and the live input (LiveGnssInput's SSR biases) all go through it.
// Inputs (ProductAssemblyInputs): orbits and clocks as precise files, broadcast
// files (+ an SSR recording) or streamed (product_sources.h); ANTEX, Bias-SINEX
// and BLQ files. Outputs: the ephemeris, the antenna calibrations (each
// satellite from the products' antenna family), the code biases, the ocean
// loading; the systems processed (signals.systems: auto); the coverage of the
// observations (product_coverage.h); the PPP-AR gate (ArGateVerdict) with the
// phase-bias provider for the epoch processor (nullptr unless the run may fix);
// and the effective configuration (config()), from which estimators must be made.
// The gate's conditions and verdicts: doc/ppp_ar.md, "When a run fixes"; the
// systems auto takes: doc/offline_tools.md, "What the products allow", and
// doc/glonass.md.
// References: Laurichesse D. et al. (2009) Navigation 56(2) (integer-recovery
// clocks); Schaer S. et al. (2021) J Geod 95:81 (phase OSBs).
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/models/antex_calibrations.h"
#include "ppp_bayes_tree/models/bias_provider.h"
#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/ppp/ambiguity/antenna_model_consistency.h"
#include "ppp_bayes_tree/ppp/ambiguity/phase_bias_consistency.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"  // PppProducts
#include "ppp_bayes_tree/ppp/pipeline/product_set.h"
#include "ppp_bayes_tree/ppp/pipeline/product_sources.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// What a product stream declares about the products it carries (a bag made by
/// ppp_to_bag, an SSR feed). Empty fields: not known.
struct StreamedProductInfo {
  std::vector<GnssSystem> systems;  // systems whose orbits and clocks the stream carries
  std::string clock_centre;         // analysis centre of its clocks, e.g. "WHU", "GRG"
  std::string antenna_model;        // satellite antenna model of its orbits/clocks, e.g. "IGS14_2148"
};

/// The orbit and clock files (OrbitClockFiles: which are given selects the
/// source, product_sources.h), and the rest of a run's product inputs.
struct ProductAssemblyInputs : OrbitClockFiles {
  std::optional<GnssTime> stream_reference_time;    // places MSM/SSR times without a week
  bool check_products = true;                       // product sanity checks of SP3/CLK
  /// Neither precise nor broadcast files: the orbits and clocks are streamed.
  StreamedProductInfo streamed;
  /// The streamed orbits and clocks are a live SSR feed (RTCM SSR, IGS-SSR): it names
  /// no satellite antenna model, the configuration's ssr.antenna_model is taken for it
  /// (as for an SSR recording); empty there: not known, auto stays float and says so.
  bool live_ssr = false;
  std::vector<std::string> atx;
  std::optional<std::string> bias, blq;
  /// The observations' span (products outside it are not read; the antenna
  /// check looks at the blocks valid at `first`). nullopt: unknown.
  std::optional<GnssTime> first, last;
  /// The satellites of the observation file's epochs (in its window), for the
  /// coverage check. nullopt: not known before the run.
  std::optional<std::set<SatelliteId>> observed_satellites;
  /// The GLONASS frequency channels of the observation file's header (RINEX
  /// GLONASS SLOT / FRQ #, or those an RTCM/UBX file's scan found). nullopt:
  /// the observations are streamed and bring their channels with them.
  std::optional<GlonassChannels> observation_glonass_channels;
  /// The source of these inputs streams its orbits and clocks (product_sources.h).
  bool streamedOrbitsAndClocks() const;
};

/// Where the run's phase information comes from.
enum class PhaseInformation {
  None,
  AnalysisCentreOsb,      // phase OSBs of the clocks' own analysis centre (Bias-SINEX)
  IntegerRecoveryClocks,  // wide-lane satellite biases of integer-recovery clocks (GRG)
  SsrPhaseBiases,         // SSR phase biases of the stream that carries the clocks
};
std::string toString(PhaseInformation p);

/// Why the gate lets a run fix or keeps it float.
enum class ArGateReason {
  Fixing,                   // the run may fix
  Disabled,                 // ambiguity_resolution.enabled: false
  NoConsistentPhaseBiases,  // no phase information consistent with the clocks
  AntennaModelDifferent,    // the satellite antennas in use are not of the products' model
  AntennaModelUnknown,      // (auto) the products' or the ANTEX's model is not known
  PhaseInformationRefused,  // the phase information there was is refused (io/bias_bounds.h): every
                            // phase OSB row, or every wide-lane line of the clock header
};
std::string toString(ArGateReason r);  // "fixing", "disabled", "no consistent phase biases", ...

struct ArGateVerdict {
  AmbiguityResolutionMode mode = AmbiguityResolutionMode::Auto;
  bool fix = false;  // phase biases go to the processor
  ArGateReason reason = ArGateReason::Disabled;
  PhaseInformation phase = PhaseInformation::None;
  std::string detail;  // the check's specifics, e.g. "clocks IGS, biases COD"
  /// "ambiguity resolution: float (auto): no consistent phase biases (clocks IGS, biases COD)",
  /// "ambiguity resolution: fixing (auto): phase OSBs of the clocks' analysis centre (WHU, from the headers)".
  std::string text() const;
};

class ProductAssembly {
 public:
  /// Reads and checks the products (throws FileOpenError / ParseError on unreadable
  /// files, std::invalid_argument on inconsistent inputs).
  static ProductAssembly assemble(const ProductAssemblyInputs& inputs, const PppConfig& config);
  ProductAssembly() = default;
  ProductAssembly(ProductAssembly&&) = default;
  ProductAssembly& operator=(ProductAssembly&&) = default;

  /// The configuration with signals.systems and ambiguity_resolution.enabled
  /// resolved: make the estimator and the epoch processor from it.
  const PppConfig& config() const { return config_; }
  /// Orbits and clocks; nullptr when streamed.
  std::shared_ptr<const EphemerisSource> ephemeris() const { return ephemeris_; }
  /// The ANTEX files' calibrations, satellites of the products' family first.
  std::shared_ptr<const AntexCalibrations> antennas() const { return antennas_; }
  /// Code biases: the Bias-SINEX file's, else the SSR recording's; nullptr: none
  /// (a streamed SSR provider is the caller's: LiveGnssInput::biases()).
  std::shared_ptr<const BiasProvider> codeBiases() const { return code_biases_; }
  /// What PppEpochProcessor::setPhaseBiases gets: nullptr unless the gate fixes.
  const BiasProvider* phaseBiases() const { return verdict_.fix ? phase_biases_ : nullptr; }
  const ArGateVerdict& arGate() const { return verdict_; }
  /// The station's ocean loading from the BLQ file (by marker name).
  OceanLoadingLookup oceanLoading(const std::string& station) const;
  /// Everything the pipeline's PppProducts hold, for `station`.
  PppProducts products(const std::string& station) const;
  /// What was loaded and decided, one line each (systems, antennas, biases, AR gate).
  const std::vector<std::string>& notes() const { return notes_; }
  /// What went wrong while reading the files: problems of every run.
  const std::vector<std::string>& problems() const { return problems_; }
  std::size_t antexFiles() const { return set_ ? set_->antexFiles() : 0; }

  /// Streamed phase biases became available (the live SSR feed, a bag's carried
  /// biases): the gate is decided again with them. `provider` must outlive the
  /// assembly's use. Returns true when phaseBiases() changed.
  bool acceptStreamedPhaseBiases(const BiasProvider* provider, PhaseInformation kind);
  /// The product stream declared what it carries (e.g. with its first message: the
  /// clock centre, the satellite antenna model): the antennas (satellite family)
  /// and the gate are decided again; the systems stay (the estimator is made).
  /// Returns true when something changed: then antennas() and phaseBiases() are
  /// to be handed to a new epoch processor. False for file products. The notes of
  /// the decision made before the declaration (the antenna check, the gate) are
  /// replaced by the new decision's; the gate keeps the configured mode
  /// (ambiguity_resolution.enabled as written, not as resolved).
  bool declareStreamedProducts(const StreamedProductInfo& info);

 private:
  // The steps of assemble().
  void resolveSystems(const ProductAssemblyInputs& in, const std::vector<GnssSystem>& candidates,
                      const OrbitClockProducts& orbit_clock);
  /// Why `system` is not covered ("" when it is): no orbits and clocks (records,
  /// SSR corrections), not in the stream, no GLONASS channels, no satellite antennas.
  std::string whyNotCovered(const ProductAssemblyInputs& in, GnssSystem system,
                            const OrbitClockProducts& orbit_clock) const;
  /// A GLONASS channel of the observation header that the navigation records contradict: a problem.
  void checkGlonassChannels(const ProductAssemblyInputs& in, const OrbitClockProducts& orbit_clock);
  /// The products' spans against the observations' (product_coverage.h): a partial
  /// cover is a note, none a refusal (throws std::runtime_error naming both spans).
  void checkCoverage(const ProductAssemblyInputs& in, const OrbitClockProducts& orbit_clock);
  /// The observed satellites of the systems processed against those the orbits and
  /// clocks carry (and, with require_code_osb, the Bias-SINEX file's code OSBs): the
  /// missing ones are a note, none carried a refusal (product_coverage.h).
  void checkObservedSatellites(const ProductAssemblyInputs& in, const OrbitClockProducts& orbit_clock);
  void checkSatelliteAntennas(const ProductAssemblyInputs& in, const std::vector<std::string>& product_models,
                              const OrbitClockProducts& orbit_clock);
  void decideArGate(const ProductAssemblyInputs& in, const OrbitClockProducts& orbit_clock);
  /// Sets verdict_.phase and detail; true when the phase information there was is refused.
  bool findPhaseInformation(const ProductAssemblyInputs& in, const OrbitClockProducts& orbit_clock);
  /// Files: the OSBs of the clocks' centre, else integer-recovery clocks (as findPhaseInformation).
  bool phaseFromClockProducts(const ProductAssemblyInputs& in, const BiasSinexFile* bias_file,
                              const std::string& refused_rows);
  /// A recording with SSR: the stream's phase biases.
  void phaseFromSsr(const ProductAssemblyInputs& in, const OrbitClockProducts& orbit_clock);
  /// Streamed orbits and clocks: a Bias-SINEX file of the stream's clock centre.
  void phaseFromStreamCentre(const ProductAssemblyInputs& in, const BiasSinexFile* bias_file);

  ProductAssemblyInputs inputs_;
  PppConfig config_;
  std::shared_ptr<ProductSet> set_;
  std::vector<RinexClockHeader> clock_headers_;  // of inputs_.clk, read once
  std::shared_ptr<const AntexCalibrations> antennas_;
  std::shared_ptr<const EphemerisSource> ephemeris_;
  std::shared_ptr<const BiasProvider> code_biases_;
  std::shared_ptr<const BiasProvider> owned_phase_biases_;  // integer-recovery clock biases
  const BiasProvider* phase_biases_ = nullptr;              // the provider the gate judged
  const BiasProvider* streamed_phase_biases_ = nullptr;     // accepted from the stream, with its kind
  PhaseInformation streamed_phase_kind_ = PhaseInformation::None;
  std::optional<AntennaModelCheck> antenna_check_;
  ArGateVerdict verdict_;
  AmbiguityResolutionMode configured_ar_mode_ = AmbiguityResolutionMode::Auto;  // as the configuration asks
  std::vector<std::string> notes_, problems_;
  std::size_t decision_notes_begin_ = 0;  // notes_ from here: the antenna check and the gate's decision
};

}  // namespace ppp
