#include "ppp_bayes_tree/ppp/ambiguity/integer_ambiguity_factor.h"

#include <cmath>
#include <stdexcept>

namespace ppp {

IntegerAmbiguityFactor::IntegerAmbiguityFactor(smoother::KeyVector biases, std::vector<double> coefficients_per_m,
                                               double value_cycles, double sigma_cycles)
    : smoother::NonlinearFactor(std::move(biases), smoother::NoiseModel::isotropic(1, sigma_cycles)),
      coefficients_per_m_(std::move(coefficients_per_m)), value_cycles_(value_cycles), sigma_cycles_(sigma_cycles) {
  if (coefficients_per_m_.size() != keys().size() || keys().empty())
    throw std::invalid_argument("IntegerAmbiguityFactor: one coefficient per bias key is required");
  if (!std::isfinite(value_cycles_) || !(sigma_cycles_ > 0.0))
    throw std::invalid_argument("IntegerAmbiguityFactor: finite value and sigma > 0 required");
}

smoother::Vector IntegerAmbiguityFactor::unwhitenedError(const smoother::Values& x,
                                                         std::vector<smoother::Matrix>* jacobians) const {
  double e = -value_cycles_;
  for (std::size_t j = 0; j < keys().size(); ++j) {
    const smoother::Vector& b = x.at(keys()[j]);
    if (b.size() != 1) throw std::invalid_argument("IntegerAmbiguityFactor: a bias variable is scalar");
    e += coefficients_per_m_[j] * b(0);
    if (jacobians) (*jacobians)[j] = smoother::Matrix::Constant(1, 1, coefficients_per_m_[j]);
  }
  return smoother::Vector::Constant(1, e);
}

}  // namespace ppp
