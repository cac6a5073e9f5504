#include "ppp_bayes_tree/models/broadcast_products.h"

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"
#include "ppp_bayes_tree/models/broadcast_ssr_ephemeris.h"
#include "ppp_bayes_tree/models/ssr_bias_provider.h"

namespace ppp {

BroadcastProducts loadBroadcastProducts(const std::vector<std::string>& nav, const std::optional<std::string>& ssr,
                                        std::optional<EphemerisReference> ssr_reference, SsrAgeLimits limits) {
  BroadcastProducts out;
  std::vector<NavData> navs;
  std::optional<GnssTime> reference_time;
  std::string names;
  for (const auto& path : nav) {
    navs.push_back(readRinexNav(path));
    if (!reference_time) reference_time = navs.back().first_toc;
    names += (names.empty() ? "" : ", ") + fileBaseName(path);
  }
  if (!ssr) {
    auto store = std::make_shared<BroadcastEphemerisStore>();
    for (const auto& n : navs) store->add(n);
    out.ephemeris = store;
    out.notes.push_back("orbits and clocks: broadcast navigation records only (" + names +
                        "): metre-level accuracy, not precise products");
    return out;
  }
  const SsrStreamFile stream = readSsrStreamFile(*ssr, reference_time);
  auto store = std::make_shared<SsrCorrectionStore>(limits);
  for (const auto& m : stream.messages) store->add(m);
  BroadcastSsrOptions options;
  const auto from_name = ssrReferenceFromStreamName(fileBaseName(*ssr));
  options.reference = ssr_reference ? *ssr_reference : from_name.value_or(EphemerisReference::CentreOfMass);
  auto eph = std::make_shared<BroadcastSsrEphemeris>(navs, store, options);
  out.notes.push_back("orbits and clocks: " + names + " corrected by SSR stream " + fileBaseName(*ssr) + " (" +
                      std::to_string(stream.summary.messages) + " messages; orbits at the " +
                      std::string(ephemerisReferenceName(options.reference)) +
                      (ssr_reference ? ", as given" : from_name ? ", from the stream name" : ", by default") + ")");
  const auto describe = [&](const StreamCounters& c, const std::string& what) {
    if (c.totalProblems() == 0) return;
    std::string text = fileBaseName(*ssr) + ": " + std::to_string(c.totalProblems()) + " " + what;
    if (!c.problems.empty()) text += ", first: " + c.problems.front().describe();
    out.problems.push_back(text);
  };
  describe(stream.counters, "problem(s) while decoding");
  describe(eph->consistency(), "SSR correction(s) without a broadcast record of their IOD");
  if (store->codeBiasCount() > 0 || store->phaseBiasCount() > 0)
    out.ssr_biases = std::make_shared<SsrBiasProvider>(store, fileBaseName(*ssr));
  out.ephemeris = eph;
  return out;
}

}  // namespace ppp
