#pragma once
// Generic factor from a function of its variables' values, for tests and prototypes.
// The function returns h(x) - z; it may fill the Jacobians (return true), or leave them
// (return false) to have them computed by central differences.
#include <functional>

#include "ppp_bayes_tree/smoother/nonlinear_factor.h"

namespace ppp::smoother {

class FunctionFactor : public NonlinearFactor {
 public:
  /// `x` holds the factor's variables in keys order; `jacobians` is null or sized.
  using ErrorFunction =
      std::function<bool(const std::vector<Vector>& x, Vector& error, std::vector<Matrix>* jacobians)>;

  FunctionFactor(KeyVector keys, NoiseModel::Ptr noise, ErrorFunction function,
                 double numerical_step = 1e-6);
  Vector unwhitenedError(const Values& x, std::vector<Matrix>* jacobians) const override;

 private:
  ErrorFunction function_;
  double step_;
};

}  // namespace ppp::smoother
