// SO(3) maps and Jacobians against closed-form values and numerical derivatives.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <vector>

#include "ppp_bayes_tree/navigation/so3.h"

namespace ppp {
namespace {

using so3::expMap;
using so3::logMap;

std::vector<Eigen::Vector3d> testVectors() {
  return {Eigen::Vector3d(0.1, -0.2, 0.3),   Eigen::Vector3d(1e-9, 2e-9, -1e-9), Eigen::Vector3d(3e-5, 0, 1e-5),
          Eigen::Vector3d(1.2, 0.4, -0.9),   Eigen::Vector3d(0.0, 0.0, 3.1),     Eigen::Vector3d(2.0, -1.5, 1.0),
          Eigen::Vector3d(0.0, 3.14159, 0.0)};
}

TEST(So3, HatAndVeeAreInverseAndGiveTheCrossProduct) {
  const Eigen::Vector3d a(0.3, -1.1, 2.0), b(-0.7, 0.2, 0.5);
  EXPECT_LT((so3::hat(a) * b - a.cross(b)).norm(), 1e-15);
  EXPECT_LT((so3::vee(so3::hat(a)) - a).norm(), 1e-15);
}

TEST(So3, ExpOfAQuarterTurnAboutZ) {
  // Rotating x by +90 deg about z gives y.
  const Eigen::Matrix3d r = expMap(Eigen::Vector3d(0, 0, M_PI / 2));
  EXPECT_LT((r * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-15);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-15);
}

TEST(So3, LogInvertsExpIncludingNearZeroAndNearPi) {
  for (const auto& phi : testVectors()) {
    const Eigen::Matrix3d r = expMap(phi);
    EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    EXPECT_LT((logMap(r) - phi).norm(), 1e-9 * std::max(1.0, phi.norm())) << phi.transpose();
  }
}

TEST(So3, LogAtExactlyPiGivesAnAngleOfPi) {
  const Eigen::Matrix3d r = expMap(Eigen::Vector3d(0, M_PI, 0));
  const Eigen::Vector3d phi = logMap(r);
  EXPECT_NEAR(phi.norm(), M_PI, 1e-9);
  EXPECT_LT((expMap(phi) - r).norm(), 1e-9);
}

TEST(So3, RightJacobianMatchesNumericalDerivative) {
  // Exp(phi + d) ~= Exp(phi) Exp(Jr d): column k of Jr is Log(Exp(phi)^T Exp(phi + h e_k)) / h.
  const double h = 1e-6;
  for (const auto& phi : testVectors()) {
    if (phi.norm() > 3.0) continue;  // the derivative of Exp is fine, but keep away from the Log cut
    Eigen::Matrix3d numeric;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = h * Eigen::Vector3d::Unit(k);
      numeric.col(k) = (logMap(expMap(phi).transpose() * expMap(phi + d)) -
                        logMap(expMap(phi).transpose() * expMap(phi - d))) / (2 * h);
    }
    EXPECT_LT((so3::rightJacobian(phi) - numeric).norm(), 1e-8) << phi.transpose();
  }
}

TEST(So3, RightJacobianInverseMatchesNumericalDerivativeOfLog) {
  // Log(Exp(phi) Exp(d)) ~= phi + Jr^-1 d.
  const double h = 1e-6;
  for (const auto& phi : testVectors()) {
    if (phi.norm() > 3.0) continue;
    Eigen::Matrix3d numeric;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = h * Eigen::Vector3d::Unit(k);
      numeric.col(k) = (logMap(expMap(phi) * expMap(d)) - logMap(expMap(phi) * expMap(-d))) / (2 * h);
    }
    EXPECT_LT((so3::rightJacobianInverse(phi) - numeric).norm(), 1e-8) << phi.transpose();
    EXPECT_LT((so3::rightJacobianInverse(phi) * so3::rightJacobian(phi) - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  }
}

TEST(So3, RightJacobianKnownValue) {
  // For phi = (0, 0, t): Jr = [[s/t, (1-c)/t, 0], [-(1-c)/t, s/t, 0], [0, 0, 1]] (Chirikjian 2011, vol. 2, 10.6).
  const double t = 0.8;
  const Eigen::Matrix3d jr = so3::rightJacobian(Eigen::Vector3d(0, 0, t));
  EXPECT_NEAR(jr(0, 0), std::sin(t) / t, 1e-15);
  EXPECT_NEAR(jr(0, 1), (1 - std::cos(t)) / t, 1e-15);
  EXPECT_NEAR(jr(1, 0), -(1 - std::cos(t)) / t, 1e-15);
  EXPECT_NEAR(jr(2, 2), 1.0, 1e-15);
}

TEST(So3, NormalizedProjectsBackToARotation) {
  Eigen::Matrix3d r = expMap(Eigen::Vector3d(0.3, 0.2, -0.1));
  r(0, 1) += 1e-6;
  const Eigen::Matrix3d n = so3::normalized(r);
  EXPECT_LT((n.transpose() * n - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  EXPECT_NEAR(n.determinant(), 1.0, 1e-14);
  EXPECT_LT((n - r).norm(), 1e-6);
}

}  // namespace
}  // namespace ppp
