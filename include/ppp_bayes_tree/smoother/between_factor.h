#pragma once
// Additive between factor on two variables of the same dimension: error (x2 - x1) - z.
#include "ppp_bayes_tree/smoother/noise_model_factor_n.h"

namespace ppp::smoother {

class BetweenFactor : public NoiseModelFactor2<Vector, Vector> {
 public:
  BetweenFactor(Key key1, Key key2, Vector z, NoiseModel::Ptr noise);
  const Vector& measured() const { return z_; }
  Vector evaluateError(const Vector& x1, const Vector& x2, Matrix* h1, Matrix* h2) const override;
  bool affineIn(Key) const override { return true; }  // (x2 - x1) - z

 private:
  Vector z_;
};

}  // namespace ppp::smoother
