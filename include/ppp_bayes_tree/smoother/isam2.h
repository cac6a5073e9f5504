#pragma once
// Incremental smoothing and mapping with the Bayes tree: iSAM2 (Kaess, Johannsson,
// Roberts, Ila, Leonard, Dellaert, "iSAM2: Incremental smoothing and mapping using the
// Bayes tree", IJRR 31(2), 2012). The state is a linearization point theta, a delta per
// variable in the tangent space (the estimate is theta (+) delta: theta + delta for a
// vector variable, the manifold retraction otherwise), the nonlinear factors with their cached
// linearizations, and the Bayes tree of the linearized system in delta. Each update
// edits only the top of the tree touched by new/removed/relinearized factors.
#include <unordered_map>
#include <unordered_set>

#include "ppp_bayes_tree/smoother/bayes_tree.h"
#include "ppp_bayes_tree/smoother/elimination.h"
#include "ppp_bayes_tree/smoother/isam2_params.h"
#include "ppp_bayes_tree/smoother/isam2_result.h"
#include "ppp_bayes_tree/smoother/nonlinear_factor.h"
#include "ppp_bayes_tree/smoother/values.h"

namespace ppp::smoother {

class ISAM2 {
 public:
  explicit ISAM2(ISAM2Params params = {});

  /// One iSAM2 step (Alg. 6 of the paper), in five steps: (1) add `new_factors` and the
  /// new variables `new_values` (initial estimates; every new variable must be involved
  /// in the graph) and remove the factors listed in `update_params`; (2) relinearize the
  /// variables marked by the (fluid) threshold check; (3) remove the top of the Bayes
  /// tree above the affected variables (BayesTree::removeTop); (4) re-eliminate it with
  /// the orphaned subtrees' cached marginals; (5) back-substitute. Throws std::invalid_argument for
  /// an unknown key, a duplicate variable or an unknown factor index, and
  /// IndeterminantSystemError for an under-constrained system.
  ISAM2Result update(const NonlinearFactorGraph& new_factors = {}, const Values& new_values = {},
                     const ISAM2UpdateParams& update_params = {});

  /// Current estimate theta + delta.
  Values calculateEstimate() const;
  Vector calculateEstimate(Key key) const;
  /// theta + the delta of a full back-substitution of the current tree (every clique
  /// solved, whatever the partial back-substitution left): the exact solution of the
  /// linearized system, for the whole trajectory at once (as GTSAM's calculateBestEstimate).
  Values calculateBestEstimate() const;
  const Values& linearizationPoint() const { return theta_; }
  const Values& delta() const { return delta_; }
  bool exists(Key key) const { return theta_.exists(key); }

  /// Marginal covariance of one variable (of the linearized system at theta).
  Matrix marginalCovariance(Key key) const { return tree_.marginalCovariance(key); }
  /// Joint marginal covariance of a few variables, blocks in the order given.
  Matrix jointMarginalCovariance(const KeyVector& keys) const {
    return tree_.jointMarginalCovariance(keys);
  }

  /// Marginalizes out the given variables where they form whole leaf subtrees of the
  /// Bayes tree: each maximal such subtree is cut off, its factors are removed and its
  /// cached marginal on the separator is added as a LinearContainerFactor. The
  /// remaining tree is unchanged (removing leaf conditionals of a Bayes net leaves the
  /// marginal of the rest). Returns the keys that were marginalized; the others stay.
  KeyVector marginalizeLeaves(const KeyVector& keys);
  /// Keys of `keys` that marginalizeLeaves() cannot take now, together with the
  /// variables of descendant cliques involving them: passing these as
  /// extra_reelim_keys and `keys` as first_keys to update() makes them leaves.
  KeyVector keysToReeliminateForMarginalization(const KeyVector& keys) const;

  const BayesTree& bayesTree() const { return tree_; }
  const ISAM2Params& params() const { return params_; }
  /// Live factor with this index, or null.
  NonlinearFactor::Ptr factor(FactorIndex index) const;
  std::size_t numFactors() const { return factors_.size(); }
  /// Indices of the live factors involving `key` (empty when unknown).
  std::vector<FactorIndex> factorsOf(Key key) const;
  /// The live factors as a graph (order unspecified but stable for the same state).
  NonlinearFactorGraph nonlinearFactors() const;
  /// Cached linearized factor (at theta), or null when not cached.
  JacobianFactor::Ptr cachedLinearFactor(FactorIndex index) const;
  std::size_t numUpdates() const { return update_count_; }

 private:
  struct FactorSlot {
    NonlinearFactor::Ptr factor;
    JacobianFactor::Ptr linear;  // at theta, valid when cached
    /// The invalidated linearization's storage, refilled by the next one (when nobody
    /// else held it); null otherwise.
    std::shared_ptr<JacobianFactor> spare;
  };
  using KeySet = std::unordered_set<Key>;

  // Steps of update() (see update()).
  /// Step 1: returns the variables affected by the new and removed factors.
  KeySet addAndRemoveFactors(const NonlinearFactorGraph& new_factors, const Values& new_values,
                             const ISAM2UpdateParams& up, ISAM2Result& result);
  void addFactorsAndVariables(const NonlinearFactorGraph& new_factors, const Values& new_values,
                              ISAM2Result& result);
  void removeFactors(const std::vector<FactorIndex>& indices, KeySet& affected, ISAM2Result& result);
  /// Step 2: marking (fluid check) and relinearization.
  KeySet gatherRelinearizeKeys(const ISAM2UpdateParams& up) const;
  void fluidCheck(const Clique& clique, KeySet& marked) const;
  void relinearize(const KeySet& relin_keys, KeySet& affected, ISAM2Result& result, bool force);
  /// Step 3: the problem to re-eliminate, cut from the tree.
  struct Top {
    KeyVector keys;                      // variables to re-eliminate
    std::vector<FactorIndex> factors;    // live factors of the removed cliques, then the new ones
    std::vector<Clique::Ptr> orphans;    // subtrees to re-attach
  };
  Top removeTop(const KeySet& affected, ISAM2Result& result);
  /// Step 4: returns the new cliques.
  std::vector<Clique*> reeliminateTop(const Top& top, const ISAM2UpdateParams& up, ISAM2Result& result);
  /// Step 4a: the constrained elimination order of the top's variables.
  struct TopOrdering {
    KeyVector ordering;                     // the top's keys in elimination order
    std::unordered_map<Key, int> pos;       // key -> position in `ordering`
    std::vector<int> group_at;              // constraint group of the variable at each position
    int newest_group = -1;                  // the group of the newest keys (-1: none)
    std::vector<const KeyVector*> pattern;  // keys of the top's factors, then its orphans' separators
    int lowest(const KeyVector& keys) const;  // first position of any of keys
  };
  TopOrdering orderTop(const Top& top, const ISAM2UpdateParams& up, const ISAM2Result& result) const;
  /// Step 4b: the cliques of the symbolic elimination, as positions in the ordering.
  struct SymbolicClique {
    std::vector<int> frontals, sep;
    std::vector<FactorIndex> factors;
    std::vector<int> orphans;  // indices into Top::orphans
    bool merged = false;       // folded into another clique
  };
  struct SymbolicTree {
    struct Buckets;
    std::vector<SymbolicClique> cliques;
    std::vector<int> var_clique;  // clique of the variable at each position
    void separatorOf(int i, const Buckets& b, const TopOrdering& ord, const std::vector<Clique::Ptr>& orphans,
                     std::vector<int>& stamp, std::vector<int>& st) const;
    int mergeNewestChildren(const std::vector<int>& children, int target, const TopOrdering& ord);
  };
  static SymbolicTree symbolicEliminate(const Top& top, const TopOrdering& ord);
  /// Step 4c: the numeric elimination of the cliques in `order`; indexed as tree.cliques.
  std::vector<Clique::Ptr> eliminateNumeric(const Top& top, const TopOrdering& ord, const SymbolicTree& tree,
                                            const std::vector<int>& order);
  /// Step 5; `new_cliques` (the re-eliminated ones) sorted by address.
  void backSubstitute(const std::vector<const Clique*>& new_cliques, ISAM2Result& result);

  const JacobianFactor& linearFactor(FactorIndex index);
  void eraseVariable(Key key);

  ISAM2Params params_;
  EliminationWorkspace workspace_;  // scratch of the clique eliminations
  Values theta_;
  Values delta_;
  BayesTree tree_;
  std::unordered_map<FactorIndex, FactorSlot> factors_;
  std::unordered_map<Key, std::vector<FactorIndex>> variable_index_;
  /// Per variable and component: the number of its live factors whose linearization
  /// depends on that component's linearization point (ISAM2Params::skip_affine_variables).
  std::unordered_map<Key, std::vector<std::size_t>> nonaffine_factors_;
  /// Variables whose relinearization was skipped: delta at the last skipped one.
  std::unordered_map<Key, Vector> affine_reference_;
  /// Effective delta (beyond the reference) above the threshold: in any component
  /// (`any`), in a component that some factor is nonlinear in (`nonlinear`).
  struct ThresholdCheck {
    bool any = false, nonlinear = false;
  };
  ThresholdCheck checkThreshold(Key key, const Vector& delta) const;
  /// Adds the factor to the variable index (and the affine bookkeeping).
  void indexFactor(FactorIndex index, const NonlinearFactor& factor);
  /// Removes the factor from the index entry of `key`.
  void unindexFactor(FactorIndex index, const NonlinearFactor& factor, Key key);
  FactorIndex next_factor_index_ = 0;
  std::size_t update_count_ = 0;
};

}  // namespace ppp::smoother
