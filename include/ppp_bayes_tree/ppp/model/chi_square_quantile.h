#pragma once
// Quantiles of the chi-square distribution for the estimators' tests: the postfit
// consistency test (postfit_screening.h), the INS process-noise adaptation and the
// gap bridge's test of a slip-candidate assignment (gap_bridge.h).
// Reference: Abramowitz M., Stegun I.A. (1964) Handbook of Mathematical Functions,
// 26.4.17 (Wilson-Hilferty cube-root normal approximation).

namespace ppp {

/// Upper quantile of the chi-square distribution: the value exceeded with
/// probability `alpha` by a chi-square variable of `dof` degrees of freedom
/// (Wilson-Hilferty cube-root normal approximation, relative error below 1 % for
/// dof >= 3 and alpha >= 1e-9; Abramowitz and Stegun 26.4.17).
double chiSquareUpperQuantile(int dof, double alpha);

/// chiSquareUpperQuantile(dof, alpha) for one `alpha` and any dof, the same numbers:
/// the normal quantile of alpha (a bisection on erfc, the costly part) is computed
/// once, at construction, instead of at every call.
class ChiSquareUpperQuantile {
 public:
  explicit ChiSquareUpperQuantile(double alpha);
  double alpha() const { return alpha_; }
  /// The quantile for `dof` degrees of freedom (0 when dof <= 0).
  double operator()(int dof) const;

 private:
  double alpha_ = 0.0;
  double normal_quantile_ = 0.0;  // z with P(Z > z) = alpha
};

}  // namespace ppp
