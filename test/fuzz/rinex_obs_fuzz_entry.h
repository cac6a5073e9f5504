#pragma once
// Fuzz entry for the RINEX observation reader (plain, gzip or Compact RINEX
// bytes): reads the header and every epoch; only the documented exceptions
// (ParseError for a bad header, FileOpenError) are caught.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ppp_bayes_tree/io/rinex/hatanaka_decoder.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"

namespace ppp::fuzz {

inline void fuzzRinexObs(const std::uint8_t* data, std::size_t size) {
  try {
    RinexObsReader reader(
        observationSource(memoryLineSource(std::string(reinterpret_cast<const char*>(data), size), "fuzz")));
    ObsEpoch epoch;
    std::size_t n = 0;
    while (reader.next(epoch)) n += epoch.observations.size();
    (void)n;
    (void)reader.report().summary();
  } catch (const ParseError&) {
  } catch (const FileOpenError&) {
  }
}

}  // namespace ppp::fuzz
