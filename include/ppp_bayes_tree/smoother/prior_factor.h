#pragma once
// Prior on one variable: error x - z.
#include "ppp_bayes_tree/smoother/noise_model_factor_n.h"

namespace ppp::smoother {

class PriorFactor : public NoiseModelFactor1<Vector> {
 public:
  /// Throws std::invalid_argument when z and the noise model differ in dimension.
  PriorFactor(Key key, Vector z, NoiseModel::Ptr noise);
  const Vector& prior() const { return z_; }
  Vector evaluateError(const Vector& x, Matrix* h) const override;
  bool affineIn(Key) const override { return true; }  // x - z

 private:
  Vector z_;
};

}  // namespace ppp::smoother
