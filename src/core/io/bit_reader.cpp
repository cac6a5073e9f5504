#include "ppp_bayes_tree/io/bit_reader.h"

namespace ppp {

std::uint64_t readBitsUnsigned(const std::uint8_t* data, std::size_t start_bit, int bits) {
  std::uint64_t value = 0;
  std::size_t bit = start_bit;
  int left = bits;
  // Leading bits up to a byte boundary, then whole bytes, then the tail.
  while (left > 0 && (bit & 7u) != 0) {
    value = (value << 1) | ((data[bit >> 3] >> (7 - (bit & 7u))) & 1u);
    ++bit;
    --left;
  }
  while (left >= 8) {
    value = (value << 8) | data[bit >> 3];
    bit += 8;
    left -= 8;
  }
  while (left > 0) {
    value = (value << 1) | ((data[bit >> 3] >> (7 - (bit & 7u))) & 1u);
    ++bit;
    --left;
  }
  return value;
}

std::uint64_t BitReader::u(int bits) {
  if (bits <= 0) return 0;
  if (bits > 64 || position_bit_ + static_cast<std::size_t>(bits) > size_bits_) {
    overrun_ = true;
    position_bit_ = size_bits_;
    return 0;
  }
  const std::uint64_t value = readBitsUnsigned(data_, position_bit_, bits);
  position_bit_ += static_cast<std::size_t>(bits);
  return value;
}

std::int64_t BitReader::s(int bits) {
  if (bits <= 0) return 0;
  const std::uint64_t raw = u(bits);
  if (bits == 64) return static_cast<std::int64_t>(raw);
  const std::uint64_t sign = std::uint64_t{1} << (bits - 1);
  // A negative field is -(2^bits - raw); 2^bits - raw is at most 2^(bits-1) and fits
  // (subtracting 2^bits as a signed number overflowed for a 63-bit field).
  return (raw & sign) ? -static_cast<std::int64_t>((sign << 1) - raw) : static_cast<std::int64_t>(raw);
}

std::int64_t BitReader::sm(int bits) {
  if (bits <= 1) return 0;
  const bool negative = u(1) != 0;
  const auto magnitude = static_cast<std::int64_t>(u(bits - 1));
  return negative ? -magnitude : magnitude;
}

void BitReader::skip(int bits) {
  if (bits <= 0) return;
  if (position_bit_ + static_cast<std::size_t>(bits) > size_bits_) {
    overrun_ = true;
    position_bit_ = size_bits_;
    return;
  }
  position_bit_ += static_cast<std::size_t>(bits);
}

}  // namespace ppp
