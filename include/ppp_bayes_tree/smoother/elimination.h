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

/// Eliminates `frontals` (dims given) from `factors`; `separator` lists the other keys,
/// in the order the marginal and the conditional's parents will use, with their dims.
/// Every key of every factor must be among frontals or separator.
EliminationResult eliminate(const std::vector<const JacobianFactor*>& factors,
                            const KeyVector& frontals, const std::vector<int>& frontal_dims,
                            const KeyVector& separator, const std::vector<int>& separator_dims,
                            Factorization method);

}  // namespace ppp::smoother
