#include "ppp_bayes_tree/smoother/fixed_lag_smoother.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_set>

namespace ppp::smoother {

FixedLagSmoother::FixedLagSmoother(FixedLagParams params)
    : params_(std::move(params)), isam_(params_.isam2) {
  if (!(params_.lag_s > 0)) throw std::invalid_argument("FixedLagParams: lag_s must be > 0");
  bucket_s_ = params_.lag_s / 10.0;
}

double FixedLagSmoother::bucketOf(double t_s) const { return std::floor(t_s / bucket_s_); }

double FixedLagSmoother::cutoff() const {
  // A variable is due once its whole age bucket is older than the lag.
  return bucketOf(now_s_ - params_.lag_s) * bucket_s_;
}

KeyVector FixedLagSmoother::dueKeys() const {
  const double cutoff = this->cutoff();
  KeyVector due;
  for (auto it = by_time_.begin(); it != by_time_.end() && it->first < cutoff; ++it) {
    auto lu = last_use_s_.find(it->second);
    if (lu != last_use_s_.end() && lu->second == it->first && isam_.exists(it->second))
      due.push_back(it->second);
  }
  return due;
}

FixedLagResult FixedLagSmoother::update(const NonlinearFactorGraph& new_factors, const Values& new_values,
                                        const std::unordered_map<Key, double>& timestamps_s,
                                        const KeyVector& newest_keys,
                                        const std::vector<FactorIndex>& remove_factor_indices) {
  for (const auto& [k, t] : timestamps_s) {
    if (!new_values.exists(k) && !isam_.exists(k))
      throw std::invalid_argument("FixedLagSmoother: timestamp for unknown variable " + keyToString(k));
  }
  // 1. Record uses: time variables carry their own stamp; other variables inherit the
  //    latest stamp of a time variable they share a factor with.
  recordUses(new_factors, timestamps_s);

  // 2. The iSAM2 update, the variables due moved to leaves.
  FixedLagResult out;
  const KeyVector due = dueKeys();
  ISAM2UpdateParams up;
  up.newest_keys = newest_keys;
  up.remove_factor_indices = remove_factor_indices;
  // Order re-eliminated variables by age bucket, oldest first, so that a bucket falling
  // out of the window is a set of leaf subtrees when it becomes due.
  up.ordering_group = [this](Key k) {
    auto it = last_use_s_.find(k);
    if (it == last_use_s_.end()) return 1 << 30;  // never time-referenced: keep high
    return static_cast<int>(std::max(-1e9, std::min(1e9, bucketOf(it->second))));
  };
  if (!due.empty()) {
    up.extra_reelim_keys = isam_.keysToReeliminateForMarginalization(due);
    if (!up.extra_reelim_keys.empty()) up.first_keys = due;
    out.variables_moved_to_leaves = up.extra_reelim_keys.size();
  }
  out.isam2 = isam_.update(new_factors, new_values, up);

  // 3. The due variables marginalized out (their last estimates kept).
  if (!due.empty()) marginalizeDue(due, out);

  // 4. Drop index entries below the cutoff that no longer name a live, due variable.
  pruneTimeIndex();
  return out;
}

void FixedLagSmoother::recordUses(const NonlinearFactorGraph& new_factors,
                                  const std::unordered_map<Key, double>& timestamps_s) {
  for (const auto& [k, t] : timestamps_s) {
    last_use_s_[k] = t;
    time_keys_.insert(k);
    by_time_.emplace(t, k);
    now_s_ = std::max(now_s_, t);
  }
  for (const auto& f : new_factors) {
    if (!f) continue;
    double latest = -1e300;
    bool any = false;
    for (Key k : f->keys())
      if (time_keys_.count(k)) {
        latest = std::max(latest, last_use_s_.at(k));
        any = true;
      }
    if (!any) continue;
    for (Key k : f->keys()) {
      if (time_keys_.count(k)) continue;
      auto it = last_use_s_.find(k);
      if (it == last_use_s_.end() || it->second < latest) {
        last_use_s_[k] = latest;
        by_time_.emplace(latest, k);
      }
    }
  }
}

void FixedLagSmoother::marginalizeDue(const KeyVector& due, FixedLagResult& out) {
  Values before;
  for (Key k : due) before.insert(k, isam_.calculateEstimate(k), isam_.linearizationPoint().manifold(k));
  const KeyVector done = isam_.marginalizeLeaves(due);
  for (Key k : done) out.marginalized_estimates.insertFrom(before, k);
  out.variables_marginalized = done.size();
  out.variables_pending = due.size() - done.size();
  for (Key k : done) {
    last_use_s_.erase(k);
    time_keys_.erase(k);
  }
}

void FixedLagSmoother::pruneTimeIndex() {
  const double cutoff = this->cutoff();
  for (auto it = by_time_.begin(); it != by_time_.end() && it->first < cutoff;) {
    auto lu = last_use_s_.find(it->second);
    const bool live = lu != last_use_s_.end() && lu->second == it->first && isam_.exists(it->second);
    it = live ? std::next(it) : by_time_.erase(it);
  }
}

}  // namespace ppp::smoother
