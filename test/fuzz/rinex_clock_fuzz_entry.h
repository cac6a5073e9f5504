#pragma once
// Fuzz entry for the RINEX clock reader: bytes -> memoryLineSource ->
// readRinexClock, then the clock service is queried on what was accepted.
// Only the documented exception types are caught.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"

namespace ppp::fuzz {

inline void fuzzRinexClock(const std::uint8_t* data, std::size_t size) {
  try {
    auto source = memoryLineSource(std::string(reinterpret_cast<const char*>(data), size), "fuzz.clk");
    const RinexClockFile file = readRinexClock(*source);
    (void)summarizeClock(file, "fuzz.clk");
    PreciseEphemeris eph;
    eph.addClocks(file);
    if (const auto span = eph.clockSpan()) {
      for (const auto& [sat, records] : file.satellite_clocks) {
        for (double f : {0.0, 0.5, 1.0}) (void)eph.clock(sat, span->first + f * (span->last - span->first));
      }
    }
  } catch (const ParseError&) {
  } catch (const FileOpenError&) {
  }
}

}  // namespace ppp::fuzz
