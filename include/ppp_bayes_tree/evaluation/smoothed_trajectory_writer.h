#pragma once
// SmoothedTrajectoryWriter: the smoothed trajectory written out incrementally, one
// CSV row per state as it leaves the fixed-lag window with its final estimate
// (PppSmoother::setMarginalizedStateSink), so that a live run of hours keeps only
// the window in memory. One header row, then one row per state, in time order:
//   gps_week, tow_s, time_gpst (ISO 8601, GPST), x_m, y_m, z_m (ECEF),
//   lat_deg, lon_deg, height_m (WGS 84 ellipsoidal), zwd_m, clock_m, state_index
// (the gps_week,tow_s,x_m,y_m,z_m names are those of SolutionCsvWriter and of
// ../shared/peers/poserr.py). Each row is flushed, so a killed run leaves every
// state written so far. A state whose time is not after the last written one
// (duplicate, time backwards: e.g. a sink fed twice) is refused, counted and
// described in lastProblem(), never written: the file stays strictly time-ordered.
#include <cstddef>
#include <fstream>
#include <memory>
#include <optional>
#include <ostream>
#include <string>

#include "ppp_bayes_tree/ppp/estimators/smoothed_trajectory_provider.h"

namespace ppp {

class SmoothedTrajectoryWriter {
 public:
  /// Creates (truncates) the file and writes the header row; throws FileOpenError.
  explicit SmoothedTrajectoryWriter(const std::string& path);
  /// Writes to `out` (which must outlive the writer); the header row first.
  explicit SmoothedTrajectoryWriter(std::ostream& out);

  /// Writes one row; false (counted, nothing written) when the time is not after the last row's.
  bool write(const SmoothedEpoch& epoch);

  std::size_t rowsWritten() const { return rows_; }
  std::size_t rowsRefused() const { return refused_; }
  /// The last refusal, readable ("" when none).
  const std::string& lastProblem() const { return last_problem_; }
  const std::string& path() const { return path_; }

  static std::string headerRow();
  static std::string row(const SmoothedEpoch& epoch);

 private:
  std::unique_ptr<std::ofstream> file_;
  std::ostream* out_ = nullptr;
  std::string path_;
  std::optional<GnssTime> last_time_;
  std::size_t rows_ = 0, refused_ = 0;
  std::string last_problem_;
};

}  // namespace ppp
