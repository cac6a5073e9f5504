#pragma once
// Fuzz entry for the simulator's trajectory CSV reader: bytes ->
// memoryLineSource -> readTrajectoryCsv, then the body elevation of every
// sample. Only the documented exceptions (ParseError, FileOpenError) are caught.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/simulation/flight_trajectory.h"

namespace ppp::fuzz {

inline void fuzzTrajectoryCsv(const std::uint8_t* data, std::size_t size) {
  auto source = memoryLineSource(std::string(reinterpret_cast<const char*>(data), size), "fuzz.csv");
  try {
    const auto samples = readTrajectoryCsv(*source, GnssTime::fromGpsWeek(2418, 0.0));
    volatile double sink = 0.0;
    for (const auto& s : samples) sink = sink + bodyElevation_rad(s, Eigen::Vector3d(0.0, 0.6, 0.8));
  } catch (const ParseError&) {
  } catch (const FileOpenError&) {
  }
}

}  // namespace ppp::fuzz
