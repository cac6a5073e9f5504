#pragma once
// Reader for RINEX clock files, versions 2.00-2.0x and 3.00-3.04.
//
// Format: "RINEX Extensions to Handle Clock Information", J. Ray and W. Gurtner,
// version 3.02 (2010), and the RINEX clock 3.04 update (2017) which widened the
// receiver/satellite name of the data records and of "SOLN STA NAME / NUM" from
// 4 to 9 characters. Both layouts are recognised line by line, whatever the
// version number says.
//
// Data records: AS (satellite clocks) and AR (receiver clocks) are kept; CR, DR,
// MS records are skipped and counted. Units: clock values are seconds, rates
// s/s, accelerations 1/s; station coordinates are read in mm and stored in m.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ppp_bayes_tree/io/file_summary.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/record_filter.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"
#include "ppp_bayes_tree/types/time_system.h"

namespace ppp {

/// One "SOLN STA NAME / NUM" header line.
struct ClockStation {
  std::string name;   // 4-character (or 9-character, 3.04) station name
  std::string domes;  // station identifier (DOMES number)
  Eigen::Vector3d position_ecef_m = Eigen::Vector3d::Zero();  // given in mm in the file
};

struct RinexClockHeader {
  std::string version_text;  // as written, e.g. "3.00"
  double version = 0.0;
  char satellite_system = ' ';  // G R E C J M or blank
  std::string program, run_by, date;
  TimeSystem time_system = TimeSystem::GPS;  // "TIME SYSTEM ID" (3.x); GPS when absent
  std::optional<int> leap_seconds;
  std::vector<std::string> data_types;  // "# / TYPES OF DATA": AS, AR, ...
  std::string analysis_center_id;       // "ANALYSIS CENTER", A3
  std::string analysis_center_name;
  std::optional<int> station_count;     // "# OF SOLN STA / TRF"
  std::string reference_frame;
  std::vector<ClockStation> stations;   // "SOLN STA NAME / NUM"
  std::optional<int> satellite_count;   // "# OF SOLN SATS"
  std::vector<SatelliteId> prn_list;    // "PRN LIST"
  std::vector<std::string> comments;
  std::vector<std::size_t> comment_lines;  // the file line of each comment (parallel to comments)
  std::string pcvs_applied;  // the first "SYS / PCVS APPLIED" source, extension removed ("igs14_2108")
  std::size_t header_lines = 0;
};

/// One clock data record (AS or AR). Values beyond the bias are optional (the
/// record's value count says how many are present).
struct ClockRecord {
  GnssTime time;  // GPST
  double clock_bias_s = 0.0;
  std::optional<double> clock_bias_sigma_s;
  std::optional<double> clock_rate_s_per_s;
  std::optional<double> clock_rate_sigma_s_per_s;
  std::optional<double> clock_acceleration_per_s;
  std::optional<double> clock_acceleration_sigma_per_s;
};

struct RinexClockReadOptions {
  /// Keep AR (receiver clock) records; when false they are only counted.
  bool keep_receiver_clocks = true;
  /// Satellite (AS) records to keep: other systems are counted before their values
  /// are parsed, records outside the time window after their epoch is. (No early
  /// stop: the format does not promise records in time order.)
  RecordFilter filter;
};

struct RinexClockFile {
  RinexClockHeader header;
  /// AS records per satellite, time-ordered, duplicates removed.
  std::map<SatelliteId, std::vector<ClockRecord>> satellite_clocks;
  /// AR records per receiver name, time-ordered.
  std::map<std::string, std::vector<ClockRecord>> receiver_clocks;
  ParseReport report;
};

/// Reads a RINEX clock file. Throws ParseError on a malformed header; malformed
/// data records are skipped into `report`.
RinexClockFile readRinexClock(LineSource& source, const RinexClockReadOptions& options = {});
/// Convenience: opens `path` (plain or gzip; throws FileOpenError) and reads it.
RinexClockFile readRinexClock(const std::string& path, const RinexClockReadOptions& options = {});
/// The header only (the file is read up to END OF HEADER). Throws like readRinexClock.
RinexClockHeader readRinexClockHeader(const std::string& path);

/// Summary for ppp_inspect: version, span, interval (most common spacing),
/// epochs, satellites per system, analysis center, time system, stations.
FileSummary summarizeClockFile(const std::string& path);
FileSummary summarizeClock(const RinexClockFile& file, const std::string& path);

}  // namespace ppp
