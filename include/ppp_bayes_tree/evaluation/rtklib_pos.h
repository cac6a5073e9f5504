#pragma once
// RTKLIB solution (.pos) files: writer and reader.
//
// Layout as written by RTKLIB 2.4.3 (solution.c, outsolheads/outsols; manual
// appendix B.5 "Solution File"): '%' header lines, then one line per epoch:
//   xyz: time  x-ecef(m) y-ecef(m) z-ecef(m)  Q ns  sdx sdy sdz sdxy sdyz sdzx  age(s) ratio
//   llh: time  latitude(deg) longitude(deg) height(m)  Q ns  sdn sde sdu sdne sdeu sdun  age(s) ratio
// with time either "week tow" (out-timeform=tow: "2418 259200.000") or a
// calendar "yyyy/mm/dd hh:mm:ss.sss" (out-timeform=hms). Fields are separated by
// blanks; numbers are written %14.4f (xyz), %14.9f (lat/lon), %10.4f (height),
// %3d (Q, ns), %8.4f (sd), %6.2f (age), %6.1f (ratio). The sd columns hold
// sqrt(|c|) * sign(c) of the covariance elements (RTKLIB sqvar()). Q follows
// RTKLIB's SOLQ_*: 1 for a solution on fixed integer ambiguities (PPP-AR), 6 for
// PPP float, 5 single. The ratio column holds the ratio test value of the integer
// search of a fixed epoch (RTKLIB's "ratio factor of ambiguity validation", capped
// at 999.9), 0 for float epochs; age is 0 (no differential corrections).
//
// The reader accepts both coordinate and time forms (RTKLIB files end lines in
// CRLF: LineSource strips it), GPST and UTC times (the "%  GPST" / "%  UTC" column
// header; UTC is converted to GPST), plain or gzip. It does not read lat/lon in
// deg-min-sec form (out-degform=dms) nor ENU baselines. Malformed records are
// skipped into the report; there is no mandatory header, so no ParseError.
#include <array>
#include <cstdio>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ppp_bayes_tree/ppp/pipeline/solution_epoch.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/time_system.h"

namespace ppp {

enum class PosTimeForm { WeekTow, Calendar };
enum class PosCoordinates { Xyz, Llh };

struct PosRecord {
  GnssTime time;  // GPST
  Eigen::Vector3d position_ecef_m = Eigen::Vector3d::Zero();  // llh files converted to ECEF
  int quality = 0;     // RTKLIB Q: 1 fix, 2 float, 5 single, 6 PPP
  int satellites = 0;  // ns
  /// sdx, sdy, sdz, sdxy, sdyz, sdzx (xyz) or sdn, sde, sdu, sdne, sdeu, sdun (llh) [m].
  std::optional<std::array<double, 6>> sd_m;
  std::optional<double> age_s, ratio;
};

struct PosFile {
  PosCoordinates coordinates = PosCoordinates::Xyz;
  PosTimeForm time_form = PosTimeForm::WeekTow;
  TimeSystem time_system = TimeSystem::GPS;
  std::vector<std::string> header_lines;  // the '%' lines, as written
  std::vector<PosRecord> records;
  ParseReport report;
};

PosFile readRtklibPos(LineSource& source);
/// Convenience: opens `path` (plain or gzip; throws FileOpenError) and reads it.
PosFile readRtklibPos(const std::string& path);
/// The records as SolutionEpoch (for the statistics).
std::vector<SolutionEpoch> toSolutionEpochs(const PosFile& file);

struct PosWriterOptions {
  PosTimeForm time_form = PosTimeForm::WeekTow;
  int time_decimals = 3;                   // RTKLIB out-timendec
  std::vector<std::string> comment_lines;  // written as "% ..." after the program line
  std::string program = "ppp_bayes_tree";
};

/// RTKLIB xyz .pos header lines (each ending in '\n').
std::string formatPosHeader(const PosWriterOptions& options);
/// One xyz record line; empty for an epoch without a position (RTKLIB writes none).
std::string formatPosRecord(const SolutionEpoch& epoch, const PosWriterOptions& options);

/// Streams an RTKLIB-compatible xyz .pos file.
class RtklibPosWriter {
 public:
  /// Writes the header to `out` (which must outlive the writer).
  RtklibPosWriter(std::ostream& out, PosWriterOptions options = {});
  void write(const SolutionEpoch& epoch);

 private:
  std::ostream& out_;
  PosWriterOptions options_;
};

}  // namespace ppp
