#include "ppp_bayes_tree/smoother/prior_factor.h"

#include <stdexcept>

namespace ppp::smoother {

PriorFactor::PriorFactor(Key key, Vector z, NoiseModel::Ptr noise)
    : NoiseModelFactor1<Vector>(std::move(noise), {key}), z_(std::move(z)) {
  if (z_.size() != dim()) throw std::invalid_argument("PriorFactor: prior and noise differ in dimension");
}

Vector PriorFactor::evaluateError(const Vector& x, Matrix* h) const {
  if (x.size() != z_.size()) throw std::invalid_argument("PriorFactor: variable dimension mismatch");
  if (h) *h = Matrix::Identity(dim(), dim());
  return x - z_;
}

}  // namespace ppp::smoother
