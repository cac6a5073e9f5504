#include "ppp_bayes_tree/smoother/prior_factor.h"

#include <stdexcept>

namespace ppp::smoother {

PriorFactor::PriorFactor(Key key, Vector z, NoiseModel::Ptr noise)
    : NonlinearFactor({key}, std::move(noise)), z_(std::move(z)) {
  if (z_.size() != dim()) throw std::invalid_argument("PriorFactor: prior and noise differ in dimension");
}

Vector PriorFactor::unwhitenedError(const Values& x, std::vector<Matrix>* jacobians) const {
  const Vector& v = x.at(keys()[0]);
  if (v.size() != z_.size()) throw std::invalid_argument("PriorFactor: variable dimension mismatch");
  if (jacobians) (*jacobians)[0] = Matrix::Identity(dim(), dim());
  return v - z_;
}

}  // namespace ppp::smoother
