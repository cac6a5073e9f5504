#pragma once
// Fuzz entry for the ANTEX reader: bytes -> memoryLineSource -> readAntex, then
// every lookup and interpolation on what was read. Only the documented
// exceptions (ParseError, FileOpenError) are caught.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ppp_bayes_tree/io/products/antex_reader.h"

namespace ppp::fuzz {

inline void fuzzAntex(const std::uint8_t* data, std::size_t size) {
  auto source = memoryLineSource(std::string(reinterpret_cast<const char*>(data), size), "fuzz.atx");
  try {
    const AntexFile file = readAntex(*source);
    volatile double sink = 0.0;
    for (const auto& a : file.antennas) {
      if (a.satellite && a.valid_from) sink = sink + (file.satellite(*a.satellite, *a.valid_from) ? 1.0 : 0.0);
      if (!a.satellite) sink = sink + (file.receiver(a.model, "XXXX").antenna ? 1.0 : 0.0);
      for (const auto& f : a.frequencies) {
        for (double z : {0.0, 0.1, 0.5, 1.0, 1.6, 3.2}) {
          for (double az : {-1.0, 0.0, 2.0, 6.28, 7.0}) {
            if (const auto v = f.pcv_m(z, az)) sink = sink + *v;
          }
          if (const auto v = f.pcv.evaluateNoAzimuth_m(z)) sink = sink + *v;
        }
      }
      sink = sink + (a.frequency(GnssSystem::GPS, 5, FrequencyFallback::NearestSameSystem).calibration ? 1.0 : 0.0);
    }
    (void)file.report.summary();
  } catch (const ParseError&) {
  } catch (const FileOpenError&) {
  }
}

}  // namespace ppp::fuzz
