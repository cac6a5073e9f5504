#pragma once
// CRC-24Q (polynomial 0x1864CFB, Qualcomm): the checksum of RTCM 3 frames
// (RTCM 10403.3, section 4) and of Galileo I/NAV pages (Galileo OS SIS ICD 2.1, 4.3.2.1).
#include <cstddef>
#include <cstdint>

namespace ppp {

/// CRC-24Q of `size` bytes.
std::uint32_t crc24q(const std::uint8_t* data, std::size_t size);

}  // namespace ppp
