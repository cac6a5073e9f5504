#include "ppp_bayes_tree/smoother/nonlinear_factor.h"

#include <cmath>
#include <stdexcept>

namespace ppp::smoother {

NonlinearFactor::NonlinearFactor(KeyVector keys, NoiseModel::Ptr noise)
    : keys_(std::move(keys)), noise_(std::move(noise)) {
  if (!noise_) throw std::invalid_argument("NonlinearFactor: null noise model");
  if (keys_.empty()) throw std::invalid_argument("NonlinearFactor: no keys");
}

double NonlinearFactor::error(const Values& x) const { return noise_->loss(unwhitenedError(x, nullptr)); }

JacobianFactor::Ptr NonlinearFactor::linearize(const Values& x) const { return relinearize(x, nullptr); }

JacobianFactor::Ptr NonlinearFactor::relinearize(const Values& x, std::shared_ptr<JacobianFactor> storage) const {
  if (!storage) storage = std::make_shared<JacobianFactor>();
  storage->refill([&](KeyVector& keys, std::vector<Matrix>& h, Vector& b) {
    keys = keys_;
    h.resize(keys_.size());
    Vector e = unwhitenedError(x, &h);
    if (e.size() != dim()) throw std::logic_error("factor error has the wrong dimension");
    noise_->whitenInPlace(e);
    for (std::size_t j = 0; j < h.size(); ++j) {
      if (h[j].rows() != dim() || h[j].cols() != x.dim(keys_[j]))
        throw std::logic_error("factor Jacobian has the wrong shape for " + keyToString(keys_[j]));
      noise_->whitenInPlace(h[j]);
    }
    // IRLS: scale the whitened system by sqrt(w(||e||)) (robust kernel as a weight).
    if (noise_->robust()) {
      const double s = std::sqrt(noise_->robust()->weight(e.norm()));
      e *= s;
      for (auto& m : h) m *= s;
    }
    b = -e;
  });
  return storage;
}

double graphError(const NonlinearFactorGraph& graph, const Values& x) {
  double sum = 0.0;
  for (const auto& f : graph)
    if (f) sum += f->error(x);
  return sum;
}

}  // namespace ppp::smoother
