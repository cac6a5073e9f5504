#include "ppp_bayes_tree/smoother/between_factor.h"

#include <stdexcept>

namespace ppp::smoother {

BetweenFactor::BetweenFactor(Key key1, Key key2, Vector z, NoiseModel::Ptr noise)
    : NoiseModelFactor2<Vector, Vector>(std::move(noise), {key1, key2}), z_(std::move(z)) {
  if (z_.size() != dim()) throw std::invalid_argument("BetweenFactor: measurement and noise differ in dimension");
}

Vector BetweenFactor::evaluateError(const Vector& x1, const Vector& x2, Matrix* h1, Matrix* h2) const {
  if (x1.size() != z_.size() || x2.size() != z_.size())
    throw std::invalid_argument("BetweenFactor: variable dimension mismatch");
  if (h1) *h1 = -Matrix::Identity(dim(), dim());
  if (h2) *h2 = Matrix::Identity(dim(), dim());
  return (x2 - x1) - z_;
}

}  // namespace ppp::smoother
