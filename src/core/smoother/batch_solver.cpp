#include "ppp_bayes_tree/smoother/batch_solver.h"

#include <Eigen/CholmodSupport>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseQR>

#include <algorithm>
#include <cmath>

#include "ppp_bayes_tree/smoother/elimination.h"

namespace ppp::smoother {

VariableLayout VariableLayout::of(const Values& values) { return of(values, values.keys()); }

VariableLayout VariableLayout::of(const Values& values, const KeyVector& order) {
  VariableLayout l;
  l.keys = order;
  for (Key k : order) {
    l.offset[k] = l.dim;
    l.dim += values.dim(k);
  }
  return l;
}

LinearSystem assemble(const GaussianFactorGraph& factors, const VariableLayout& layout) {
  std::vector<Eigen::Triplet<double>> trip;
  int rows = 0;
  for (const auto& f : factors) rows += f->rows();
  LinearSystem sys;
  sys.b.resize(rows);
  int r = 0;
  for (const auto& f : factors) {
    for (std::size_t j = 0; j < f->keys().size(); ++j) {
      const int off = layout.offset.at(f->keys()[j]);
      const Matrix& a = f->block(j);
      for (int c = 0; c < a.cols(); ++c)
        for (int i = 0; i < a.rows(); ++i)
          if (a(i, c) != 0.0) trip.emplace_back(r + i, off + c, a(i, c));
    }
    sys.b.segment(r, f->rows()) = f->b();
    r += f->rows();
  }
  sys.A.resize(rows, layout.dim);
  sys.A.setFromTriplets(trip.begin(), trip.end());
  return sys;
}

void denseInformation(const GaussianFactorGraph& factors, const VariableLayout& layout,
                      Matrix& information, Vector& eta) {
  const LinearSystem sys = assemble(factors, layout);
  const Matrix a = Matrix(sys.A);
  information = a.transpose() * a;
  eta = a.transpose() * sys.b;
}

GaussianFactorGraph linearizeGraph(const NonlinearFactorGraph& graph, const Values& x) {
  GaussianFactorGraph out;
  for (const auto& f : graph)
    if (f) out.push_back(f->linearize(x));
  return out;
}

namespace {

/// linearizeGraph into `linear`: on the first call a new linearization; later (the same
/// graph) each factor's linearization is refilled in the storage of the previous one
/// where nobody else holds it (NonlinearFactor::relinearize; the same numbers).
void relinearizeGraph(const NonlinearFactorGraph& graph, const Values& x, GaussianFactorGraph& linear) {
  if (linear.empty()) {
    linear = linearizeGraph(graph, x);
    return;
  }
  std::size_t j = 0;
  for (const auto& f : graph) {
    if (!f) continue;
    JacobianFactor::Ptr& slot = linear[j++];
    // Created non-const by relinearize(), so refilling it is sound.
    std::shared_ptr<JacobianFactor> storage;
    if (slot.use_count() == 1) storage = std::const_pointer_cast<JacobianFactor>(slot);
    slot.reset();
    slot = f->relinearize(x, std::move(storage));
  }
}

Values solveNormal(const Eigen::SparseMatrix<double>& h, const Vector& eta, const VariableLayout& layout,
                   const Values& like) {
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> llt;
  llt.compute(h);
  if (llt.info() != Eigen::Success)
    throw IndeterminantSystemError("batch solve: normal equations not positive definite");
  Vector x = llt.solve(eta);
  // Two steps of iterative refinement against the (squared-conditioned) normal equations.
  for (int i = 0; i < 2 && x.allFinite(); ++i) x += llt.solve(Vector(eta - h * x));
  if (llt.info() != Eigen::Success || !x.allFinite())
    throw IndeterminantSystemError("batch solve: solve failed");
  Values out;
  for (Key k : layout.keys) out.insert(k, x.segment(layout.offset.at(k), like.dim(k)));
  return out;
}

Values solveSparseQr(const LinearSystem& sys, const VariableLayout& layout, const Values& like) {
  Eigen::SparseMatrix<double> a = sys.A;
  a.makeCompressed();
  Eigen::SparseQR<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> qr;
  qr.compute(a);
  if (qr.info() != Eigen::Success || qr.rank() < a.cols())
    throw IndeterminantSystemError("batch solve: Jacobian is rank deficient");
  const Vector x = qr.solve(sys.b);
  Values out;
  for (Key k : layout.keys) out.insert(k, x.segment(layout.offset.at(k), like.dim(k)));
  return out;
}

}  // namespace

Values solveLinear(const GaussianFactorGraph& factors, const Values& like, LinearSolver solver) {
  const VariableLayout layout = VariableLayout::of(like);
  const LinearSystem sys = assemble(factors, layout);
  if (solver == LinearSolver::SparseQR) return solveSparseQr(sys, layout, like);
  const Eigen::SparseMatrix<double> h = (sys.A.transpose() * sys.A).pruned();
  return solveNormal(h, sys.A.transpose() * sys.b, layout, like);
}

BatchResult optimizeBatch(const NonlinearFactorGraph& graph, const Values& initial,
                          const BatchParams& params) {
  BatchResult res;
  res.values = initial;
  double error = graphError(graph, res.values);
  double lambda = params.initial_lambda;
  const VariableLayout layout = VariableLayout::of(initial);
  GaussianFactorGraph linear;  // refilled at every iteration
  for (int it = 0; it < params.max_iterations; ++it) {
    res.iterations = it + 1;
    relinearizeGraph(graph, res.values, linear);
    const LinearSystem sys = assemble(linear, layout);
    Eigen::SparseMatrix<double> h = sys.A.transpose() * sys.A;
    const Vector eta = sys.A.transpose() * sys.b;
    Values delta;
    double new_error = error;
    Values candidate;
    if (params.method == BatchParams::Method::GaussNewton) {
      delta = params.solver == LinearSolver::SparseQR ? solveSparseQr(sys, layout, initial)
                                                       : solveNormal(h, eta, layout, initial);
      candidate = res.values.retract(delta);
      new_error = graphError(graph, candidate);
    } else {
      // Levenberg-Marquardt: damp with lambda * diag(H) until the error decreases.
      bool accepted = false;
      for (int tries = 0; tries < 30 && !accepted; ++tries) {
        Eigen::SparseMatrix<double> damped = h;
        for (int i = 0; i < damped.rows(); ++i) damped.coeffRef(i, i) += lambda * std::max(h.coeff(i, i), 1e-12);
        delta = solveNormal(damped, eta, layout, initial);
        candidate = res.values.retract(delta);
        new_error = graphError(graph, candidate);
        if (new_error <= error) {
          accepted = true;
          lambda = std::max(lambda / 10.0, 1e-12);
        } else {
          lambda *= 10.0;
        }
      }
      if (!accepted) {
        res.converged = true;  // no decrease possible: at a minimum to numerical precision
        break;
      }
    }
    double max_delta = 0.0;
    for (const auto& [k, d] : delta) max_delta = std::max(max_delta, d.size() ? d.cwiseAbs().maxCoeff() : 0.0);
    res.values = candidate;
    const double rel = std::abs(error - new_error) / std::max(error, 1e-300);
    error = new_error;
    if (max_delta < params.absolute_delta_tolerance || rel < params.relative_error_tolerance) {
      res.converged = true;
      break;
    }
  }
  res.final_error = error;
  return res;
}

Matrix batchMarginalCovariance(const NonlinearFactorGraph& graph, const Values& x, const KeyVector& keys) {
  // Dense QR of the whitened Jacobian (not the squared information): Sigma = R^-1 R^-T.
  const VariableLayout layout = VariableLayout::of(x);
  const LinearSystem sys = assemble(linearizeGraph(graph, x), layout);
  if (sys.A.rows() < layout.dim) throw IndeterminantSystemError("batchMarginalCovariance: too few rows");
  Eigen::HouseholderQR<Matrix> qr(Matrix(sys.A));
  const Matrix rr = qr.matrixQR().topRows(layout.dim).triangularView<Eigen::Upper>();
  Matrix rinv = Matrix::Identity(layout.dim, layout.dim);
  rr.triangularView<Eigen::Upper>().solveInPlace(rinv);
  const Matrix cov = rinv * rinv.transpose();
  int m = 0;
  for (Key k : keys) m += x.dim(k);
  Matrix out(m, m);
  int r = 0;
  for (Key a : keys) {
    int c = 0;
    const int da = x.dim(a);
    for (Key b : keys) {
      const int db = x.dim(b);
      out.block(r, c, da, db) = cov.block(layout.offset.at(a), layout.offset.at(b), da, db);
      c += db;
    }
    r += da;
  }
  return out;
}

}  // namespace ppp::smoother
