#pragma once
// Integer least squares (ILS) for carrier-phase ambiguities: the LAMBDA method.
//
// Given float ambiguities a_hat (cycles) with covariance Q, find the integer
// vectors a that minimise (a_hat - a)^T Q^-1 (a_hat - a). Steps:
//  1. LtDL decomposition Q = L^T D L, L unit lower triangular, D diagonal,
//     computed from the last element up: d[n-1] is the variance of the last
//     element, d[k] the variance of element k conditioned on k+1..n-1.
//  2. Decorrelation (the "Z-transformation"): integer Gauss transformations
//     (L := L Z_ij with Z_ij = I - round(L(i,j)) e_i e_j^T, which leaves the
//     lattice Z^n unchanged, |det Z| = 1) and permutations of neighbours whenever
//     that makes the conditional variance searched first smaller. The result is
//     z_hat = Z^T a_hat, Q_z = Z^T Q Z = L_z^T D_z L_z with the conditional
//     variances close to sorted d[0] >= ... >= d[n-1] ("flattened spectrum").
//  3. Search in the z-space: depth first from element n-1 down to 0, each level
//     enumerating integers around its conditional estimate in order of growing
//     distance (Schnorr-Euchner zig-zag), and shrinking the ellipsoid to the
//     largest norm among the m best candidates kept (de Jonge and Tiberius 1996
//     ch. 4; Chang, Yang and Zhou 2005). Candidates go back to a = Z^-T z.
//  4. Validation: the ratio test (second-best over best squared norm >= c, a
//     fixed threshold; Euler and Schaffrin 1991; discussed in Verhagen and
//     Teunissen 2013, who show that a fixed c does not fix the failure rate),
//     and the bootstrapped success rate (Teunissen 1998), P = prod_k
//     (2 Phi(1 / (2 sqrt(d_k))) - 1), a sharp lower bound of the ILS success rate.
//  5. Partial ambiguity resolution (Teunissen, Joosten and Tiberius 1999): when
//     the full set fails, fix the subset of the p most precise decorrelated
//     ambiguities z[n-p..n-1]. Their own LtDL factor is the bottom-right block of
//     L_z and D_z, so the subset needs no new decomposition. p starts at the
//     largest subset whose bootstrapped success rate reaches the threshold and
//     is lowered until the ratio test passes.
//
// References:
//  * Teunissen P.J.G. (1995) The least-squares ambiguity decorrelation
//    adjustment: a method for fast GPS integer ambiguity estimation. J Geod 70:65-82.
//  * de Jonge P., Tiberius C. (1996) The LAMBDA method for integer ambiguity
//    estimation: implementation aspects. LGR Series 12, Delft Geodetic Computing Centre.
//  * Chang X.-W., Yang X., Zhou T. (2005) MLAMBDA: a modified LAMBDA method for
//    integer least-squares estimation. J Geod 79:552-565.
//  * Teunissen P.J.G. (1998) Success probability of integer GPS ambiguity
//    rounding and bootstrapping. J Geod 72:606-612.
//  * Teunissen P.J.G., Joosten P., Tiberius C. (1999) Geometry-free ambiguity
//    success rates in case of partial fixing. ION NTM 1999.
//  * Verhagen S., Teunissen P.J.G. (2013) The ratio test for future GNSS
//    ambiguity resolution. GPS Solutions 17:535-548.
//
// Units: ambiguities in cycles; squared norms dimensionless (chi-square like).
// Pure functions; nothing here knows about satellites or estimators.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ppp {

/// Q = L^T diag(d) L with L unit lower triangular.
struct LtdlFactor {
  Eigen::MatrixXd L;
  Eigen::VectorXd d;
};

/// LtDL of a symmetric positive definite Q; nullopt when Q is not square, not
/// finite or not positive definite (a pivot <= 0).
std::optional<LtdlFactor> ltdlDecompose(const Eigen::MatrixXd& Q);

/// The decorrelating Z-transformation: Z integral with |det Z| = 1 (held in a
/// double matrix with integer entries), and the LtDL factor of Q_z = Z^T Q Z.
struct Decorrelation {
  Eigen::MatrixXd Z;
  LtdlFactor factor;
  int gauss_transformations = 0;
  int permutations = 0;
};

/// Decorrelates Q; nullopt as ltdlDecompose.
std::optional<Decorrelation> decorrelate(const Eigen::MatrixXd& Q);

/// The m best integer vectors of an ILS problem given in factored form, best first.
struct IntegerCandidates {
  std::vector<Eigen::VectorXd> vectors;  // integer values held as double
  std::vector<double> squared_norms;     // ascending
  long nodes_visited = 0;                // search cost
};

/// Search with the shrinking ellipsoid for the m >= 1 integer vectors z that
/// minimise (z_hat - z)^T (L^T D L)^-1 (z_hat - z).
IntegerCandidates searchIntegerCandidates(const Eigen::VectorXd& z_hat, const LtdlFactor& factor,
                                          int candidates);

/// Bootstrapped success rate of the given conditional variances (cycles^2).
double bootstrapSuccessRate(const Eigen::VectorXd& conditional_variances);

/// Why an ILS problem ended float.
enum class IlsFloatReason {
  None,               // fixed (fully or partially)
  InvalidInput,       // sizes mismatch, non-finite values, Q not positive definite
  TooFewAmbiguities,  // fewer than min_fixed ambiguities offered
  LowSuccessRate,     // not even min_fixed decorrelated ambiguities reach the success rate
  RatioTestFailed,    // no subset of at least min_fixed passed the ratio test
};
std::string toString(IlsFloatReason reason);

struct IlsOptions {
  double ratio_threshold = 3.0;        // second-best / best squared norm, >= to accept
  double min_success_rate = 0.999;     // bootstrapped, for the subset to try first
  /// The float covariance times this factor is what the success rate is
  /// computed from (>= 1): the a-posteriori variance factor of the floats. A
  /// PPP float covariance that models its errors as white is optimistic (the
  /// held single differences' residual statistic T/m, chi-square per degree of
  /// freedom, is about 1 for an honest covariance and several times that on
  /// real stations); the search and the ratio test do not depend on it.
  /// PPP-AR's default is in ambiguity_resolution.h.
  double success_rate_variance_factor = 1.0;
  int min_fixed = 4;                   // smallest subset worth fixing
  bool partial = true;                 // try subsets when the full set fails
};

/// Result of one fixing attempt. The fixed subset is expressed as integer
/// linear constraints on the original ambiguities: constraint_rows * a = values,
/// where each row is integral (rows of Z^T for the kept z elements). When all n
/// are fixed, `fixed_ambiguities` also holds the ILS solution a = Z^-T z.
struct IlsResult {
  IlsFloatReason float_reason = IlsFloatReason::None;
  int ambiguities = 0;  // n offered
  int fixed = 0;        // p fixed (0 when float)
  double ratio = 0.0;   // of the accepted subset, else of the last subset tried
  double bootstrap_success_rate = 0.0;  // of the accepted (or last tried) subset
  Eigen::MatrixXd constraint_rows;      // p x n
  Eigen::VectorXd constraint_values;    // p
  std::optional<Eigen::VectorXd> fixed_ambiguities;  // set only when p == n
  long nodes_visited = 0;
  bool isFixed() const { return fixed > 0; }
};

/// LAMBDA with ratio test and partial fixing (see the header comment).
IlsResult solveIntegerLeastSquares(const Eigen::VectorXd& a_hat, const Eigen::MatrixXd& Q,
                                   const IlsOptions& options = {});

}  // namespace ppp
