#include "ppp_bayes_tree/smoother/noise_model.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <cmath>
#include <stdexcept>

namespace ppp::smoother {

double RobustKernel::loss(double r) const {
  const double a = std::abs(r);
  if (type == Type::Huber) return a <= k ? 0.5 * r * r : k * a - 0.5 * k * k;
  return 0.5 * k * k * std::log1p((r / k) * (r / k));
}

double RobustKernel::weight(double r) const {
  const double a = std::abs(r);
  if (type == Type::Huber) return a <= k ? 1.0 : k / a;
  return 1.0 / (1.0 + (r / k) * (r / k));
}

NoiseModel::Ptr NoiseModel::covariance(const Eigen::MatrixXd& covariance) {
  if (covariance.rows() != covariance.cols() || covariance.rows() == 0)
    throw std::invalid_argument("NoiseModel::covariance: matrix must be square and non-empty");
  // Information = P^-1 = U^T U with U upper triangular: from P = L L^T, P^-1 = L^-T L^-1,
  // so R = L^-1 (lower triangular, R^T R = P^-1).
  Eigen::LLT<Eigen::MatrixXd> llt(covariance);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("NoiseModel::covariance: not positive definite");
  const Eigen::MatrixXd l = llt.matrixL();
  return sqrtInformation(l.triangularView<Eigen::Lower>().solve(
      Eigen::MatrixXd::Identity(covariance.rows(), covariance.cols())));
}

NoiseModel::Ptr NoiseModel::sqrtInformation(const Eigen::MatrixXd& r) {
  if (r.rows() != r.cols() || r.rows() == 0)
    throw std::invalid_argument("NoiseModel::sqrtInformation: matrix must be square and non-empty");
  auto m = std::shared_ptr<NoiseModel>(new NoiseModel());
  m->dim_ = static_cast<int>(r.rows());
  m->full_ = true;
  m->sqrt_info_ = r;
  return m;
}

NoiseModel::Ptr NoiseModel::sigmas(const Eigen::VectorXd& sigmas) {
  if (sigmas.size() == 0 || !(sigmas.array() > 0).all() || !sigmas.allFinite())
    throw std::invalid_argument("NoiseModel::sigmas: sigmas must be finite and > 0");
  auto m = std::shared_ptr<NoiseModel>(new NoiseModel());
  m->dim_ = static_cast<int>(sigmas.size());
  m->inv_sigmas_ = sigmas.cwiseInverse();
  return m;
}

NoiseModel::Ptr NoiseModel::isotropic(int dim, double sigma) {
  if (dim <= 0) throw std::invalid_argument("NoiseModel::isotropic: dim must be > 0");
  return sigmas(Eigen::VectorXd::Constant(dim, sigma));
}

NoiseModel::Ptr NoiseModel::withRobust(RobustKernel kernel) const {
  if (!(kernel.k > 0)) throw std::invalid_argument("RobustKernel: k must be > 0");
  auto m = std::shared_ptr<NoiseModel>(new NoiseModel(*this));
  m->robust_ = kernel;
  return m;
}

Eigen::VectorXd NoiseModel::whiten(const Eigen::VectorXd& e) const {
  if (e.size() != dim_) throw std::invalid_argument("NoiseModel::whiten: dimension mismatch");
  if (full_) return sqrt_info_ * e;
  return inv_sigmas_.cwiseProduct(e);
}

// In place for diagonal models: row i times 1/sigma_i, the same products as
// whiten() forms (no new matrix or vector).
void NoiseModel::whitenInPlace(Eigen::MatrixXd& h) const {
  if (full_) h = sqrt_info_ * h;
  else h.array().colwise() *= inv_sigmas_.array();
}

void NoiseModel::whitenInPlace(Eigen::VectorXd& e) const {
  if (full_ || e.size() != dim_) {
    e = whiten(e);
    return;
  }
  e.array() *= inv_sigmas_.array();
}

Eigen::MatrixXd NoiseModel::covarianceMatrix() const {
  if (!full_) return inv_sigmas_.cwiseInverse().cwiseAbs2().asDiagonal();
  const Eigen::MatrixXd info = sqrt_info_.transpose() * sqrt_info_;
  return info.inverse();
}

double NoiseModel::loss(const Eigen::VectorXd& e) const {
  if (full_) {
    const Eigen::VectorXd w = whiten(e);
    if (!robust_) return 0.5 * w.squaredNorm();
    return robust_->loss(w.norm());
  }
  // Diagonal: the whitened error's squared norm over the same products as whiten()'s
  // (the same reduction), without storing them.
  if (e.size() != dim_) throw std::invalid_argument("NoiseModel::whiten: dimension mismatch");
  const double squared = inv_sigmas_.cwiseProduct(e).squaredNorm();
  if (!robust_) return 0.5 * squared;
  return robust_->loss(std::sqrt(squared));
}

}  // namespace ppp::smoother
