// Prints reading times of the WUM SP3/CLK products and the cost of one orbit and
// clock query. Usage: ppp_bench_precise_products [sp3] [clk]   (defaults: the CCJ2
// dataset under ../shared/data beside the repository, or $PPP_SHARED_DATA).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/products/sp3_reader.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"

namespace {
double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

int main(int argc, char** argv) {
  const char* env = std::getenv("PPP_SHARED_DATA");
  const std::string data = env ? env : "../shared/data";
  const std::string sp3 = argc > 1 ? argv[1] : data + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz";
  const std::string clk = argc > 2 ? argv[2] : data + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz";
  try {
    auto t0 = std::chrono::steady_clock::now();
    const ppp::Sp3File orbit = ppp::readSp3(sp3);
    std::printf("read SP3  %-70s %8.3f s (%zu epochs, %zu satellites)\n", sp3.c_str(), secondsSince(t0),
                orbit.epochs.size(), orbit.satellites.size());
    t0 = std::chrono::steady_clock::now();
    const ppp::RinexClockFile clock = ppp::readRinexClock(clk, ppp::RinexClockReadOptions{false});
    std::printf("read CLK  %-70s %8.3f s (%zu satellites)\n", clk.c_str(), secondsSince(t0),
                clock.satellite_clocks.size());
    ppp::PreciseEphemeris eph;
    t0 = std::chrono::steady_clock::now();
    eph.addOrbits(orbit);
    eph.addClocks(clock);
    std::printf("build service %.3f s\n", secondsSince(t0));
    const auto span = eph.orbitSpan();
    if (!span) return 1;
    std::size_t n = 0, ok = 0;
    t0 = std::chrono::steady_clock::now();
    for (double dt = 0.0; dt <= span->last - span->first; dt += 30.0) {
      for (const auto& [sat, records] : orbit.satellites) {
        ok += eph.orbit(sat, span->first + dt).ok();
        ++n;
      }
    }
    const double orbit_s = secondsSince(t0);
    std::printf("orbit queries: %zu (%zu ok), %.2f us each\n", n, ok, 1e6 * orbit_s / static_cast<double>(n));
    n = ok = 0;
    t0 = std::chrono::steady_clock::now();
    for (double dt = 0.0; dt <= span->last - span->first; dt += 30.0) {
      for (const auto& [sat, records] : orbit.satellites) {
        ok += eph.clock(sat, span->first + dt + 7.0).ok();
        ++n;
      }
    }
    std::printf("clock queries: %zu (%zu ok), %.2f us each\n", n, ok,
                1e6 * secondsSince(t0) / static_cast<double>(n));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
