#include "ppp_bayes_tree/smoother/gaussian_factor.h"

#include <stdexcept>

namespace ppp::smoother {

JacobianFactor::JacobianFactor(KeyVector keys, std::vector<Matrix> blocks, Vector b)
    : keys_(std::move(keys)), blocks_(std::move(blocks)), b_(std::move(b)) {
  checkShape();
}

void JacobianFactor::checkShape() const {
  if (keys_.size() != blocks_.size()) throw std::invalid_argument("JacobianFactor: keys/blocks mismatch");
  for (const auto& m : blocks_)
    if (m.rows() != b_.size()) throw std::invalid_argument("JacobianFactor: block row count mismatch");
}

Vector JacobianFactor::residual(const Values& x) const {
  Vector r = -b_;
  for (std::size_t j = 0; j < keys_.size(); ++j) r += blocks_[j] * x.at(keys_[j]);
  return r;
}

}  // namespace ppp::smoother
