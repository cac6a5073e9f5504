#pragma once
// Fuzz entry for the Compact RINEX decoder alone: the bytes are always treated
// as Compact RINEX (a CRINEX 3.0 or 1.0 first line is prepended when absent, so
// that the fuzzer spends its time in the decoder), every restored line is read.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ppp_bayes_tree/io/rinex/hatanaka_decoder.h"

namespace ppp::fuzz {

inline void fuzzHatanaka(const std::uint8_t* data, std::size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  if (bytes.find("COMPACT RINEX FORMAT") == std::string::npos) {
    const bool v1 = size > 0 && (data[0] & 1) != 0;
    std::string first = v1 ? "1.0" : "3.0";
    first.resize(20, ' ');
    first += "COMPACT RINEX FORMAT";
    first.resize(60, ' ');
    first += "CRINEX VERS   / TYPE\n";
    bytes = first + bytes;
  }
  try {
    auto source = observationSource(memoryLineSource(std::move(bytes), "fuzz.crx"));
    std::string line;
    while (source->next(line)) {
    }
    if (auto* crx = dynamic_cast<HatanakaDecoder*>(source.get())) (void)crx->takeProblems();
  } catch (const ParseError&) {
  } catch (const FileOpenError&) {
  }
}

}  // namespace ppp::fuzz
