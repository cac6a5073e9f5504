#pragma once
// BitWriter: the inverse of BitReader, for encoders (RTCM SSR streams made from
// precise products, generated MSM streams for benchmarks, test frames).
// Values that do not fit their field are an error the caller must avoid:
// fits()/fitsSigned() tell, and put*() throw std::out_of_range otherwise.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ppp {

class BitWriter {
 public:
  void putUnsigned(std::uint64_t value, int bits);
  void putSigned(std::int64_t value, int bits);
  /// Sign-magnitude (sign bit first).
  void putSignMagnitude(std::int64_t value, int bits);
  void putFlag(bool value) { putUnsigned(value ? 1u : 0u, 1); }

  static bool fits(std::uint64_t value, int bits);
  static bool fitsSigned(std::int64_t value, int bits);

  std::size_t sizeBits() const { return size_bits_; }
  /// The bytes, the last one padded with zero bits.
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
  std::size_t size_bits_ = 0;
};

}  // namespace ppp
