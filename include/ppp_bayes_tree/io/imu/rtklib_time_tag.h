#pragma once
// RtklibTimeTag: RTKLIB's time-tag file (".tag" beside a logged stream, written by
// str2str / strsvr with time tags on). Layout, little-endian:
//   60 bytes   header text "TIMETAG RTKLIB EX ..." padded with zeros,
//   uint32     the logging computer's tick [ms] when the file started,
//   uint32     start time, whole seconds counted like Unix time but in GPST,
//   double     start time, fraction of a second,
//   then 8-byte records: uint32 milliseconds since the start, uint32 byte
//   offset in the stream when that many bytes had been logged.
#include <cstdint>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

struct TimeTagRecord {
  std::uint32_t elapsed_ms = 0;   ///< since the start time
  std::uint32_t file_offset = 0;  ///< bytes of the stream logged by then
};

struct RtklibTimeTag {
  std::string header_text;       ///< the header's text up to its first zero byte
  std::uint32_t start_tick_ms = 0;
  GnssTime start;                ///< GPST of the first byte
  std::vector<TimeTagRecord> records;
  ParseReport report;            ///< a cut last record is counted here

  /// GPST of the last record (the start when there is none).
  GnssTime lastRecordTime() const;
};

/// Reads a time-tag file. Throws FileOpenError when it cannot be read and
/// ParseError (file, byte offset as "line" 0, reason) when the header is short or
/// is not RTKLIB's.
RtklibTimeTag readRtklibTimeTag(const std::string& path);

/// Seconds between the Unix epoch and the GPS epoch (1980-01-06): 3657 days.
constexpr std::int64_t kUnixToGpsEpoch_s = 315964800;

}  // namespace ppp
