#pragma once
// Numerical Jacobians by central differences, and a checker comparing a factor's
// analytic Jacobians with them (for every factor's unit tests).
#include <string>

#include "ppp_bayes_tree/smoother/nonlinear_factor.h"

namespace ppp::smoother {

/// d(unwhitened error)/d(x_j) for each key of the factor, by central differences of
/// half-width `step` per tangent component: x_j (+) (+-step e_i), addition for a vector
/// variable, the manifold's retraction otherwise.
std::vector<Matrix> numericalJacobians(const NonlinearFactor& factor, const Values& x,
                                       double step = 1e-6);

struct JacobianCheck {
  bool ok = true;
  double max_abs_error = 0.0;  // largest |analytic - numerical| element
  std::string report;          // names the worst key and element when !ok
};

/// Compares analytic and numerical Jacobians at x: ok when every element agrees within
/// `tolerance` (absolute, scaled by max(1, |numerical element|)).
JacobianCheck checkJacobians(const NonlinearFactor& factor, const Values& x,
                             double tolerance = 1e-6, double step = 1e-6);

}  // namespace ppp::smoother
