#include "ppp_bayes_tree/smoother/function_factor.h"

#include <stdexcept>

#include "ppp_bayes_tree/smoother/numerical_jacobian.h"

namespace ppp::smoother {

FunctionFactor::FunctionFactor(KeyVector keys, NoiseModel::Ptr noise, ErrorFunction function,
                               double numerical_step)
    : NonlinearFactor(std::move(keys), std::move(noise)), function_(std::move(function)),
      step_(numerical_step) {
  if (!function_) throw std::invalid_argument("FunctionFactor: empty function");
}

Vector FunctionFactor::unwhitenedError(const Values& x, std::vector<Matrix>* jacobians) const {
  std::vector<Vector> args;
  args.reserve(keys().size());
  for (Key k : keys()) args.push_back(x.at(k));
  Vector e;
  const bool analytic = function_(args, e, jacobians);
  if (jacobians && !analytic) *jacobians = numericalJacobians(*this, x, step_);
  return e;
}

}  // namespace ppp::smoother
