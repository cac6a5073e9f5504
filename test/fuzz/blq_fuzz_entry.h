#pragma once
// Fuzz entry for the BLQ reader: bytes -> memoryLineSource -> readBlq, then a
// lookup of every station read. BLQ never throws ParseError; FileOpenError and
// ParseError are still the only exceptions caught.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ppp_bayes_tree/io/products/blq_reader.h"

namespace ppp::fuzz {

inline void fuzzBlq(const std::uint8_t* data, std::size_t size) {
  auto source = memoryLineSource(std::string(reinterpret_cast<const char*>(data), size), "fuzz.blq");
  try {
    const BlqFile file = readBlq(*source);
    volatile double sink = 0.0;
    for (const auto& s : file.stations) {
      if (const auto* c = file.find(s.station).coefficients) sink = sink + c->amplitude_radial_m[0];
    }
    (void)file.find("ZIM200CHE");
    (void)file.report.summary();
  } catch (const ParseError&) {
  } catch (const FileOpenError&) {
  }
}

}  // namespace ppp::fuzz
