#include "ppp_bayes_tree/smoother/linear_container_factor.h"

namespace ppp::smoother {

LinearContainerFactor::LinearContainerFactor(const JacobianFactor& factor, const Values& theta0)
    : NonlinearFactor(factor.keys(), NoiseModel::unit(factor.rows())), factor_(factor) {
  for (Key k : factor.keys()) theta0_.insertFrom(theta0, k);
}

Vector LinearContainerFactor::unwhitenedError(const Values& x, std::vector<Matrix>* jacobians) const {
  Vector e = -factor_.b();
  for (std::size_t j = 0; j < keys().size(); ++j) {
    const Key k = keys()[j];
    const Manifold::Ptr m = theta0_.manifold(k);
    if (m)
      e += factor_.block(j) * m->localCoordinates(theta0_.at(k), x.at(k));
    else
      e += factor_.block(j) * (x.at(k) - theta0_.at(k));
    if (jacobians) (*jacobians)[j] = factor_.block(j);
  }
  return e;
}

JacobianFactor::Ptr LinearContainerFactor::linearize(const Values& x) const {
  // A (theta + delta - theta0) - b = A delta - (b - A (theta - theta0)).
  return std::make_shared<JacobianFactor>(factor_.keys(), factor_.blocks(),
                                          -unwhitenedError(x, nullptr));
}

}  // namespace ppp::smoother
