#pragma once
// SolutionIntegrity: whether a published solution's postfit residuals agree with
// its covariance (the epoch consistency test, postfit_screening.h). An
// inconsistent solution is never published as a plain "ok": it is flagged, and
// its covariance inflated (or the solution withheld: a "no solution" epoch).
#include <string>

namespace ppp {

enum class SolutionIntegrity {
  Unchecked,     // no test ran (no solution, the test switched off, or not an estimator output)
  Consistent,    // the postfit chi-square is within its quantile
  Inconsistent,  // the residuals contradict the covariance: covariance inflated by T / m
};
/// "unchecked", "consistent", "inconsistent".
std::string toString(SolutionIntegrity integrity);

}  // namespace ppp
