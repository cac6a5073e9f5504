#pragma once
// Reader for RINEX navigation files:
//  - RINEX 2.10/2.11 GPS ("N") and GLONASS ("G") navigation files,
//  - RINEX 3.00-3.05 navigation files, single-system and mixed,
//  - RINEX 4.00/4.01/4.02 navigation files ("> EPH G01 LNAV" record headers).
// GPS LNAV, QZSS LNAV, Galileo I/NAV and F/NAV, GLONASS FDMA and BeiDou D1/D2
// records (RINEX 3.05 table A14, RINEX 4 "D1"/"D2") are decoded; SBAS,
// NavIC/IRNSS records, RINEX 4 CNAV/CNV1/CNV2/... messages
// and RINEX 4 STO/EOP/ION records are skipped and counted in the report.
//
// Bad input (project policy): a malformed header throws ParseError(file, line,
// reason); a malformed record is skipped with report.addProblem(line, reason)
// and reading resumes at the next record.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/file_summary.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/types/beidou_ephemeris.h"
#include "ppp_bayes_tree/types/glonass_channels.h"
#include "ppp_bayes_tree/types/navigation_records.h"

namespace ppp {

/// One "TIME SYSTEM CORR" header line (RINEX 3.05 table A5), or the RINEX 2
/// "DELTA-UTC: A0,A1,T,W" line (type "GPUT").
struct TimeSystemCorrection {
  std::string type;            // "GPUT", "GAUT", "GPGA", "GLUT", ...
  double a0_s = 0.0;
  double a1_sps = 0.0;
  long long reference_sow = 0;  // T
  long long reference_week = 0;  // W
  std::string source;          // "EGNOS", "G10", ... (may be empty)
  std::optional<int> utc_id;
};

struct RinexNavHeader {
  std::string version_text;     // as written, e.g. "3.04"
  double version = 0.0;
  char file_type = 'N';         // 'N' (RINEX 3/4 and RINEX 2 GPS), 'G' (RINEX 2 GLONASS)
  char system = 'G';            // 'G', 'R', 'E', 'M', ... (RINEX 2: 'G' or 'R')
  /// "IONOSPHERIC CORR" lines by type ("GPSA", "GPSB", "GAL", "BDSA", ...); RINEX 2
  /// "ION ALPHA" / "ION BETA" appear as "GPSA" / "GPSB". Values as written (blank
  /// trailing fields omitted).
  std::map<std::string, std::vector<double>> ionospheric_corrections;
  std::vector<TimeSystemCorrection> time_system_corrections;
  /// "LEAP SECONDS": current number of leap seconds (GPS - UTC) when given.
  std::optional<int> leap_seconds;
  std::size_t header_lines = 0;
};

/// Everything read from one navigation file.
struct NavData {
  RinexNavHeader header;
  /// GPS and QZSS LNAV records (QZSS satellites carry GnssSystem::QZSS).
  std::vector<GpsLnavEphemeris> gps;
  /// Galileo I/NAV and F/NAV records, both kept (see GalileoEphemeris::type).
  std::vector<GalileoEphemeris> galileo;
  std::vector<GlonassEphemeris> glonass;
  /// BeiDou D1 (MEO/IGSO) and D2 (GEO) records.
  std::vector<BeidouEphemeris> beidou;
  /// GLONASS FDMA channel numbers from the records' frequency numbers.
  GlonassChannels glonass_channels;
  /// Every satellite that had a record, decoded or skipped.
  std::set<SatelliteId> satellites;
  /// Reference clock epochs (toc) of decoded records: earliest and latest.
  std::optional<GnssTime> first_toc;
  std::optional<GnssTime> last_toc;
  /// Skipped records are counted here under "<system> records skipped (...)";
  /// malformed ones are problems.
  ParseReport report;

  std::size_t recordCount() const { return gps.size() + galileo.size() + glonass.size() + beidou.size(); }
};

/// Reads a navigation file from a line source (plain or gzip).
NavData readRinexNav(LineSource& source);
/// Convenience: opens `path` (plain or gzip). Throws FileOpenError / ParseError.
NavData readRinexNav(const std::string& path);

/// What ppp_inspect shows for a navigation file.
FileSummary summarizeNavFile(const std::string& path);

}  // namespace ppp
