#pragma once
// The attitude a GNSS/INS estimator starts with (PppInsEkf, PppInsSmoother): the
// given attitude (InsEkfOptions::initial_rotation_ecef_body), or the given heading
// with roll and pitch from levelling the readings up to the start (at rest,
// ins_alignment.h). Neither, or a levelling refused: no attitude, with the reason.
// Also the velocity they start with.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/ppp/estimators/ins_ekf_options.h"

namespace ppp {

struct InsStartAttitude {
  std::optional<Eigen::Matrix3d> rotation_ecef_body;  ///< nullopt: no attitude (see problem)
  std::string problem;                               ///< why there is none
};

InsStartAttitude insStartAttitude(const InsEkfOptions& options, const std::vector<ImuSample>& readings_to_start,
                                  const Eigen::Vector3d& position_ecef_m);

/// The start velocity, ECEF [m/s]: InsEkfOptions::initial_velocity_ned_mps turned at
/// `position_ecef_m` when given, else initial_velocity_ecef_mps.
Eigen::Vector3d insStartVelocity_ecef_mps(const InsEkfOptions& options, const Eigen::Vector3d& position_ecef_m);

}  // namespace ppp
