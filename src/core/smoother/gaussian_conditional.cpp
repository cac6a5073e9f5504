#include "ppp_bayes_tree/smoother/gaussian_conditional.h"

#include <stdexcept>

namespace ppp::smoother {

GaussianConditional::GaussianConditional(KeyVector frontals, std::vector<int> frontal_dims,
                                         KeyVector parents, Matrix r, std::vector<Matrix> s, Vector d)
    : frontals_(std::move(frontals)), frontal_dims_(std::move(frontal_dims)),
      parents_(std::move(parents)), r_(std::move(r)), s_(std::move(s)), d_(std::move(d)) {
  if (frontals_.size() != frontal_dims_.size() || parents_.size() != s_.size())
    throw std::invalid_argument("GaussianConditional: size mismatch");
  int off = 0;
  for (int n : frontal_dims_) {
    offsets_.push_back(off);
    off += n;
  }
  if (off != r_.rows() || r_.rows() != r_.cols() || d_.size() != off)
    throw std::invalid_argument("GaussianConditional: R/d dimension mismatch");
}

Vector GaussianConditional::solve(const Values& x) const {
  Vector rhs = d_;
  for (std::size_t j = 0; j < parents_.size(); ++j) rhs.noalias() -= s_[j] * x.at(parents_[j]);
  r_.triangularView<Eigen::Upper>().solveInPlace(rhs);
  return rhs;
}

}  // namespace ppp::smoother
