// Keys, values, noise models, factors (with Jacobian checks), elimination, ordering and
// the batch reference solver.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>

#include <Eigen/Cholesky>

#include "smoother_test_util.h"
#include "ppp_bayes_tree/smoother/between_factor.h"
#include "ppp_bayes_tree/smoother/elimination.h"
#include "ppp_bayes_tree/smoother/linear_container_factor.h"
#include "ppp_bayes_tree/smoother/noise_model_factor_n.h"
#include "ppp_bayes_tree/smoother/numerical_jacobian.h"
#include "ppp_bayes_tree/smoother/ordering.h"
#include "ppp_bayes_tree/smoother/prior_factor.h"

using namespace ppp::smoother;
using namespace ppp::smoother::test;

namespace {

/// True when a and b hold the same bits (the sign of a zero included).
bool sameBits(const Matrix& a, const Matrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

}  // namespace

TEST(SmootherKey, SymbolForms) {
  const Key x = symbolKey('x', 42);
  EXPECT_EQ(keyToString(x), "x42");
  EXPECT_EQ(keySymbol(x), 'x');
  EXPECT_EQ(keyIndex(x), 42u);
  EXPECT_EQ(keyLabel(x), "");
  const Key b = symbolKey('b', "G05", 3);
  EXPECT_EQ(keyToString(b), "b(G05,3)");
  EXPECT_EQ(keyLabel(b), "G05");
  EXPECT_EQ(keyIndex(b), 3u);
  EXPECT_NE(b, symbolKey('b', "G06", 3));
  EXPECT_NE(b, symbolKey('b', 3));
  EXPECT_THROW(symbolKey('b', "G05X", 3), std::invalid_argument);
}

TEST(SmootherValues, InsertRetractErrors) {
  Values v;
  v.insert(symbolKey('x', 1), Eigen::Vector2d(1, 2));
  EXPECT_THROW(v.insert(symbolKey('x', 1), Eigen::Vector2d(0, 0)), std::invalid_argument);
  EXPECT_THROW(v.at(symbolKey('x', 2)), std::out_of_range);
  Values d;
  d.insert(symbolKey('x', 1), Eigen::Vector2d(0.5, -1));
  const Values r = v.retract(d);
  EXPECT_DOUBLE_EQ(r.at(symbolKey('x', 1))[0], 1.5);
  EXPECT_DOUBLE_EQ(r.at(symbolKey('x', 1))[1], 1.0);
  EXPECT_EQ(v.dim(), 2u);
}

TEST(SmootherNoise, WhiteningMatchesMahalanobis) {
  Eigen::Matrix3d p;
  p << 4, 1, 0.5, 1, 2, 0.2, 0.5, 0.2, 1;
  const auto full = NoiseModel::covariance(p);
  const Eigen::Vector3d e(0.3, -1.2, 2.0);
  EXPECT_NEAR(full->whiten(e).squaredNorm(), e.dot(p.inverse() * e), 1e-12);
  EXPECT_LT((full->covarianceMatrix() - p).cwiseAbs().maxCoeff(), 1e-12);
  const auto diag = NoiseModel::sigmas(Eigen::Vector3d(1, 2, 4));
  EXPECT_NEAR(diag->whiten(e)[1], -0.6, 1e-15);
  EXPECT_NEAR(NoiseModel::isotropic(3, 2.0)->loss(e), 0.5 * e.squaredNorm() / 4.0, 1e-15);
  EXPECT_THROW(NoiseModel::sigmas(Eigen::Vector2d(1, 0)), std::invalid_argument);
  EXPECT_THROW(NoiseModel::covariance(-Eigen::Matrix2d::Identity()), std::invalid_argument);
}

TEST(SmootherNoise, WhitenInPlaceIsWhitenBitForBit) {
  Eigen::Matrix3d p;
  p << 4, 1, 0.5, 1, 2, 0.2, 0.5, 0.2, 1;
  const Matrix h = Matrix::Random(3, 4);
  const Vector e = Vector::Random(3);
  for (const auto& model : {NoiseModel::covariance(p), NoiseModel::sigmas(Eigen::Vector3d(0.3, 2, 7))}) {
    Vector e_in_place = e;
    model->whitenInPlace(e_in_place);
    EXPECT_TRUE(sameBits(e_in_place, model->whiten(e)));
    Matrix h_in_place = h;
    model->whitenInPlace(h_in_place);
    Matrix h_by_column(3, 4);
    for (int j = 0; j < 4; ++j) h_by_column.col(j) = model->whiten(h.col(j));
    EXPECT_TRUE(sameBits(h_in_place, h_by_column));
  }
  Vector wrong = Vector::Ones(2);
  EXPECT_THROW(NoiseModel::isotropic(3, 1.0)->whitenInPlace(wrong), std::invalid_argument);
}

TEST(SmootherNoise, LossIsHalfTheWhitenedSquaredNormBitForBit) {
  // The diagonal loss forms the whitened error's squared norm without storing the
  // whitened error: the same products and the same sum as whiten(e).squaredNorm().
  Eigen::Matrix3d p;
  p << 4, 1, 0.5, 1, 2, 0.2, 0.5, 0.2, 1;
  for (int n : {1, 2, 3, 5, 8, 13}) {
    const Vector e = Vector::Random(n) * 7.0;
    const Vector sigmas = (Vector::Random(n).array().abs() + 0.1).matrix();
    const auto diagonal = NoiseModel::sigmas(sigmas);
    EXPECT_EQ(diagonal->loss(e), 0.5 * diagonal->whiten(e).squaredNorm()) << n;
    const auto robust = diagonal->withRobust({RobustKernel::Type::Huber, 1.345});
    EXPECT_EQ(robust->loss(e), robust->robust()->loss(robust->whiten(e).norm())) << n;
  }
  const auto full = NoiseModel::covariance(p);
  const Vector e3 = Vector::Random(3);
  EXPECT_EQ(full->loss(e3), 0.5 * full->whiten(e3).squaredNorm());
  EXPECT_THROW(NoiseModel::isotropic(3, 1.0)->loss(Vector::Ones(2)), std::invalid_argument);
}

TEST(SmootherNoise, RobustWeights) {
  // Huber: w = k/|r| beyond k (Zhang 1997, Table 1): r = 2k gives 1/2.
  const RobustKernel huber{RobustKernel::Type::Huber, 1.345};
  EXPECT_DOUBLE_EQ(huber.weight(1.0), 1.0);
  EXPECT_DOUBLE_EQ(huber.weight(2.69), 0.5);
  EXPECT_DOUBLE_EQ(huber.loss(2.69), 1.345 * 2.69 - 0.5 * 1.345 * 1.345);
  // Cauchy: w = 1/(1+(r/k)^2): r = k gives 1/2.
  const RobustKernel cauchy{RobustKernel::Type::Cauchy, 2.0};
  EXPECT_DOUBLE_EQ(cauchy.weight(2.0), 0.5);
  EXPECT_NEAR(cauchy.loss(2.0), 2.0 * std::log(2.0), 1e-15);
  // The linearization is scaled by sqrt(w) of the whitened error norm.
  const Key x = symbolKey('x', 0);
  Values v;
  v.insert(x, Vector::Constant(1, 5.0));
  PriorFactor plain(x, Vector::Zero(1), NoiseModel::isotropic(1, 0.5));
  PriorFactor robust(x, Vector::Zero(1), NoiseModel::isotropic(1, 0.5)->withRobust(huber));
  const auto lp = plain.linearize(v), lr = robust.linearize(v);
  const double s = std::sqrt(1.345 / 10.0);  // whitened error 10
  EXPECT_NEAR(lr->block(0)(0, 0), s * lp->block(0)(0, 0), 1e-12);
  EXPECT_NEAR(lr->b()[0], s * lp->b()[0], 1e-12);
  EXPECT_NEAR(lp->b()[0], -10.0, 1e-12);
}

TEST(SmootherFactors, JacobianChecksForEveryFactorType) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n01;
  auto rnd = [&](int d) { Vector v(d); for (int i = 0; i < d; ++i) v[i] = n01(rng); return v; };
  const Key a = symbolKey('x', 0), b = symbolKey('x', 1), l = symbolKey('l', 0), c = symbolKey('b', "G05", 1);
  Values v;
  v.insert(a, rnd(3));
  v.insert(b, rnd(3));
  Vector lm(2);
  lm << 3.0, 4.0;
  v.insert(l, lm);
  v.insert(c, rnd(1));
  Values s5;
  s5.insert(a, rnd(5));
  s5.insert(c, rnd(1));
  const auto n3 = NoiseModel::isotropic(3, 0.1);

  std::vector<std::pair<std::string, std::pair<NonlinearFactor::Ptr, const Values*>>> cases;
  cases.push_back({"prior", {std::make_shared<PriorFactor>(a, rnd(3), n3), &v}});
  cases.push_back({"between", {std::make_shared<BetweenFactor>(a, b, rnd(3), n3), &v}});
  cases.push_back({"range-bearing", {std::make_shared<RangeBearingFactor>(a, l, Eigen::Vector2d(5, 0.1),
                                                                          NoiseModel::sigmas(Eigen::Vector2d(0.1, 0.01))), &v}});
  cases.push_back({"range-like", {std::make_shared<RangeLikeFactor>(a, c, Eigen::Vector3d(20, 10, 30), 1.7, 40.0,
                                                                    NoiseModel::isotropic(1, 0.01)), &s5}});
  Matrix a0 = Matrix::Random(2, 3), a1 = Matrix::Random(2, 1);
  cases.push_back({"function(analytic)", {linearFactor({a, c}, {a0, a1}, rnd(2), NoiseModel::isotropic(2, 1.0)), &v}});
  cases.push_back({"function(numerical)",
                   {std::make_shared<FunctionFactor>(
                        KeyVector{a, l}, NoiseModel::isotropic(1, 1.0),
                        [](const std::vector<Vector>& x, Vector& e, std::vector<Matrix>*) {
                          e = Vector::Constant(1, std::sin(x[0][0]) * x[1][1] + x[0][2] * x[0][2]);
                          return false;
                        }),
                    &v}});
  JacobianFactor jf({a, l}, {Matrix::Random(2, 3), Matrix::Random(2, 2)}, rnd(2));
  cases.push_back({"linear-container", {std::make_shared<LinearContainerFactor>(jf, v), &v}});
  for (const auto& [name, fv] : cases) {
    const JacobianCheck check = checkJacobians(*fv.first, *fv.second, 1e-5);
    EXPECT_TRUE(check.ok) << name << ": " << check.report;
  }
  // The checker catches a wrong Jacobian.
  auto wrong = std::make_shared<FunctionFactor>(
      KeyVector{a}, NoiseModel::isotropic(1, 1.0), [](const std::vector<Vector>& x, Vector& e, std::vector<Matrix>* h) {
        e = Vector::Constant(1, x[0][0] * x[0][0]);
        if (h) (*h)[0] = Matrix::Zero(1, 3);  // should be [2 x0, 0, 0]
        return true;
      });
  Values w;
  w.insert(a, Eigen::Vector3d(1.0, 0, 0));
  EXPECT_FALSE(checkJacobians(*wrong, w).ok);
}

namespace {

// A factor on three value types: a fixed-size 3-vector p, a scalar s, a dynamic vector d:
// e = [p0 s + d0, p1 - p2 d1] - z.
class MixedTypesFactor : public NoiseModelFactorN<Eigen::Vector3d, double, Vector> {
 public:
  MixedTypesFactor(Key p, Key s, Key d, Eigen::Vector2d z, NoiseModel::Ptr noise)
      : NoiseModelFactorN(std::move(noise), {p, s, d}), z_(z) {}
  Vector evaluateError(const Eigen::Vector3d& p, const double& s, const Vector& d, Matrix* hp, Matrix* hs,
                       Matrix* hd) const override {
    if (hp) *hp = (Matrix(2, 3) << s, 0, 0, 0, 1, -d(1)).finished();
    if (hs) *hs = (Matrix(2, 1) << p(0), 0).finished();
    if (hd) *hd = (Matrix(2, 2) << 1, 0, 0, -p(2)).finished();
    return Eigen::Vector2d(p(0) * s + d(0), p(1) - p(2) * d(1)) - z_;
  }

 private:
  Eigen::Vector2d z_;
};

}  // namespace

TEST(SmootherFactors, RelinearizeIntoOldStorageEqualsAFreshLinearizationBitForBit) {
  // A robust between factor (full noise model: whitening by a product, then the IRLS
  // scale), linearized at one point, then relinearized at another into the first
  // linearization's storage: the same object comes back, with exactly the numbers of a
  // fresh linearization at the second point.
  const Key a = symbolKey('x', 0), b = symbolKey('x', 1);
  Matrix cov(3, 3);
  cov << 2.0, 0.3, 0.1, 0.3, 1.5, -0.2, 0.1, -0.2, 0.8;
  const auto noise = NoiseModel::covariance(cov)->withRobust({RobustKernel::Type::Huber, 1.345});
  const BetweenFactor f(a, b, (Vector(3) << 0.1, -0.2, 0.3).finished(), noise);
  Values v1, v2;
  v1.insert(a, (Vector(3) << 1.0, 2.0, 3.0).finished());
  v1.insert(b, (Vector(3) << 1.5, 1.0, 7.0).finished());
  v2.insert(a, (Vector(3) << -4.0, 0.5, 2.0).finished());
  v2.insert(b, (Vector(3) << 3.0, 2.5, -1.0).finished());
  auto storage = std::const_pointer_cast<JacobianFactor>(f.relinearize(v1, nullptr));
  const JacobianFactor* first = storage.get();
  const auto refilled = f.relinearize(v2, std::move(storage));
  const auto fresh = f.linearize(v2);
  EXPECT_EQ(refilled.get(), first);
  EXPECT_EQ(refilled->keys(), fresh->keys());
  ASSERT_EQ(refilled->blocks().size(), 2u);
  for (std::size_t j = 0; j < 2; ++j) EXPECT_TRUE(sameBits(refilled->block(j), fresh->block(j))) << j;
  EXPECT_TRUE(sameBits(refilled->b(), fresh->b()));
  EXPECT_FALSE(sameBits(refilled->b(), f.linearize(v1)->b()));  // the point did change
}

TEST(SmootherFactors, TypedBaseLooksUpConvertsAndLinearizes) {
  const Key p = symbolKey('p', 0), s = symbolKey('b', "G05", 1), d = symbolKey('d', 0);
  const Eigen::Vector3d pv(1.5, -2.0, 0.25);
  const double sv = 3.0;
  const Eigen::Vector2d dv(0.5, 4.0);
  Values v;
  v.insert(p, pv);
  v.insert(s, Vector::Constant(1, sv));
  v.insert(d, dv);
  const auto noise = NoiseModel::sigmas(Eigen::Vector2d(0.5, 2.0));
  const MixedTypesFactor f(p, s, d, Eigen::Vector2d(1.0, -1.0), noise);
  EXPECT_EQ(f.key<0>(), p);
  EXPECT_EQ(f.key<1>(), s);
  EXPECT_EQ(f.key<2>(), d);
  EXPECT_EQ(f.keys(), (KeyVector{p, s, d}));
  // The values found by key, in their types.
  Matrix hp, hs, hd;
  const Vector direct = f.evaluateError(pv, sv, dv, &hp, &hs, &hd);
  const Vector e = f.unwhitenedError(v, nullptr);
  EXPECT_EQ(e, direct);
  EXPECT_DOUBLE_EQ(e(0), 1.5 * 3.0 + 0.5 - 1.0);
  EXPECT_DOUBLE_EQ(e(1), -2.0 - 0.25 * 4.0 + 1.0);
  const JacobianCheck check = checkJacobians(f, v, 1e-6);
  EXPECT_TRUE(check.ok) << check.report;
  // Linearization: A_j = R H_j and b = -R e with R = diag(1/sigma).
  const JacobianFactor::Ptr lin = f.linearize(v);
  ASSERT_EQ(lin->keys(), f.keys());
  EXPECT_EQ(lin->block(0), Matrix(Eigen::Vector2d(2.0, 0.5).asDiagonal() * hp));
  EXPECT_EQ(lin->block(1), Matrix(Eigen::Vector2d(2.0, 0.5).asDiagonal() * hs));
  EXPECT_EQ(lin->block(2), Matrix(Eigen::Vector2d(2.0, 0.5).asDiagonal() * hd));
  EXPECT_EQ(lin->b(), Vector(-noise->whiten(e)));
  EXPECT_DOUBLE_EQ(f.error(v), 0.5 * noise->whiten(e).squaredNorm());
  // A value of the wrong dimension for its type is refused, naming the key.
  for (Key wrong : {p, s}) {
    Values bad = v;
    bad.at(wrong) = Vector::Zero(2);
    try {
      f.unwhitenedError(bad, nullptr);
      ADD_FAILURE() << "no exception for " << keyToString(wrong);
    } catch (const std::invalid_argument& ex) {
      EXPECT_NE(std::string(ex.what()).find(keyToString(wrong)), std::string::npos) << ex.what();
    }
  }
  EXPECT_THROW(f.unwhitenedError(Values{}, nullptr), std::out_of_range);
}

TEST(SmootherElimination, CholeskyAndQrAgreeAndMarginalIsSchurComplement) {
  // Three variables x0 (2), x1 (1), x2 (3); eliminate x0 then separator {x1, x2}.
  std::mt19937 rng(3);
  const Key k0 = symbolKey('x', 0), k1 = symbolKey('x', 1), k2 = symbolKey('x', 2);
  std::vector<JacobianFactor> fs;
  fs.emplace_back(KeyVector{k0, k1}, std::vector<Matrix>{Matrix::Random(3, 2), Matrix::Random(3, 1)}, Vector::Random(3));
  fs.emplace_back(KeyVector{k0, k2}, std::vector<Matrix>{Matrix::Random(4, 2), Matrix::Random(4, 3)}, Vector::Random(4));
  fs.emplace_back(KeyVector{k2}, std::vector<Matrix>{Matrix::Random(3, 3)}, Vector::Random(3));
  std::vector<const JacobianFactor*> ptrs;
  for (auto& f : fs) ptrs.push_back(&f);
  // Dense reference: information over [x0 x1 x2].
  Values like;
  like.insert(k0, Vector::Zero(2));
  like.insert(k1, Vector::Zero(1));
  like.insert(k2, Vector::Zero(3));
  GaussianFactorGraph g;
  for (auto& f : fs) g.push_back(std::make_shared<JacobianFactor>(f));
  Matrix info;
  Vector eta;
  denseInformation(g, VariableLayout::of(like, {k0, k1, k2}), info, eta);
  const Matrix schur = info.bottomRightCorner(4, 4) -
                       info.bottomLeftCorner(4, 2) * info.topLeftCorner(2, 2).inverse() * info.topRightCorner(2, 4);
  const Vector eta_s = eta.tail(4) - info.bottomLeftCorner(4, 2) * info.topLeftCorner(2, 2).inverse() * eta.head(2);
  for (auto method : {Factorization::Cholesky, Factorization::QR}) {
    const auto er = eliminate(ptrs, {k0}, {2}, {k1, k2}, {1, 3}, method);
    const auto& c = er.conditional;
    // R^T R equals the frontal information block, R^T S the off-diagonal block.
    EXPECT_LT((c.R().transpose() * c.R() - info.topLeftCorner(2, 2)).cwiseAbs().maxCoeff(), 1e-10);
    Matrix s(2, 4);
    s << c.S()[0], c.S()[1];
    EXPECT_LT((c.R().transpose() * s - info.topRightCorner(2, 4)).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_LT((c.R().transpose() * c.d() - eta.head(2)).cwiseAbs().maxCoeff(), 1e-10);
    Matrix m_info;
    Vector m_eta;
    denseInformation({er.marginal}, VariableLayout::of(like, {k1, k2}), m_info, m_eta);
    EXPECT_LT((m_info - schur).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT((m_eta - eta_s).cwiseAbs().maxCoeff(), 1e-9);
  }
  // An unconstrained frontal variable is reported.
  JacobianFactor only12({k1}, {Matrix::Ones(1, 1)}, Vector::Ones(1));
  JacobianFactor zero0({k0}, {Matrix::Zero(1, 2)}, Vector::Ones(1));
  EXPECT_THROW(eliminate({&zero0, &only12}, {k0}, {2}, {k1}, {1}, Factorization::Cholesky), IndeterminantSystemError);
  EXPECT_THROW(eliminate({&zero0, &only12}, {k0}, {2}, {k1}, {1}, Factorization::QR), IndeterminantSystemError);
}

TEST(SmootherElimination, AReusedWorkspaceGivesTheSameResultBitForBit) {
  // One workspace through eliminations of different sizes (a large one first, so the
  // later ones run on buffers holding old numbers, then a larger one that grows them),
  // with both factorizations: conditional and marginal equal those of a fresh
  // elimination bit for bit.
  const Key k0 = symbolKey('x', 0), k1 = symbolKey('x', 1), k2 = symbolKey('x', 2);
  const auto factors = [&](int rows) {
    std::vector<JacobianFactor> fs;
    fs.emplace_back(KeyVector{k0, k1}, std::vector<Matrix>{Matrix::Random(rows, 2), Matrix::Random(rows, 1)},
                    Vector::Random(rows));
    fs.emplace_back(KeyVector{k0, k2}, std::vector<Matrix>{Matrix::Random(rows + 1, 2), Matrix::Random(rows + 1, 3)},
                    Vector::Random(rows + 1));
    return fs;
  };
  EliminationWorkspace workspace;
  for (auto method : {Factorization::Cholesky, Factorization::QR})
    for (int rows : {9, 3, 4, 12}) {
      const std::vector<JacobianFactor> fs = factors(rows);
      const std::vector<const JacobianFactor*> ptrs{&fs[0], &fs[1]};
      const auto fresh = eliminate(ptrs, {k0}, {2}, {k1, k2}, {1, 3}, method);
      const auto reused = eliminate(ptrs, {k0}, {2}, {k1, k2}, {1, 3}, method, &workspace);
      EXPECT_TRUE(sameBits(reused.conditional.R(), fresh.conditional.R())) << rows;
      EXPECT_TRUE(sameBits(reused.conditional.d(), fresh.conditional.d())) << rows;
      for (std::size_t j = 0; j < 2; ++j) {
        EXPECT_TRUE(sameBits(reused.conditional.S()[j], fresh.conditional.S()[j])) << rows;
        EXPECT_TRUE(sameBits(reused.marginal->block(j), fresh.marginal->block(j))) << rows;
      }
      EXPECT_TRUE(sameBits(reused.marginal->b(), fresh.marginal->b())) << rows;
    }
}

TEST(SmootherElimination, UnitUpperTimesPermutationIsTheDenseProductBitForBit) {
  // The pivoted LDL^T of augmented Schur complements, full rank and rank deficient,
  // with zeros of both signs in U: the gather gives what U * (T I) gives, bit for bit.
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> pick(0, 3);
  for (int n : {1, 2, 3, 5, 8, 13, 24}) {
    for (int rank : {n, std::max(1, n / 2)}) {
      const Matrix a = Matrix::Random(rank, n);
      const Eigen::LDLT<Matrix> ldlt(a.transpose() * a);
      Matrix u = ldlt.matrixU();
      for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
          if (pick(rng) == 0) u(i, j) = pick(rng) < 2 ? -0.0 : 0.0;
      Matrix p = Matrix::Identity(n, n);
      p = ldlt.transpositionsP() * p;
      const Matrix dense = u * p;
      EXPECT_TRUE(sameBits(unitUpperTimesPermutation(u, ldlt.transpositionsP()), dense)) << "n " << n << " rank " << rank;
    }
  }
  // A non-finite entry: the dense product's NaNs (inf x 0) as well.
  const Eigen::LDLT<Matrix> ldlt(Matrix::Identity(3, 3));
  Matrix u = ldlt.matrixU();
  u(0, 2) = std::numeric_limits<double>::infinity();
  Matrix p = Matrix::Identity(3, 3);
  p = ldlt.transpositionsP() * p;
  EXPECT_TRUE(sameBits(unitUpperTimesPermutation(u, ldlt.transpositionsP()), u * p));
}

TEST(SmootherOrdering, ConstrainedKeysComeLast) {
  // A chain x0..x9 with a landmark l linked to every state.
  std::vector<KeyVector> pattern;
  KeyVector keys;
  const Key l = symbolKey('l', 0);
  for (int i = 0; i < 10; ++i) {
    keys.push_back(symbolKey('x', i));
    pattern.push_back({symbolKey('x', i), l});
    if (i) pattern.push_back({symbolKey('x', i - 1), symbolKey('x', i)});
  }
  keys.push_back(l);
  std::unordered_map<Key, int> groups;
  for (Key k : keys) groups[k] = 0;
  groups[symbolKey('x', 9)] = 1;
  groups[l] = 1;
  const Ordering o = computeOrdering(pattern, keys, &groups);
  ASSERT_EQ(o.size(), keys.size());
  const KeyVector tail(o.end() - 2, o.end());
  EXPECT_TRUE((tail == KeyVector{l, symbolKey('x', 9)}) || (tail == KeyVector{symbolKey('x', 9), l}));
  KeyVector sorted = o;
  std::sort(sorted.begin(), sorted.end());
  KeyVector expected = keys;
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(sorted, expected);
}

TEST(SmootherBatch, GaussNewtonAndLmReachTheSameOptimum) {
  // Range-bearing: 4 poses on a line, 2 landmarks; the optimum must reproduce exact
  // (noise-free) measurements, so the batch solution equals the truth.
  NonlinearFactorGraph g;
  Values truth, init;
  std::vector<Vector> poses;
  for (int i = 0; i < 4; ++i) {
    Vector p(3);
    p << i * 1.0, 0.2 * i, 0.1 * i;
    poses.push_back(p);
    truth.insert(symbolKey('x', i), p);
    init.insert(symbolKey('x', i), p + Eigen::Vector3d(0.2, -0.1, 0.05));
  }
  Vector l0(2), l1(2);
  l0 << 2.0, 3.0;
  l1 << 1.0, -2.0;
  truth.insert(symbolKey('l', 0), l0);
  truth.insert(symbolKey('l', 1), l1);
  init.insert(symbolKey('l', 0), l0 + Eigen::Vector2d(0.3, 0.3));
  init.insert(symbolKey('l', 1), l1 + Eigen::Vector2d(-0.3, 0.2));
  g.push_back(std::make_shared<PriorFactor>(symbolKey('x', 0), poses[0], NoiseModel::isotropic(3, 0.01)));
  for (int i = 1; i < 4; ++i)
    g.push_back(std::make_shared<BetweenFactor>(symbolKey('x', i - 1), symbolKey('x', i), poses[i] - poses[i - 1],
                                                NoiseModel::isotropic(3, 0.1)));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 2; ++j)
      g.push_back(std::make_shared<RangeBearingFactor>(symbolKey('x', i), symbolKey('l', j),
                                                       RangeBearingFactor::measure(poses[i], j ? l1 : l0),
                                                       NoiseModel::sigmas(Eigen::Vector2d(0.05, 0.01))));
  const BatchResult gn = optimizeBatch(g, init);
  BatchParams lmp;
  lmp.method = BatchParams::Method::LevenbergMarquardt;
  const BatchResult lm = optimizeBatch(g, init, lmp);
  EXPECT_TRUE(gn.converged);
  EXPECT_LT(maxDiff(gn.values, truth), 1e-8);
  EXPECT_LT(maxDiff(lm.values, truth), 1e-6);
  EXPECT_LT(gn.final_error, 1e-12);
}
