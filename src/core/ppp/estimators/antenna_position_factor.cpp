#include "ppp_bayes_tree/ppp/estimators/antenna_position_factor.h"

#include <stdexcept>
#include <string>

#include "ppp_bayes_tree/navigation/so3.h"

namespace ppp {

AntennaPositionFactor::AntennaPositionFactor(smoother::Key receiver_state, smoother::Key nav_state, int position_index,
                                             const Eigen::Vector3d& lever_arm_body_m, double sigma_m)
    : NoiseModelFactorN(smoother::NoiseModel::isotropic(3, sigma_m), {receiver_state, nav_state}),
      position_index_(position_index),
      lever_arm_body_m_(lever_arm_body_m) {
  if (position_index < 0) throw std::invalid_argument("AntennaPositionFactor: negative position index");
}

smoother::Vector AntennaPositionFactor::evaluateError(const smoother::Vector& receiver, const NavState& nav,
                                                      smoother::Matrix* h_receiver, smoother::Matrix* h_nav) const {
  if (receiver.size() < position_index_ + 3)
    throw std::invalid_argument("AntennaPositionFactor: receiver state of " + std::to_string(receiver.size()) +
                                " components has no position at " + std::to_string(position_index_));
  if (h_receiver) {
    *h_receiver = smoother::Matrix::Zero(3, receiver.size());
    h_receiver->block<3, 3>(0, position_index_).setIdentity();
  }
  if (h_nav) {
    *h_nav = smoother::Matrix::Zero(3, 9);
    h_nav->block<3, 3>(0, 0) = nav.rotation_world_body * so3::hat(lever_arm_body_m_);
    h_nav->block<3, 3>(0, 6) = -Eigen::Matrix3d::Identity();
  }
  return receiver.segment<3>(position_index_) - antennaOf(nav, lever_arm_body_m_);
}

}  // namespace ppp
