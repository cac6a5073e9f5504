#pragma once
// InertialState: what a GNSS/INS estimator tells of its IMU state after an epoch
// (PppEstimator::inertialState(); the GNSS-only estimators have none): the IMU's
// NavState and bias at the last epoch it reached (also through epochs without a
// GNSS solution: dead-reckoned), the antenna position of that NavState, and, when
// the estimator keeps them, the attitude's alignment and quality, the INS
// error covariance and the epoch's Doppler velocity update. The attitude file of ppp_solve and the EKF node's odometry
// and status are made from it.
#include <Eigen/Core>
#include <optional>

#include "ppp_bayes_tree/navigation/imu_bias.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/navigation/ins_error_state.h"
#include "ppp_bayes_tree/navigation/nav_state.h"
#include "ppp_bayes_tree/ppp/estimators/doppler_update.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

struct InertialState {
  GnssTime time;                                      ///< the epoch the state is at
  NavState nav;                                       ///< IMU origin and axes, ECEF
  ImuBias bias;                                       ///< the IMU bias estimate
  Eigen::Vector3d antenna_ecef_m = Eigen::Vector3d::Zero();  ///< the antenna of `nav` (lever arm) [m]
  std::optional<InsAttitudeQuality> attitude_quality;  ///< alignment, sigmas, publishable; nullopt: not kept
  std::optional<Matrix15d> error_covariance;          ///< INS error covariance (ins_error_state.h order); nullopt: not kept
  std::optional<DopplerUpdate> doppler;               ///< the epoch's Doppler velocity update; nullopt: none kept
};

}  // namespace ppp
