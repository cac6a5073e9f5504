#include "ppp_bayes_tree/navigation/so3.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace ppp {
namespace so3 {
namespace {

/// Below this angle [rad] the closed forms lose digits: their Taylor series are used.
constexpr double kSmallAngle_rad = 1e-4;

}  // namespace

Eigen::Matrix3d hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0.0, -w.z(), w.y(),  //
      w.z(), 0.0, -w.x(),   //
      -w.y(), w.x(), 0.0;
  return m;
}

Eigen::Vector3d vee(const Eigen::Matrix3d& w_hat) {
  return 0.5 * Eigen::Vector3d(w_hat(2, 1) - w_hat(1, 2), w_hat(0, 2) - w_hat(2, 0), w_hat(1, 0) - w_hat(0, 1));
}

Eigen::Matrix3d expMap(const Eigen::Vector3d& phi) {
  const double theta2 = phi.squaredNorm();
  const double theta = std::sqrt(theta2);
  const Eigen::Matrix3d w = hat(phi);
  // R = I + a [phi]x + b [phi]x^2, a = sin(t)/t, b = (1 - cos(t))/t^2.
  double a, b;
  if (theta < kSmallAngle_rad) {
    a = 1.0 - theta2 / 6.0;
    b = 0.5 - theta2 / 24.0;
  } else {
    a = std::sin(theta) / theta;
    b = (1.0 - std::cos(theta)) / theta2;
  }
  return Eigen::Matrix3d::Identity() + a * w + b * w * w;
}

Eigen::Vector3d logMap(const Eigen::Matrix3d& r) {
  const double cos_theta = std::clamp(0.5 * (r.trace() - 1.0), -1.0, 1.0);
  const double theta = std::acos(cos_theta);
  const Eigen::Vector3d skew = vee(r);  // = sin(theta) * axis
  if (theta < kSmallAngle_rad) return (1.0 + theta * theta / 6.0) * skew;
  if (theta < 3.0) return (theta / std::sin(theta)) * skew;
  // Near pi sin(theta) is small: take the axis from the symmetric part,
  // R + R^T - 2 cos(theta) I = 2 (1 - cos(theta)) axis axis^T, then its sign from skew.
  const Eigen::Matrix3d sym = 0.5 * (r + r.transpose()) - cos_theta * Eigen::Matrix3d::Identity();
  int k = 0;
  sym.diagonal().maxCoeff(&k);
  Eigen::Vector3d axis = sym.col(k) / std::sqrt(std::max(sym(k, k) * (1.0 - cos_theta), 1e-300));
  axis.normalize();
  if (axis.dot(skew) < 0.0) axis = -axis;
  return theta * axis;
}

Eigen::Matrix3d rightJacobian(const Eigen::Vector3d& phi) {
  const double theta2 = phi.squaredNorm();
  const double theta = std::sqrt(theta2);
  const Eigen::Matrix3d w = hat(phi);
  // Jr = I - c1 [phi]x + c2 [phi]x^2, c1 = (1 - cos t)/t^2, c2 = (t - sin t)/t^3.
  double c1, c2;
  if (theta < kSmallAngle_rad) {
    c1 = 0.5 - theta2 / 24.0;
    c2 = 1.0 / 6.0 - theta2 / 120.0;
  } else {
    c1 = (1.0 - std::cos(theta)) / theta2;
    c2 = (theta - std::sin(theta)) / (theta2 * theta);
  }
  return Eigen::Matrix3d::Identity() - c1 * w + c2 * w * w;
}

Eigen::Matrix3d rightJacobianInverse(const Eigen::Vector3d& phi) {
  const double theta2 = phi.squaredNorm();
  const double theta = std::sqrt(theta2);
  const Eigen::Matrix3d w = hat(phi);
  // Jr^-1 = I + 1/2 [phi]x + c [phi]x^2, c = 1/t^2 - (1 + cos t)/(2 t sin t).
  double c;
  if (theta < kSmallAngle_rad) {
    c = 1.0 / 12.0 + theta2 / 720.0;
  } else {
    c = 1.0 / theta2 - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta));
  }
  return Eigen::Matrix3d::Identity() + 0.5 * w + c * w * w;
}

Eigen::Matrix3d normalized(const Eigen::Matrix3d& m) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

}  // namespace so3
}  // namespace ppp
