#pragma once
// Dense elimination of a set of frontal variables from a set of Jacobian factors.
//
// The factors' blocks are stacked into one dense system [A_f A_s | b] over the frontal
// variables (in the given order) and the separator (every other variable involved, in
// the given separator order). Eliminating x_f gives the conditional R x_f + S x_s = d and
// a marginal factor on the separator, A' x_s = b' (Dellaert & Kaess, "Factor Graphs for
// Robot Perception", 2017, Sec. 3.3-3.4, and Kaess et al. IJRR 2012, Alg. 1):
//  - Cholesky (default): form the augmented information [A b]^T [A b], Cholesky of the
//    frontal block, Schur complement on the separator; the marginal is returned in
//    Jacobian form through a pivoted LDL^T of the (positive semidefinite) augmented
//    Schur complement. This squares the condition number of A.
//  - QR: Householder QR of the stacked [A | b] directly; better for ill-conditioned A.
#include <stdexcept>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ppp_bayes_tree/smoother/gaussian_conditional.h"
#include "ppp_bayes_tree/smoother/gaussian_factor.h"

namespace ppp::smoother {

enum class Factorization { Cholesky, QR };

/// Thrown when the frontal block is not positive definite (under-constrained variable).
class IndeterminantSystemError : public std::runtime_error {
 public:
  explicit IndeterminantSystemError(const std::string& what) : std::runtime_error(what) {}
};

struct EliminationResult {
  GaussianConditional conditional;
  JacobianFactor::Ptr marginal;  // on the separator, possibly with zero rows
};

/// U P for a unit upper triangular U (as LDLT::matrixU() gives) and the permutation
/// matrix P = T I of the transpositions T (LDLT::transpositionsP()), equal bit for bit
/// to the dense product U * P (zero entries come out +0, as from the product), in n^2
/// instead of n^3 work. The Cholesky elimination forms the marginal's rows from it.
Matrix unitUpperTimesPermutation(const Matrix& u, const Eigen::Transpositions<Eigen::Dynamic>& t);

/// Scratch storage of eliminate(): the stacked system [A | b] and its information
/// matrix, needed only while one elimination runs. A caller that eliminates many
/// cliques (iSAM2) keeps one and passes it to every call, so that these two, the
/// largest matrices of an elimination, are not allocated per clique. Aligned as Eigen
/// aligns a Matrix's storage, so the same kernels run on the same numbers.
class EliminationWorkspace {
 public:
  using Buffer = std::vector<double, Eigen::aligned_allocator<double>>;
  using MatrixMap = Eigen::Map<Matrix, Eigen::AlignedMax>;
  /// A rows x cols matrix on the stacked-system buffer (grown when too small).
  MatrixMap stacked(Eigen::Index rows, Eigen::Index cols) { return map(stacked_, rows, cols); }
  /// A rows x cols matrix on the information buffer (grown when too small).
  MatrixMap information(Eigen::Index rows, Eigen::Index cols) { return map(information_, rows, cols); }

 private:
  static MatrixMap map(Buffer& buffer, Eigen::Index rows, Eigen::Index cols);
  Buffer stacked_, information_;
};

/// Eliminates `frontals` (dims given) from `factors`; `separator` lists the other keys,
/// in the order the marginal and the conditional's parents will use, with their dims.
/// Every key of every factor must be among frontals or separator. `workspace` (optional)
/// is scratch storage reused across calls; the result does not depend on it.
EliminationResult eliminate(const std::vector<const JacobianFactor*>& factors,
                            const KeyVector& frontals, const std::vector<int>& frontal_dims,
                            const KeyVector& separator, const std::vector<int>& separator_dims,
                            Factorization method, EliminationWorkspace* workspace = nullptr);

}  // namespace ppp::smoother
