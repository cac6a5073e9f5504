#pragma once
// Inspection: what `ppp_inspect` does, as a library class. Each added file is
// recognised by content and summarised; observation files are then checked
// against the orbit and clock products given alongside them.
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/file_summary.h"
#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/products/sp3_reader.h"

namespace ppp {

class Inspection {
 public:
  /// Reads and summarises one file (throws ParseError on a malformed header,
  /// FileOpenError when it cannot be read, std::runtime_error for an unknown type).
  FileSummary add(const std::string& path);

  /// For each observation file added: do the SP3/CLK products cover its span,
  /// and which observed satellites do they miss. Empty without both kinds.
  std::string coverageReport() const;

 private:
  std::vector<FileSummary> observations_;
  std::vector<Sp3File> orbits_;
  std::vector<RinexClockFile> clocks_;
};

/// Summary of a RINEX observation file for ppp_inspect (streamed, in one pass
/// with bounded memory: rinex_obs_summary.cpp).
FileSummary summarizeObservationFile(const std::string& path);

}  // namespace ppp
