#pragma once
// A NavState as a variable of the smoother: its Manifold (SO(3) x R^6 with the tangent
// [dtheta (right, body); dv; dp] of nav_state.h) and how a factor reads it. The stored
// vector holds 15 numbers, [R_world_body column by column (9); velocity (3);
// position (3)]; the variable's dimension in the linear system is 9. Also the
// prior factor on a NavState (error: the local coordinates of the state at the prior)
// and the bias's ValueTraits (an ImuBias is the 6-vector [accel; gyro]).
#include <Eigen/Core>

#include "ppp_bayes_tree/navigation/imu_bias.h"
#include "ppp_bayes_tree/navigation/nav_state.h"
#include "ppp_bayes_tree/smoother/noise_model_factor_n.h"
#include "ppp_bayes_tree/smoother/value_traits.h"
#include "ppp_bayes_tree/smoother/values.h"

namespace ppp {

/// Stored components of a NavState variable and its tangent dimension.
inline constexpr int kNavStateStorageDim = 15;
inline constexpr int kNavStateTangentDim = 9;

class NavStateManifold : public smoother::Manifold {
 public:
  /// The one instance every NavState variable names.
  static const smoother::Manifold::Ptr& instance();

  const char* name() const override { return "nav_state"; }
  int storageDim() const override { return kNavStateStorageDim; }
  int tangentDim() const override { return kNavStateTangentDim; }
  Eigen::VectorXd retract(const Eigen::VectorXd& x, const Eigen::VectorXd& delta) const override;
  Eigen::VectorXd localCoordinates(const Eigen::VectorXd& x, const Eigen::VectorXd& y) const override;
};

/// The 15 stored numbers of a state, and back.
Eigen::VectorXd navStateStorage(const NavState& state);
NavState navStateFromStorage(const Eigen::VectorXd& storage);

/// Inserts a NavState variable (with its manifold).
void insertNavState(smoother::Values& values, smoother::Key key, const NavState& state);
/// Reads a NavState variable; throws std::invalid_argument naming the key when the
/// variable is not a NavState.
NavState navStateAt(const smoother::Values& values, smoother::Key key);

/// Prior on a NavState: error = the tangent d with prior (+) d == x, 9-vector
/// [dtheta; dv; dp]; Jacobian Jr^-1(dtheta) on the rotation block, identity elsewhere.
class NavStatePriorFactor : public smoother::NoiseModelFactor1<NavState> {
 public:
  NavStatePriorFactor(smoother::Key key, const NavState& prior, smoother::NoiseModel::Ptr noise);
  smoother::Vector evaluateError(const NavState& x, smoother::Matrix* h) const override;
  const NavState& prior() const { return prior_; }

 private:
  NavState prior_;
};

}  // namespace ppp

namespace ppp::smoother {

template <>
struct ValueTraits<NavState> {
  static constexpr int kDim = kNavStateTangentDim;
  static NavState read(const Vector& stored, Key key);
};

template <>
struct ValueTraits<ImuBias> {
  static constexpr int kDim = 6;
  static ImuBias read(const Vector& stored, Key key);
};

}  // namespace ppp::smoother
