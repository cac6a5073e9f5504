#include "ppp_bayes_tree/smoother/numerical_jacobian.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ppp::smoother {

std::vector<Matrix> numericalJacobians(const NonlinearFactor& factor, const Values& x, double step) {
  std::vector<Matrix> out;
  Values xp = x;
  for (Key k : factor.keys()) {
    const Vector x0 = x.at(k);
    const int dim = x.dim(k);
    Matrix h(factor.dim(), dim);
    for (int i = 0; i < dim; ++i) {
      Vector d = Vector::Zero(dim);
      d[i] = step;
      xp.update(k, x0);
      xp.retractInPlace(k, d);
      const Vector ep = factor.unwhitenedError(xp, nullptr);
      d[i] = -step;
      xp.update(k, x0);
      xp.retractInPlace(k, d);
      const Vector em = factor.unwhitenedError(xp, nullptr);
      h.col(i) = (ep - em) / (2.0 * step);
    }
    xp.update(k, x0);
    out.push_back(std::move(h));
  }
  return out;
}

JacobianCheck checkJacobians(const NonlinearFactor& factor, const Values& x, double tolerance,
                             double step) {
  JacobianCheck check;
  std::vector<Matrix> analytic(factor.keys().size());
  factor.unwhitenedError(x, &analytic);
  const std::vector<Matrix> numeric = numericalJacobians(factor, x, step);
  for (std::size_t j = 0; j < numeric.size(); ++j) {
    const Key k = factor.keys()[j];
    if (analytic[j].rows() != numeric[j].rows() || analytic[j].cols() != numeric[j].cols()) {
      check.ok = false;
      check.report = "Jacobian for " + keyToString(k) + " has the wrong shape";
      return check;
    }
    for (int r = 0; r < numeric[j].rows(); ++r)
      for (int c = 0; c < numeric[j].cols(); ++c) {
        const double err = std::abs(analytic[j](r, c) - numeric[j](r, c));
        check.max_abs_error = std::max(check.max_abs_error, err);
        if (err > tolerance * std::max(1.0, std::abs(numeric[j](r, c))) && check.ok) {
          check.ok = false;
          std::ostringstream os;
          os << "d(error)/d(" << keyToString(k) << ")(" << r << "," << c << "): analytic "
             << analytic[j](r, c) << " vs numerical " << numeric[j](r, c);
          check.report = os.str();
        }
      }
  }
  return check;
}

}  // namespace ppp::smoother
