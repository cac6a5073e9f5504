#pragma once
// Reader for SP3 precise orbit files, versions a to d.
//
// Format: "The Extended Standard Product 3 Orbit Format (SP3-d)", S. Hilla,
// NGS/NOAA, 21 February 2016 (and SP3-c, 17 August 2010). Column numbers in the
// comments of sp3_reader.cpp are the 1-based columns of that document.
//
// Units are converted on reading: positions km -> m, clocks microseconds -> s,
// velocities dm/s -> m/s, clock rates 1e-4 microseconds/s -> s/s. All epochs are
// converted from the file's time system (the %c line) to GPST.
//
// Bad or absent values (SP3-d, "Position and Clock Record"): a position component
// written as 0.000000 and a clock written as 999999.999999 are absent; they come
// back as std::nullopt, never as 0.
#include <array>
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

struct Sp3Header {
  char version = 'c';  // 'a' .. 'd' (line 1, column 2)
  char pv_flag = 'P';  // 'P' positions only, 'V' positions and velocities (column 3)
  CalendarTime first_epoch_calendar;  // as written, in `time_system`
  GnssTime first_epoch;               // GPST
  long long epoch_count = 0;          // as announced in line 1 (columns 33-39)
  std::string data_used;              // e.g. "ORBIT", "u+U"
  std::string coordinate_system;      // e.g. "IGS14", "IGc20"
  std::string orbit_type;             // e.g. "FIT", "HLM", "BCT"
  std::string agency;                 // e.g. "IGS", "WHU"
  int gps_week = 0;                   // line 2
  double seconds_of_week = 0.0;
  double interval_s = 0.0;            // epoch interval
  long long mjd = 0;                  // MJD of the first epoch (integer part)
  double fractional_day = 0.0;
  /// Satellites of the "+" lines, in file order (SP3-d allows up to 999).
  std::vector<SatelliteId> satellites;
  /// Accuracy exponents of the "++" lines, one per satellite; nullopt for 0
  /// ("unknown"). Accuracy = 2^exponent mm.
  std::vector<std::optional<int>> accuracy_exponents;
  char file_type = 'G';               // first %c line, column 4: G M R E C J L ...
  TimeSystem time_system = TimeSystem::GPS;  // first %c line, columns 10-12
  std::string time_system_code = "GPS";      // as written ("ccc" in old files -> GPS)
  /// %f line: floating-point bases for the standard deviations of the records
  /// (position/velocity base, clock/clock-rate base); 0 means not given.
  double position_base = 0.0;
  double clock_base = 0.0;
  std::vector<std::string> comments;  // "/*" lines, without the leading "/* "
  std::size_t header_lines = 0;
};

/// One satellite at one epoch: the P record and, when present, the V record.
struct Sp3Record {
  GnssTime time;  // GPST
  std::optional<Eigen::Vector3d> position_ecef_m;
  std::optional<double> clock_bias_s;
  std::optional<Eigen::Vector3d> velocity_ecef_mps;
  std::optional<double> clock_rate_s_per_s;
  /// Standard deviations from the record exponents (base^n mm or ps), when the
  /// exponent and the %f base are given.
  std::array<std::optional<double>, 3> position_sigma_m;
  std::optional<double> clock_sigma_s;
  bool clock_event = false;      // column 75 'E'
  bool clock_predicted = false;  // column 76 'P'
  bool maneuver = false;         // column 79 'M'
  bool orbit_predicted = false;  // column 80 'P'
  /// True when the P record carried a bad-value marker (position or clock).
  bool position_marked_bad = false;
  bool clock_marked_bad = false;
};

struct Sp3File {
  Sp3Header header;
  /// Epochs read ("*" lines), strictly increasing, GPST.
  std::vector<GnssTime> epochs;
  /// Per satellite, records in time order.
  std::map<SatelliteId, std::vector<Sp3Record>> satellites;
  /// True when the "EOF" line was found.
  bool complete = false;
  /// True when reading stopped at the first epoch after the filter's window (the
  /// epochs are strictly increasing, so nothing later could be kept).
  bool stopped_after_window = false;
  ParseReport report;
};

struct Sp3ReadOptions {
  /// Records to keep; the others are counted, not parsed.
  RecordFilter filter;
  /// The time window is widened by this many epoch intervals (header line 2) on each
  /// side, for the interpolation windows around its edges.
  int margin_epochs = 0;
};

/// Reads an SP3 file from a line source (plain or gzip). Throws ParseError on a
/// malformed header; skips malformed records into `report`; a truncated file
/// keeps what was read (complete == false, a problem is added).
Sp3File readSp3(LineSource& source, const Sp3ReadOptions& options = {});
/// Convenience: opens `path` (throws FileOpenError) and reads it.
Sp3File readSp3(const std::string& path, const Sp3ReadOptions& options = {});

/// Summary for ppp_inspect: version, span, interval, epochs, satellites per
/// system, agency / frame / time system / orbit type, problems.
FileSummary summarizeSp3File(const std::string& path);
FileSummary summarizeSp3(const Sp3File& file, const std::string& path);

}  // namespace ppp
