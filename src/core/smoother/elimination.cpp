#include "ppp_bayes_tree/smoother/elimination.h"

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace ppp::smoother {
namespace {

// Column offsets of the stacked system [x_f x_s | b]. A clique has a few tens of
// variables at most: a linear search beats building hash maps for every clique.
struct Layout {
  struct Column {
    Key key;
    int offset, dim;
  };
  std::vector<Column> columns;
  int nf = 0;
  int ns = 0;

  const Column* find(Key key) const {
    for (const Column& c : columns)
      if (c.key == key) return &c;
    return nullptr;
  }
};

Layout makeLayout(const KeyVector& frontals, const std::vector<int>& fdims,
                  const KeyVector& separator, const std::vector<int>& sdims) {
  Layout l;
  l.columns.reserve(frontals.size() + separator.size());
  int off = 0;
  for (std::size_t i = 0; i < frontals.size(); ++i) {
    l.columns.push_back({frontals[i], off, fdims[i]});
    off += fdims[i];
  }
  l.nf = off;
  for (std::size_t i = 0; i < separator.size(); ++i) {
    l.columns.push_back({separator[i], off, sdims[i]});
    off += sdims[i];
  }
  l.ns = off - l.nf;
  return l;
}

using MatrixMap = EliminationWorkspace::MatrixMap;

// Stacks the factors into one dense [A | b], on the workspace's buffer.
MatrixMap stack(const std::vector<const JacobianFactor*>& factors, const Layout& l,
                EliminationWorkspace& workspace) {
  int rows = 0;
  for (const auto* f : factors) rows += f->rows();
  const int n = l.nf + l.ns;
  MatrixMap ab = workspace.stacked(rows, n + 1);
  ab.setZero();
  int r = 0;
  for (const auto* f : factors) {
    for (std::size_t j = 0; j < f->keys().size(); ++j) {
      const Layout::Column* col = l.find(f->keys()[j]);
      if (!col)
        throw std::invalid_argument("eliminate: factor key " + keyToString(f->keys()[j]) +
                                    " is neither frontal nor separator");
      if (f->block(j).cols() != col->dim)
        throw std::invalid_argument("eliminate: dimension mismatch for " + keyToString(f->keys()[j]));
      ab.block(r, col->offset, f->rows(), f->block(j).cols()) = f->block(j);
    }
    ab.block(r, n, f->rows(), 1) = f->b();
    r += f->rows();
  }
  return ab;
}

// Splits the rows [R S d] of the eliminated frontals into a conditional.
GaussianConditional makeConditional(const Matrix& rows, const KeyVector& frontals,
                                    const std::vector<int>& fdims, const KeyVector& separator,
                                    const std::vector<int>& sdims, int nf) {
  const int n = static_cast<int>(rows.cols()) - 1;
  std::vector<Matrix> s;
  int off = nf;
  for (int d : sdims) {
    s.push_back(rows.block(0, off, nf, d));
    off += d;
  }
  Matrix r = rows.leftCols(nf).triangularView<Eigen::Upper>();
  return GaussianConditional(frontals, fdims, separator, std::move(r), std::move(s), rows.col(n));
}

// Marginal factor on the separator from rows [A_s | b_s].
JacobianFactor::Ptr makeMarginal(const Matrix& rows, const KeyVector& separator,
                                 const std::vector<int>& sdims) {
  const int n = static_cast<int>(rows.cols()) - 1;
  std::vector<Matrix> blocks;
  int off = 0;
  for (int d : sdims) {
    blocks.push_back(rows.middleCols(off, d));
    off += d;
  }
  return std::make_shared<JacobianFactor>(separator, std::move(blocks), rows.col(n));
}

// Marginal factor on the separator whose row i is sqrt(d(keep[i])) times row keep[i] of
// [A_s | b_s] (the same products as scaling those rows first), written straight into
// the factor's blocks.
JacobianFactor::Ptr scaledRowsMarginal(const Matrix& rows, const Eigen::VectorXd& d,
                                       const std::vector<int>& keep, const KeyVector& separator,
                                       const std::vector<int>& sdims) {
  const auto m = static_cast<Eigen::Index>(keep.size());
  std::vector<double> scale(keep.size());
  for (std::size_t i = 0; i < keep.size(); ++i) scale[i] = std::sqrt(d[keep[i]]);
  const auto scaled = [&](Eigen::Index col, Eigen::Index width) {
    Matrix out(m, width);
    for (Eigen::Index c = 0; c < width; ++c)
      for (Eigen::Index i = 0; i < m; ++i) out(i, c) = scale[static_cast<std::size_t>(i)] * rows(keep[i], col + c);
    return out;
  };
  std::vector<Matrix> blocks;
  blocks.reserve(sdims.size());
  Eigen::Index off = 0;
  for (int dim : sdims) {
    blocks.push_back(scaled(off, dim));
    off += dim;
  }
  return std::make_shared<JacobianFactor>(separator, std::move(blocks), Vector(scaled(off, 1)));
}

std::string describe(const KeyVector& frontals) {
  return "eliminate: frontal block of " + keysToString(frontals) +
         " is not positive definite (under-constrained variable)";
}

// m = (m + m^T) / 2 in place, entry by entry as the dense expression 0.5 * (m + m^T)
// computes it (the two sums of a pair are the same sum), without its temporary.
void symmetrizeInPlace(Matrix& m) {
  for (Eigen::Index j = 0; j < m.cols(); ++j)
    for (Eigen::Index i = 0; i <= j; ++i) {
      const double v = 0.5 * (m(i, j) + m(j, i));
      m(i, j) = v;
      m(j, i) = v;
    }
}

EliminationResult eliminateCholesky(const MatrixMap& ab, const KeyVector& frontals,
                                    const std::vector<int>& fdims, const KeyVector& separator,
                                    const std::vector<int>& sdims, int nf, int ns,
                                    EliminationWorkspace& workspace) {
  const int n1 = nf + ns + 1;
  MatrixMap h = workspace.information(n1, n1);
  h.setZero();
  h.selfadjointView<Eigen::Lower>().rankUpdate(ab.transpose());
  h.triangularView<Eigen::StrictlyUpper>() = h.transpose();
  Eigen::LLT<Matrix> llt(h.topLeftCorner(nf, nf));
  if (llt.info() != Eigen::Success) throw IndeterminantSystemError(describe(frontals));
  // Rows of the augmented square-root information on the frontals: L^-1 H_f,[f s b].
  Matrix top = llt.matrixL().solve(h.topRows(nf));
  top.leftCols(nf) = llt.matrixU();
  if (!top.allFinite()) throw IndeterminantSystemError(describe(frontals));
  EliminationResult out;
  out.conditional = makeConditional(top, frontals, fdims, separator, sdims, nf);
  if (ns == 0) {
    out.marginal = std::make_shared<JacobianFactor>();
    return out;
  }
  // Augmented Schur complement [H_ss' eta_s'; eta_s'^T c'] (positive semidefinite), and a
  // square root of it by pivoted LDL^T: P^T L D L^T P = M  =>  J = D^1/2 L^T P, J^T J = M.
  const Matrix t = top.rightCols(ns + 1);
  Matrix schur = h.bottomRightCorner(ns + 1, ns + 1);
  schur.noalias() -= t.transpose() * t;
  symmetrizeInPlace(schur);
  Eigen::LDLT<Matrix> ldlt(schur);
  const Eigen::VectorXd dvec = ldlt.vectorD();
  const double dmax = std::max(dvec.maxCoeff(), 0.0);
  const Matrix lt_p = unitUpperTimesPermutation(Matrix(ldlt.matrixU()), ldlt.transpositionsP());
  std::vector<int> keep;
  for (int i = 0; i < dvec.size(); ++i)
    if (dvec[i] > 1e-14 * dmax && dvec[i] > 0) keep.push_back(i);
  out.marginal = scaledRowsMarginal(lt_p, dvec, keep, separator, sdims);
  return out;
}

EliminationResult eliminateQr(MatrixMap& ab, const KeyVector& frontals, const std::vector<int>& fdims,
                              const KeyVector& separator, const std::vector<int>& sdims, int nf,
                              int ns) {
  const int m = static_cast<int>(ab.rows());
  const int n1 = nf + ns + 1;
  if (m < nf) throw IndeterminantSystemError(describe(frontals));
  Eigen::HouseholderQR<Eigen::Ref<Matrix>> qr(ab);  // in place
  const int rank_rows = std::min(m, n1);
  Matrix r = ab.topRows(rank_rows).triangularView<Eigen::Upper>();
  const double scale = std::max(1.0, r.topLeftCorner(nf, nf).diagonal().cwiseAbs().maxCoeff());
  for (int i = 0; i < nf; ++i)
    if (!(std::abs(r(i, i)) > 1e-13 * scale)) throw IndeterminantSystemError(describe(frontals));
  EliminationResult out;
  out.conditional = makeConditional(r.topRows(nf), frontals, fdims, separator, sdims, nf);
  if (ns == 0) {
    out.marginal = std::make_shared<JacobianFactor>();
    return out;
  }
  out.marginal = makeMarginal(r.bottomRightCorner(rank_rows - nf, ns + 1), separator, sdims);
  return out;
}

}  // namespace

// Column j of U P is column k of U, where P(k, j) = 1. In the dense product every
// other term is an exact zero, so a nonzero entry comes out as it is; a zero entry
// comes out +0 whatever the sign of U's zero, because the term of U's unit diagonal
// (1 x 0 or 1 x 1) is among the summands. A non-finite U (inf x 0 is no zero) takes
// the dense product.
Matrix unitUpperTimesPermutation(const Matrix& u, const Eigen::Transpositions<Eigen::Dynamic>& t) {
  const Eigen::Index n = u.cols();
  if (!u.allFinite()) {
    Matrix p = Matrix::Identity(n, n);
    p = t * p;
    return u * p;
  }
  // (T x)(k) = x(pi(k)), so P(k, j) = 1 exactly when pi(k) = j.
  Eigen::VectorXd index(n);
  for (Eigen::Index k = 0; k < n; ++k) index(k) = static_cast<double>(k);
  index = t * index;
  std::vector<Eigen::Index> source_column(static_cast<std::size_t>(n));
  for (Eigen::Index k = 0; k < n; ++k) source_column[static_cast<std::size_t>(index(k))] = k;
  Matrix out(u.rows(), n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Index k = source_column[static_cast<std::size_t>(j)];
    for (Eigen::Index i = 0; i < u.rows(); ++i) out(i, j) = u(i, k) == 0.0 ? 0.0 : u(i, k);
  }
  return out;
}


EliminationWorkspace::MatrixMap EliminationWorkspace::map(Buffer& buffer, Eigen::Index rows, Eigen::Index cols) {
  const auto size = static_cast<std::size_t>(rows * cols);
  if (buffer.size() < size) {
    buffer.clear();  // nothing to keep: grown without copying the old contents
    buffer.resize(size);
  }
  return MatrixMap(buffer.data(), rows, cols);
}

EliminationResult eliminate(const std::vector<const JacobianFactor*>& factors,
                            const KeyVector& frontals, const std::vector<int>& frontal_dims,
                            const KeyVector& separator, const std::vector<int>& separator_dims,
                            Factorization method, EliminationWorkspace* workspace) {
  if (frontals.empty()) throw std::invalid_argument("eliminate: no frontal variables");
  if (frontals.size() != frontal_dims.size() || separator.size() != separator_dims.size())
    throw std::invalid_argument("eliminate: keys/dims size mismatch");
  const Layout l = makeLayout(frontals, frontal_dims, separator, separator_dims);
  EliminationWorkspace local;
  EliminationWorkspace& ws = workspace ? *workspace : local;
  MatrixMap ab = stack(factors, l, ws);
  if (method == Factorization::QR)
    return eliminateQr(ab, frontals, frontal_dims, separator, separator_dims, l.nf, l.ns);
  return eliminateCholesky(ab, frontals, frontal_dims, separator, separator_dims, l.nf, l.ns, ws);
}

}  // namespace ppp::smoother
