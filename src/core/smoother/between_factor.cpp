#include "ppp_bayes_tree/smoother/between_factor.h"

#include <stdexcept>

namespace ppp::smoother {

BetweenFactor::BetweenFactor(Key key1, Key key2, Vector z, NoiseModel::Ptr noise)
    : NonlinearFactor({key1, key2}, std::move(noise)), z_(std::move(z)) {
  if (z_.size() != dim()) throw std::invalid_argument("BetweenFactor: measurement and noise differ in dimension");
}

Vector BetweenFactor::unwhitenedError(const Values& x, std::vector<Matrix>* jacobians) const {
  const Vector& a = x.at(keys()[0]);
  const Vector& b = x.at(keys()[1]);
  if (a.size() != z_.size() || b.size() != z_.size())
    throw std::invalid_argument("BetweenFactor: variable dimension mismatch");
  if (jacobians) {
    (*jacobians)[0] = -Matrix::Identity(dim(), dim());
    (*jacobians)[1] = Matrix::Identity(dim(), dim());
  }
  return (b - a) - z_;
}

}  // namespace ppp::smoother
