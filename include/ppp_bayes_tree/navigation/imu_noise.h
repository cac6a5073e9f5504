#pragma once
// ImuNoise: the stochastic parameters of an IMU grade, in SI units:
// - white noise densities of the accelerometers and gyros (the velocity and
//   angle random walks),
// - the bias instability (the flat floor of the Allan deviation, or the
//   datasheet's in-run bias stability),
// - the bias random-walk densities the estimators use to let the biases move.
//
// Named presets come from real datasheets; doc/gnss_ins.md lists the part, the
// datasheet figure used and how sure each figure is. Datasheets give no bias
// random walk: the presets derive it as instability / sqrt(kBiasCorrelationTime_s),
// a modelling choice, not a measured figure.
#include <optional>
#include <string>

namespace ppp {

enum class ImuGrade { ConsumerMems, IndustrialMems, Tactical };
/// "consumer MEMS", "industrial MEMS", "tactical".
std::string imuGradeText(ImuGrade grade);
/// The grade a configuration or command line names: its key ("consumer_mems",
/// "industrial_mems", "tactical") or the short form ("consumer", "industrial");
/// nullopt for any other name (the caller says which names it takes).
std::optional<ImuGrade> imuGradeFromName(const std::string& name);

struct ImuNoise {
  std::string name;    ///< e.g. "Bosch BMI088"
  std::string source;  ///< the datasheet and figures used
  double accel_noise_density_mps2_per_sqrthz = 0.0;   ///< [m/s^2/sqrt(Hz)]
  double gyro_noise_density_radps_per_sqrthz = 0.0;   ///< [rad/s/sqrt(Hz)]
  double accel_bias_instability_mps2 = 0.0;           ///< [m/s^2]
  double gyro_bias_instability_radps = 0.0;           ///< [rad/s]
  double accel_bias_random_walk_mps3_per_sqrthz = 0.0;  ///< [m/s^3/sqrt(Hz)]
  double gyro_bias_random_walk_radps2_per_sqrthz = 0.0;  ///< [rad/s^2/sqrt(Hz)]
};

/// Time over which a preset's bias random walk reaches its bias instability [s].
constexpr double kBiasCorrelationTime_s = 100.0;

/// The preset of a grade: consumer = Bosch BMI088, industrial = Analog Devices
/// ADIS16465-1, tactical = Northrop Grumman LN-200.
ImuNoise imuNoisePreset(ImuGrade grade);

// Unit conversions used by the presets and readers.
/// Standard gravity, the unit "g" of accelerometer datasheets and logs [m/s^2]
/// (3rd CGPM, 1901).
constexpr double kStandardGravity_mps2 = 9.80665;
/// deg/h -> rad/s.
double degPerHourToRadps(double deg_per_hour);
/// deg/sqrt(h) (angle random walk) -> rad/s/sqrt(Hz).
double degPerSqrtHourToRadpsPerSqrtHz(double deg_per_sqrt_hour);
/// m/s/sqrt(h) (velocity random walk) -> m/s^2/sqrt(Hz).
double mpsPerSqrtHourToMps2PerSqrtHz(double mps_per_sqrt_hour);

}  // namespace ppp
