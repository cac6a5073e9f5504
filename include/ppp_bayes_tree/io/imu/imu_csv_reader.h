#pragma once
// Reader of the plain IMU CSV (the documented input format for IMU files, see
// doc/gnss_ins.md): one reading per line,
//   gps_week,seconds_of_week,fx,fy,fz,wx,wy,wz
// GPST week and seconds of week [s], specific force [m/s^2] and angular rate
// [rad/s] in the IMU's own axes. Lines starting with '#' and blank lines are
// skipped; a first line that does not start with a number is a column header.
// Short, non-numeric, NaN, backward and repeated lines are skipped and gaps kept,
// each counted in the report with its line. Accelerations that look like g
// (mean |f| of the first readings near 1 instead of near 9.8) are reported as
// such: the file is read as given, and `units_look_like_g` is set.
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/navigation/imu_input_screen.h"  // meanSpecificForceMagnitude
#include "ppp_bayes_tree/navigation/imu_sample.h"

namespace ppp {

struct ImuCsvOptions {
  double max_gap_s = 0.05;  ///< a larger step between readings is reported as a gap
};

struct ImuCsvRead {
  std::vector<ImuSample> samples;
  ParseReport report;
  std::size_t lines = 0;
  bool units_look_like_g = false;
};

/// Throws FileOpenError when the file cannot be read; everything else is counted.
ImuCsvRead readImuCsv(const std::string& path, const ImuCsvOptions& options = {});


}  // namespace ppp
