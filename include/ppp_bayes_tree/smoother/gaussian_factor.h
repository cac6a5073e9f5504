#pragma once
// Linear (Gaussian) factor in Jacobian form: error 0.5 ||sum_j A_j x_j - b||^2, one
// dense block A_j per variable. Linearized nonlinear factors are already whitened, so
// the model is unit.
#include <Eigen/Core>

#include <memory>
#include <vector>

#include "ppp_bayes_tree/smoother/key.h"
#include "ppp_bayes_tree/smoother/values.h"

namespace ppp::smoother {

class JacobianFactor {
 public:
  using Ptr = std::shared_ptr<const JacobianFactor>;

  JacobianFactor() = default;
  /// keys.size() == blocks.size(); every block has b.size() rows. Throws on mismatch.
  JacobianFactor(KeyVector keys, std::vector<Matrix> blocks, Vector b);

  const KeyVector& keys() const { return keys_; }
  const std::vector<Matrix>& blocks() const { return blocks_; }
  const Matrix& block(std::size_t i) const { return blocks_[i]; }
  const Vector& b() const { return b_; }
  int rows() const { return static_cast<int>(b_.size()); }
  bool empty() const { return b_.size() == 0; }

  /// Refills the factor in place, reusing its buffers where the sizes agree (a factor
  /// relinearized in iSAM2 keeps its shape): `fill(keys, blocks, b)` writes the new
  /// contents; the constructor's shape checks are made again afterwards.
  template <typename Fill>
  void refill(Fill&& fill) {
    fill(keys_, blocks_, b_);
    checkShape();
  }

  /// A x - b (x must hold every key).
  Vector residual(const Values& x) const;
  /// 0.5 ||A x - b||^2.
  double error(const Values& x) const { return 0.5 * residual(x).squaredNorm(); }

 private:
  void checkShape() const;

  KeyVector keys_;
  std::vector<Matrix> blocks_;
  Vector b_;
};

using GaussianFactorGraph = std::vector<JacobianFactor::Ptr>;

}  // namespace ppp::smoother
