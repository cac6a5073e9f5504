#pragma once
// iSAM2 options (constructor-time) and per-call update options, kept apart as in GTSAM's
// ISAM2Params / ISAM2UpdateParams.
#include <Eigen/Core>
#include <functional>
#include <unordered_map>
#include <vector>

#include "ppp_bayes_tree/smoother/elimination.h"
#include "ppp_bayes_tree/smoother/key.h"
#include "ppp_bayes_tree/smoother/nonlinear_factor.h"

namespace ppp::smoother {

struct ISAM2Params {
  /// Only Gauss-Newton steps are implemented (one GN step per update, as in iSAM2).
  enum class Optimizer { GaussNewton };
  Optimizer optimizer = Optimizer::GaussNewton;

  /// Dense factorization of each clique.
  Factorization factorization = Factorization::Cholesky;

  /// Relinearize a variable when max_i |delta_i| exceeds its threshold (Kaess et al. IJRR
  /// 2012, Alg. 5). The threshold is per variable type (key symbol), else the default.
  bool enable_relinearization = true;
  double relinearize_threshold = 0.1;
  std::unordered_map<char, double> relinearize_threshold_by_symbol;
  /// Per-component thresholds of a variable type (as GTSAM's relinearizeThreshold
  /// map of vectors): relinearize when any |delta_i| > threshold_i. Takes precedence
  /// over the scalar thresholds for that symbol; the size must be the variable's.
  std::unordered_map<char, Eigen::VectorXd> relinearize_thresholds_by_symbol;
  /// Check for relinearization only every `relinearize_skip` updates.
  int relinearize_skip = 10;
  /// Fluid check: descend the tree from the roots and stop below cliques none of whose
  /// variables needs relinearization; false checks every variable.
  bool fluid_relinearization = true;
  /// Skip the relinearization of a variable that exceeds its threshold only in
  /// components that every one of its factors is affine in, with a constant
  /// coefficient and no robust kernel (NonlinearFactor::linearizationIndependentOf:
  /// a PPP phase bias; a PPP state's ZWD and clock): relinearizing it would leave the
  /// linear system unchanged and only re-eliminate every clique of its factors. The
  /// (fluid) check still sees it move: its current delta becomes its reference and
  /// the threshold applies to delta - reference, so the descent below it is the same
  /// as with the relinearization done. A forced full relinearization is not skipped.
  bool skip_affine_variables = false;

  /// Partial ("wildfire") back-substitution (Alg. 7): stop descending where no variable
  /// of a clique changed by more than `wildfire_threshold`. False: full back-substitution.
  bool enable_partial_backsubstitution = true;
  double wildfire_threshold = 1e-3;

  /// Keep the linearized factors between updates (re-linearize only relinearized ones).
  bool cache_linearized_factors = true;

  /// True when `delta` of variable `key` exceeds its relinearization threshold.
  bool exceedsThreshold(Key key, const Eigen::VectorXd& delta) const {
    auto v = relinearize_thresholds_by_symbol.find(keySymbol(key));
    if (v != relinearize_thresholds_by_symbol.end() && v->second.size() == delta.size())
      return (delta.array().abs() > v->second.array()).any();
    const double t = thresholdFor(key);
    return delta.size() > 0 && delta.cwiseAbs().maxCoeff() > t;
  }
  double thresholdFor(Key key) const {
    auto it = relinearize_threshold_by_symbol.find(keySymbol(key));
    return it == relinearize_threshold_by_symbol.end() ? relinearize_threshold : it->second;
  }
};

struct ISAM2UpdateParams {
  /// Indices (as returned in earlier results) of factors to remove.
  std::vector<FactorIndex> remove_factor_indices;
  /// Variables to eliminate last (they form the root clique): typically the newest
  /// state and the active landmarks. Empty: the keys of the new factors (GTSAM default).
  KeyVector newest_keys;
  /// Variables to eliminate first among the re-eliminated ones (e.g. about to be
  /// marginalized by a fixed-lag smoother).
  KeyVector first_keys;
  /// Optional ordering groups for the other re-eliminated variables: lower groups are
  /// eliminated first (e.g. a fixed-lag smoother groups variables by age so that the
  /// oldest sit at the leaves). Ignored for first_keys and newest_keys.
  std::function<int(Key)> ordering_group;
  /// Additional variables whose cliques must be re-eliminated.
  KeyVector extra_reelim_keys;
  /// Variables never to relinearize in this update.
  KeyVector no_relin_keys;
  /// Relinearize every variable now (whatever the thresholds and skip count).
  bool force_full_relinearization = false;
};

}  // namespace ppp::smoother
