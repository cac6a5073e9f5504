#pragma once
// Reader of an IMU logged as text beside a GNSS receiver by RTKLIB (the u-blox
// walk's imu_1730.csv with its time-tag file imu_1730.csv.tag): lines
//   ax,ay,az,gx,gy,gz,tick
// with accelerations in g, rates in deg/s and the IMU's millisecond tick since
// power-up. The tick carries the sample spacing; the time-tag file carries GPST:
// the first kept tick is mapped to the tag's start time and the last kept tick to
// its last record's time, linearly in between (as the data set's own converter
// does). Output: ImuSample in SI units (standard gravity 9.80665 m/s^2 per g)
// with GPS times.
//
// Lines that are short (a log cut mid-line), hold a non-number, or whose tick goes
// backwards or repeats are skipped; gaps are kept; all are counted in the report
// with the line number.
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"

namespace ppp {

struct LoggedImuOptions {
  double max_gap_ms = 50.0;  ///< a larger tick step is reported as a gap
  /// Tick span and time-tag span differing by more than this fraction is reported.
  double max_clock_mismatch = 0.01;
};

struct LoggedImuRead {
  std::vector<ImuSample> samples;
  ParseReport report;          ///< problems of the CSV (and the tag's, prefixed)
  std::size_t lines = 0;       ///< lines read
  double seconds_per_tick = 1e-3;  ///< the linear map's slope [s of GPST per tick]
};

/// Throws FileOpenError when either file cannot be read and ParseError for a bad
/// time-tag header; everything else is counted.
LoggedImuRead readLoggedImu(const std::string& csv_path, const std::string& tag_path,
                            const LoggedImuOptions& options = {});

}  // namespace ppp
