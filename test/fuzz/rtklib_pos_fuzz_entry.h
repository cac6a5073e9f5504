#pragma once
// Fuzz entry for the RTKLIB .pos reader: bytes -> memoryLineSource ->
// readRtklibPos, then the statistics of what was read (any truth point).
// The reader never throws ParseError; FileOpenError and ParseError are still the
// only exceptions caught.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ppp_bayes_tree/evaluation/position_error_statistics.h"
#include "ppp_bayes_tree/evaluation/rtklib_pos.h"

namespace ppp::fuzz {

inline void fuzzRtklibPos(const std::uint8_t* data, std::size_t size) {
  auto source = memoryLineSource(std::string(reinterpret_cast<const char*>(data), size), "fuzz.pos");
  try {
    const PosFile file = readRtklibPos(*source);
    const auto stats =
        computePositionErrorStatistics(toSolutionEpochs(file), Eigen::Vector3d(4331299.5841, 567537.7070, 4633133.9645));
    (void)formatStatisticsTable(stats, "fuzz");
    (void)statisticsToJson(stats);
    (void)file.report.summary();
  } catch (const ParseError&) {
  } catch (const FileOpenError&) {
  }
}

}  // namespace ppp::fuzz
