#pragma once
// Reader for ANTEX 1.4 antenna calibration files (IGS ANTEX format, version 1.4,
// R. Schmid, 2010/2016), as published by the IGS (igs20.atx).
//
// Header: "ANTEX VERSION / SYST", "PCV TYPE / REFANT", comments, "END OF HEADER".
// A malformed or missing header line throws ParseError(file, line, reason).
// Antenna blocks: "START OF ANTENNA" .. "END OF ANTENNA". A malformed block is
// skipped (report.addProblem) and reading resumes at the next START OF ANTENNA.
// RMS blocks ("START OF FREQ RMS" .. "END OF FREQ RMS") are skipped and counted.
// Satellite blocks whose code lies outside its system's PRN range (old test
// satellites such as GIOVE E51/E52 in the IGS files) are skipped and listed in
// skipped_satellite_codes, not reported as problems.
//
// Limits (so that absurd input cannot allocate without bound or divide by
// zero): DZEN > 0 with at most kMaxZenithNodes nodes, DAZI = 0 or 360/DAZI an
// integer with at most kMaxAzimuthRows rows, at most kMaxFrequencies per block.
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ppp_bayes_tree/io/file_summary.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/types/antenna_calibration.h"

namespace ppp {

struct AntexHeader {
  std::string version;  // as written, e.g. "1.4"
  /// Satellite system of the file: a system letter, or 'M' (mixed).
  char system = 'G';
  /// 'A' absolute or 'R' relative phase-centre variations.
  char pcv_type = 'A';
  std::string reference_antenna;  // relative PCV only (blank for absolute)
  std::string reference_serial;
  std::vector<std::string> comments;
};

/// Result of a receiver-antenna lookup.
struct ReceiverAntennaLookup {
  const AntennaCalibration* antenna = nullptr;  // nullptr: not in the file
  /// True when the radome asked for was missing or not in the file and the
  /// NONE radome calibration of the same model is used instead.
  bool radome_substituted = false;
  /// Human-readable explanation whenever the result is not an exact match, e.g.
  /// "TRM59800.00 SCIS not found, using TRM59800.00 NONE".
  std::string note;
};

class AntexFile {
 public:
  AntexHeader header;
  std::vector<AntennaCalibration> antennas;
  ParseReport report;
  /// Satellite codes of blocks skipped because the PRN is outside the system's
  /// range (e.g. "E51", "E52": the GIOVE test satellites of the IGS files), each
  /// once, in file order. Not a problem of the file: counted in the report.
  std::vector<std::string> skipped_satellite_codes;

  /// The satellite antenna block of `satellite` valid at `t` (validity period
  /// from VALID FROM / VALID UNTIL); when periods overlap, the one that started
  /// last. nullptr when none is valid.
  const AntennaCalibration* satellite(const SatelliteId& satellite, const GnssTime& t) const;
  /// Receiver antenna by model and radome (blank radome is read as "NONE").
  /// When the radome is blank or not in the file, falls back to the model with
  /// radome NONE and says so in the note. Type-mean calibrations (blank serial)
  /// are preferred over individual ones.
  ReceiverAntennaLookup receiver(std::string_view model, std::string_view radome) const;
  /// Same, from an antenna type as written in RINEX "ANT # / TYPE" (model in
  /// columns 1-16, radome in 17-20) or as "MODEL RADOME" separated by blanks.
  ReceiverAntennaLookup receiver(std::string_view antenna_type) const;

  std::size_t receiverCount() const;
  std::size_t satelliteCount() const;
};

/// Limits on the grid declared by a block (see the file comment).
constexpr std::size_t kAntexMaxZenithNodes = 1801;  // e.g. 0..180 deg step 0.1
constexpr std::size_t kAntexMaxAzimuthRows = 3601;  // DAZI >= 0.1 deg
constexpr std::size_t kAntexMaxGridValues = 400000; // rows * nodes per frequency
constexpr std::size_t kAntexMaxFrequencies = 64;

/// Reads a whole ANTEX file from a line source. Throws ParseError on a
/// malformed header.
AntexFile readAntex(LineSource& source);
/// Convenience: opens `path` (plain or gzip). Throws FileOpenError, ParseError.
AntexFile readAntexFile(const std::string& path);

/// What ppp_inspect shows: version, antenna counts, satellites per system,
/// frequencies per system, facts, report. Throws like readAntexFile.
FileSummary summarizeAntexFile(const std::string& path);

}  // namespace ppp
