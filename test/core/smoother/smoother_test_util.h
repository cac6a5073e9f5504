#pragma once
// Shared helpers for the smoother tests: test factors (range-bearing, PPP-like
// pseudorange/phase, random linear) and checks against the batch oracle.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>

#include "ppp_bayes_tree/smoother/batch_solver.h"
#include "ppp_bayes_tree/smoother/function_factor.h"
#include "ppp_bayes_tree/smoother/isam2.h"
#include "ppp_bayes_tree/smoother/noise_model_factor_n.h"

namespace ppp::smoother::test {

/// 2D range-bearing from a pose (x, y, theta) to a landmark (lx, ly): z = [range, bearing].
class RangeBearingFactor : public NoiseModelFactor2<Eigen::Vector3d, Eigen::Vector2d> {
 public:
  RangeBearingFactor(Key pose, Key landmark, Eigen::Vector2d z, NoiseModel::Ptr noise)
      : NoiseModelFactor2<Eigen::Vector3d, Eigen::Vector2d>(std::move(noise), {pose, landmark}), z_(z) {}
  Vector evaluateError(const Eigen::Vector3d& p, const Eigen::Vector2d& l, Matrix* hp, Matrix* hl) const override {
    const double dx = l[0] - p[0], dy = l[1] - p[1];
    const double q = dx * dx + dy * dy, r = std::sqrt(q);
    Vector e(2);
    e[0] = r - z_[0];
    e[1] = std::remainder(std::atan2(dy, dx) - p[2] - z_[1], 2 * M_PI);
    if (hp) *hp = (Matrix(2, 3) << -dx / r, -dy / r, 0, dy / q, -dx / q, -1).finished();
    if (hl) *hl = (Matrix(2, 2) << dx / r, dy / r, -dy / q, dx / q).finished();
    return e;
  }
  static Eigen::Vector2d measure(const Vector& p, const Vector& l) {
    const double dx = l[0] - p[0], dy = l[1] - p[1];
    return {std::hypot(dx, dy), std::remainder(std::atan2(dy, dx) - p[2], 2 * M_PI)};
  }

 private:
  Eigen::Vector2d z_;
};

/// PPP-shaped measurement on a 5-dim state s = (position 3, clock, zenith delay) and an
/// optional (phase) bias b: z = |sat - s.pos| + s.clock + m * s.zd (+ b).
class RangeLikeFactor : public NonlinearFactor {
 public:
  RangeLikeFactor(Key state, std::optional<Key> bias, Eigen::Vector3d sat, double mapping, double z,
                  NoiseModel::Ptr noise)
      : NonlinearFactor(bias ? KeyVector{state, *bias} : KeyVector{state}, std::move(noise)),
        sat_(sat), m_(mapping), z_(z), has_bias_(bias.has_value()) {}
  static double predict(const Vector& s, const Eigen::Vector3d& sat, double m) {
    return (sat - s.head<3>()).norm() + s[3] + m * s[4];
  }
  Vector unwhitenedError(const Values& x, std::vector<Matrix>* h) const override {
    const Vector& s = x.at(keys()[0]);
    double pred = predict(s, sat_, m_);
    if (has_bias_) pred += x.at(keys()[1])[0];
    if (h) {
      Matrix hs(1, 5);
      const Eigen::Vector3d u = (s.head<3>() - sat_).normalized();
      hs << u.x(), u.y(), u.z(), 1.0, m_;
      (*h)[0] = hs;
      if (has_bias_) (*h)[1] = Matrix::Ones(1, 1);
    }
    Vector e(1);
    e[0] = pred - z_;
    return e;
  }

 private:
  Eigen::Vector3d sat_;
  double m_, z_;
  bool has_bias_;
};

/// Linear factor sum_j A_j x_j - z, as a nonlinear factor with analytic Jacobians.
inline NonlinearFactor::Ptr linearFactor(const KeyVector& keys, const std::vector<Matrix>& a,
                                         const Vector& z, NoiseModel::Ptr noise) {
  return std::make_shared<FunctionFactor>(
      keys, noise, [a, z](const std::vector<Vector>& x, Vector& e, std::vector<Matrix>* h) {
        e = -z;
        for (std::size_t j = 0; j < x.size(); ++j) e += a[j] * x[j];
        if (h) *h = a;
        return true;
      });
}

/// Max |a - b| over the keys of b.
inline double maxDiff(const Values& a, const Values& b) {
  double m = 0.0;
  for (const auto& [k, v] : b) m = std::max(m, (a.at(k) - v).cwiseAbs().maxCoeff());
  return m;
}

/// The incremental delta equals the batch least-squares solution of all live factors
/// linearized at the same linearization point.
inline void expectDeltaEqualsBatch(const ISAM2& isam, double tol) {
  const Values& theta = isam.linearizationPoint();
  const Values batch = solveLinear(linearizeGraph(isam.nonlinearFactors(), theta), theta, LinearSolver::SparseQR);
  EXPECT_LT(maxDiff(isam.delta(), batch), tol);
}

/// Tree invariants, plus: the tree holds exactly the variables, and the conditionals
/// reproduce the linear system (R^T R = A^T A and R^T d = A^T b for the whole tree).
inline void expectTreeConsistent(const ISAM2& isam, double tol) {
  const BayesTree& tree = isam.bayesTree();
  EXPECT_EQ(tree.checkInvariants(), "");
  const Values& theta = isam.linearizationPoint();
  EXPECT_EQ(tree.numVariables(), theta.size());
  for (const auto& [k, v] : theta) EXPECT_TRUE(tree.contains(k)) << keyToString(k);
  // Stack all conditionals, deeper cliques first (upper triangular).
  std::vector<std::pair<int, const Clique*>> cl;
  for (const Clique* c : tree.cliquesTopDown()) {
    int d = 0;
    for (const Clique* p = c->parent; p; p = p->parent) ++d;
    cl.emplace_back(-d, c);
  }
  std::stable_sort(cl.begin(), cl.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  KeyVector order;
  for (const auto& [d, c] : cl)
    for (Key k : c->frontals) order.push_back(k);
  const VariableLayout layout = VariableLayout::of(theta, order);
  Matrix r = Matrix::Zero(layout.dim, layout.dim);
  Vector d = Vector::Zero(layout.dim);
  for (const auto& [dd, c] : cl) {
    const auto& cond = c->conditional;
    const int row = layout.offset.at(c->frontals[0]);
    r.block(row, row, cond.frontalDim(), cond.frontalDim()) = cond.R();
    for (std::size_t j = 0; j < cond.parents().size(); ++j) {
      const Key p = cond.parents()[j];
      r.block(row, layout.offset.at(p), cond.frontalDim(), theta.at(p).size()) = cond.S()[j];
    }
    d.segment(row, cond.frontalDim()) = cond.d();
  }
  EXPECT_TRUE(r.isUpperTriangular());
  Matrix info;
  Vector eta;
  denseInformation(linearizeGraph(isam.nonlinearFactors(), theta), layout, info, eta);
  const double scale = std::max(1.0, info.cwiseAbs().maxCoeff());
  EXPECT_LT((r.transpose() * r - info).cwiseAbs().maxCoeff(), tol * scale);
  EXPECT_LT((r.transpose() * d - eta).cwiseAbs().maxCoeff(), tol * std::max(1.0, eta.cwiseAbs().maxCoeff()));
}

}  // namespace ppp::smoother::test
