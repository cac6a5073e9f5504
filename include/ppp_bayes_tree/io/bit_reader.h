#pragma once
// BitReader: reads the big-endian (most significant bit first) bit fields of
// RTCM 3 messages (RTCM 10403.3, section 3.3: DF types uint/int/sign-magnitude)
// and of navigation-message words.
//
// Reading past the end does not throw: it returns 0 and sets overrun(), so a
// decoder reads a whole message and then checks ok() once, reporting a
// truncated message with its type and length instead of crashing.
#include <cstddef>
#include <cstdint>

namespace ppp {

class BitReader {
 public:
  BitReader(const std::uint8_t* data, std::size_t size_bytes, std::size_t start_bit = 0)
      : data_(data), size_bits_(size_bytes * 8), position_bit_(start_bit) {}

  /// Unsigned field of `bits` (0..64) bits.
  std::uint64_t u(int bits);
  /// Two's-complement signed field of `bits` (1..64) bits.
  std::int64_t s(int bits);
  /// Sign-magnitude field (sign bit first), as GLONASS ICD fields (RTCM DF "intS").
  std::int64_t sm(int bits);
  bool flag() { return u(1) != 0; }
  void skip(int bits);

  std::size_t positionBits() const { return position_bit_; }
  std::size_t sizeBits() const { return size_bits_; }
  std::size_t remainingBits() const { return position_bit_ >= size_bits_ ? 0 : size_bits_ - position_bit_; }
  /// True when a read went past the end of the data.
  bool overrun() const { return overrun_; }
  bool ok() const { return !overrun_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_bits_;
  std::size_t position_bit_;
  bool overrun_ = false;
};

/// Unsigned big-endian bit field at `start_bit` of `data` (no bounds check: the
/// caller guarantees start_bit + bits <= 8 * size).
std::uint64_t readBitsUnsigned(const std::uint8_t* data, std::size_t start_bit, int bits);

}  // namespace ppp
