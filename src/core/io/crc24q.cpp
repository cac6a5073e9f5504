#include "ppp_bayes_tree/io/crc24q.h"

#include <array>

namespace ppp {
namespace {

std::array<std::uint32_t, 256> makeCrc24qTable() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t crc = i << 16;
    for (int bit = 0; bit < 8; ++bit) {
      crc <<= 1;
      if (crc & 0x1000000u) crc ^= 0x1864CFBu;
    }
    table[i] = crc & 0xFFFFFFu;
  }
  return table;
}

}  // namespace

std::uint32_t crc24q(const std::uint8_t* data, std::size_t size) {
  static const std::array<std::uint32_t, 256> table = makeCrc24qTable();
  std::uint32_t crc = 0;
  for (std::size_t i = 0; i < size; ++i) {
    crc = ((crc << 8) & 0xFFFFFFu) ^ table[((crc >> 16) ^ data[i]) & 0xFFu];
  }
  return crc;
}

}  // namespace ppp
