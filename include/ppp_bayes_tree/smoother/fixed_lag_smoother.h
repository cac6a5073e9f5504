#pragma once
// Fixed-lag smoothing on top of iSAM2: variables older than the lag are marginalized.
//
// The caller states which variables are "time" variables by giving each a timestamp.
// Every other variable (a landmark, a carrier-phase bias) inherits, as its last use, the
// largest timestamp of a time variable sharing a factor with it; it is kept while that
// is within the lag, so long-lived landmarks stay as long as recent factors refer to
// them. Variables that never share a factor with a time variable are never
// marginalized. Ages are grouped in buckets of a tenth of the lag: re-eliminated
// variables are ordered oldest bucket first (constrained CCOLAMD), and a bucket is
// marginalized as a whole once all of it is older than the lag, so variables stay
// between lag and 1.1 lag. Marginalization cuts whole leaf subtrees off the Bayes tree and keeps
// their information as a dense linear prior on the variables they connect to
// (ISAM2::marginalizeLeaves); variables not yet at the leaves are first moved there by
// re-eliminating them first (constrained ordering), as GTSAM's
// IncrementalFixedLagSmoother does. Time and memory stay bounded by the lag.
#include <map>
#include <unordered_map>
#include <unordered_set>

#include "ppp_bayes_tree/smoother/isam2.h"

namespace ppp::smoother {

struct FixedLagParams {
  double lag_s = 600.0;
  ISAM2Params isam2;
};

struct FixedLagResult {
  ISAM2Result isam2;
  std::size_t variables_marginalized = 0;
  std::size_t variables_pending = 0;  // due, but not yet at the leaves
  std::size_t variables_moved_to_leaves = 0;  // re-eliminated to bring due ones to the leaves
  /// The estimate (linearization point + delta) of each variable marginalized by this
  /// update, as it was just before its removal (after this update's solve): its final value.
  Values marginalized_estimates;
};

class FixedLagSmoother {
 public:
  explicit FixedLagSmoother(FixedLagParams params = {});

  /// `timestamps_s`: timestamps of the new time variables (seconds, any origin);
  /// `newest_keys`: variables to keep in the root clique (see ISAM2UpdateParams);
  /// `remove_factor_indices`: factors to remove (indices from earlier results).
  FixedLagResult update(const NonlinearFactorGraph& new_factors, const Values& new_values,
                        const std::unordered_map<Key, double>& timestamps_s,
                        const KeyVector& newest_keys = {},
                        const std::vector<FactorIndex>& remove_factor_indices = {});

  const ISAM2& isam2() const { return isam_; }
  Values calculateEstimate() const { return isam_.calculateEstimate(); }
  Matrix marginalCovariance(Key key) const { return isam_.marginalCovariance(key); }
  /// Latest timestamp seen.
  double currentTime() const { return now_s_; }
  std::size_t numVariables() const { return isam_.linearizationPoint().size(); }

 private:
  KeyVector dueKeys() const;
  /// Stamps the time variables and the variables sharing a factor with one (update step 1).
  void recordUses(const NonlinearFactorGraph& new_factors, const std::unordered_map<Key, double>& timestamps_s);
  /// Marginalizes the due variables that are leaves, keeping their estimates (update step 3).
  void marginalizeDue(const KeyVector& due, FixedLagResult& out);
  /// Drops time-index entries below the cutoff that name no live variable (update step 4).
  void pruneTimeIndex();
  double bucketOf(double t_s) const;
  double cutoff() const;

  FixedLagParams params_;
  ISAM2 isam_;
  std::unordered_map<Key, double> last_use_s_;  // time variables: own stamp; others: last use
  std::unordered_set<Key> time_keys_;
  std::multimap<double, Key> by_time_;          // (last use, key), possibly stale entries
  double now_s_ = -1e300;
  double bucket_s_ = 60.0;
};

}  // namespace ppp::smoother
