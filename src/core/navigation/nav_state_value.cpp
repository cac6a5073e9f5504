#include "ppp_bayes_tree/navigation/nav_state_value.h"

#include <stdexcept>
#include <string>

#include "ppp_bayes_tree/navigation/so3.h"

namespace ppp {

const smoother::Manifold::Ptr& NavStateManifold::instance() {
  static const smoother::Manifold::Ptr manifold = std::make_shared<const NavStateManifold>();
  return manifold;
}

Eigen::VectorXd NavStateManifold::retract(const Eigen::VectorXd& x, const Eigen::VectorXd& delta) const {
  const Eigen::Matrix<double, 9, 1> d = delta;
  return navStateStorage(navStateFromStorage(x).retract(d));
}

Eigen::VectorXd NavStateManifold::localCoordinates(const Eigen::VectorXd& x, const Eigen::VectorXd& y) const {
  return navStateFromStorage(x).localCoordinates(navStateFromStorage(y));
}

Eigen::VectorXd navStateStorage(const NavState& state) {
  Eigen::VectorXd s(kNavStateStorageDim);
  s.head<9>() = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(state.rotation_world_body.data());
  s.segment<3>(9) = state.velocity_world_mps;
  s.segment<3>(12) = state.position_world_m;
  return s;
}

NavState navStateFromStorage(const Eigen::VectorXd& storage) {
  NavState state;
  state.rotation_world_body = Eigen::Map<const Eigen::Matrix3d>(storage.data());
  state.velocity_world_mps = storage.segment<3>(9);
  state.position_world_m = storage.segment<3>(12);
  return state;
}

void insertNavState(smoother::Values& values, smoother::Key key, const NavState& state) {
  values.insert(key, navStateStorage(state), NavStateManifold::instance());
}

NavState navStateAt(const smoother::Values& values, smoother::Key key) {
  return smoother::ValueTraits<NavState>::read(values.at(key), key);
}

NavStatePriorFactor::NavStatePriorFactor(smoother::Key key, const NavState& prior, smoother::NoiseModel::Ptr noise)
    : NoiseModelFactorN(std::move(noise), {key}), prior_(prior) {
  if (dim() != kNavStateTangentDim)
    throw std::invalid_argument("NavStatePriorFactor: the noise model has " + std::to_string(dim()) +
                                " rows, a NavState prior needs 9");
}

smoother::Vector NavStatePriorFactor::evaluateError(const NavState& x, smoother::Matrix* h) const {
  const Eigen::Matrix<double, 9, 1> d = prior_.localCoordinates(x);
  if (h) {
    *h = smoother::Matrix::Identity(9, 9);
    h->topLeftCorner<3, 3>() = so3::rightJacobianInverse(d.head<3>());
  }
  return d;
}

}  // namespace ppp

namespace ppp::smoother {

NavState ValueTraits<NavState>::read(const Vector& stored, Key key) {
  if (stored.size() != kNavStateStorageDim)
    throw std::invalid_argument("factor expects a NavState (15 stored components) for " + keyToString(key) +
                                ", the value has " + std::to_string(stored.size()));
  return navStateFromStorage(stored);
}

ImuBias ValueTraits<ImuBias>::read(const Vector& stored, Key key) {
  if (stored.size() != 6)
    throw std::invalid_argument("factor expects an IMU bias (6 components) for " + keyToString(key) +
                                ", the value has " + std::to_string(stored.size()));
  return ImuBias::fromVector(stored);
}

}  // namespace ppp::smoother
