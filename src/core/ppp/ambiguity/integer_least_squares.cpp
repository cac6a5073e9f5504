#include "ppp_bayes_tree/ppp/ambiguity/integer_least_squares.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/LU>

namespace ppp {

namespace {

bool allFinite(const Eigen::MatrixXd& m) { return m.allFinite(); }

/// Integer Gauss transformation on column j with pivot row i (i > j): makes
/// |L(i,j)| <= 1/2. L := L Z_ij, Z := Z Z_ij, Z_ij = I - mu e_i e_j^T.
bool gaussTransform(Eigen::MatrixXd& L, Eigen::MatrixXd& Z, int i, int j) {
  const double mu = std::round(L(i, j));
  if (mu == 0.0) return false;
  const int n = static_cast<int>(L.rows());
  for (int r = i; r < n; ++r) L(r, j) -= mu * L(r, i);
  Z.col(j) -= mu * Z.col(i);
  return true;
}

/// Swaps elements k and k+1 of the factored problem (a permutation Z_P):
/// the conditional variances of the pair and the rows/columns of L they touch.
void permute(Eigen::MatrixXd& L, Eigen::VectorXd& d, Eigen::MatrixXd& Z, int k, double delta) {
  const int n = static_cast<int>(L.rows());
  const double l = L(k + 1, k);
  const double eta = d(k) / delta;         // ratio of the new to the old conditioning
  const double lambda = d(k + 1) * l / delta;
  d(k) = eta * d(k + 1);
  d(k + 1) = delta;
  // Rows k and k+1 over the columns before k.
  for (int c = 0; c < k; ++c) {
    const double a0 = L(k, c);
    const double a1 = L(k + 1, c);
    L(k, c) = -l * a0 + a1;
    L(k + 1, c) = eta * a0 + lambda * a1;
  }
  L(k + 1, k) = lambda;
  // Rows after k+1: the two columns trade places.
  for (int r = k + 2; r < n; ++r) std::swap(L(r, k), L(r, k + 1));
  Z.col(k).swap(Z.col(k + 1));
}

double standardNormalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

}  // namespace

std::optional<LtdlFactor> ltdlDecompose(const Eigen::MatrixXd& Q) {
  const int n = static_cast<int>(Q.rows());
  if (Q.cols() != n || n == 0 || !allFinite(Q)) return std::nullopt;
  Eigen::MatrixXd A = 0.5 * (Q + Q.transpose());
  LtdlFactor f{Eigen::MatrixXd::Zero(n, n), Eigen::VectorXd::Zero(n)};
  // Q(j,k) = sum_{i >= max(j,k)} L(i,j) d_i L(i,k): peel off the last element,
  // then recurse on the Schur complement of the leading block.
  for (int i = n - 1; i >= 0; --i) {
    const double di = A(i, i);
    if (!(di > 0.0)) return std::nullopt;
    f.d(i) = di;
    for (int k = 0; k <= i; ++k) f.L(i, k) = A(i, k) / di;
    for (int j = 0; j < i; ++j)
      for (int k = 0; k <= j; ++k) {
        A(j, k) -= f.L(i, j) * di * f.L(i, k);
        A(k, j) = A(j, k);
      }
  }
  return f;
}

std::optional<Decorrelation> decorrelate(const Eigen::MatrixXd& Q) {
  auto factor = ltdlDecompose(Q);
  if (!factor) return std::nullopt;
  const int n = static_cast<int>(Q.rows());
  Decorrelation out{Eigen::MatrixXd::Identity(n, n), std::move(*factor), 0, 0};
  Eigen::MatrixXd& L = out.factor.L;
  Eigen::VectorXd& d = out.factor.d;
  // Relative margin against endless swapping of (numerically) equal pairs.
  constexpr double kSwapMargin = 1e-12;
  int j = n - 2;
  while (j >= 0) {
    for (int i = j + 1; i < n; ++i)
      if (gaussTransform(L, out.Z, i, j)) ++out.gauss_transformations;
    // Variance of element j+1 once element j is put after it (unconditioned on j).
    const double delta = d(j) + L(j + 1, j) * L(j + 1, j) * d(j + 1);
    if (delta < d(j + 1) * (1.0 - kSwapMargin)) {
      permute(L, d, out.Z, j, delta);
      ++out.permutations;
      j = std::min(j + 1, n - 2);  // the pair above sees a new d(j+1)
    } else {
      --j;
    }
  }
  return out;
}

namespace {

/// The levels of the search tree: level k holds the integer z(k) given z(k+1..n-1),
/// its integers visited nearest the conditional centre first (Schnorr-Euchner).
struct SearchLevels {
  SearchLevels(const Eigen::VectorXd& z_hat_in, const Eigen::MatrixXd& L_in)
      : z_hat(z_hat_in), L(L_in), n(static_cast<int>(z_hat_in.size())), z(n), center(n), step(n) {}

  double conditionalCenter(int k) const {
    double c = z_hat(k);
    for (int i = k + 1; i < n; ++i) c += L(i, k) * (z(i) - center(i));
    return c;
  }
  void start(int k) {
    center(k) = conditionalCenter(k);
    z(k) = std::round(center(k));
    step(k) = (center(k) - z(k) >= 0.0) ? 1.0 : -1.0;
  }
  void advance(int k) {  // next integer of level k in order of growing distance
    z(k) += step(k);
    step(k) = -step(k) - (step(k) > 0.0 ? 1.0 : -1.0);
  }

  const Eigen::VectorXd& z_hat;
  const Eigen::MatrixXd& L;
  const int n;
  Eigen::VectorXd z, center, step;
};

/// The best m candidates found so far, unsorted; once m are kept, the worst of them
/// bounds the search.
struct KeptCandidates {
  explicit KeptCandidates(int m_in) : m(m_in) {}

  void add(double dist, const Eigen::VectorXd& z) {
    const auto by_norm = [](const auto& a, const auto& b) { return a.first < b.first; };
    if (static_cast<int>(kept.size()) < m) {
      kept.emplace_back(dist, z);
    } else {
      *std::max_element(kept.begin(), kept.end(), by_norm) = {dist, z};
    }
    if (static_cast<int>(kept.size()) == m) bound = std::max_element(kept.begin(), kept.end(), by_norm)->first;
  }
  void sortInto(IntegerCandidates& out) {
    std::sort(kept.begin(), kept.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& [norm, v] : kept) {
      out.squared_norms.push_back(norm);
      out.vectors.push_back(std::move(v));
    }
  }

  const int m;
  std::vector<std::pair<double, Eigen::VectorXd>> kept;
  double bound = std::numeric_limits<double>::infinity();
};

}  // namespace

IntegerCandidates searchIntegerCandidates(const Eigen::VectorXd& z_hat, const LtdlFactor& factor,
                                          int candidates) {
  IntegerCandidates out;
  const int n = static_cast<int>(z_hat.size());
  const int m = std::max(1, candidates);
  if (n == 0 || factor.L.rows() != n || factor.d.size() != n) return out;
  const Eigen::VectorXd& d = factor.d;
  SearchLevels levels(z_hat, factor.L);
  Eigen::VectorXd partial(n + 1);  // partial(k): squared distance of levels k..n-1
  partial(n) = 0.0;
  KeptCandidates kept(m);

  // Depth first from the last level: down while inside the ellipsoid, a candidate at
  // level 0, up to the next integer of the level above once outside.
  int k = n - 1;
  levels.start(k);
  while (true) {
    ++out.nodes_visited;
    const double e = levels.z(k) - levels.center(k);
    const double dist = partial(k + 1) + e * e / d(k);
    if (dist < kept.bound) {
      if (k > 0) {
        partial(k) = dist;
        --k;
        levels.start(k);
        continue;
      }
      kept.add(dist, levels.z);  // a full candidate
      levels.advance(0);
      continue;
    }
    // Outside the ellipsoid: every further integer of this level is farther too.
    if (k == n - 1) break;
    ++k;
    levels.advance(k);
  }
  kept.sortInto(out);
  return out;
}

double bootstrapSuccessRate(const Eigen::VectorXd& conditional_variances) {
  double p = 1.0;
  for (int i = 0; i < conditional_variances.size(); ++i)
    p *= 2.0 * standardNormalCdf(1.0 / (2.0 * std::sqrt(conditional_variances(i)))) - 1.0;
  return p;
}

std::string toString(IlsFloatReason reason) {
  switch (reason) {
    case IlsFloatReason::None: return "fixed";
    case IlsFloatReason::InvalidInput: return "invalid float ambiguities or covariance";
    case IlsFloatReason::TooFewAmbiguities: return "too few ambiguities";
    case IlsFloatReason::LowSuccessRate: return "bootstrapped success rate too low";
    case IlsFloatReason::RatioTestFailed: return "ratio test failed";
  }
  return "unknown";
}

namespace {

/// The largest p >= min_fixed whose last p decorrelated ambiguities reach the
/// bootstrapped success rate (variances scaled by k); 0 when none does.
int largestReliableSubset(const Eigen::VectorXd& d, double k, int min_fixed, double min_success_rate) {
  for (int p = static_cast<int>(d.size()); p >= min_fixed; --p) {
    if (bootstrapSuccessRate(k * d.tail(p)) >= min_success_rate) return p;
  }
  return 0;
}

/// The fix of the last p decorrelated ambiguities to z; with all of them, the
/// original ambiguities too (a = Z^-T z; Z is unimodular, so the rounded solve is exact).
void setFixed(const Decorrelation& dec, int p, const Eigen::VectorXd& z, IlsResult& out) {
  const int n = static_cast<int>(dec.Z.rows());
  out.fixed = p;
  out.constraint_rows = dec.Z.rightCols(p).transpose();
  out.constraint_values = z;
  if (p != n) return;
  Eigen::VectorXd a = dec.Z.transpose().fullPivLu().solve(z);
  for (int i = 0; i < n; ++i) a(i) = std::round(a(i));
  out.fixed_ambiguities = a;
}

}  // namespace

IlsResult solveIntegerLeastSquares(const Eigen::VectorXd& a_hat, const Eigen::MatrixXd& Q,
                                   const IlsOptions& options) {
  IlsResult out;
  const int n = static_cast<int>(a_hat.size());
  out.ambiguities = n;
  if (Q.rows() != n || Q.cols() != n || !a_hat.allFinite()) {
    out.float_reason = IlsFloatReason::InvalidInput;
    return out;
  }
  const auto dec = decorrelate(Q);
  if (!dec) {
    out.float_reason = IlsFloatReason::InvalidInput;
    return out;
  }
  const int min_fixed = std::max(1, options.min_fixed);
  if (n < min_fixed) {
    out.float_reason = IlsFloatReason::TooFewAmbiguities;
    return out;
  }
  const Eigen::VectorXd z_hat = dec->Z.transpose() * a_hat;
  const Eigen::VectorXd& d = dec->factor.d;
  const double k = std::max(1.0, options.success_rate_variance_factor);

  // 1. Largest subset (the last p decorrelated elements) reaching the success rate.
  const int p_start = options.partial ? largestReliableSubset(d, k, min_fixed, options.min_success_rate) : n;
  if (p_start == 0) {
    out.float_reason = IlsFloatReason::LowSuccessRate;
    out.bootstrap_success_rate = bootstrapSuccessRate(k * d.tail(min_fixed));
    return out;
  }
  // 2. From it down, the first subset whose best candidate passes the ratio test.
  const int p_end = options.partial ? min_fixed : n;
  for (int p = p_start; p >= p_end; --p) {
    const LtdlFactor sub{dec->factor.L.bottomRightCorner(p, p), d.tail(p)};
    const IntegerCandidates cand = searchIntegerCandidates(z_hat.tail(p), sub, 2);
    out.nodes_visited += cand.nodes_visited;
    if (cand.vectors.size() < 2) continue;
    const double best = cand.squared_norms[0];
    const double second = cand.squared_norms[1];
    out.ratio = best > 0.0 ? second / best : std::numeric_limits<double>::infinity();
    out.bootstrap_success_rate = bootstrapSuccessRate(k * sub.d);
    if (out.ratio >= options.ratio_threshold) {
      setFixed(*dec, p, cand.vectors[0], out);
      return out;
    }
  }
  out.float_reason = IlsFloatReason::RatioTestFailed;
  return out;
}

}  // namespace ppp
