#pragma once
// What one iSAM2 update did: counts and the wall time of each numbered step of
// ISAM2::update (1 add/remove factors, 2 relinearize, 3 remove top, 4 re-eliminate,
// 5 back-substitute).
#include <array>
#include <cstddef>
#include <vector>

#include "ppp_bayes_tree/smoother/nonlinear_factor.h"

namespace ppp::smoother {

struct ISAM2Result {
  std::vector<FactorIndex> new_factor_indices;  // one per new factor, in order
  std::size_t factors_added = 0;
  std::size_t factors_removed = 0;
  std::size_t variables_added = 0;
  std::size_t variables_relinearized = 0;  // linearization point moved in step 2
  std::size_t variables_reeliminated = 0;  // variables in the re-eliminated top
  /// Factors linearized again at a moved linearization point: those involving a
  /// relinearized variable, each counted once (new factors are not counted).
  std::size_t factors_relinearized = 0;
  std::size_t cliques_removed = 0;         // top of the old tree
  std::size_t cliques_created = 0;         // new top
  std::size_t orphans = 0;
  std::size_t cliques_backsubstituted = 0; // cliques whose delta was recomputed
  bool relinearization_checked = false;
  enum Step : std::size_t { kAddFactors, kRelinearize, kRemoveTop, kReeliminate, kBackSubstitute, kNumSteps };
  /// Short name of each step, for reports.
  static constexpr std::array<const char*, kNumSteps> kStepNames{"add factors", "relinearize", "remove top",
                                                                   "re-eliminate", "back-substitute"};
  /// Seconds spent in each step (indexed by Step).
  std::array<double, kNumSteps> step_time_s{};
  double total_time_s = 0.0;
  /// Cliques touched: removed + created + back-substituted.
  std::size_t cliquesTouched() const {
    return cliques_removed + cliques_created + cliques_backsubstituted;
  }
};

}  // namespace ppp::smoother
