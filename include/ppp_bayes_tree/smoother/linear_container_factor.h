#pragma once
// A linear factor frozen at a linearization point theta0 and used as a nonlinear factor:
// whitened error A (x (-) theta0) - b (x - theta0 for a vector variable, the local
// coordinates of x at theta0 for a manifold variable), Jacobian A (in the tangent
// space at theta0; constant for vector variables). It carries marginal information
// (e.g. from fixed-lag marginalization) into later re-eliminations; its unit noise model
// means the stored A, b are already whitened.
#include "ppp_bayes_tree/smoother/nonlinear_factor.h"

namespace ppp::smoother {

class LinearContainerFactor : public NonlinearFactor {
 public:
  /// `theta0` must hold every key of `factor`.
  LinearContainerFactor(const JacobianFactor& factor, const Values& theta0);
  Vector unwhitenedError(const Values& x, std::vector<Matrix>* jacobians) const override;
  JacobianFactor::Ptr linearize(const Values& x) const override;
  /// linearize(x) (its blocks are the stored ones; nothing to reuse).
  JacobianFactor::Ptr relinearize(const Values& x, std::shared_ptr<JacobianFactor>) const override {
    return linearize(x);
  }
  /// Constant Jacobian A in a vector variable; not so in a manifold variable.
  bool affineIn(Key key) const override { return !theta0_.manifold(key); }

 private:
  JacobianFactor factor_;
  Values theta0_;  // the linearization point of each key, with its manifold
};

}  // namespace ppp::smoother
