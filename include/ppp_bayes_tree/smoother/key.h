#pragma once
// Variable keys of the factor graph, with a readable symbol form.
//
// A Key packs, in 64 bits: a symbol character (8 bits), an optional label of up to
// three printable characters (24 bits) and an index (32 bits). Keys print as "x42"
// (no label) or "b(G05,3)" (label "G05"). The label is opaque to the library: it is
// only part of the key's identity and of its printed form.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ppp::smoother {

using Key = std::uint64_t;
using KeyVector = std::vector<Key>;

/// Builds the key for symbol `symbol` and index `index` ("x42").
constexpr Key symbolKey(char symbol, std::uint32_t index) {
  return (static_cast<Key>(static_cast<unsigned char>(symbol)) << 56) | index;
}

/// Builds the key for symbol, label (at most 3 characters, printable ASCII; longer
/// labels throw std::invalid_argument) and index ("b(G05,3)").
Key symbolKey(char symbol, std::string_view label, std::uint32_t index);

/// Symbol character of a key.
constexpr char keySymbol(Key key) { return static_cast<char>((key >> 56) & 0xff); }
/// Index part of a key.
constexpr std::uint32_t keyIndex(Key key) { return static_cast<std::uint32_t>(key & 0xffffffffu); }
/// Label part of a key ("" when none).
std::string keyLabel(Key key);

/// "x42" or "b(G05,3)".
std::string keyToString(Key key);
/// Comma-separated list of keyToString.
std::string keysToString(const KeyVector& keys);

}  // namespace ppp::smoother
