#pragma once
// Reference batch solver on a whole nonlinear factor graph: the oracle for the
// incremental smoother's tests, and the "batch re-solve" of the benchmark. The linear
// system is assembled as a sparse whitened Jacobian J and solved through the normal
// equations J^T J delta = J^T b with CHOLMOD's supernodal Cholesky (Eigen's
// CholmodSupport); Levenberg-Marquardt adds lambda*diag(J^T J).
#include <Eigen/SparseCore>

#include <unordered_map>

#include "ppp_bayes_tree/smoother/nonlinear_factor.h"
#include "ppp_bayes_tree/smoother/values.h"

namespace ppp::smoother {

/// Column layout of the stacked system: offset of each key (keys in the given order).
struct VariableLayout {
  KeyVector keys;
  std::unordered_map<Key, int> offset;
  int dim = 0;
  static VariableLayout of(const Values& values);                 // sorted keys
  static VariableLayout of(const Values& values, const KeyVector& order);
};

struct LinearSystem {
  Eigen::SparseMatrix<double> A;  // whitened Jacobian, rows = stacked factor rows
  Eigen::VectorXd b;
};

/// Assembles the linear factors on `layout`.
LinearSystem assemble(const GaussianFactorGraph& factors, const VariableLayout& layout);
/// Dense information matrix J^T J and vector J^T b.
void denseInformation(const GaussianFactorGraph& factors, const VariableLayout& layout,
                      Matrix& information, Vector& eta);
/// Linearizes every (non-null) factor at x.
GaussianFactorGraph linearizeGraph(const NonlinearFactorGraph& graph, const Values& x);
/// Sparse linear least-squares method: CHOLMOD on the normal equations (fast, squares
/// the condition number) or Eigen's SparseQR on J itself (slower, accurate: the oracle).
enum class LinearSolver { Cholmod, SparseQR };

/// Least-squares solution of the linear factors; throws IndeterminantSystemError when
/// the system is rank deficient (not positive definite).
Values solveLinear(const GaussianFactorGraph& factors, const Values& like,
                   LinearSolver solver = LinearSolver::Cholmod);

struct BatchParams {
  enum class Method { GaussNewton, LevenbergMarquardt };
  Method method = Method::GaussNewton;
  int max_iterations = 100;
  double relative_error_tolerance = 1e-12;
  double absolute_delta_tolerance = 1e-12;  // stop when max |delta| is below
  double initial_lambda = 1e-5;
  LinearSolver solver = LinearSolver::Cholmod;  // Gauss-Newton steps
};

struct BatchResult {
  Values values;
  int iterations = 0;
  double final_error = 0.0;
  bool converged = false;
};

/// Nonlinear least squares from `initial`.
BatchResult optimizeBatch(const NonlinearFactorGraph& graph, const Values& initial,
                          const BatchParams& params = {});

/// Dense marginal covariance blocks of `keys` (in order), as the inverse of the full
/// information matrix at x: for tests on small graphs.
Matrix batchMarginalCovariance(const NonlinearFactorGraph& graph, const Values& x,
                               const KeyVector& keys);

}  // namespace ppp::smoother
