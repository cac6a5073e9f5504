#pragma once
// ImuInputScreen: the checks an IMU stream passes before its readings reach an
// estimator, whatever the source (a file reader, a sensor_msgs/Imu topic, the
// simulator). Each problem is named, counted and kept with its first example;
// a refused reading is dropped and the stream goes on:
//   - a non-finite reading;
//   - a stamp that goes backwards or repeats (refused), or jumps forward by more
//     than the allowed gap (kept, counted: the estimator bridges or restarts);
//   - a saturated axis: at or beyond the configured full scale of the sensor
//     (the accelerometer and gyro ranges the sensor is set to; unchecked when
//     not given);
//   - accelerations in g where m/s^2 is expected: the mean specific force over
//     the first readings of a stream near 1 instead of near 9.8 (at rest or in
//     unaccelerated flight the accelerometers read gravity), after which the
//     whole stream is refused: a reading in g would be 9.8 times too small;
//   - a time base far from the GNSS time: a stamp more than the allowed offset
//     from the latest GNSS epoch time given (a stream in another time scale or
//     epoch, e.g. seconds since boot).
// The first readings are held until the units are decided, then released.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

enum class ImuInputProblem {
  NonFinite,          ///< a NaN or infinite value (refused)
  TimeBackwards,      ///< the stamp is earlier than the previous reading's (refused)
  DuplicateTime,      ///< the stamp equals the previous reading's (refused)
  Gap,                ///< the stamp jumps forward by more than max_gap_s (kept)
  Saturated,          ///< an axis at or beyond the sensor's full scale (refused)
  InGravityUnits,     ///< the stream's accelerations are in g, not m/s^2 (refused)
  FarFromGnssTime,    ///< the stamp is more than max_gnss_offset_s from the GNSS time (refused)
};
/// "non-finite value", "time going backwards", "duplicate time", "gap", "saturated",
/// "accelerations in g, not m/s^2", "far from the GNSS time".
std::string imuInputProblemText(ImuInputProblem problem);

/// The units of a stream's accelerations, decided from its first readings.
enum class ImuAccelerationUnits { Undecided, MetresPerSecondSquared, Gravity };
std::string imuAccelerationUnitsText(ImuAccelerationUnits units);

/// Mean |f| [as given] of the first `count` readings (0 for none): near 9.8 at
/// rest in m/s^2, near 1 when the readings are in g.
double meanSpecificForceMagnitude(const std::vector<ImuSample>& samples, std::size_t count);
/// Whether a mean specific force reads as 1 g in units of g (in [0.5, 2.0]): in
/// m/s^2 it would be a platform falling at 0.8-0.95 g for the whole window.
bool meanForceLooksLikeGravityUnits(double mean_specific_force);

struct ImuInputScreenOptions {
  double max_gap_s = 0.1;  ///< largest step between readings that is not a gap [s], > 0
  /// Full scale of the accelerometers [m/s^2] and gyros [rad/s] as the sensor is
  /// set; a reading at or beyond `saturation_fraction` of it is saturated. Unset:
  /// not checked.
  std::optional<double> accel_full_scale_mps2;
  std::optional<double> gyro_full_scale_radps;
  double saturation_fraction = 0.999;  ///< (0, 1]
  /// Largest |IMU stamp - latest GNSS epoch time| [s] (unchecked before the first GNSS epoch).
  double max_gnss_offset_s = 2.0;
  /// Readings whose mean specific force decides the units (held until then).
  std::size_t units_readings = 50;
  /// false: the stamps were checked before (a file reader refuses backward and
  /// repeated stamps and counts gaps by line, io/imu/imu_file_loader.h); the screen
  /// then checks values, saturation and units only.
  bool check_time_order = true;
};

/// A problem's count and its first example ("reading at 2020-06-25 00:00:01.005: ...").
struct ImuProblemCount {
  std::size_t count = 0;
  std::string first;
};

class ImuInputScreen {
 public:
  explicit ImuInputScreen(ImuInputScreenOptions options = {});

  /// Screens one reading; returns the readings released to the estimator (none
  /// while the units are undecided, then the held ones in order).
  /// `gnss_time`: the latest GNSS epoch time, when there is one.
  std::vector<ImuSample> push(const ImuSample& reading, const std::optional<GnssTime>& gnss_time = std::nullopt);
  /// Releases the held readings at the end of a stream (units decided from
  /// what there is; nothing when they read as g).
  std::vector<ImuSample> finish();

  ImuAccelerationUnits units() const { return units_; }
  const std::map<ImuInputProblem, ImuProblemCount>& problems() const { return problems_; }
  std::size_t count(ImuInputProblem problem) const;
  std::size_t accepted() const { return accepted_; }
  /// "N readings accepted; M refused (k saturated, ...); G gaps", one line.
  std::string summary() const;

 private:
  void note(ImuInputProblem problem, const ImuSample& reading, const std::string& detail);
  /// The problem that refuses `reading`, if any (counts gaps and moves the last stamp on).
  std::optional<ImuInputProblem> refusal(const ImuSample& reading, const std::optional<GnssTime>& gnss_time);
  std::vector<ImuSample> decideUnits();

  ImuInputScreenOptions options_;
  ImuAccelerationUnits units_ = ImuAccelerationUnits::Undecided;
  std::optional<GnssTime> last_time_;
  std::vector<ImuSample> held_;
  std::map<ImuInputProblem, ImuProblemCount> problems_;
  std::size_t accepted_ = 0;
};

}  // namespace ppp
