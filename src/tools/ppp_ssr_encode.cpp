// ppp_ssr_encode --nav NAV [--nav NAV ...] --sp3 SP3 --clk CLK [--bia BIA] [--atx ATX]
//                --out STREAM [--reference com|apc|apc-l1] [--interval-s 5] [--systems GER] [--orbit-clock-separate]
// Writes an RTCM 3 SSR stream (orbit+clock 1060/1066/1243, or 1057+1058/...,
// and code biases 1059/1065/1242 from --bia) that corrects the broadcast
// ephemeris of NAV towards the precise SP3/CLK products, as an analysis centre
// would (models/ssr_from_precise.h). --reference apc (= apc-if: the
// ionosphere-free phase centre) and apc-l1 (the L1 phase centre, as the IGS SSRA
// streams) need --atx (satellite PCO); models/satellite_reference_point.h.
// Default: centre of mass, 5 s, all systems the products and the NAV file share.
// Integer-recovery clocks (the clock header lists wide-lane satellite biases, "WL"
// comment lines of the CNES/CLS GRG products): phase biases 1265 (GPS L1/L2) and
// 1267 (Galileo E1/E5a) with the integer indicators set, whose ionosphere-free
// combination is zero and whose wide lane is the header's
// (models/clock_wide_lane_bias_provider.h); without --bia, the code biases are
// then those of the clocks' reference codes (zero: C1W/C2W, C1C/C5Q, C1X/C5X).
// --no-phase-biases leaves them out. The stream carries no antenna model: a user
// of it declares the products' one (config ssr.antenna_model, e.g. IGS14 for GRG).
#include <fstream>
#include <iostream>
#include <string>

#include "ppp_bayes_tree/io/products/antex_reader.h"
#include "ppp_bayes_tree/io/products/bias_sinex_reader.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_encoder.h"
#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/models/antex_calibrations.h"
#include "ppp_bayes_tree/models/clock_wide_lane_bias_provider.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/models/satellite_reference_point.h"
#include "ppp_bayes_tree/models/sinex_bias_provider.h"
#include "ppp_bayes_tree/models/ssr_from_precise.h"

namespace {
int usage(const std::string& why) {
  if (!why.empty()) std::cerr << "ppp_ssr_encode: " << why << "\n";
  std::cerr << "usage: ppp_ssr_encode --nav NAV [--nav NAV ...] --sp3 SP3 --clk CLK [--bia BIA] [--atx ATX]\n"
               "                      --out STREAM [--reference com|apc|apc-if|apc-l1] [--interval-s 5] [--systems GER]\n"
               "                      [--orbit-clock-separate] [--no-phase-biases]\n";
  return 2;
}
}  // namespace

int main(int argc, char** argv) {
  using namespace ppp;
  std::vector<std::string> nav, sp3, clk;
  std::optional<std::string> bia, atx;
  std::string out_path;
  SsrFromPreciseOptions options;
  bool phase_biases_wanted = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&](std::string& v) { if (i + 1 >= argc) return false; v = argv[++i]; return true; };
    std::string v;
    if (a == "--nav" && value(v)) nav.push_back(v);
    else if (a == "--sp3" && value(v)) sp3.push_back(v);
    else if (a == "--clk" && value(v)) clk.push_back(v);
    else if (a == "--bia" && value(v)) bia = v;
    else if (a == "--atx" && value(v)) atx = v;
    else if (a == "--out" && value(v)) out_path = v;
    else if (a == "--reference" && value(v)) {
      const auto parsed = parseEphemerisReference(v);
      if (!parsed) return usage("--reference is com, apc (apc-if) or apc-l1");
      options.reference = *parsed;
    } else if (a == "--interval-s" && value(v)) {
      try { options.interval_s = std::stod(v); } catch (...) { return usage("--interval-s needs seconds"); }
    } else if (a == "--systems" && value(v)) {
      options.systems.clear();
      for (char c : v) {
        const auto s = systemFromLetter(c);
        if (!s) return usage(std::string("unknown system letter ") + c);
        options.systems.push_back(*s);
      }
    } else if (a == "--orbit-clock-separate") options.combined = false;
    else if (a == "--no-phase-biases") phase_biases_wanted = false;
    else return usage("unknown or incomplete argument " + a);
  }
  if (nav.empty() || sp3.empty() || clk.empty() || out_path.empty()) return usage("--nav, --sp3, --clk and --out are required");
  try {
    std::vector<NavData> navs;
    for (const auto& n : nav) navs.push_back(readRinexNav(n));
    const PreciseEphemeris precise = PreciseEphemeris::load(sp3, clk);
    std::unique_ptr<AntexCalibrations> antennas;
    if (atx) antennas = std::make_unique<AntexCalibrations>(std::vector<AntexSource>{{fileBaseName(*atx), readAntexFile(*atx)}});
    std::unique_ptr<BiasSinexFile> bias_file;
    std::unique_ptr<SinexBiasProvider> biases;
    if (bia) {
      bias_file = std::make_unique<BiasSinexFile>(readBiasSinexFile(*bia));
      biases = std::make_unique<SinexBiasProvider>(*bias_file, fileBaseName(*bia));
    }
    // Integer phase biases from the wide-lane biases of integer-recovery clocks.
    std::shared_ptr<const ClockWideLaneBiasProvider> wide_lane;
    if (phase_biases_wanted) {
      std::vector<RinexClockHeader> headers;
      for (const auto& c : clk) headers.push_back(readRinexClockHeader(c));
      std::vector<std::string> problems;
      wide_lane = integerRecoveryClockBiases(headers, clk, problems);
      for (const auto& p : problems) std::cerr << "ppp_ssr_encode: " << p << "\n";
      std::cout << (wide_lane ? "phase biases: " + std::to_string(wide_lane->size()) +
                                    " wide-lane satellite biases of the integer-recovery clocks"
                              : std::string("phase biases: none (the clock header lists no wide-lane biases)"))
                << "\n";
    }
    const BiasProvider* code_biases = biases ? static_cast<const BiasProvider*>(biases.get()) : wide_lane.get();
    const auto orbit_span = precise.orbitSpan();
    const auto clock_span = precise.clockSpan();
    if (!orbit_span || !clock_span) throw std::runtime_error("no precise orbits or clocks loaded");
    const GnssTime first = std::max(orbit_span->first, clock_span->first);
    const GnssTime last = std::min(orbit_span->last, clock_span->last);
    const SsrFromPreciseResult r = ssrFromPrecise(navs, precise, antennas.get(), code_biases, first, last, options, wide_lane.get());
    std::ofstream out(out_path, std::ios::binary);
    if (!out) throw std::runtime_error("cannot write " + out_path);
    std::size_t bytes = 0;
    for (const auto& m : r.messages) {
      const auto frame = encodeSsrFrame(m);
      out.write(reinterpret_cast<const char*>(frame.data()), static_cast<std::streamsize>(frame.size()));
      bytes += frame.size();
    }
    if (!out) throw std::runtime_error("error writing " + out_path);
    for (const auto& n : r.notes) std::cout << n << "\n";
    std::cout << "reference point: "
              << ephemerisReferenceName(options.reference)
              << "\n";
    std::cout << "wrote " << out_path << ": " << r.messages.size() << " messages, " << bytes << " bytes, " << r.epochs
              << " epochs at " << options.interval_s << " s, " << r.satellite_epochs << " satellite-epochs\n";
    return r.messages.empty() ? 1 : 0;
  } catch (const std::exception& e) {
    std::cerr << "ppp_ssr_encode: " << e.what() << "\n";
    return 1;
  }
}
