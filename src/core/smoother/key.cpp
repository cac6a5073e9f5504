#include "ppp_bayes_tree/smoother/key.h"

#include <stdexcept>

namespace ppp::smoother {

Key symbolKey(char symbol, std::string_view label, std::uint32_t index) {
  if (label.size() > 3) throw std::invalid_argument("key label longer than 3 characters: " + std::string(label));
  Key key = symbolKey(symbol, index);
  for (std::size_t i = 0; i < label.size(); ++i) {
    const auto c = static_cast<unsigned char>(label[i]);
    if (c < 0x21 || c > 0x7e) throw std::invalid_argument("key label must be printable ASCII");
    key |= static_cast<Key>(c) << (48 - 8 * i);
  }
  return key;
}

std::string keyLabel(Key key) {
  std::string label;
  for (int i = 0; i < 3; ++i) {
    const char c = static_cast<char>((key >> (48 - 8 * i)) & 0xff);
    if (c == 0) break;
    label.push_back(c);
  }
  return label;
}

std::string keyToString(Key key) {
  const std::string label = keyLabel(key);
  std::string out(1, keySymbol(key));
  if (label.empty()) return out + std::to_string(keyIndex(key));
  return out + "(" + label + "," + std::to_string(keyIndex(key)) + ")";
}

std::string keysToString(const KeyVector& keys) {
  std::string out;
  for (std::size_t i = 0; i < keys.size(); ++i) out += (i ? "," : "") + keyToString(keys[i]);
  return out;
}

}  // namespace ppp::smoother
