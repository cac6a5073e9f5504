#pragma once
// AntennaPositionFactor: ties the position of a receiver state (the point the code and
// phase factors are evaluated at) to the antenna of a NavState,
//   error = x.position - (p + R lever_arm_body),
// with a stiff sigma, so that the GNSS factors of the receiver state act on the pose
// (attitude through the lever arm, position) by the chain rule. Jacobians: +I on the
// receiver position, 0 on its other components; on the NavState tangent
// [dtheta; dv; dp]: R [lever_arm]x, 0, -I.
#include <Eigen/Core>

#include "ppp_bayes_tree/navigation/nav_state_value.h"
#include "ppp_bayes_tree/smoother/noise_model_factor_n.h"

namespace ppp {

class AntennaPositionFactor : public smoother::NoiseModelFactorN<smoother::Vector, NavState> {
 public:
  /// `position_index`: first of the 3 position components in the receiver state.
  AntennaPositionFactor(smoother::Key receiver_state, smoother::Key nav_state, int position_index,
                        const Eigen::Vector3d& lever_arm_body_m, double sigma_m);
  smoother::Vector evaluateError(const smoother::Vector& receiver, const NavState& nav, smoother::Matrix* h_receiver,
                                 smoother::Matrix* h_nav) const override;
  static Eigen::Vector3d antennaOf(const NavState& nav, const Eigen::Vector3d& lever_arm_body_m) {
    return nav.position_world_m + nav.rotation_world_body * lever_arm_body_m;
  }

 private:
  int position_index_;
  Eigen::Vector3d lever_arm_body_m_;
};

}  // namespace ppp
