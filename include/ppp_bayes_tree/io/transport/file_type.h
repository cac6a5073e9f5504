#pragma once
// Recognises a GNSS file by its content (first lines, or binary RTCM 3 / UBX
// frames), whatever its name, and whether it is gzip-compressed.
#include <string>
#include <string_view>

namespace ppp {

enum class GnssFileType {
  RinexObservation,
  CompactRinexObservation,  // Hatanaka CRX 1.0 / 3.0
  RinexNavigation,
  RinexClock,
  RinexMeteo,
  Sp3,
  Antex,
  BiasSinex,
  Blq,
  Rtcm3Stream,  // binary: a frame with a good CRC-24Q (io/transport/stream_format.h)
  UbxStream,    // binary: a UBX frame with a good checksum
  Unknown,
};

std::string_view fileTypeName(GnssFileType type);

/// Looks at the first lines of the file (plain or gzip). Throws FileOpenError
/// when the file cannot be opened.
GnssFileType detectFileType(const std::string& path);
/// The same on a first line and, for BLQ, the first non-blank lines.
GnssFileType detectFileTypeFromFirstLine(std::string_view first_line);

}  // namespace ppp
