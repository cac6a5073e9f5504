#pragma once
// Fuzz entry for the SP3 reader: bytes -> memoryLineSource -> readSp3, then the
// precise-ephemeris service built on the result is queried, so interpolation on
// whatever the reader accepted is exercised too. Only the documented exception
// types are caught.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/products/sp3_reader.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"

namespace ppp::fuzz {

inline void fuzzSp3(const std::uint8_t* data, std::size_t size) {
  try {
    auto source = memoryLineSource(std::string(reinterpret_cast<const char*>(data), size), "fuzz.sp3");
    const Sp3File file = readSp3(*source);
    (void)summarizeSp3(file, "fuzz.sp3");
    PreciseEphemeris eph;
    eph.addOrbits(file);
    if (const auto span = eph.orbitSpan()) {
      for (const auto& [sat, records] : file.satellites) {
        for (double f : {0.0, 0.37, 0.5, 1.0}) {
          const GnssTime t = span->first + f * (span->last - span->first);
          (void)eph.orbit(sat, t);
          (void)eph.clock(sat, t);
        }
      }
    }
  } catch (const ParseError&) {
  } catch (const FileOpenError&) {
  }
}

}  // namespace ppp::fuzz
