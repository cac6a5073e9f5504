#pragma once
// Nonlinear factor interface. A factor supplies only its unwhitened error h(x) - z and
// the Jacobians of that error with respect to each of its variables; the library whitens
// with the noise model, applies the robust kernel (IRLS) and linearizes. Factors on a
// fixed number of variables derive from NoiseModelFactorN (noise_model_factor_n.h),
// which looks the values up by key and hands them over typed; only factors of a
// run-time number of variables implement unwhitenedError on the Values themselves.
#include <cstdint>
#include <memory>
#include <vector>

#include "ppp_bayes_tree/smoother/gaussian_factor.h"
#include "ppp_bayes_tree/smoother/key.h"
#include "ppp_bayes_tree/smoother/noise_model.h"
#include "ppp_bayes_tree/smoother/values.h"

namespace ppp::smoother {

/// Index of a factor inside a smoother (stable for the factor's lifetime).
using FactorIndex = std::uint64_t;

class NonlinearFactor {
 public:
  using Ptr = std::shared_ptr<const NonlinearFactor>;

  NonlinearFactor(KeyVector keys, NoiseModel::Ptr noise);
  virtual ~NonlinearFactor() = default;

  const KeyVector& keys() const { return keys_; }
  const NoiseModel::Ptr& noiseModel() const { return noise_; }
  /// Error dimension.
  int dim() const { return noise_->dim(); }

  /// Unwhitened error h(x) - z. When `jacobians` is non-null it has keys().size()
  /// entries, which the factor fills with d(error)/d(x_j) (dim() x dim(x_j)).
  virtual Vector unwhitenedError(const Values& x, std::vector<Matrix>* jacobians) const = 0;

  /// Loss: 0.5 ||whitened error||^2, or rho(||whitened error||) with a robust kernel.
  double error(const Values& x) const;

  /// Whitened, robust-reweighted linearization at x, in delta coordinates:
  /// A delta - b with A = sqrt(w) R J and b = -sqrt(w) R e(x).
  virtual JacobianFactor::Ptr linearize(const Values& x) const;
  /// The same linearization (the same numbers), written into `storage` when given: a
  /// factor that nobody else holds, from an earlier linearization of this factor, whose
  /// buffers are reused (iSAM2 relinearizes most factors many times). A derived class
  /// that overrides linearize() overrides this too.
  virtual JacobianFactor::Ptr relinearize(const Values& x, std::shared_ptr<JacobianFactor> storage) const;

  /// True when the error is affine in variable `key` with a constant coefficient,
  /// e(x) = g(the other variables) + A x_key (A independent of every variable), as a
  /// phase factor in its bias or a prior. Default false (the safe answer).
  virtual bool affineIn(Key /*key*/) const { return false; }
  /// The same for one component of the variable: the error is affine in that
  /// component with a constant coefficient and no Jacobian block depends on it (as
  /// the PPP factors in a state's ZWD and clock). Default: affineIn(key).
  virtual bool affineInComponent(Key key, int /*component*/) const { return affineIn(key); }
  /// True when the linearization does not depend on the linearization point of this
  /// component of `key` beyond the shift of the right-hand side: affine in it and no
  /// robust kernel (whose weight depends on the residual). Moving only such
  /// components leaves the linear system, and so the solution, unchanged (iSAM2 may
  /// then skip the relinearization).
  bool linearizationIndependentOf(Key key, int component) const {
    return !noise_->robust() && affineInComponent(key, component);
  }

 private:
  KeyVector keys_;
  NoiseModel::Ptr noise_;
};

using NonlinearFactorGraph = std::vector<NonlinearFactor::Ptr>;

/// Total loss of a graph (null entries skipped).
double graphError(const NonlinearFactorGraph& graph, const Values& x);

}  // namespace ppp::smoother
