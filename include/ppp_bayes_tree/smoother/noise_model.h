#pragma once
// Gaussian noise models with whitening, and robust kernels (M-estimators) applied by
// iteratively reweighted least squares.
//
// A Gaussian model with covariance P is represented by its square-root information
// R (upper triangular, R^T R = P^-1); whitening maps an error e to R e, whose squared
// norm is the Mahalanobis distance. Diagonal and isotropic models store sigmas only.
// A robust kernel rho(r) of the whitened error norm r is applied as the IRLS weight
// w(r) = rho'(r)/r: the whitened error and Jacobians are scaled by sqrt(w) (Zhang,
// "Parameter estimation techniques: a tutorial with application to conic fitting",
// 1997, Sec. 5; Huber 1964; Cauchy/Lorentzian kernel).
#include <Eigen/Core>

#include <memory>
#include <optional>

namespace ppp::smoother {

/// Robust kernel of the whitened error norm r.
struct RobustKernel {
  enum class Type { Huber, Cauchy };
  Type type = Type::Huber;
  double k = 1.345;  // kernel width, in whitened units (sigmas)

  /// rho(r): Huber r^2/2 (|r|<=k), k|r|-k^2/2 otherwise; Cauchy k^2/2 log(1+(r/k)^2).
  double loss(double r) const;
  /// IRLS weight w(r) = rho'(r)/r: Huber 1 or k/|r|; Cauchy 1/(1+(r/k)^2).
  double weight(double r) const;
};

class NoiseModel {
 public:
  using Ptr = std::shared_ptr<const NoiseModel>;

  /// Full covariance (symmetric positive definite); throws std::invalid_argument otherwise.
  static Ptr covariance(const Eigen::MatrixXd& covariance);
  /// Full square-root information R (R^T R = information); R need not be triangular.
  static Ptr sqrtInformation(const Eigen::MatrixXd& r);
  /// Independent sigmas (all > 0).
  static Ptr sigmas(const Eigen::VectorXd& sigmas);
  /// Same sigma on `dim` components.
  static Ptr isotropic(int dim, double sigma);
  /// Unit model (already whitened).
  static Ptr unit(int dim) { return isotropic(dim, 1.0); }

  /// Same Gaussian model with a robust kernel.
  Ptr withRobust(RobustKernel kernel) const;

  int dim() const { return dim_; }
  bool isDiagonal() const { return !full_; }
  const std::optional<RobustKernel>& robust() const { return robust_; }

  /// R e.
  Eigen::VectorXd whiten(const Eigen::VectorXd& e) const;
  /// R H (in place).
  void whitenInPlace(Eigen::MatrixXd& h) const;
  void whitenInPlace(Eigen::VectorXd& e) const;
  /// Covariance P = (R^T R)^-1.
  Eigen::MatrixXd covarianceMatrix() const;
  /// 0.5 ||R e||^2 for a Gaussian model, rho(||R e||) with a robust kernel.
  double loss(const Eigen::VectorXd& e) const;

 private:
  NoiseModel() = default;
  int dim_ = 0;
  bool full_ = false;
  Eigen::MatrixXd sqrt_info_;         // when full_
  Eigen::VectorXd inv_sigmas_;        // when !full_
  std::optional<RobustKernel> robust_;
};

}  // namespace ppp::smoother
