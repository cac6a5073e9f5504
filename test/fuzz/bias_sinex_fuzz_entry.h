#pragma once
// Fuzz entry for the Bias-SINEX reader: bytes -> memoryLineSource ->
// readBiasSinex, then lookups on every row read. Only the documented exceptions
// (ParseError, FileOpenError) are caught.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ppp_bayes_tree/io/products/bias_sinex_reader.h"

namespace ppp::fuzz {

inline void fuzzBiasSinex(const std::uint8_t* data, std::size_t size) {
  auto source = memoryLineSource(std::string(reinterpret_cast<const char*>(data), size), "fuzz.bia");
  try {
    const BiasSinexFile file = readBiasSinex(*source);
    volatile double sink = 0.0;
    for (const auto& r : file.records) {
      const GnssTime t = r.start ? *r.start : GnssTime();
      if (r.satellite) {
        if (const auto v = file.osb(*r.satellite, r.obs1, t)) sink = sink + v->value;
        if (r.obs2) {
          if (const auto v = file.dsb(*r.satellite, r.obs1, *r.obs2, t)) sink = sink + v->value;
        }
      } else if (const auto v = file.stationOsb(r.station, r.system, r.obs1, t)) {
        sink = sink + v->value;
      }
    }
    (void)file.stations();
    (void)file.report.summary();
  } catch (const ParseError&) {
  } catch (const FileOpenError&) {
  }
}

}  // namespace ppp::fuzz
