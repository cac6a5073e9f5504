#pragma once
// ImuBias: the additive accelerometer and gyro biases of an IMU. The sensor reads
// f_measured = f_true + accel + noise and w_measured = w_true + gyro + noise.
// As a 6-vector the order is [accel; gyro].
#include <Eigen/Core>

namespace ppp {

struct ImuBias {
  Eigen::Vector3d accel_mps2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_radps = Eigen::Vector3d::Zero();

  Eigen::Matrix<double, 6, 1> vector() const {
    Eigen::Matrix<double, 6, 1> v;
    v << accel_mps2, gyro_radps;
    return v;
  }
  static ImuBias fromVector(const Eigen::Matrix<double, 6, 1>& v) {
    return ImuBias{v.head<3>(), v.tail<3>()};
  }
};

}  // namespace ppp
