// iSAM2 update, following Kaess et al., "iSAM2: Incremental smoothing and mapping using
// the Bayes tree", IJRR 31(2) 2012: Alg. 6 (one iSAM2 step) with Alg. 4/5 (updating the
// Bayes tree, fluid relinearization) and Alg. 7 (partial state update, "wildfire").
#include "ppp_bayes_tree/smoother/isam2.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <stdexcept>

#include "ppp_bayes_tree/smoother/elimination.h"
#include "ppp_bayes_tree/smoother/linear_container_factor.h"
#include "ppp_bayes_tree/smoother/ordering.h"

namespace ppp::smoother {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}


}  // namespace

ISAM2::ISAM2(ISAM2Params params) : params_(std::move(params)) {
  if (params_.relinearize_skip < 1) throw std::invalid_argument("ISAM2Params: relinearize_skip must be >= 1");
}

ISAM2Result ISAM2::update(const NonlinearFactorGraph& new_factors, const Values& new_values,
                          const ISAM2UpdateParams& up) {
  const auto t_start = Clock::now();
  ISAM2Result result;
  for (FactorIndex i : up.remove_factor_indices)
    if (!factors_.count(i)) throw std::invalid_argument("ISAM2::update: no factor with index " + std::to_string(i));

  // ---- 1. Add the new factors and variables (validated first: no state change on bad
  // input) and remove the listed factors. `affected` collects the variables whose
  // cliques (and the paths from them to the root) are re-eliminated.
  auto t = Clock::now();
  KeySet affected = addAndRemoveFactors(new_factors, new_values, up, result);
  ++update_count_;
  result.step_time_s[ISAM2Result::kAddFactors] = secondsSince(t);

  // ---- 2. Relinearize: every relinearize_skip updates, mark the variables whose delta
  // exceeds the threshold (fluid check, Alg. 5), move their linearization point by delta
  // and invalidate the linearization of every factor involving them.
  t = Clock::now();
  if (params_.enable_relinearization &&
      (up.force_full_relinearization || update_count_ % params_.relinearize_skip == 0)) {
    result.relinearization_checked = true;
    relinearize(gatherRelinearizeKeys(up), affected, result, up.force_full_relinearization);
  }
  result.step_time_s[ISAM2Result::kRelinearize] = secondsSince(t);

  // ---- 3. Remove the top of the Bayes tree above the affected variables (Alg. 4): the
  // subtrees below it become orphans.
  t = Clock::now();
  Top top = removeTop(affected, result);
  result.step_time_s[ISAM2Result::kRemoveTop] = secondsSince(t);

  // ---- 4. Re-eliminate the top's factors and the orphans' cached marginals under a
  // constrained ordering, and re-attach the orphans.
  t = Clock::now();
  const std::vector<Clique*> created = reeliminateTop(top, up, result);
  result.step_time_s[ISAM2Result::kReeliminate] = secondsSince(t);

  // ---- 5. Back-substitution (Alg. 7), partial ("wildfire") when enabled.
  t = Clock::now();
  std::vector<const Clique*> created_sorted(created.begin(), created.end());
  std::sort(created_sorted.begin(), created_sorted.end());
  backSubstitute(created_sorted, result);
  result.step_time_s[ISAM2Result::kBackSubstitute] = secondsSince(t);
  result.total_time_s = secondsSince(t_start);
  return result;
}

// ---------------------------------------------------------------------------
// Step 1
ISAM2::KeySet ISAM2::addAndRemoveFactors(const NonlinearFactorGraph& new_factors, const Values& new_values,
                                         const ISAM2UpdateParams& up, ISAM2Result& result) {
  addFactorsAndVariables(new_factors, new_values, result);
  KeySet affected;
  for (const auto& [k, v] : new_values) affected.insert(k);
  for (FactorIndex i : result.new_factor_indices)
    for (Key k : factors_.at(i).factor->keys()) affected.insert(k);
  removeFactors(up.remove_factor_indices, affected, result);
  for (Key k : up.extra_reelim_keys)
    if (theta_.exists(k)) affected.insert(k);
  return affected;
}

void ISAM2::addFactorsAndVariables(const NonlinearFactorGraph& new_factors, const Values& new_values,
                                   ISAM2Result& result) {
  KeySet used;
  for (const auto& [k, v] : new_values)
    if (theta_.exists(k)) throw std::invalid_argument("ISAM2::update: variable exists: " + keyToString(k));
  for (const auto& f : new_factors) {
    if (!f) throw std::invalid_argument("ISAM2::update: null factor");
    for (Key k : f->keys()) {
      if (!theta_.exists(k) && !new_values.exists(k))
        throw std::invalid_argument("ISAM2::update: factor on unknown variable " + keyToString(k));
      used.insert(k);
    }
  }
  for (const auto& [k, v] : new_values)
    if (!used.count(k))
      throw std::invalid_argument("ISAM2::update: new variable in no new factor: " + keyToString(k));

  for (const auto& [k, v] : new_values) {
    theta_.insertFrom(new_values, k);
    delta_.insert(k, Vector::Zero(theta_.dim(k)));
    ++result.variables_added;
  }
  for (const auto& f : new_factors) {
    const FactorIndex i = next_factor_index_++;
    factors_.emplace(i, FactorSlot{f, nullptr});
    indexFactor(i, *f);
    result.new_factor_indices.push_back(i);
  }
  result.factors_added = new_factors.size();
}

void ISAM2::removeFactors(const std::vector<FactorIndex>& indices, KeySet& affected,
                          ISAM2Result& result) {
  for (FactorIndex i : indices) {
    auto it = factors_.find(i);
    if (it == factors_.end()) continue;  // listed twice
    for (Key k : it->second.factor->keys()) {
      affected.insert(k);
      unindexFactor(i, *it->second.factor, k);
    }
    factors_.erase(it);
    ++result.factors_removed;
  }
}

void ISAM2::indexFactor(FactorIndex index, const NonlinearFactor& factor) {
  for (Key k : factor.keys()) {
    variable_index_[k].push_back(index);
    if (!params_.skip_affine_variables) continue;
    const int dim = theta_.dim(k);
    auto& counts = nonaffine_factors_[k];
    counts.resize(static_cast<std::size_t>(dim), 0);
    for (int c = 0; c < dim; ++c)
      if (!factor.linearizationIndependentOf(k, c)) ++counts[static_cast<std::size_t>(c)];
  }
}

void ISAM2::unindexFactor(FactorIndex index, const NonlinearFactor& factor, Key key) {
  auto& list = variable_index_[key];
  auto pos = std::find(list.begin(), list.end(), index);
  if (pos == list.end()) return;
  list.erase(pos);
  auto it = nonaffine_factors_.find(key);
  if (it == nonaffine_factors_.end()) return;
  for (std::size_t c = 0; c < it->second.size(); ++c)
    if (!factor.linearizationIndependentOf(key, static_cast<int>(c)) && it->second[c] > 0) --it->second[c];
}

ISAM2::ThresholdCheck ISAM2::checkThreshold(Key key, const Vector& delta) const {
  auto ref = affine_reference_.find(key);
  const Vector e = ref == affine_reference_.end() ? delta : Vector(delta - ref->second);
  ThresholdCheck out;
  out.any = params_.exceedsThreshold(key, e);
  if (!out.any || !params_.skip_affine_variables) {
    out.nonlinear = out.any;
    return out;
  }
  // Only components that some factor is nonlinear in call for a relinearization.
  auto counts = nonaffine_factors_.find(key);
  if (counts == nonaffine_factors_.end()) return out;
  Vector masked = Vector::Zero(e.size());
  for (Eigen::Index c = 0; c < e.size(); ++c)
    if (static_cast<std::size_t>(c) < counts->second.size() && counts->second[static_cast<std::size_t>(c)] > 0)
      masked(c) = e(c);
  out.nonlinear = params_.exceedsThreshold(key, masked);
  return out;
}

// ---------------------------------------------------------------------------
// Step 2
ISAM2::KeySet ISAM2::gatherRelinearizeKeys(const ISAM2UpdateParams& up) const {
  KeySet marked;
  if (up.force_full_relinearization) {
    for (const auto& [k, v] : theta_) marked.insert(k);
  } else if (params_.fluid_relinearization) {
    for (const auto& root : tree_.roots()) fluidCheck(*root, marked);
  } else {
    for (const auto& [k, d] : delta_)
      if (checkThreshold(k, d).any) marked.insert(k);
  }
  for (Key k : up.no_relin_keys) marked.erase(k);
  return marked;
}

void ISAM2::fluidCheck(const Clique& clique, KeySet& marked) const {
  // Alg. 5: a clique whose frontal deltas are all below threshold stops the descent,
  // since back-substitution changes below it are no larger than its own.
  bool any = false;
  for (Key k : clique.frontals)
    if (checkThreshold(k, delta_.at(k)).any) {
      marked.insert(k);
      any = true;
    }
  if (!any) return;
  for (const auto& ch : clique.children) fluidCheck(*ch, marked);
}

void ISAM2::relinearize(const KeySet& relin_keys, KeySet& affected, ISAM2Result& result, bool force) {
  std::size_t done = 0;
  for (Key k : relin_keys) {
    Vector& d = delta_.at(k);
    if (params_.skip_affine_variables && !force && !checkThreshold(k, d).nonlinear) {
      // Moved only in components every factor is affine in: the linear system would
      // not change; move the reference instead (the fluid check sees the step).
      affine_reference_[k] = d;
      continue;
    }
    affine_reference_.erase(k);
    ++done;
    theta_.retractInPlace(k, d);
    d.setZero();
    affected.insert(k);
    for (FactorIndex i : variable_index_[k]) {
      FactorSlot& slot = factors_.at(i);
      if (slot.linear) {  // linearized before (not new) and not yet counted in this update
        // Sole owner: keep the storage for the relinearization (the object was created
        // non-const by NonlinearFactor::relinearize, so writing to it is sound).
        if (slot.linear.use_count() == 1) slot.spare = std::const_pointer_cast<JacobianFactor>(slot.linear);
        slot.linear.reset();
        ++result.factors_relinearized;
      }
      for (Key other : slot.factor->keys()) affected.insert(other);
    }
  }
  result.variables_relinearized = done;
}

const JacobianFactor& ISAM2::linearFactor(FactorIndex index) {
  FactorSlot& slot = factors_.at(index);
  if (!slot.linear || !params_.cache_linearized_factors)
    slot.linear = slot.factor->relinearize(theta_, std::move(slot.spare));
  return *slot.linear;
}

// ---------------------------------------------------------------------------
// Step 3
ISAM2::Top ISAM2::removeTop(const KeySet& affected, ISAM2Result& result) {
  RemovedTop removed = tree_.removeTop(KeyVector(affected.begin(), affected.end()));
  Top top;
  top.keys = std::move(removed.frontals);
  top.orphans = std::move(removed.orphans);
  for (FactorIndex i : removed.factor_indices)
    if (factors_.count(i)) top.factors.push_back(i);  // not removed in step 1
  for (FactorIndex i : result.new_factor_indices) top.factors.push_back(i);
  // Variables not in the tree yet (new ones).
  for (Key k : affected)
    if (!tree_.contains(k) && theta_.exists(k) && std::find(top.keys.begin(), top.keys.end(), k) == top.keys.end())
      top.keys.push_back(k);
  // Unused variables (all their factors removed) leave the problem.
  top.keys.erase(std::remove_if(top.keys.begin(), top.keys.end(),
                                [&](Key k) {
                                  auto it = variable_index_.find(k);
                                  if (it != variable_index_.end() && !it->second.empty()) return false;
                                  eraseVariable(k);
                                  return true;
                                }),
                 top.keys.end());
  result.cliques_removed = removed.cliques.size();
  result.orphans = top.orphans.size();
  return top;
}

void ISAM2::eraseVariable(Key key) {
  theta_.erase(key);
  delta_.erase(key);
  variable_index_.erase(key);
  nonaffine_factors_.erase(key);
  affine_reference_.erase(key);
  tree_.eraseKey(key);
}

// ---------------------------------------------------------------------------
// Step 4
std::vector<Clique*> ISAM2::reeliminateTop(const Top& top, const ISAM2UpdateParams& up, ISAM2Result& result) {
  result.variables_reeliminated = top.keys.size();
  if (top.keys.empty()) return {};
  // 4a. Constrained ordering (CCOLAMD): first_keys in the first group, the caller's newest
  // keys (default: the keys of the new factors) in the last group -> the root clique.
  const TopOrdering ordering = orderTop(top, up, result);

  // 4b. Symbolic elimination into cliques (fundamental supernodes: a variable joins its
  // child clique when that child's separator is exactly the variable plus its own
  // separator, and both lie in the same constraint group). The newest group is gathered
  // into one clique even where it would split (e.g. a new landmark seen once): merging a
  // child clique into its parent variable's clique keeps a valid Bayes tree (zero blocks
  // in the conditional), and puts every newest variable in the root clique.
  const SymbolicTree sym = symbolicEliminate(top, ordering);

  // 4c. Numeric elimination, children before parents (by last frontal position).
  std::vector<int> order;
  for (std::size_t c = 0; c < sym.cliques.size(); ++c)
    if (!sym.cliques[c].merged) order.push_back(static_cast<int>(c));
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return sym.cliques[a].frontals.back() < sym.cliques[b].frontals.back();
  });
  const std::vector<Clique::Ptr> cliques = eliminateNumeric(top, ordering, sym, order);
  result.cliques_created = order.size();

  // 4d. Re-attach each orphan below the clique holding the first-eliminated variable of
  // its separator (that clique contains the whole separator).
  for (std::size_t c = 0; c < sym.cliques.size(); ++c)
    for (int o : sym.cliques[c].merged ? std::vector<int>{} : sym.cliques[c].orphans) {
      top.orphans[o]->parent = cliques[c].get();
      cliques[c]->children.push_back(top.orphans[o]);
    }
  std::vector<Clique*> created;
  for (int c : order) created.push_back(cliques[c].get());
  return created;
}

int ISAM2::TopOrdering::lowest(const KeyVector& keys) const {
  int best = static_cast<int>(ordering.size());
  for (Key k : keys) {
    auto it = pos.find(k);
    if (it == pos.end()) throw std::logic_error("iSAM2: factor key outside the re-eliminated top: " + keyToString(k));
    best = std::min(best, it->second);
  }
  return best;
}

namespace {

constexpr long kFirstGroup = -(1L << 40), kNewestGroup = 1L << 40;

void setGroup(std::unordered_map<Key, long>& raw, const KeyVector& keys, long group) {
  for (Key k : keys) {
    auto it = raw.find(k);
    if (it != raw.end()) it->second = group;
  }
}

/// The composite groups (first, optional caller group, newest) renumbered 0.. without
/// gaps, as CCOLAMD wants; returns the number of the newest group (-1: none).
int renumberGroups(const std::unordered_map<Key, long>& raw, std::unordered_map<Key, int>& groups) {
  std::vector<long> levels;
  for (const auto& [k, g] : raw) levels.push_back(g);
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  groups.reserve(raw.size());
  for (const auto& [k, g] : raw)
    groups[k] = static_cast<int>(std::lower_bound(levels.begin(), levels.end(), g) - levels.begin());
  return levels.back() == kNewestGroup ? static_cast<int>(levels.size()) - 1 : -1;
}

}  // namespace

ISAM2::TopOrdering ISAM2::orderTop(const Top& top, const ISAM2UpdateParams& up, const ISAM2Result& result) const {
  std::unordered_map<Key, long> raw;
  raw.reserve(top.keys.size());
  for (Key k : top.keys) raw[k] = up.ordering_group ? up.ordering_group(k) : 0;
  const KeyVector* last = &up.newest_keys;
  KeyVector observed;
  if (up.newest_keys.empty()) {
    for (FactorIndex i : result.new_factor_indices)
      for (Key k : factors_.at(i).factor->keys()) observed.push_back(k);
    last = &observed;
  }
  setGroup(raw, *last, kNewestGroup);
  setGroup(raw, up.first_keys, kFirstGroup);
  TopOrdering ord;
  std::unordered_map<Key, int> groups;
  ord.newest_group = renumberGroups(raw, groups);
  ord.pattern.reserve(top.factors.size() + top.orphans.size());
  for (FactorIndex i : top.factors) ord.pattern.push_back(&factors_.at(i).factor->keys());
  for (const auto& o : top.orphans) ord.pattern.push_back(&o->separator);
  ord.ordering = computeOrdering(ord.pattern, top.keys, &groups);
  const int n = static_cast<int>(top.keys.size());
  ord.pos.reserve(n);
  for (int i = 0; i < n; ++i) ord.pos[ord.ordering[i]] = i;
  ord.group_at.resize(n);
  for (int i = 0; i < n; ++i) ord.group_at[i] = groups.at(ord.ordering[i]);
  return ord;
}

/// What the symbolic elimination gathers at each position of the ordering.
struct ISAM2::SymbolicTree::Buckets {
  std::vector<std::vector<FactorIndex>> factors_at;
  std::vector<std::vector<const KeyVector*>> factor_keys_at;  // their keys, same order
  std::vector<std::vector<int>> orphans_at;
  std::vector<std::vector<int>> children_at;  // cliques whose separator starts at var i
};

void ISAM2::SymbolicTree::separatorOf(int i, const Buckets& b, const TopOrdering& ord,
                                      const std::vector<Clique::Ptr>& orphans, std::vector<int>& stamp,
                                      std::vector<int>& st) const {
  st.clear();
  stamp[i] = i;
  auto add = [&](int p) {
    if (stamp[p] != i) {
      stamp[p] = i;
      st.push_back(p);
    }
  };
  for (const KeyVector* keys : b.factor_keys_at[i])
    for (Key k : *keys) add(ord.pos.at(k));
  for (int o : b.orphans_at[i])
    for (Key k : orphans[o]->separator) add(ord.pos.at(k));
  for (int c : b.children_at[i])
    for (int p : cliques[c].sep) add(p);
  std::sort(st.begin(), st.end());
}

int ISAM2::SymbolicTree::mergeNewestChildren(const std::vector<int>& children, int target, const TopOrdering& ord) {
  for (int c : children) {
    if (c == target || ord.group_at[cliques[c].frontals.back()] != ord.newest_group) continue;
    if (target < 0) {
      target = c;
      continue;
    }
    SymbolicClique& into = cliques[target];
    SymbolicClique& from = cliques[c];
    for (int p : from.frontals) var_clique[p] = target;
    into.frontals.insert(into.frontals.end(), from.frontals.begin(), from.frontals.end());
    std::sort(into.frontals.begin(), into.frontals.end());
    into.factors.insert(into.factors.end(), from.factors.begin(), from.factors.end());
    into.orphans.insert(into.orphans.end(), from.orphans.begin(), from.orphans.end());
    from = SymbolicClique{};
    from.merged = true;
  }
  return target;
}

ISAM2::SymbolicTree ISAM2::symbolicEliminate(const Top& top, const TopOrdering& ord) {
  const int n = static_cast<int>(top.keys.size());
  SymbolicTree tree;
  tree.var_clique.assign(n, -1);
  SymbolicTree::Buckets b{std::vector<std::vector<FactorIndex>>(n), std::vector<std::vector<const KeyVector*>>(n),
                          std::vector<std::vector<int>>(n), std::vector<std::vector<int>>(n)};
  for (std::size_t j = 0; j < top.factors.size(); ++j) {
    const int at = ord.lowest(*ord.pattern[j]);  // pattern[j]: the keys of top.factors[j]
    b.factors_at[at].push_back(top.factors[j]);
    b.factor_keys_at[at].push_back(ord.pattern[j]);
  }
  for (std::size_t o = 0; o < top.orphans.size(); ++o)
    b.orphans_at[ord.lowest(top.orphans[o]->separator)].push_back(static_cast<int>(o));
  std::vector<int> stamp(n, -1);
  std::vector<int> st;
  for (int i = 0; i < n; ++i) {
    tree.separatorOf(i, b, ord, top.orphans, stamp, st);
    int target = -1;
    for (int c : b.children_at[i])
      if (tree.cliques[c].sep.size() == st.size() + 1 &&
          ord.group_at[tree.cliques[c].frontals.back()] == ord.group_at[i]) {
        target = c;
        break;
      }
    if (ord.newest_group >= 0 && ord.group_at[i] == ord.newest_group)
      target = tree.mergeNewestChildren(b.children_at[i], target, ord);
    if (target < 0) {
      target = static_cast<int>(tree.cliques.size());
      tree.cliques.emplace_back();
    }
    SymbolicClique& s = tree.cliques[target];
    s.frontals.push_back(i);
    s.sep = st;
    s.factors.insert(s.factors.end(), b.factors_at[i].begin(), b.factors_at[i].end());
    s.orphans.insert(s.orphans.end(), b.orphans_at[i].begin(), b.orphans_at[i].end());
    tree.var_clique[i] = target;
    if (!st.empty()) b.children_at[st.front()].push_back(target);
  }
  return tree;
}

std::vector<Clique::Ptr> ISAM2::eliminateNumeric(const Top& top, const TopOrdering& ord, const SymbolicTree& tree,
                                                 const std::vector<int>& order) {
  const std::vector<SymbolicClique>& sym = tree.cliques;
  std::vector<Clique::Ptr> cliques(sym.size());
  std::vector<std::vector<int>> new_children(sym.size());
  for (std::size_t c = 0; c < sym.size(); ++c)
    if (!sym[c].merged && !sym[c].sep.empty())
      new_children[tree.var_clique[sym[c].sep.front()]].push_back(static_cast<int>(c));
  std::vector<const JacobianFactor*> gathered;
  for (int c : order) {
    const SymbolicClique& s = sym[c];
    auto clique = std::make_shared<Clique>();
    std::vector<int> fdims, sdims;
    for (int p : s.frontals) {
      clique->frontals.push_back(ord.ordering[p]);
      fdims.push_back(theta_.dim(ord.ordering[p]));
    }
    for (int p : s.sep) {
      clique->separator.push_back(ord.ordering[p]);
      sdims.push_back(theta_.dim(ord.ordering[p]));
    }
    gathered.clear();
    for (FactorIndex f : s.factors) gathered.push_back(&linearFactor(f));
    for (int o : s.orphans) gathered.push_back(top.orphans[o]->cached_marginal.get());
    for (int ch : new_children[c]) gathered.push_back(cliques[ch]->cached_marginal.get());
    EliminationResult er = eliminate(gathered, clique->frontals, fdims, clique->separator, sdims,
                                     params_.factorization, &workspace_);
    clique->conditional = std::move(er.conditional);
    clique->cached_marginal = std::move(er.marginal);
    clique->factor_indices = s.factors;
    for (int ch : new_children[c]) {
      cliques[ch]->parent = clique.get();
      clique->children.push_back(cliques[ch]);
    }
    for (Key k : clique->frontals) tree_.setClique(k, clique.get());
    if (s.sep.empty()) tree_.mutableRoots().push_back(clique);
    cliques[c] = std::move(clique);
  }
  return cliques;
}

// ---------------------------------------------------------------------------
// Step 5
void ISAM2::backSubstitute(const std::vector<const Clique*>& new_cliques, ISAM2Result& result) {
  // Alg. 7: top-down; a clique is solved again when it was re-eliminated or when one of its
  // separator variables differs by more than the threshold from its value when the clique
  // was last solved (not merely since the last update: steps below the threshold would
  // pile up unseen); the descent stops below cliques that were not solved again.
  const bool wildfire = params_.enable_partial_backsubstitution;
  const double threshold = params_.wildfire_threshold;
  std::vector<Clique*> stack;
  Vector sep;
  for (const auto& r : tree_.roots()) stack.push_back(r.get());
  while (!stack.empty()) {
    Clique* c = stack.back();
    stack.pop_back();
    int n = 0;
    for (Key k : c->separator) n += static_cast<int>(delta_.at(k).size());
    sep.resize(n);
    n = 0;
    for (Key k : c->separator) {
      const Vector& d = delta_.at(k);
      sep.segment(n, d.size()) = d;
      n += static_cast<int>(d.size());
    }
    bool recompute = !wildfire || std::binary_search(new_cliques.begin(), new_cliques.end(), c) || c->solved_separator_delta.size() != n;
    if (!recompute && n > 0) recompute = (sep - c->solved_separator_delta).cwiseAbs().maxCoeff() > threshold;
    if (!recompute) continue;
    const Vector x = c->conditional.solve(delta_);
    const auto& cond = c->conditional;
    for (std::size_t i = 0; i < c->frontals.size(); ++i)
      delta_.at(c->frontals[i]) = x.segment(cond.frontalOffset(i), cond.frontalDims()[i]);
    c->solved_separator_delta = sep;
    ++result.cliques_backsubstituted;
    for (const auto& ch : c->children) stack.push_back(ch.get());
  }
}

// ---------------------------------------------------------------------------
// Queries and marginalization
Values ISAM2::calculateEstimate() const { return theta_.retract(delta_); }

Vector ISAM2::calculateEstimate(Key key) const {
  const Manifold::Ptr m = theta_.manifold(key);
  return m ? m->retract(theta_.at(key), delta_.at(key)) : Vector(theta_.at(key) + delta_.at(key));
}

Values ISAM2::calculateBestEstimate() const {
  Values delta = delta_;
  for (const Clique* c : tree_.cliquesTopDown()) {  // parents first
    const Vector x = c->conditional.solve(delta);
    for (std::size_t i = 0; i < c->frontals.size(); ++i)
      delta.at(c->frontals[i]) = x.segment(c->conditional.frontalOffset(i), c->conditional.frontalDims()[i]);
  }
  return theta_.retract(delta);
}

std::vector<FactorIndex> ISAM2::factorsOf(Key key) const {
  auto it = variable_index_.find(key);
  return it == variable_index_.end() ? std::vector<FactorIndex>{} : it->second;
}

NonlinearFactorGraph ISAM2::nonlinearFactors() const {
  std::vector<FactorIndex> idx;
  for (const auto& [i, s] : factors_) idx.push_back(i);
  std::sort(idx.begin(), idx.end());
  NonlinearFactorGraph g;
  for (FactorIndex i : idx) g.push_back(factors_.at(i).factor);
  return g;
}

NonlinearFactor::Ptr ISAM2::factor(FactorIndex index) const {
  auto it = factors_.find(index);
  return it == factors_.end() ? nullptr : it->second.factor;
}

JacobianFactor::Ptr ISAM2::cachedLinearFactor(FactorIndex index) const {
  auto it = factors_.find(index);
  return it == factors_.end() ? nullptr : it->second.linear;
}

KeyVector ISAM2::marginalizeLeaves(const KeyVector& keys) {
  const KeySet m(keys.begin(), keys.end());
  std::unordered_map<const Clique*, bool> memo;
  // A clique can go when all its frontals are to be marginalized and all its children can.
  std::function<bool(const Clique*)> removable = [&](const Clique* c) {
    auto it = memo.find(c);
    if (it != memo.end()) return it->second;
    bool ok = std::all_of(c->frontals.begin(), c->frontals.end(), [&](Key k) { return m.count(k) != 0; });
    for (std::size_t i = 0; ok && i < c->children.size(); ++i) ok = removable(c->children[i].get());
    memo[c] = ok;
    return ok;
  };
  std::vector<Clique*> subtree_roots;
  std::unordered_set<Clique*> seen_roots;
  for (Key k : keys) {
    Clique* c = tree_.clique(k);
    if (!c || !removable(c)) continue;
    while (c->parent && removable(c->parent)) c = c->parent;
    if (seen_roots.insert(c).second) subtree_roots.push_back(c);
  }
  KeyVector done;
  for (Clique* top : subtree_roots) {
    std::vector<Clique*> sub{top};
    for (std::size_t i = 0; i < sub.size(); ++i)
      for (const auto& ch : sub[i]->children) sub.push_back(ch.get());
    KeySet gone;
    std::vector<FactorIndex> gone_factors;
    for (Clique* c : sub) {
      gone.insert(c->frontals.begin(), c->frontals.end());
      gone_factors.insert(gone_factors.end(), c->factor_indices.begin(), c->factor_indices.end());
    }
    // Remove the subtree's factors: exactly the factors involving its variables.
    for (FactorIndex i : gone_factors) {
      auto it = factors_.find(i);
      if (it == factors_.end()) continue;
      for (Key k : it->second.factor->keys())
        if (!gone.count(k)) unindexFactor(i, *it->second.factor, k);
      factors_.erase(it);
    }
    if (Clique* parent = top->parent) {
      // The subtree's information on the rest is its cached marginal on the separator.
      if (top->cached_marginal && top->cached_marginal->rows() > 0) {
        const FactorIndex i = next_factor_index_++;
        auto f = std::make_shared<LinearContainerFactor>(*top->cached_marginal, theta_);
        factors_.emplace(i, FactorSlot{f, top->cached_marginal});
        indexFactor(i, *f);
        parent->factor_indices.push_back(i);
      }
    }
    const Clique::Ptr cut = tree_.removeSubtree(top);  // freed at the end of this iteration
    for (Key k : gone) {
      eraseVariable(k);
      done.push_back(k);
    }
  }
  return done;
}

KeyVector ISAM2::keysToReeliminateForMarginalization(const KeyVector& keys) const {
  const KeySet m(keys.begin(), keys.end());
  std::function<bool(const Clique*)> removable = [&](const Clique* c) {
    if (!std::all_of(c->frontals.begin(), c->frontals.end(), [&](Key k) { return m.count(k) != 0; }))
      return false;
    for (const auto& ch : c->children)
      if (!removable(ch.get())) return false;
    return true;
  };
  KeySet out;
  for (Key k : keys) {
    const Clique* c = tree_.clique(k);
    if (!c || removable(c)) continue;
    out.insert(k);
    // Descendant cliques involving k (as frontal or separator) must be re-eliminated too,
    // otherwise they would come back as orphans hanging below k.
    std::vector<const Clique*> stack(1, c);
    while (!stack.empty()) {
      const Clique* q = stack.back();
      stack.pop_back();
      for (const auto& ch : q->children) {
        const auto& s = ch->separator;
        if (std::find(s.begin(), s.end(), k) == s.end()) continue;
        out.insert(ch->frontals.begin(), ch->frontals.end());
        stack.push_back(ch.get());
      }
    }
  }
  return KeyVector(out.begin(), out.end());
}

}  // namespace ppp::smoother
