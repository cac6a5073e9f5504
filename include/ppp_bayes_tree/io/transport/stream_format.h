#pragma once
// Recognises a binary receiver/correction stream by its content: an RTCM 3 frame
// (preamble 0xD3, length, CRC-24Q) or a u-blox UBX frame (sync 0xB5 0x62, class,
// id, length, Fletcher checksum). A format is recognised only on a complete frame
// with a good checksum within the bytes given, so text files never pass.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

enum class StreamFormat { Rtcm3, Ubx, Unknown };

std::string_view streamFormatName(StreamFormat format);
StreamFormat detectStreamFormat(const std::uint8_t* data, std::size_t size);
/// Looks at the first 64 KiB of a file (throws FileOpenError when it cannot be opened).
StreamFormat detectStreamFormatOfFile(const std::string& path);

/// Parses "YYYY/MM/DD" or "YYYY/MM/DD HH:MM:SS" (GPST) as convbin -tr does; nullopt on bad text.
std::optional<GnssTime> parseReferenceDate(std::string_view text);

}  // namespace ppp
