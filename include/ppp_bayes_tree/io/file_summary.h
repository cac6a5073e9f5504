#pragma once
// FileSummary: what `ppp_inspect` prints for one input file. Each reader fills
// one through its summarize function; the tool only formats it.
#include <cstddef>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

struct FileSummary {
  std::string path;
  std::string type;     // "RINEX observation", "SP3 orbit", "RINEX clock", "ANTEX", ...
  std::string version;  // as written in the file, e.g. "3.04", "d", "1.4"
  std::optional<GnssTime> first_epoch;
  std::optional<GnssTime> last_epoch;
  std::optional<double> interval_s;
  std::size_t epoch_count = 0;  // epochs / records, as meaningful for the type
  /// What epoch_count counts, as printed: "epochs", "bias rows", "antennas", ...
  std::string count_label = "epochs";
  /// Label of interval_s, as printed ("interval", "parameter spacing").
  std::string interval_label = "interval";
  /// Satellites seen, per system.
  std::map<GnssSystem, std::set<SatelliteId>> satellites;
  /// Signals / observation codes / frequencies, per system (e.g. "C1C", "L2W").
  std::map<GnssSystem, std::set<std::string>> signals;
  /// Free-form facts worth showing: "marker ZIM2", "antenna TRM59800.00 NONE".
  std::vector<std::string> facts;
  /// Problems found while reading (skipped records, truncation, ...).
  ParseReport report;
};

}  // namespace ppp

namespace ppp {
/// Human-readable multi-line text of a summary, as printed by ppp_inspect.
std::string formatSummary(const FileSummary& summary);
}  // namespace ppp
