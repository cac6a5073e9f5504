#pragma once
// SolutionEpoch: one epoch of a position solution as the estimators report it
// and as the output writers (CSV, RTKLIB .pos) and the error statistics use it.
#include <optional>

#include <Eigen/Core>

#include "ppp_bayes_tree/ppp/screening/solution_integrity.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

enum class SolutionStatus {
  NoSolution,  // too few satellites or a failed update: no position this epoch
  Single,      // code-only solution
  PppFloat,    // PPP with float ambiguities
  PppFixed,    // PPP with fixed ambiguities
};
/// "no-solution", "single", "ppp-float", "ppp-fixed".
const char* solutionStatusName(SolutionStatus status);
/// RTKLIB quality flag Q (RTKLIB 2.4.3 rtklib.h SOLQ_*): 0 none, 5 single, 6 PPP, 1 fix.
int rtklibQuality(SolutionStatus status);

struct SolutionEpoch {
  GnssTime time;  // GPST
  SolutionStatus status = SolutionStatus::PppFloat;
  /// nullopt when the epoch has no solution (never a stale estimate).
  std::optional<Eigen::Vector3d> position_ecef_m;
  /// Position covariance in ECEF [m^2], when the estimator provides it.
  std::optional<Eigen::Matrix3d> covariance_ecef_m2;
  int satellites_used = 0;
  int satellites_rejected = 0;
  std::optional<double> zwd_m;             // zenith wet delay
  std::optional<double> receiver_clock_m;  // receiver clock times c
  /// The ratio test value of the integer search behind a fixed solution
  /// (AmbiguityFixSummary::ratio of this epoch's search when it passed, else of the
  /// latest one that passed since the solution became fixed: held integers are not
  /// searched again every epoch); nullopt unless status is PppFixed.
  std::optional<double> ambiguity_ratio;
  /// The epoch consistency test of the estimator's solution (solution_integrity.h).
  SolutionIntegrity integrity = SolutionIntegrity::Unchecked;
};

}  // namespace ppp
