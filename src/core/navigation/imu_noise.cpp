#include "ppp_bayes_tree/navigation/imu_noise.h"

#include <cmath>

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

constexpr double kMicroG_mps2 = 1e-6 * kStandardGravity_mps2;

/// Fills the bias random walks from the instabilities (see kBiasCorrelationTime_s).
ImuNoise withDerivedRandomWalks(ImuNoise n) {
  const double root_tau = std::sqrt(kBiasCorrelationTime_s);
  n.accel_bias_random_walk_mps3_per_sqrthz = n.accel_bias_instability_mps2 / root_tau;
  n.gyro_bias_random_walk_radps2_per_sqrthz = n.gyro_bias_instability_radps / root_tau;
  return n;
}

ImuNoise bmi088() {
  ImuNoise n;
  n.name = "Bosch BMI088";
  n.source =
      "Bosch Sensortec BMI088 data sheet BST-BMI088-DS001 (rev. 1.3/1.4, 2018), specification tables: "
      "gyro rate noise density 0.014 deg/s/sqrt(Hz), gyro bias stability 2 deg/h; accelerometer noise "
      "density 175 ug/sqrt(Hz) (typical; the table differs by axis and range, taken as +-10%); "
      "accelerometer bias instability not specified: 100 ug assumed";
  n.gyro_noise_density_radps_per_sqrthz = 0.014 * kDegToRad;
  n.gyro_bias_instability_radps = degPerHourToRadps(2.0);
  n.accel_noise_density_mps2_per_sqrthz = 175.0 * kMicroG_mps2;
  n.accel_bias_instability_mps2 = 100.0 * kMicroG_mps2;
  return withDerivedRandomWalks(n);
}

ImuNoise adis16465() {
  ImuNoise n;
  n.name = "Analog Devices ADIS16465-1";
  n.source =
      "Analog Devices ADIS16465 data sheet, features list: gyro in-run bias stability 2 deg/h "
      "(ADIS16465-1), angle random walk 0.15 deg/sqrt(h); accelerometer in-run bias stability 3.6 ug; "
      "velocity random walk 0.012 m/s/sqrt(h) (from the specification table, less certain)";
  n.gyro_noise_density_radps_per_sqrthz = degPerSqrtHourToRadpsPerSqrtHz(0.15);
  n.gyro_bias_instability_radps = degPerHourToRadps(2.0);
  n.accel_noise_density_mps2_per_sqrthz = mpsPerSqrtHourToMps2PerSqrtHz(0.012);
  n.accel_bias_instability_mps2 = 3.6 * kMicroG_mps2;
  return withDerivedRandomWalks(n);
}

ImuNoise ln200() {
  ImuNoise n;
  n.name = "Northrop Grumman LN-200";
  n.source =
      "Northrop Grumman LN-200 product data sheet: gyro bias 1 deg/h (1 sigma), angle random walk "
      "0.07 deg/sqrt(h); accelerometer bias 300 ug (1 sigma), white noise 50 ug/sqrt(Hz). The bias "
      "figures are turn-on repeatability; the in-run instability is smaller, so these are pessimistic";
  n.gyro_noise_density_radps_per_sqrthz = degPerSqrtHourToRadpsPerSqrtHz(0.07);
  n.gyro_bias_instability_radps = degPerHourToRadps(1.0);
  n.accel_noise_density_mps2_per_sqrthz = 50.0 * kMicroG_mps2;
  n.accel_bias_instability_mps2 = 300.0 * kMicroG_mps2;
  return withDerivedRandomWalks(n);
}

}  // namespace

std::optional<ImuGrade> imuGradeFromName(const std::string& name) {
  if (name == "consumer_mems" || name == "consumer") return ImuGrade::ConsumerMems;
  if (name == "industrial_mems" || name == "industrial") return ImuGrade::IndustrialMems;
  if (name == "tactical") return ImuGrade::Tactical;
  return std::nullopt;
}

std::string imuGradeText(ImuGrade grade) {
  switch (grade) {
    case ImuGrade::ConsumerMems: return "consumer MEMS";
    case ImuGrade::IndustrialMems: return "industrial MEMS";
    case ImuGrade::Tactical: return "tactical";
  }
  return "unknown grade";
}

ImuNoise imuNoisePreset(ImuGrade grade) {
  switch (grade) {
    case ImuGrade::ConsumerMems: return bmi088();
    case ImuGrade::IndustrialMems: return adis16465();
    case ImuGrade::Tactical: return ln200();
  }
  return bmi088();
}

double degPerHourToRadps(double deg_per_hour) { return deg_per_hour * kDegToRad / 3600.0; }

double degPerSqrtHourToRadpsPerSqrtHz(double deg_per_sqrt_hour) {
  return deg_per_sqrt_hour * kDegToRad / 60.0;  // sqrt(3600 s) = 60
}

double mpsPerSqrtHourToMps2PerSqrtHz(double mps_per_sqrt_hour) { return mps_per_sqrt_hour / 60.0; }

}  // namespace ppp
