// ppp_ssr_check --nav NAV [--nav NAV2 ...] --ssr STREAM --sp3 SP3 [--atx ATX] [--reference com|apc|apc-l1|apc-if] [--apc l1|if]
// (--clk: compare the clocks with RINEX clock files instead of the SP3 clocks;
//  --reference apc: the antenna phase centre, of L1 unless --apc if, as the IGS SSRA streams;
//  apc-l1 / apc-if name the phase centre directly; --apc overrides it;
//  models/satellite_reference_point.h)
// Compares SSR-corrected broadcast orbits and clocks with a precise SP3 file
// (evaluation/ssr_check.h). Last line: "orbit 3D RMS <m> m, clock RMS <ns> ns, <N> satellite-epochs".
#include <iostream>
#include <string>

#include "ppp_bayes_tree/evaluation/ssr_check.h"
#include "ppp_bayes_tree/models/satellite_reference_point.h"

namespace {
int usage() {
  std::cerr << "usage: ppp_ssr_check --nav NAV [--nav NAV ...] --ssr STREAM --sp3 SP3 [--clk CLK] [--atx ATX] [--reference com|apc|apc-l1|apc-if] [--apc l1|if]\n";
  return 2;
}
}  // namespace

int main(int argc, char** argv) {
  ppp::SsrCheckRequest req;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    const char* v = nullptr;
    if (a == "--nav" && (v = next())) req.nav.emplace_back(v);
    else if (a == "--ssr" && (v = next())) req.ssr = v;
    else if (a == "--sp3" && (v = next())) req.sp3 = v;
    else if (a == "--atx" && (v = next())) req.atx = v;
    else if (a == "--clk" && (v = next())) req.clk.emplace_back(v);
    else if (a == "--reference" && (v = next())) {
      const std::string r = v;
      if (r == "apc") req.reference = ppp::EphemerisReference::AntennaPhaseCentreL1;  // this tool's default flavour
      else if (const auto parsed = ppp::parseEphemerisReference(r)) req.reference = *parsed;
      else return usage();
    } else if (a == "--apc" && (v = next())) {
      const std::string r = v;
      if (r == "l1") req.apc = ppp::SsrApcFrequency::FirstFrequency;
      else if (r == "if") req.apc = ppp::SsrApcFrequency::IonosphereFree;
      else return usage();
    } else return usage();
  }
  if (req.nav.empty() || req.ssr.empty() || req.sp3.empty()) return usage();
  try {
    const ppp::SsrCheckResult result = ppp::checkSsrAgainstSp3(req);
    std::cout << ppp::formatSsrCheck(result);
    return result.satellite_epochs > 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "ppp_ssr_check: " << e.what() << "\n";
    return 1;
  }
}
