#pragma once
// Gaussian Bayes tree (Kaess et al., IJRR 2012, Sec. 3): a directed tree of cliques, each
// holding a conditional density p(F_k | S_k) on its frontal variables F_k given its
// separator S_k (a subset of the parent clique's variables), the marginal factor on S_k
// that eliminating the clique's subtree passed to its parent (cached for re-use when the
// clique becomes an orphan), and the indices of the nonlinear factors eliminated in it.
// Every variable is a frontal variable of exactly one clique.
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "ppp_bayes_tree/smoother/gaussian_conditional.h"
#include "ppp_bayes_tree/smoother/gaussian_factor.h"
#include "ppp_bayes_tree/smoother/nonlinear_factor.h"

namespace ppp::smoother {

/// Created with std::make_shared (the tree finds a clique's owning pointer from the clique).
struct Clique : std::enable_shared_from_this<Clique> {
  using Ptr = std::shared_ptr<Clique>;

  KeyVector frontals;              // in elimination order
  KeyVector separator;             // conditional parents, in elimination order
  GaussianConditional conditional;
  JacobianFactor::Ptr cached_marginal;       // on the separator
  std::vector<FactorIndex> factor_indices;   // factors whose first-eliminated key is here
  /// The separator's stacked delta when the frontals were last solved (iSAM2's partial
  /// back-substitution compares against it, so that small changes cannot pile up).
  Vector solved_separator_delta;
  Clique* parent = nullptr;
  std::vector<Ptr> children;

  int frontalDim() const { return conditional.frontalDim(); }
};

/// What BayesTree::removeTop cut off: the removed cliques (detached: no children), their
/// frontal variables and factors, and the orphans, the subtrees that hung below them.
struct RemovedTop {
  /// In the order found: the path from each key's clique up to the root (or to a clique
  /// already removed), the keys taken in the order given.
  std::vector<Clique::Ptr> cliques;
  KeyVector frontals;                        // of the removed cliques, in their order
  std::vector<FactorIndex> factor_indices;   // eliminated in the removed cliques, same order
  /// Children of removed cliques that were not removed themselves (parent set to null),
  /// by removed clique, then child order. Their cached marginals stand for them.
  std::vector<Clique::Ptr> orphans;
};

class BayesTree {
 public:
  const std::vector<Clique::Ptr>& roots() const { return roots_; }
  /// Clique holding `key` as a frontal variable, or null.
  Clique* clique(Key key) const;
  bool contains(Key key) const { return nodes_.count(key) != 0; }
  std::size_t numVariables() const { return nodes_.size(); }
  /// Number of cliques (walks the tree).
  std::size_t numCliques() const;
  /// All cliques, parents before children.
  std::vector<const Clique*> cliquesTopDown() const;
  /// Depth of the tree (a root alone has depth 1).
  std::size_t depth() const;

  /// Structural invariants: each variable is a frontal of exactly one clique and the
  /// node map agrees; each separator is a subset of the parent's variables, roots have
  /// none; parent/child links agree; conditional parents equal the separator.
  /// Returns "" when all hold, else a description of the first violation.
  std::string checkInvariants() const;

  /// Joint marginal covariance of `keys` (blocks in the given order), from the Bayes
  /// net formed by the cliques on the paths from the keys' cliques to their roots: for a
  /// root-clique variable only the root conditional is touched. Throws
  /// std::out_of_range for an unknown key.
  Matrix jointMarginalCovariance(const KeyVector& keys) const;
  /// Marginal covariance of every variable, in one top-down pass: with the joint
  /// covariance C_S of a clique's separator (from its parent's pass), the conditional
  /// x_F = R^-1 d - G x_S, G = R^-1 S, gives C_FF = R^-1 R^-T + G C_S G^T and
  /// C_FS = -G C_S (Kaess and Dellaert, "Covariance recovery from a square root
  /// information matrix", 2009). Linear in the number of cliques, where calling
  /// jointMarginalCovariance per variable grows with each one's depth.
  std::unordered_map<Key, Matrix> marginalCovariances() const;
  /// Marginal covariance of one variable by the same top-down recursion, along the path
  /// from the root to the variable's clique only: time linear in that path's length,
  /// memory of one clique's joint. jointMarginalCovariance({key}) instead stacks a dense
  /// R over the whole path (n x n for n variable dimensions on it): for the oldest state
  /// of a fixed-lag window, whose path spans the window (10 Hz, lag 60 s: about 600
  /// states), that was about 20 ms and 100+ MB of page faults per call
  /// (scripts/bench_live_realtime.sh: the smoother node fell 19 s behind at 10 epochs/s).
  /// Throws std::out_of_range for an unknown key.
  Matrix marginalCovariance(Key key) const;

  // --- editing (used by ISAM2) ---
  /// Removes the top of the tree above `keys` (Kaess et al. IJRR 2012, Alg. 4 step 1,
  /// as GTSAM's BayesTree::removeTop): every clique holding one of the keys as a frontal
  /// variable and all its ancestors up to the root. Keys not in the tree are ignored.
  /// The removed variables leave the node map. The orphaned subtrees are detached
  /// (returned, to be re-attached below the re-eliminated top) but their variables stay
  /// in the node map: once they are re-attached, the tree is consistent again. The
  /// trees not touched stay as they were.
  RemovedTop removeTop(const KeyVector& keys);
  /// Cuts the subtree rooted at `top` off the tree (from its parent's children, or from
  /// the roots) and removes its variables from the node map; returns it, detached
  /// (parent null). Used to marginalize leaf subtrees.
  Clique::Ptr removeSubtree(Clique* top);
  std::vector<Clique::Ptr>& mutableRoots() { return roots_; }
  void setClique(Key key, Clique* c) { nodes_[key] = c; }
  void eraseKey(Key key) { nodes_.erase(key); }
  void clear() { roots_.clear(); nodes_.clear(); }

 private:
  std::vector<Clique::Ptr> roots_;
  std::unordered_map<Key, Clique*> nodes_;
};

}  // namespace ppp::smoother
