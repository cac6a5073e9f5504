#include "ppp_bayes_tree/io/imu/imu_file_loader.h"

#include <stdexcept>

#include "ppp_bayes_tree/io/imu/imu_csv_reader.h"
#include "ppp_bayes_tree/io/imu/logged_imu_reader.h"

namespace ppp {

std::string imuFileFormatText(ImuFileFormat format) {
  switch (format) {
    case ImuFileFormat::PlainCsv: return "csv";
    case ImuFileFormat::RtklibLogged: return "logged";
  }
  return "unknown";
}

namespace {

/// The reader's readings, report and line count, by format.
void readFile(const ImuFileOptions& options, ImuFileLoad& out, std::vector<ImuSample>& read) {
  if (options.format == ImuFileFormat::RtklibLogged) {
    if (options.tag_path.empty())
      throw std::invalid_argument("IMU file " + options.path + ": the logged format needs its time-tag file");
    LoggedImuRead r = readLoggedImu(options.path, options.tag_path);
    read = std::move(r.samples);
    out.report = std::move(r.report);
    out.lines = r.lines;
    return;
  }
  ImuCsvRead r = readImuCsv(options.path);
  read = std::move(r.samples);
  out.report = std::move(r.report);
  out.lines = r.lines;
}

/// The readings through the screen (value checks only: the reader checked the stamps).
void screenReadings(const ImuFileOptions& options, const std::vector<ImuSample>& read, ImuFileLoad& out) {
  ImuInputScreenOptions screen_options = options.screen;
  screen_options.check_time_order = false;
  ImuInputScreen screen(screen_options);
  const auto keep = [&out](const std::vector<ImuSample>& released) {
    out.samples.insert(out.samples.end(), released.begin(), released.end());
  };
  for (const ImuSample& reading : read) keep(screen.push(reading));
  keep(screen.finish());
  out.units = screen.units();
  out.saturated = screen.count(ImuInputProblem::Saturated);
  out.refused = read.size() - screen.accepted();
  out.screen_problems = screen.problems();
  out.screen_summary = screen.summary();
}

}  // namespace

ImuFileLoad loadImuFile(const ImuFileOptions& options) {
  ImuFileLoad out;
  std::vector<ImuSample> read;
  readFile(options, out, read);
  out.readings_read = read.size();
  screenReadings(options, read, out);
  if (options.rotation_body_imu)
    for (ImuSample& s : out.samples) {
      s.specific_force_mps2 = *options.rotation_body_imu * s.specific_force_mps2;
      s.angular_rate_radps = *options.rotation_body_imu * s.angular_rate_radps;
    }
  return out;
}

std::vector<std::string> ImuFileLoad::problemLines() const {
  std::vector<std::string> lines;
  const std::string path = report.file();
  if (const std::string headline = report.headline(path); !headline.empty()) lines.push_back(headline);
  for (const auto& [problem, count] : screen_problems)
    lines.push_back(path + ": " + std::to_string(count.count) + " x " + count.first);
  return lines;
}

}  // namespace ppp
