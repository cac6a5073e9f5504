#pragma once
// sensor_msgs/Imu <-> ImuSample (navigation/imu_sample.h), after REP 145
// ("Conventions for IMU Sensor Drivers"): the message is in the IMU's own frame;
// linear_acceleration is what the accelerometers read, gravity included (at rest
// +9.8 m/s^2 along the axis pointing up): the specific force; angular_velocity
// in rad/s. The stamp is UTC (ROS time), the reading's time GPST (utcStamp,
// fromUtcStamp). A reading carries no orientation: orientation_covariance[0] is
// -1 ("no orientation estimate"), and the noise covariances are left unknown
// (all zero) unless given.
#include <optional>
#include <string>

#include <sensor_msgs/Imu.h>

#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"

namespace ppp_ros {

/// The message of a reading in `frame_id`; with `noise`, the covariances of
/// one reading at `rate_hz` from the white-noise densities (density^2 * rate).
sensor_msgs::Imu toImuMessage(const ppp::ImuSample& reading, const std::string& frame_id,
                              const std::optional<ppp::ImuNoise>& noise = std::nullopt, double rate_hz = 0.0);

/// The reading of a message (the orientation, if any, is not used).
ppp::ImuSample fromImuMessage(const sensor_msgs::Imu& message);

}  // namespace ppp_ros
