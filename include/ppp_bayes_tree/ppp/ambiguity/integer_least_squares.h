#pragma once
// Integer least squares (ILS) for carrier-phase ambiguities: the LAMBDA method.
// Given float ambiguities a_hat [cycles] with covariance Q, finds the integer
// vectors minimising (a_hat - a)^T Q^-1 (a_hat - a): LtDL decomposition,
// decorrelation (Z-transformation), search (Schnorr-Euchner), validation (ratio
// test, bootstrapped success rate) and partial fixing of the most precise
// decorrelated subset. Pure functions; nothing here knows about satellites or
// estimators. The steps: doc/ppp_ar.md, "The integer search (LAMBDA)".
// References: Teunissen (1995) J Geod 70:65-82 (LAMBDA); de Jonge & Tiberius
// (1996) LGR Series 12, Delft; Chang, Yang & Zhou (2005) J Geod 79:552-565
// (MLAMBDA); Teunissen (1998) J Geod 72:606-612 (bootstrapping); Teunissen,
// Joosten & Tiberius (1999) ION NTM (partial fixing); Euler & Schaffrin (1991)
// and Verhagen & Teunissen (2013) GPS Solutions 17:535-548 (the ratio test).
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
