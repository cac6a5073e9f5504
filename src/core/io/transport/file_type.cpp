#include "ppp_bayes_tree/io/transport/file_type.h"

#include "ppp_bayes_tree/io/fixed_width.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"

namespace ppp {

std::string_view fileTypeName(GnssFileType type) {
  switch (type) {
    case GnssFileType::RinexObservation: return "RINEX observation";
    case GnssFileType::CompactRinexObservation: return "Compact RINEX (Hatanaka) observation";
    case GnssFileType::RinexNavigation: return "RINEX navigation";
    case GnssFileType::RinexClock: return "RINEX clock";
    case GnssFileType::RinexMeteo: return "RINEX meteorological";
    case GnssFileType::Sp3: return "SP3 orbit";
    case GnssFileType::Antex: return "ANTEX antenna calibration";
    case GnssFileType::BiasSinex: return "Bias-SINEX";
    case GnssFileType::Blq: return "BLQ ocean loading";
    case GnssFileType::Rtcm3Stream: return "RTCM 3 stream";
    case GnssFileType::UbxStream: return "u-blox UBX stream";
    case GnssFileType::Unknown: return "unknown";
  }
  return "unknown";
}

GnssFileType detectFileTypeFromFirstLine(std::string_view line) {
  const std::string_view label = trim(column(line, 60, 20));
  if (label.rfind("CRINEX VERS", 0) == 0 || line.find("COMPACT RINEX FORMAT") != std::string_view::npos) {
    return GnssFileType::CompactRinexObservation;
  }
  if (label == "RINEX VERSION / TYPE") {
    // RINEX 2/3/4 (sec. 5.1 of each): the file type letter is in column 21;
    // RINEX 2 navigation uses N (GPS), G (GLONASS), H (SBAS); RINEX 3/4 use N.
    const std::string_view type = column(line, 20, 1);
    if (type == "O") return GnssFileType::RinexObservation;
    if (type == "N" || type == "G" || type == "H") return GnssFileType::RinexNavigation;
    if (type == "M") return GnssFileType::RinexMeteo;
    // Clock files: 'C' in column 21 (clock 2.x-3.02), or the words CLOCK DATA.
    if (type == "C" || line.find("CLOCK DATA") != std::string_view::npos) {
      return GnssFileType::RinexClock;
    }
    return GnssFileType::Unknown;
  }
  if (line.size() >= 3 && line[0] == '#' && (line[1] >= 'a' && line[1] <= 'd') &&
      (line[2] == 'P' || line[2] == 'V')) {
    return GnssFileType::Sp3;
  }
  if (label == "ANTEX VERSION / SYST") return GnssFileType::Antex;
  if (line.rfind("%=BIA", 0) == 0) return GnssFileType::BiasSinex;
  if (line.rfind("$$", 0) == 0) return GnssFileType::Blq;
  return GnssFileType::Unknown;
}

GnssFileType detectFileType(const std::string& path) {
  switch (detectStreamFormatOfFile(path)) {
    case StreamFormat::Rtcm3: return GnssFileType::Rtcm3Stream;
    case StreamFormat::Ubx: return GnssFileType::UbxStream;
    case StreamFormat::Unknown: break;
  }
  auto source = openLineSource(path);
  std::string line;
  // Skip leading blank lines (seen in some BLQ files).
  for (int i = 0; i < 5 && source->next(line); ++i) {
    if (!isBlank(line)) return detectFileTypeFromFirstLine(line);
  }
  return GnssFileType::Unknown;
}

}  // namespace ppp
