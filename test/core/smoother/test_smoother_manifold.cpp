// Manifold variables in the smoother: a NavState (rotation + velocity + position,
// tangent [dtheta; dv; dp]) beside vector variables. Retract and local coordinates
// round-trip; a chain of rotating states solved by iSAM2 one state at a time equals
// the batch solver; the fixed-lag smoother marginalizes NavStates at their manifold
// values (LinearContainerFactor in local coordinates).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>

#include "ppp_bayes_tree/navigation/nav_state_value.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/smoother/batch_solver.h"
#include "ppp_bayes_tree/smoother/fixed_lag_smoother.h"
#include "ppp_bayes_tree/smoother/isam2.h"
#include "ppp_bayes_tree/smoother/linear_container_factor.h"
#include "ppp_bayes_tree/smoother/numerical_jacobian.h"
#include "ppp_bayes_tree/smoother/prior_factor.h"

namespace ppp::smoother {
namespace {

using Vector9 = Eigen::Matrix<double, 9, 1>;

/// Relative motion between two states: [Log(Z^T R_i^T R_j); v_j - v_i - dv; p_j - p_i - dp].
class RelativeStateFactor : public NoiseModelFactorN<NavState, NavState> {
 public:
  RelativeStateFactor(Key i, Key j, const Eigen::Matrix3d& dr, const Eigen::Vector3d& dv, const Eigen::Vector3d& dp,
                      NoiseModel::Ptr noise)
      : NoiseModelFactorN(std::move(noise), {i, j}), dr_(dr), dv_(dv), dp_(dp) {}
  Vector evaluateError(const NavState& a, const NavState& b, Matrix* ha, Matrix* hb) const override {
    const Eigen::Matrix3d rel = a.rotation_world_body.transpose() * b.rotation_world_body;
    Vector9 e;
    e << so3::logMap(dr_.transpose() * rel), b.velocity_world_mps - a.velocity_world_mps - dv_,
        b.position_world_m - a.position_world_m - dp_;
    const Eigen::Matrix3d jinv = so3::rightJacobianInverse(e.head<3>());
    if (ha) {
      *ha = -Matrix::Identity(9, 9);
      ha->topLeftCorner<3, 3>() = -jinv * rel.transpose();
    }
    if (hb) {
      *hb = Matrix::Identity(9, 9);
      hb->topLeftCorner<3, 3>() = jinv;
    }
    return e;
  }

 private:
  Eigen::Matrix3d dr_;
  Eigen::Vector3d dv_, dp_;
};

NavState stateAt(int k) {
  NavState s;
  s.rotation_world_body = so3::expMap(Eigen::Vector3d(0.3 * k, -0.2 * k, 0.5 + 0.4 * k));
  s.velocity_world_mps = Eigen::Vector3d(1.0 + 0.1 * k, -2.0, 0.05 * k * k);
  s.position_world_m = Eigen::Vector3d(10.0 * k, 3.0 * std::sin(k), -0.5 * k);
  return s;
}

NavState perturbed(const NavState& s, std::mt19937& rng, double scale) {
  std::normal_distribution<double> n(0.0, scale);
  Vector9 d;
  for (int i = 0; i < 9; ++i) d[i] = n(rng);
  return s.retract(d);
}

double stateDistance(const NavState& a, const NavState& b) { return a.localCoordinates(b).norm(); }

NonlinearFactor::Ptr relativeFactor(int k, std::mt19937& rng, double meas_sigma) {
  const NavState a = stateAt(k - 1), b = stateAt(k);
  std::normal_distribution<double> n(0.0, meas_sigma);
  const Eigen::Vector3d noise_r(n(rng), n(rng), n(rng));
  const Eigen::Matrix3d dr = a.rotation_world_body.transpose() * b.rotation_world_body * so3::expMap(noise_r);
  const Eigen::Vector3d dv = b.velocity_world_mps - a.velocity_world_mps + Eigen::Vector3d(n(rng), n(rng), n(rng));
  const Eigen::Vector3d dp = b.position_world_m - a.position_world_m + Eigen::Vector3d(n(rng), n(rng), n(rng));
  return std::make_shared<RelativeStateFactor>(symbolKey('x', k - 1), symbolKey('x', k), dr, dv, dp,
                                               NoiseModel::isotropic(9, 0.01));
}

NonlinearFactor::Ptr priorFactor(int k, double sigma) {
  return std::make_shared<NavStatePriorFactor>(symbolKey('x', k), stateAt(k), NoiseModel::isotropic(9, sigma));
}

TEST(SmootherManifold, RetractAndLocalCoordinatesRoundTrip) {
  Values x;
  insertNavState(x, symbolKey('x', 0), stateAt(3));
  x.insert(symbolKey('c', 0), Vector::Constant(2, 1.5));
  EXPECT_EQ(x.dim(symbolKey('x', 0)), 9);
  EXPECT_EQ(x.at(symbolKey('x', 0)).size(), 15);
  EXPECT_EQ(x.dim(), 11u);
  Values delta = Values::zeroLike(x);
  EXPECT_EQ(delta.at(symbolKey('x', 0)).size(), 9);
  delta.at(symbolKey('x', 0)) << 0.4, -1.2, 1.9, 1, 2, 3, -4, 5, -6;  // angle below pi
  delta.at(symbolKey('c', 0)) << 0.25, -0.5;
  const Values y = x.retract(delta);
  EXPECT_EQ(y.manifold(symbolKey('x', 0)), NavStateManifold::instance());
  EXPECT_EQ(y.manifold(symbolKey('c', 0)), nullptr);
  const Values back = y.localCoordinates(x);
  EXPECT_LT((back.at(symbolKey('x', 0)) - delta.at(symbolKey('x', 0))).norm(), 1e-12);
  EXPECT_EQ(back.at(symbolKey('c', 0)), delta.at(symbolKey('c', 0)));
  // The rotation stays a rotation.
  const Eigen::Matrix3d r = navStateAt(y, symbolKey('x', 0)).rotation_world_body;
  EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
}

TEST(SmootherManifold, BadStorageAndWrongKindAreRejectedWithTheKey) {
  Values x;
  EXPECT_THROW(x.insert(symbolKey('x', 0), Vector::Zero(9), NavStateManifold::instance()), std::invalid_argument);
  x.insert(symbolKey('c', 0), Vector::Zero(9));
  try {
    navStateAt(x, symbolKey('c', 0));
    FAIL() << "a 9-vector read as a NavState";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(keyToString(symbolKey('c', 0))), std::string::npos) << e.what();
  }
}

TEST(SmootherManifold, FactorJacobiansInTheTangentSpace) {
  Values x;
  std::mt19937 rng(3);
  insertNavState(x, symbolKey('x', 0), perturbed(stateAt(0), rng, 0.3));
  insertNavState(x, symbolKey('x', 1), perturbed(stateAt(1), rng, 0.3));
  const NavStatePriorFactor prior(symbolKey('x', 0), stateAt(0), NoiseModel::isotropic(9, 0.1));
  const JacobianCheck cp = checkJacobians(prior, x, 1e-6);
  EXPECT_TRUE(cp.ok) << cp.report;
  const auto between = relativeFactor(1, rng, 0.0);
  const JacobianCheck cb = checkJacobians(*between, x, 1e-6);
  EXPECT_TRUE(cb.ok) << cb.report;
}

TEST(SmootherManifold, RotationChainIncrementalEqualsBatch) {
  std::mt19937 rng(7);
  ISAM2Params p;
  p.relinearize_threshold = 1e-3;
  p.relinearize_skip = 1;
  ISAM2 isam(p);
  NonlinearFactorGraph graph;
  Values initial;
  const int n = 25;
  for (int k = 0; k < n; ++k) {
    NonlinearFactorGraph f;
    Values v;
    insertNavState(v, symbolKey('x', k), perturbed(stateAt(k), rng, 0.05));
    if (k == 0) f.push_back(priorFactor(0, 0.01));
    if (k > 0) f.push_back(relativeFactor(k, rng, 0.01));
    if (k % 10 == 9) f.push_back(priorFactor(k, 0.5));
    isam.update(f, v);
    isam.update();
    graph.insert(graph.end(), f.begin(), f.end());
    initial.insertFrom(v, symbolKey('x', k));
  }
  for (int i = 0; i < 5; ++i) isam.update();
  const BatchResult batch = optimizeBatch(graph, initial);
  ASSERT_TRUE(batch.converged);
  const Values inc = isam.calculateBestEstimate();
  double worst = 0.0, worst_truth = 0.0;
  for (int k = 0; k < n; ++k) {
    const Key key = symbolKey('x', k);
    worst = std::max(worst, stateDistance(navStateAt(inc, key), navStateAt(batch.values, key)));
    worst_truth = std::max(worst_truth, stateDistance(navStateAt(batch.values, key), stateAt(k)));
  }
  EXPECT_LT(worst, 1e-6);
  // The batch answer is the truth within the measurement noise (0.01 per step, 25 steps).
  EXPECT_LT(worst_truth, 0.5);
  EXPECT_GT(worst_truth, 1e-4);  // the measurements are noisy: not the truth by construction
}

TEST(SmootherManifold, FixedLagMarginalizesNavStatesAtTheirManifoldValues) {
  std::mt19937 rng(11);
  FixedLagParams p;
  p.lag_s = 4.0;
  p.isam2.relinearize_threshold = 1e-4;
  p.isam2.relinearize_skip = 1;
  FixedLagSmoother fl(p);
  NonlinearFactorGraph graph;
  Values initial, marginalized;
  const int n = 20;
  for (int k = 0; k < n; ++k) {
    NonlinearFactorGraph f;
    Values v;
    insertNavState(v, symbolKey('x', k), perturbed(stateAt(k), rng, 0.05));
    if (k == 0) f.push_back(priorFactor(0, 0.01));
    if (k > 0) f.push_back(relativeFactor(k, rng, 0.001));
    const FixedLagResult r = fl.update(f, v, {{symbolKey('x', k), static_cast<double>(k)}});
    for (Key m : r.marginalized_estimates.keys()) marginalized.insertFrom(r.marginalized_estimates, m);
    graph.insert(graph.end(), f.begin(), f.end());
    initial.insertFrom(v, symbolKey('x', k));
  }
  EXPECT_GE(marginalized.size(), 10u);
  for (Key m : marginalized.keys()) EXPECT_EQ(marginalized.manifold(m), NavStateManifold::instance());
  const BatchResult batch = optimizeBatch(graph, initial);
  ASSERT_TRUE(batch.converged);
  // A chain without loops: the filtered newest state of the fixed-lag smoother is the
  // batch answer up to the linearization of the marginals.
  const Values est = fl.calculateEstimate();
  const Key last = symbolKey('x', n - 1);
  EXPECT_LT(stateDistance(navStateAt(est, last), navStateAt(batch.values, last)), 1e-6);
  EXPECT_FALSE(fl.isam2().exists(symbolKey('x', 0)));
}

TEST(SmootherManifold, LinearContainerFactorUsesLocalCoordinates) {
  Values theta0;
  insertNavState(theta0, symbolKey('x', 0), stateAt(2));
  JacobianFactor lin({symbolKey('x', 0)}, {Matrix::Identity(9, 9)}, Vector::Zero(9));
  const LinearContainerFactor f(lin, theta0);
  EXPECT_LT(f.unwhitenedError(theta0, nullptr).norm(), 1e-15);
  Vector9 d;
  d << 0.1, -0.2, 0.3, 1, 2, 3, 4, 5, 6;
  Values moved = theta0.retract([&] {
    Values dv;
    dv.insert(symbolKey('x', 0), d);
    return dv;
  }());
  EXPECT_LT((f.unwhitenedError(moved, nullptr) - d).norm(), 1e-12);
  EXPECT_FALSE(f.affineIn(symbolKey('x', 0)));
}

}  // namespace
}  // namespace ppp::smoother
