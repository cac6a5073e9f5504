#pragma once
// The table of orbit and clock sources: the one place that says which product
// inputs make which source, how the source is loaded, whether its satellite
// antenna model is the configuration's (ssr.antenna_model) and where its phase
// information for PPP-AR comes from. ProductAssembly (ppp_solve, the nodes, the
// live input) selects its row from the inputs given and goes through it;
// ppp_solve checks its options against it and lists it in --help.
//
// Adding a source: its loader (its own files, e.g. models/<source>_products.h);
// here its input (a field of OrbitClockFiles, a ProductInput bit), its row in
// kProductSources and its loader function (product_sources.cpp); and the
// ppp_solve option that gives its files. See doc/layout.md.
//
// The table is a constant (no registration at static initialisation).
#include <array>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "ppp_bayes_tree/models/bias_provider.h"
#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/ppp/pipeline/product_coverage.h"
#include "ppp_bayes_tree/types/glonass_channels.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

struct ProductAssemblyInputs;
struct PppConfig;
struct RecordFilter;

/// The orbit and clock files of a run (ppp_solve's options, PppInputFiles and
/// ProductAssemblyInputs are made of them): which are given selects the source.
struct OrbitClockFiles {
  /// Precise orbits and clocks (both, or neither).
  std::vector<std::string> sp3, clk;
  /// Broadcast navigation files: orbits and clocks from them instead of SP3/CLK,
  /// corrected by the SSR stream when one is given (models/broadcast_products.h).
  std::vector<std::string> nav;
  std::optional<std::string> ssr;
  std::optional<EphemerisReference> ssr_reference;  // nullopt: from the stream name
};

/// The product inputs a source is made of (a set: bits).
enum ProductInput : unsigned {
  kProductSp3 = 1u << 0,      // SP3 orbit files
  kProductClk = 1u << 1,      // RINEX clock files
  kProductNav = 1u << 2,      // broadcast navigation files (RINEX, or RTCM 3 / UBX recordings)
  kProductSsr = 1u << 3,      // an RTCM SSR recording
  kProductLiveSsr = 1u << 4,  // a live SSR feed (the nodes' ros.live corrections)
};
/// "SP3 + clock", "navigation + SSR", "nothing (streamed)".
std::string productInputNames(unsigned inputs);

/// What a source's loader gives: the ephemeris (null when streamed), the
/// satellites it carries (satellites_known false: not known before the run)
/// and the SSR biases of a recording.
struct OrbitClockProducts {
  std::shared_ptr<const EphemerisSource> ephemeris;
  /// Precise: the satellites with orbits (and clocks); broadcast: those with
  /// navigation records; broadcast + SSR: those with records and SSR orbit and
  /// clock corrections.
  std::set<SatelliteId> satellites;
  bool satellites_known = false;
  /// Broadcast sources: the satellites with navigation records (the SSR stream
  /// corrects some of them); empty for precise and streamed sources.
  std::set<SatelliteId> record_satellites;
  bool from_navigation_records = false;  // a broadcast source (with SSR: `satellites` are those it corrects)
  /// Why `system` has no satellite here ("no orbits and clocks in the products",
  /// "no navigation records", "no SSR orbit and clock corrections in the stream").
  std::string missingReason(GnssSystem system) const;
  std::shared_ptr<const BiasProvider> ssr_biases;
  bool ssr_phase_biases = false;
  GlonassChannels glonass_channels;  // from navigation records (broadcast sources)
  /// The spans of the orbit and clock records read (precise sources), for the
  /// coverage check (product_coverage.h); empty where the source states none.
  std::vector<ProductTimeSpan> spans;
};

using OrbitClockLoader = OrbitClockProducts (*)(const ProductAssemblyInputs& in, const PppConfig& config,
                                                const RecordFilter& filter, std::vector<std::string>& notes,
                                                std::vector<std::string>& problems);

/// Where the PPP-AR gate looks for phase information of a source's clocks.
enum class SourcePhaseInformation {
  ClockProducts,  // phase OSBs of the clocks' analysis centre, integer-recovery clock headers
  SsrRecording,   // the SSR recording's phase biases (none from broadcast records alone)
  Stream,         // a Bias-SINEX file of the stream's clock centre, the stream's biases later
};

struct ProductSource {
  std::string_view name;         // "precise": in notes and --help
  std::string_view description;  // one line for --help
  unsigned inputs = 0;           // exactly these inputs select the row (ProductInput bits)
  bool streamed = false;         // orbits and clocks arrive during the run (not known at the start)
  bool ssr_antenna_model = false;  // its satellite antenna model is the configuration's ssr.antenna_model
  SourcePhaseInformation phase = SourcePhaseInformation::ClockProducts;
  OrbitClockLoader load = nullptr;
  /// `signals.systems: auto` may take the frequency-division systems (GLONASS)
  /// from this source. False for a live SSR feed: it shows which systems it
  /// corrects only as it streams, after the receiver state (one clock per
  /// system) is made, and GLONASS corrections are not in every feed.
  bool auto_frequency_division = true;
};

// The loaders of the sources (product_sources.cpp).
OrbitClockProducts loadPreciseOrbitsAndClocks(const ProductAssemblyInputs& in, const PppConfig& config,
                                              const RecordFilter& filter, std::vector<std::string>& notes,
                                              std::vector<std::string>& problems);
OrbitClockProducts loadBroadcastOrbitsAndClocks(const ProductAssemblyInputs& in, const PppConfig& config,
                                                const RecordFilter& filter, std::vector<std::string>& notes,
                                                std::vector<std::string>& problems);
OrbitClockProducts loadStreamedOrbitsAndClocks(const ProductAssemblyInputs& in, const PppConfig& config,
                                           const RecordFilter& filter, std::vector<std::string>& notes,
                                           std::vector<std::string>& problems);

/// Every orbit and clock source.
inline constexpr std::array<ProductSource, 5> kProductSources{{
    {"precise", "SP3 orbits and RINEX clocks (ppp_solve --sp3 --clk): centimetre level", kProductSp3 | kProductClk,
     false, false, SourcePhaseInformation::ClockProducts, &loadPreciseOrbitsAndClocks},
    {"broadcast+ssr",
     "broadcast records corrected by an RTCM SSR recording (--nav --ssr), broadcast where the corrections are too old",
     kProductNav | kProductSsr, false, true, SourcePhaseInformation::SsrRecording, &loadBroadcastOrbitsAndClocks},
    {"broadcast", "broadcast navigation records only (--nav): metre level", kProductNav, false, false,
     SourcePhaseInformation::SsrRecording, &loadBroadcastOrbitsAndClocks},
    {"live-ssr", "a live SSR feed with its broadcast records (the nodes' ros.live corrections)", kProductLiveSsr, true,
     true, SourcePhaseInformation::Stream, &loadStreamedOrbitsAndClocks, false},
    {"streamed",
     "orbits and clocks streamed to a node (a PreciseCorrections topic or bag, or the live broadcast records)", 0u,
     true, false, SourcePhaseInformation::Stream, &loadStreamedOrbitsAndClocks},
}};

/// The ProductInput bits of the files given (and of a live SSR feed, without files).
unsigned productInputsGiven(const OrbitClockFiles& files, bool live_ssr = false);
unsigned productInputsGiven(const ProductAssemblyInputs& in);
/// The row `inputs` select; nullptr when none does.
const ProductSource* findProductSource(unsigned inputs);
/// The row of `in`; throws std::invalid_argument naming the inputs given and the
/// combinations the table accepts when none matches.
const ProductSource& selectProductSource(const ProductAssemblyInputs& in);
/// Empty when `inputs` select a row, else why not (for a tool's usage message).
std::string productInputsProblem(unsigned inputs);
/// As productInputsProblem for a run from files (ppp_solve): a streamed source
/// (no orbit and clock file at all) is a problem too, since nothing streams them.
std::string fileProductInputsProblem(unsigned inputs);

}  // namespace ppp
