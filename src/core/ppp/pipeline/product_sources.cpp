#include "ppp_bayes_tree/ppp/pipeline/product_sources.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/record_filter.h"
#include "ppp_bayes_tree/models/broadcast_products.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"

namespace ppp {

namespace {

struct InputName {
  ProductInput bit;
  std::string_view name;
};
constexpr std::array<InputName, 5> kInputNames{{
    {kProductSp3, "SP3"},
    {kProductClk, "clock"},
    {kProductNav, "navigation"},
    {kProductSsr, "SSR"},
    {kProductLiveSsr, "live SSR"},
}};

/// "a.sp3, b.sp3": the base names of `paths`.
std::string fileNames(const std::vector<std::string>& paths) {
  std::string out;
  for (const auto& p : paths) out += (out.empty() ? "" : ", ") + fileBaseName(p);
  return out;
}

ProductTimeSpan timeSpan(std::string kind, const std::vector<std::string>& paths,
                         const std::optional<ProductSpan>& span) {
  ProductTimeSpan out;
  out.kind = std::move(kind);
  out.files = fileNames(paths);
  if (span) {
    out.first = span->first;
    out.last = span->last;
  }
  return out;
}

/// The orbit records' span and, with clock files, the clock records' span.
std::vector<ProductTimeSpan> preciseSpans(const ProductAssemblyInputs& in, const PreciseEphemeris& ephemeris) {
  std::vector<ProductTimeSpan> spans = {timeSpan("orbits", in.sp3, ephemeris.orbitSpan())};
  if (!in.clk.empty()) spans.push_back(timeSpan("clocks", in.clk, ephemeris.clockSpan()));
  return spans;
}

}  // namespace

std::string productInputNames(unsigned inputs) {
  std::string out;
  for (const InputName& n : kInputNames)
    if (inputs & n.bit) out += (out.empty() ? "" : " + ") + std::string(n.name);
  return out.empty() ? std::string("nothing (streamed)") : out;
}

std::string OrbitClockProducts::missingReason(GnssSystem system) const {
  const auto of_system = [system](const SatelliteId& s) { return s.system == system; };
  if (!from_navigation_records) return "no orbits and clocks in the products";
  if (std::none_of(record_satellites.begin(), record_satellites.end(), of_system)) return "no navigation records";
  return "no SSR orbit and clock corrections in the stream";
}

OrbitClockProducts loadPreciseOrbitsAndClocks(const ProductAssemblyInputs& in, const PppConfig&,
                                              const RecordFilter& filter, std::vector<std::string>& notes,
                                              std::vector<std::string>& problems) {
  OrbitClockProducts out;
  PreciseEphemerisOptions options;
  options.check_products = in.check_products;
  auto ephemeris = std::make_shared<PreciseEphemeris>(PreciseEphemeris::load(in.sp3, in.clk, filter, options));
  const ParseReport& merge = ephemeris->mergeReport();
  if (!merge.problems().empty() || !merge.counters().empty()) notes.push_back("products merged: " + merge.summary(5));
  for (const auto& p : merge.problems()) problems.push_back(p.reason);
  if (merge.problemCount() > merge.problems().size())
    problems.push_back("... and " + std::to_string(merge.problemCount() - merge.problems().size()) +
                       " more problem(s) of the precise products");
  // A satellite is carried when it has orbits, and clocks when clock files are given.
  const std::set<SatelliteId> orbits = ephemeris->orbitSatellites();
  const std::set<SatelliteId> clocks = in.clk.empty() ? orbits : ephemeris->clockSatellites();
  std::set_intersection(orbits.begin(), orbits.end(), clocks.begin(), clocks.end(),
                        std::inserter(out.satellites, out.satellites.begin()));
  out.satellites_known = true;
  out.spans = preciseSpans(in, *ephemeris);
  out.ephemeris = std::move(ephemeris);
  return out;
}

OrbitClockProducts loadBroadcastOrbitsAndClocks(const ProductAssemblyInputs& in, const PppConfig& config,
                                                const RecordFilter&, std::vector<std::string>& notes,
                                                std::vector<std::string>& problems) {
  OrbitClockProducts out;
  std::optional<ObservationSpan> span;
  if (in.first && in.last) span = ObservationSpan{*in.first, *in.last};
  BroadcastProducts broadcast = loadBroadcastProducts(in.nav, in.ssr, in.ssr_reference, config.ssr,
                                                      config.ssr.fallback, in.stream_reference_time, span);
  out.ephemeris = std::move(broadcast.ephemeris);
  out.ssr_biases = std::move(broadcast.ssr_biases);
  out.ssr_phase_biases = broadcast.ssr_phase_biases;
  out.glonass_channels = broadcast.glonass_channels;
  // Carried: the satellites with records, and with SSR those the stream corrects.
  out.record_satellites = broadcast.record_satellites;
  out.from_navigation_records = true;
  if (in.ssr) {
    std::set_intersection(broadcast.record_satellites.begin(), broadcast.record_satellites.end(),
                          broadcast.corrected_satellites.begin(), broadcast.corrected_satellites.end(),
                          std::inserter(out.satellites, out.satellites.begin()));
  } else {
    out.satellites = broadcast.record_satellites;
  }
  out.satellites_known = true;
  notes.insert(notes.end(), broadcast.notes.begin(), broadcast.notes.end());
  problems.insert(problems.end(), broadcast.problems.begin(), broadcast.problems.end());
  return out;
}

OrbitClockProducts loadStreamedOrbitsAndClocks(const ProductAssemblyInputs&, const PppConfig&, const RecordFilter&,
                                           std::vector<std::string>&, std::vector<std::string>&) {
  return {};  // they arrive during the run
}

unsigned productInputsGiven(const OrbitClockFiles& files, bool live_ssr) {
  unsigned inputs = 0;
  if (!files.sp3.empty()) inputs |= kProductSp3;
  if (!files.clk.empty()) inputs |= kProductClk;
  if (!files.nav.empty()) inputs |= kProductNav;
  if (files.ssr) inputs |= kProductSsr;
  if (live_ssr && !inputs) inputs |= kProductLiveSsr;  // a live feed only without files
  return inputs;
}

unsigned productInputsGiven(const ProductAssemblyInputs& in) { return productInputsGiven(in, in.live_ssr); }

const ProductSource* findProductSource(unsigned inputs) {
  for (const ProductSource& s : kProductSources)
    if (s.inputs == inputs) return &s;
  return nullptr;
}

namespace {

/// "--sp3 --clk (precise); ..." : the file sources a tool accepts.
std::string acceptedFileSources() {
  std::string accepted;
  for (const ProductSource& s : kProductSources)
    if (!s.streamed) accepted += (accepted.empty() ? "" : "; ") + productInputNames(s.inputs) + " (" +
                                 std::string(s.name) + ")";
  return accepted;
}

}  // namespace

std::string productInputsProblem(unsigned inputs) {
  if (findProductSource(inputs)) return {};
  return "orbit and clock inputs " + productInputNames(inputs) + " make no product source: give " +
         acceptedFileSources();
}

std::string fileProductInputsProblem(unsigned inputs) {
  const ProductSource* source = findProductSource(inputs);
  if (source && !source->streamed) return {};
  if (source) return "no orbit and clock products given: give " + acceptedFileSources();
  return productInputsProblem(inputs);
}

const ProductSource& selectProductSource(const ProductAssemblyInputs& in) {
  const unsigned inputs = productInputsGiven(in);
  if (const ProductSource* s = findProductSource(inputs)) return *s;
  throw std::invalid_argument("product inputs: " + productInputsProblem(inputs));
}

}  // namespace ppp
