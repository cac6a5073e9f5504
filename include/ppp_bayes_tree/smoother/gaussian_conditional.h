#pragma once
// Gaussian conditional density p(x_f | x_s) in square-root form R x_f + S x_s = d, with
// R upper triangular (frontal variables in order) and one block S_j per separator
// (parent) variable; the result of eliminating the frontal variables.
#include <Eigen/Core>

#include <vector>

#include "ppp_bayes_tree/smoother/key.h"
#include "ppp_bayes_tree/smoother/values.h"

namespace ppp::smoother {

class GaussianConditional {
 public:
  GaussianConditional() = default;
  GaussianConditional(KeyVector frontals, std::vector<int> frontal_dims, KeyVector parents,
                      Matrix r, std::vector<Matrix> s, Vector d);

  const KeyVector& frontals() const { return frontals_; }
  const std::vector<int>& frontalDims() const { return frontal_dims_; }
  const KeyVector& parents() const { return parents_; }
  const Matrix& R() const { return r_; }
  const std::vector<Matrix>& S() const { return s_; }
  const Vector& d() const { return d_; }
  int frontalDim() const { return static_cast<int>(d_.size()); }
  /// Offset of frontal i inside R's columns.
  int frontalOffset(std::size_t i) const { return offsets_[i]; }

  /// x_f = R^-1 (d - S x_s), with the parents' values read from `x`; returns the stacked
  /// frontal vector (frontals in order).
  Vector solve(const Values& x) const;

 private:
  KeyVector frontals_;
  std::vector<int> frontal_dims_;
  std::vector<int> offsets_;
  KeyVector parents_;
  Matrix r_;
  std::vector<Matrix> s_;
  Vector d_;
};

}  // namespace ppp::smoother
