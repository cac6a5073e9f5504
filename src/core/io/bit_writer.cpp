#include "ppp_bayes_tree/io/bit_writer.h"

#include <stdexcept>
#include <string>

namespace ppp {

bool BitWriter::fits(std::uint64_t value, int bits) {
  if (bits >= 64) return true;
  if (bits <= 0) return value == 0;
  return value < (std::uint64_t{1} << bits);
}

bool BitWriter::fitsSigned(std::int64_t value, int bits) {
  if (bits >= 64) return true;
  if (bits <= 0) return value == 0;
  const std::int64_t max = (std::int64_t{1} << (bits - 1)) - 1;
  return value >= -max - 1 && value <= max;
}

void BitWriter::putUnsigned(std::uint64_t value, int bits) {
  if (bits < 0 || bits > 64 || !fits(value, bits)) {
    throw std::out_of_range("BitWriter: " + std::to_string(value) + " does not fit " + std::to_string(bits) +
                            " unsigned bits");
  }
  for (int i = bits - 1; i >= 0; --i) {
    if ((size_bits_ & 7u) == 0) bytes_.push_back(0);
    if ((value >> i) & 1u) bytes_.back() |= static_cast<std::uint8_t>(0x80u >> (size_bits_ & 7u));
    ++size_bits_;
  }
}

void BitWriter::putSigned(std::int64_t value, int bits) {
  if (bits <= 0 || bits > 64 || !fitsSigned(value, bits)) {
    throw std::out_of_range("BitWriter: " + std::to_string(value) + " does not fit " + std::to_string(bits) +
                            " signed bits");
  }
  const std::uint64_t mask = bits == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1;
  putUnsigned(static_cast<std::uint64_t>(value) & mask, bits);
}

void BitWriter::putSignMagnitude(std::int64_t value, int bits) {
  const std::uint64_t magnitude = static_cast<std::uint64_t>(value < 0 ? -value : value);
  if (bits <= 1 || bits > 64 || !fits(magnitude, bits - 1)) {
    throw std::out_of_range("BitWriter: " + std::to_string(value) + " does not fit " + std::to_string(bits) +
                            " sign-magnitude bits");
  }
  putUnsigned(value < 0 ? 1u : 0u, 1);
  putUnsigned(magnitude, bits - 1);
}

}  // namespace ppp
