// Fixed-lag smoothing: in a linear problem, marginalizing old variables is exact, so the
// kept variables' estimates and marginal covariances equal those of the full batch
// solution of every factor ever added.
#include <gtest/gtest.h>

#include "smoother_test_util.h"
#include "ppp_bayes_tree/smoother/between_factor.h"
#include "ppp_bayes_tree/smoother/fixed_lag_smoother.h"
#include "ppp_bayes_tree/smoother/prior_factor.h"

using namespace ppp::smoother;
using namespace ppp::smoother::test;

namespace {

void runFixedLagLinear(Factorization method) {
  FixedLagParams p;
  p.lag_s = 8.0;
  p.isam2.factorization = method;
  p.isam2.wildfire_threshold = 0.0;
  p.isam2.enable_relinearization = false;
  FixedLagSmoother fl(p);
  std::mt19937 rng(5);
  std::normal_distribution<double> n01;
  NonlinearFactorGraph all;
  Values all_values;
  const Key forever = symbolKey('l', 0);  // referenced by every epoch: never marginalized
  std::vector<int> arc_id(3, -1), arc_end(3, -1);
  std::size_t marginalized = 0, max_vars = 0;
  BatchParams qr;
  qr.solver = LinearSolver::SparseQR;
  for (int t = 0; t < 60; ++t) {
    NonlinearFactorGraph f;
    Values v;
    const Key x = symbolKey('x', t);
    v.insert(x, Vector::Zero(2));
    Matrix m(1, 2);
    m << 1.0, 0.3 * (t % 5);
    f.push_back(linearFactor({x}, {m}, Vector::Constant(1, n01(rng)), NoiseModel::isotropic(1, 0.5)));
    if (t == 0) {
      f.push_back(std::make_shared<PriorFactor>(x, Vector::Zero(2), NoiseModel::isotropic(2, 1.0)));
      v.insert(forever, Vector::Zero(1));
    } else {
      f.push_back(std::make_shared<BetweenFactor>(symbolKey('x', t - 1), x, Vector::Constant(2, 0.1 * n01(rng)),
                                                  NoiseModel::isotropic(2, 0.2)));
    }
    f.push_back(linearFactor({x, forever}, {Matrix::Ones(1, 2), Matrix::Ones(1, 1)}, Vector::Constant(1, n01(rng)),
                             NoiseModel::isotropic(1, 0.3)));
    KeyVector newest{x, forever};
    for (int s = 0; s < 3; ++s) {  // arc landmarks of 3..12 epochs
      if (t > arc_end[s]) {
        ++arc_id[s];
        arc_end[s] = t + 3 + static_cast<int>(rng() % 10);
        v.insert(symbolKey('b', std::string(1, char('A' + s)), arc_id[s]), Vector::Zero(1));
      }
      const Key b = symbolKey('b', std::string(1, char('A' + s)), arc_id[s]);
      Matrix mx(1, 2);
      mx << 1.0, -0.5 + s;
      f.push_back(linearFactor({x, b}, {mx, Matrix::Ones(1, 1)}, Vector::Constant(1, n01(rng)), NoiseModel::isotropic(1, 0.1)));
      newest.push_back(b);
    }
    for (const auto& k : f) all.push_back(k);
    for (const auto& [k, val] : v) all_values.insert(k, val);
    const FixedLagResult r = fl.update(f, v, {{x, static_cast<double>(t)}}, newest);
    marginalized += r.variables_marginalized;
    EXPECT_EQ(r.variables_pending, 0u) << t;
    max_vars = std::max(max_vars, fl.numVariables());

    const ISAM2& isam = fl.isam2();
    expectTreeConsistent(isam, 1e-8);
    const BatchResult batch = optimizeBatch(all, all_values, qr);
    const Values est = fl.calculateEstimate();
    for (const auto& [k, val] : est) EXPECT_LT((val - batch.values.at(k)).cwiseAbs().maxCoeff(), 1e-8) << keyToString(k);
    // Old states are gone, recent ones kept.
    if (t >= 10) {
      EXPECT_FALSE(isam.exists(symbolKey('x', t - 10)));
      EXPECT_TRUE(isam.exists(symbolKey('x', t - 8)));
    }
    EXPECT_TRUE(isam.exists(forever));
    if (t % 10 == 9) {
      for (Key k : {x, symbolKey('x', t - 5), forever}) {
        const Matrix b = batchMarginalCovariance(all, batch.values, {k});
        EXPECT_LT((fl.marginalCovariance(k) - b).cwiseAbs().maxCoeff(), 1e-8) << keyToString(k) << " at " << t;
      }
      const KeyVector joint{x, symbolKey('x', t - 6), forever};
      EXPECT_LT((isam.jointMarginalCovariance(joint) - batchMarginalCovariance(all, batch.values, joint)).cwiseAbs().maxCoeff(),
                1e-8);
    }
    if (::testing::Test::HasFailure()) {
      ADD_FAILURE() << "at epoch " << t;
      return;
    }
  }
  // Ended arcs older than the lag are gone; time and memory stay bounded.
  EXPECT_FALSE(fl.isam2().exists(symbolKey('b', "A", 0)));
  EXPECT_GE(marginalized, 60u);  // 51 states + the ended arcs
  EXPECT_LE(max_vars, 10u + 1u + 3u * 3u);  // lag window states + forever + a few arcs each
  EXPECT_LT(fl.isam2().numFactors(), 80u);
}

}  // namespace

TEST(SmootherFixedLag, LinearMarginalsEqualBatchCholesky) { runFixedLagLinear(Factorization::Cholesky); }
TEST(SmootherFixedLag, LinearMarginalsEqualBatchQr) { runFixedLagLinear(Factorization::QR); }

TEST(SmootherFixedLag, RejectsBadInput) {
  EXPECT_THROW(FixedLagSmoother(FixedLagParams{0.0, {}}), std::invalid_argument);
  FixedLagSmoother fl;
  EXPECT_THROW(fl.update({}, {}, {{symbolKey('x', 0), 0.0}}), std::invalid_argument);
}

TEST(SmootherFixedLag, MarginalizingAnInteriorVariableReordersItToALeaf) {
  // Chain x0..x9 (newest last): x5 sits in the middle of the tree, above x0..x4.
  ISAM2Params p;
  p.wildfire_threshold = 0.0;
  ISAM2 isam(p);
  NonlinearFactorGraph all;
  Values all_values;
  for (int t = 0; t < 10; ++t) {
    NonlinearFactorGraph f;
    Values v;
    const Key k = symbolKey('x', t);
    v.insert(k, Vector::Zero(1));
    if (t == 0) f.push_back(std::make_shared<PriorFactor>(k, Vector::Zero(1), NoiseModel::isotropic(1, 1.0)));
    else f.push_back(std::make_shared<BetweenFactor>(symbolKey('x', t - 1), k, Vector::Constant(1, 1.0 + 0.1 * t),
                                                     NoiseModel::isotropic(1, 0.1 + 0.01 * t)));
    f.push_back(std::make_shared<PriorFactor>(k, Vector::Constant(1, 0.9 * t), NoiseModel::isotropic(1, 2.0)));
    for (const auto& x : f) all.push_back(x);
    all_values.insert(k, v.at(k));
    ISAM2UpdateParams up;
    up.newest_keys = {k};
    isam.update(f, v, up);
  }
  const Key x5 = symbolKey('x', 5);
  EXPECT_TRUE(isam.marginalizeLeaves({x5}).empty());  // not a leaf: nothing happens
  EXPECT_TRUE(isam.exists(x5));
  const KeyVector extra = isam.keysToReeliminateForMarginalization({x5});
  EXPECT_FALSE(extra.empty());
  ISAM2UpdateParams up;
  up.extra_reelim_keys = extra;
  up.first_keys = {x5};
  isam.update({}, {}, up);
  EXPECT_EQ(isam.marginalizeLeaves({x5}), KeyVector{x5});
  EXPECT_FALSE(isam.exists(x5));
  expectTreeConsistent(isam, 1e-10);
  expectDeltaEqualsBatch(isam, 1e-10);
  // The rest keeps the full batch marginals.
  BatchParams qr;
  qr.solver = LinearSolver::SparseQR;
  const BatchResult batch = optimizeBatch(all, all_values, qr);
  for (int t : {0, 4, 6, 9}) {
    const Key k = symbolKey('x', t);
    EXPECT_NEAR(isam.calculateEstimate(k)[0], batch.values.at(k)[0], 1e-9);
    EXPECT_NEAR(isam.marginalCovariance(k)(0, 0), batchMarginalCovariance(all, batch.values, {k})(0, 0), 1e-10);
  }
}

// The fixed-lag smoother passes iSAM2's result through: a chain whose x2 starts 3 off
// relinearizes x2 on the next update, which re-linearizes its factors.
TEST(SmootherFixedLag, ResultCarriesTheFactorsRelinearized) {
  FixedLagParams p;
  p.lag_s = 100.0;
  p.isam2.relinearize_skip = 1;
  p.isam2.fluid_relinearization = false;
  p.isam2.wildfire_threshold = 0.0;
  FixedLagSmoother fl(p);
  NonlinearFactorGraph g;
  Values v;
  std::unordered_map<Key, double> stamps;
  for (int i = 0; i < 5; ++i) {
    v.insert(symbolKey('x', i), Vector::Constant(1, i + (i == 2 ? 3.0 : 0.0)));
    stamps[symbolKey('x', i)] = i;
    if (i > 0)
      g.push_back(std::make_shared<BetweenFactor>(symbolKey('x', i - 1), symbolKey('x', i), Vector::Ones(1),
                                                  NoiseModel::isotropic(1, 0.1)));
  }
  g.push_back(std::make_shared<PriorFactor>(symbolKey('x', 0), Vector::Zero(1), NoiseModel::isotropic(1, 0.1)));
  EXPECT_EQ(fl.update(g, v, stamps).isam2.factors_relinearized, 0u);
  // Next epoch: x5 after x4; x2 (delta -3) is relinearized with its two between factors.
  Values v5;
  v5.insert(symbolKey('x', 5), Vector::Constant(1, 5.0));
  const FixedLagResult r =
      fl.update({std::make_shared<BetweenFactor>(symbolKey('x', 4), symbolKey('x', 5), Vector::Ones(1),
                                                 NoiseModel::isotropic(1, 0.1))},
                v5, {{symbolKey('x', 5), 5.0}});
  EXPECT_EQ(r.isam2.variables_relinearized, 1u);
  EXPECT_EQ(r.isam2.factors_relinearized, 2u);
  EXPECT_NEAR(fl.calculateEstimate().at(symbolKey('x', 2))(0), 2.0, 1e-9);
}
