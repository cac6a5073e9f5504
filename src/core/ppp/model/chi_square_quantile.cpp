#include "ppp_bayes_tree/ppp/model/chi_square_quantile.h"

#include <cmath>

namespace ppp {
namespace {

/// Upper standard-normal quantile z with P(Z > z) = alpha, by bisection on erfc
/// (exact to double rounding; alpha in (0, 0.5]).
double normalUpperQuantile(double alpha) {
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (0.5 * std::erfc(mid / std::sqrt(2.0)) > alpha)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

double chiSquareUpperQuantile(int dof, double alpha) {
  if (dof <= 0) return 0.0;
  return ChiSquareUpperQuantile(alpha)(dof);
}

ChiSquareUpperQuantile::ChiSquareUpperQuantile(double alpha)
    : alpha_(alpha), normal_quantile_(normalUpperQuantile(alpha)) {}

double ChiSquareUpperQuantile::operator()(int dof) const {
  if (dof <= 0) return 0.0;
  const double z = normal_quantile_;
  const double k = static_cast<double>(dof);
  const double a = 2.0 / (9.0 * k);
  const double c = 1.0 - a + z * std::sqrt(a);
  return k * c * c * c;
}

}  // namespace ppp
