#include "ppp_bayes_tree/io/imu/logged_imu_reader.h"

#include <cmath>
#include <fstream>

#include "ppp_bayes_tree/io/imu/imu_line_screen.h"
#include "ppp_bayes_tree/io/imu/rtklib_time_tag.h"
#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

constexpr std::size_t kFields = 7;

struct TickReading {
  double tick_ms;
  ImuSample sample;  // time filled once the tick map is known
};

std::vector<TickReading> readTickReadings(const std::string& csv_path, const LoggedImuOptions& options,
                                          LoggedImuRead& out) {
  std::ifstream in(csv_path);
  if (!in) throw FileOpenError("cannot open IMU log " + csv_path);
  ImuLineScreen screen(out.report, kFields, options.max_gap_ms);
  std::vector<TickReading> readings;
  std::string line;
  while (std::getline(in, line)) {
    ++out.lines;
    const auto v = screen.numbers(line, out.lines);
    if (!v || !screen.acceptStamp((*v)[6], out.lines)) continue;
    TickReading r;
    r.tick_ms = (*v)[6];
    r.sample.specific_force_mps2 = Eigen::Vector3d((*v)[0], (*v)[1], (*v)[2]) * kStandardGravity_mps2;
    r.sample.angular_rate_radps = Eigen::Vector3d((*v)[3], (*v)[4], (*v)[5]) * kDegToRad;
    readings.push_back(r);
  }
  return readings;
}

/// Stamps the readings: first tick -> tag start, last tick -> tag's last record.
void stampReadings(std::vector<TickReading>& readings, const RtklibTimeTag& tag, const LoggedImuOptions& options,
                   LoggedImuRead& out) {
  if (readings.empty()) return;
  const double tick_span_s = (readings.back().tick_ms - readings.front().tick_ms) * 1e-3;
  const double tag_span_s = tag.lastRecordTime() - tag.start;
  if (tick_span_s > 0.0 && tag_span_s > 0.0) {
    out.seconds_per_tick = 1e-3 * tag_span_s / tick_span_s;
    if (std::abs(tag_span_s / tick_span_s - 1.0) > options.max_clock_mismatch) {
      out.report.count("clock mismatch");
      out.report.addProblem(0, "IMU ticks span " + std::to_string(tick_span_s) + " s but the time tags " +
                                   std::to_string(tag_span_s) + " s (" + tag.report.file() + ")");
    }
  }
  for (auto& r : readings) {
    r.sample.time = tag.start + (r.tick_ms - readings.front().tick_ms) * out.seconds_per_tick;
    out.samples.push_back(r.sample);
  }
}

}  // namespace

LoggedImuRead readLoggedImu(const std::string& csv_path, const std::string& tag_path,
                            const LoggedImuOptions& options) {
  const RtklibTimeTag tag = readRtklibTimeTag(tag_path);
  LoggedImuRead out;
  out.report.setFile(csv_path);
  for (const auto& p : tag.report.problems()) out.report.addProblem(0, tag_path + ": " + p.reason);
  std::vector<TickReading> readings = readTickReadings(csv_path, options, out);
  stampReadings(readings, tag, options, out);
  return out;
}

}  // namespace ppp
