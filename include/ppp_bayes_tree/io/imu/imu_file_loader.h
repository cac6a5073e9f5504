#pragma once
// loadImuFile: an IMU file as the estimators take it, whatever its format: the
// plain IMU CSV (imu_csv_reader.h) or an IMU logged by RTKLIB with its time-tag
// file (logged_imu_reader.h), then the IMU input screen
// (navigation/imu_input_screen.h). The reader checks each line (fields, numbers,
// stamps forward, gaps: counted with the file and line); the screen then checks
// the readings' values only (saturation against the given full scale, the
// acceleration units): its time checks are for streams and are not run twice.
// Used by ppp_solve --imu and ppp_to_bag --imu.
#include <Eigen/Core>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/navigation/imu_input_screen.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"

namespace ppp {

enum class ImuFileFormat { PlainCsv, RtklibLogged };
/// "csv", "logged".
std::string imuFileFormatText(ImuFileFormat format);

struct ImuFileOptions {
  std::string path;
  ImuFileFormat format = ImuFileFormat::PlainCsv;
  std::string tag_path;  ///< the time-tag file (RtklibLogged only)
  /// The screen's value checks (full scales, units window); its time checks are off.
  ImuInputScreenOptions screen;
  /// The IMU's mounting, R_body_imu: when set, the kept readings are turned from the
  /// sensor's axes into the body axes (f_body = R f_imu, w_body = R w_imu), after the
  /// screen (which checks the sensor's own axes against their full scale).
  std::optional<Eigen::Matrix3d> rotation_body_imu;
};

struct ImuFileLoad {
  std::vector<ImuSample> samples;  ///< the readings the screen kept, in time order
  ParseReport report;              ///< the reader's line problems (file and line)
  std::size_t lines = 0;           ///< lines read
  std::size_t readings_read = 0;   ///< readings the reader kept (before the screen)
  std::size_t refused = 0;         ///< readings the screen refused
  ImuAccelerationUnits units = ImuAccelerationUnits::Undecided;
  std::size_t saturated = 0;       ///< readings refused as saturated
  /// The screen's problems, each with its count and first example.
  std::map<ImuInputProblem, ImuProblemCount> screen_problems;
  std::string screen_summary;      ///< ImuInputScreen::summary()

  /// The problems to print: the reader's headline (when it has problems) and one
  /// line per screen problem with its count and first example, each starting with
  /// the path; empty for a clean file.
  std::vector<std::string> problemLines() const;
};

/// Reads and screens one IMU file. Throws std::invalid_argument for a logged file
/// without a tag path, FileOpenError when a file cannot be read, ParseError for a
/// bad time-tag header; everything else is counted in the result.
ImuFileLoad loadImuFile(const ImuFileOptions& options);

}  // namespace ppp
