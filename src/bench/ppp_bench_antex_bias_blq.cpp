// Prints read times of the ANTEX, Bias-SINEX and BLQ readers on the shared data
// and the ANTEX PCV interpolation rate.
// Usage: ppp_bench_antex_bias_blq [shared_data_dir]   (default ../shared/data)
#include <chrono>
#include <cstdio>
#include <string>

#include "ppp_bayes_tree/io/products/antex_reader.h"
#include "ppp_bayes_tree/io/products/bias_sinex_reader.h"
#include "ppp_bayes_tree/types/constants.h"

namespace {

template <typename F>
double bestOf(int runs, F f) {
  double best = 1e300;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (ms < best) best = ms;
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "../shared/data";
  try {
    const std::string atx = dir + "/antex/igs20_gps_satellites_trim.atx";
    const std::string bia = dir + "/zim2-2026-133/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz";
    std::size_t n = 0;
    std::printf("readAntexFile %s: %.1f ms (best of 5)\n", atx.c_str(),
                bestOf(5, [&] { n = ppp::readAntexFile(atx).antennas.size(); }));
    std::printf("  %zu antenna blocks\n", n);
    std::printf("readBiasSinexFile %s: %.1f ms (best of 5)\n", bia.c_str(),
                bestOf(5, [&] { n = ppp::readBiasSinexFile(bia).records.size(); }));
    std::printf("  %zu bias rows\n", n);

    const ppp::AntexFile file = ppp::readAntexFile(dir + "/antex/igs20_zim2_gps_trim.atx");
    const auto* g01 = file.receiver("TRM59800.00 NONE").antenna->frequency(ppp::GnssSystem::GPS, 1);
    constexpr int kEvaluations = 1000000;
    volatile double sink = 0.0;
    const double ms = bestOf(3, [&] {
      for (int i = 0; i < kEvaluations; ++i) {
        sink = sink + *g01->pcv_m((i % 9000) * 1e-4, (i % 6283) * 1e-3);
      }
    });
    std::printf("bilinear PCV evaluation: %.1f ns per call\n", ms * 1e6 / kEvaluations);

    const ppp::BiasSinexFile biases = ppp::readBiasSinexFile(bia);
    const auto sat = *ppp::SatelliteId::parse("G01");
    const auto code = *ppp::ObservationCode::parse("C1C");
    const ppp::GnssTime t = *biases.header.data_start + 1800.0;
    const double ms_osb = bestOf(3, [&] {
      for (int i = 0; i < 100000; ++i) sink = sink + biases.osb(sat, code, t)->value;
    });
    std::printf("osb() lookup: %.1f ns per call\n", ms_osb * 1e6 / 100000);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
