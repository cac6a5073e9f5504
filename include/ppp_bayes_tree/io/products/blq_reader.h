#pragma once
// Reader for BLQ ocean loading tables (format of the Onsala Space Observatory
// ocean loading service, http://holt.oso.chalmers.se/loading/, also read by
// Bernese, GAMIT, RTKLIB):
//   "$$" lines are comments (a "$$ ... lon/lat: LON LAT [H]" comment inside a
//   station block gives its coordinates);
//   a station line "  NAME [DOMES or more words]";
//   then 6 lines of 11 numbers in the constituent order M2 S2 N2 K2 K1 O1 P1 Q1
//   MF MM SSA: amplitudes radial, west, south [m], then phases radial, west,
//   south [deg].
// BLQ has no header to validate: nothing throws ParseError. A malformed station
// block (wrong count, non-numeric, negative amplitude, phase beyond +-360 deg,
// block cut short) is skipped with report.addProblem and reading resumes at the
// next station line.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ppp_bayes_tree/io/file_summary.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/types/ocean_loading_coefficients.h"

namespace ppp {

/// Result of a station lookup.
struct BlqLookup {
  const OceanLoadingCoefficients* coefficients = nullptr;  // nullptr: not found
  /// True when matched through the 4-character marker of a 9-character long
  /// name (e.g. "ZIM200CHE" asked, "ZIM2" in the file, or the reverse).
  bool matched_by_marker = false;
  std::string note;
};

class BlqFile {
 public:
  std::vector<OceanLoadingCoefficients> stations;
  ParseReport report;

  /// Case-insensitive lookup of a station name (4 characters or longer).
  /// Exact name first; else the 4-character marker of a long name, when that
  /// match is unique.
  BlqLookup find(std::string_view station) const;
};

/// Reads a BLQ file from a line source (never throws ParseError; see above).
BlqFile readBlq(LineSource& source);
/// Convenience: opens `path` (plain or gzip). Throws FileOpenError.
BlqFile readBlqFile(const std::string& path);

/// ppp_inspect view: station count and names, report.
FileSummary summarizeBlqFile(const std::string& path);

}  // namespace ppp
