#include "ppp_bayes_tree/io/imu/imu_csv_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>

#include "ppp_bayes_tree/io/imu/imu_line_screen.h"
#include "ppp_bayes_tree/navigation/imu_input_screen.h"

namespace ppp {
namespace {

constexpr std::size_t kFields = 8;
/// Readings averaged for the unit check, and the band of mean |f| read as "in g".
constexpr std::size_t kUnitCheckReadings = 100;

constexpr double kSecondsPerWeek = 604800.0;
constexpr double kMaxGpsWeek = 10000.0;

/// True for an integer week in [0, kMaxGpsWeek] and seconds of week in [0, 604800).
bool timeInRange(const std::vector<double>& v) {
  return v[0] == std::floor(v[0]) && v[0] >= 0.0 && v[0] <= kMaxGpsWeek && v[1] >= 0.0 && v[1] < kSecondsPerWeek;
}

bool isSkippable(const std::string& line) {
  const auto first = line.find_first_not_of(" \t\r");
  return first == std::string::npos || line[first] == '#';
}

bool startsWithNumber(const std::string& line) {
  const auto first = line.find_first_not_of(" \t");
  if (first == std::string::npos) return false;
  const char c = line[first];
  return std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.';
}

ImuSample sampleOf(const std::vector<double>& v) {
  ImuSample s;
  s.time = GnssTime::fromGpsWeek(static_cast<int>(v[0]), v[1]);
  s.specific_force_mps2 = Eigen::Vector3d(v[2], v[3], v[4]);
  s.angular_rate_radps = Eigen::Vector3d(v[5], v[6], v[7]);
  return s;
}

void checkUnits(ImuCsvRead& out) {
  if (out.samples.empty()) return;
  const double mean = meanSpecificForceMagnitude(out.samples, kUnitCheckReadings);
  if (!meanForceLooksLikeGravityUnits(mean)) return;
  out.units_look_like_g = true;
  out.report.count("accelerations look like g");
  out.report.addProblem(0, "accelerations look like g, not m/s^2: mean |f| of the first readings is " +
                               std::to_string(mean));
}

}  // namespace

ImuCsvRead readImuCsv(const std::string& path, const ImuCsvOptions& options) {
  std::ifstream in(path);
  if (!in) throw FileOpenError("cannot open IMU file " + path);
  ImuCsvRead out;
  out.report.setFile(path);
  ImuLineScreen screen(out.report, kFields, options.max_gap_s);
  std::optional<GnssTime> first_time;
  bool seen_data_line = false;
  std::string line;
  while (std::getline(in, line)) {
    ++out.lines;
    if (isSkippable(line)) continue;
    if (!seen_data_line && !startsWithNumber(line)) {
      seen_data_line = true;
      out.report.count("header line");
      continue;
    }
    seen_data_line = true;
    const auto v = screen.numbers(line, out.lines);
    if (!v) continue;
    if (!timeInRange(*v)) {
      screen.reject(ImuLineProblem::TimeOutOfRange, out.lines,
                    "week " + std::to_string((*v)[0]) + ", seconds of week " + std::to_string((*v)[1]));
      continue;
    }
    const ImuSample s = sampleOf(*v);
    if (!first_time) first_time = s.time;
    if (!screen.acceptStamp(s.time - *first_time, out.lines)) continue;
    out.samples.push_back(s);
  }
  checkUnits(out);
  return out;
}

}  // namespace ppp
