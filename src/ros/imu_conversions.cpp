#include "ppp_bayes_tree/ros/imu_conversions.h"

#include "ppp_bayes_tree/ros/message_conversions.h"

namespace ppp_ros {

sensor_msgs::Imu toImuMessage(const ppp::ImuSample& reading, const std::string& frame_id,
                              const std::optional<ppp::ImuNoise>& noise, double rate_hz) {
  sensor_msgs::Imu m;
  m.header.stamp = utcStamp(reading.time);
  m.header.frame_id = frame_id;
  m.orientation.w = 1.0;
  m.orientation_covariance[0] = -1.0;  // REP 145: no orientation estimate
  m.linear_acceleration.x = reading.specific_force_mps2.x();
  m.linear_acceleration.y = reading.specific_force_mps2.y();
  m.linear_acceleration.z = reading.specific_force_mps2.z();
  m.angular_velocity.x = reading.angular_rate_radps.x();
  m.angular_velocity.y = reading.angular_rate_radps.y();
  m.angular_velocity.z = reading.angular_rate_radps.z();
  if (noise && rate_hz > 0.0) {
    const double accel_var = noise->accel_noise_density_mps2_per_sqrthz * noise->accel_noise_density_mps2_per_sqrthz * rate_hz;
    const double gyro_var = noise->gyro_noise_density_radps_per_sqrthz * noise->gyro_noise_density_radps_per_sqrthz * rate_hz;
    for (int i = 0; i < 3; ++i) {
      m.linear_acceleration_covariance[static_cast<std::size_t>(4 * i)] = accel_var;
      m.angular_velocity_covariance[static_cast<std::size_t>(4 * i)] = gyro_var;
    }
  }
  return m;
}

ppp::ImuSample fromImuMessage(const sensor_msgs::Imu& message) {
  ppp::ImuSample s;
  s.time = fromUtcStamp(message.header.stamp);
  s.specific_force_mps2 = {message.linear_acceleration.x, message.linear_acceleration.y, message.linear_acceleration.z};
  s.angular_rate_radps = {message.angular_velocity.x, message.angular_velocity.y, message.angular_velocity.z};
  return s;
}

}  // namespace ppp_ros
