#pragma once
// Additive between factor on two variables of the same dimension: error (x2 - x1) - z.
#include "ppp_bayes_tree/smoother/nonlinear_factor.h"

namespace ppp::smoother {

class BetweenFactor : public NonlinearFactor {
 public:
  BetweenFactor(Key key1, Key key2, Vector z, NoiseModel::Ptr noise);
  const Vector& measured() const { return z_; }
  Vector unwhitenedError(const Values& x, std::vector<Matrix>* jacobians) const override;
  bool affineIn(Key) const override { return true; }  // (x2 - x1) - z

 private:
  Vector z_;
};

}  // namespace ppp::smoother
