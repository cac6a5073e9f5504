#include "ppp_bayes_tree/smoother/bayes_tree.h"

#include <algorithm>
#include <stdexcept>
#include <unordered_set>

namespace ppp::smoother {

Clique* BayesTree::clique(Key key) const {
  auto it = nodes_.find(key);
  return it == nodes_.end() ? nullptr : it->second;
}

std::vector<const Clique*> BayesTree::cliquesTopDown() const {
  std::vector<const Clique*> out;
  for (const auto& r : roots_) out.push_back(r.get());
  for (std::size_t i = 0; i < out.size(); ++i)
    for (const auto& c : out[i]->children) out.push_back(c.get());
  return out;
}

std::size_t BayesTree::numCliques() const { return cliquesTopDown().size(); }

std::size_t BayesTree::depth() const {
  std::size_t best = 0;
  std::vector<std::pair<const Clique*, std::size_t>> stack;
  for (const auto& r : roots_) stack.emplace_back(r.get(), 1);
  while (!stack.empty()) {
    auto [c, d] = stack.back();
    stack.pop_back();
    best = std::max(best, d);
    for (const auto& ch : c->children) stack.emplace_back(ch.get(), d + 1);
  }
  return best;
}

std::string BayesTree::checkInvariants() const {
  std::unordered_set<Key> seen;
  for (const Clique* c : cliquesTopDown()) {
    const std::string name = "clique {" + keysToString(c->frontals) + "}";
    if (c->frontals.empty()) return name + " has no frontal variable";
    for (Key k : c->frontals) {
      if (!seen.insert(k).second) return keyToString(k) + " is frontal in more than one clique";
      if (clique(k) != c) return "node map of " + keyToString(k) + " does not point to its clique";
    }
    if (c->conditional.frontals() != c->frontals) return name + ": conditional frontals differ";
    if (c->conditional.parents() != c->separator) return name + ": conditional parents differ from separator";
    for (const auto& ch : c->children)
      if (ch->parent != c) return name + ": child's parent link is wrong";
    if (!c->parent) {
      if (!c->separator.empty()) return name + " is a root with a separator";
      continue;
    }
    const Clique* p = c->parent;
    for (Key k : c->separator) {
      const bool in_parent =
          std::find(p->frontals.begin(), p->frontals.end(), k) != p->frontals.end() ||
          std::find(p->separator.begin(), p->separator.end(), k) != p->separator.end();
      if (!in_parent) return name + ": separator variable " + keyToString(k) + " not in parent clique";
    }
  }
  if (seen.size() != nodes_.size()) return "node map holds variables that are in no clique";
  return "";
}

RemovedTop BayesTree::removeTop(const KeyVector& keys) {
  RemovedTop out;
  // Paths to the roots; a path stops at a clique already removed (its ancestors are).
  std::unordered_set<const Clique*> removed;
  std::vector<Clique*> path_order;
  for (Key k : keys)
    for (Clique* c = clique(k); c && removed.insert(c).second; c = c->parent) path_order.push_back(c);
  if (path_order.empty()) return out;
  for (Clique* c : path_order) {
    for (const auto& ch : c->children)
      if (!removed.count(ch.get())) {
        ch->parent = nullptr;
        out.orphans.push_back(ch);
      }
    for (Key k : c->frontals) {
      out.frontals.push_back(k);
      nodes_.erase(k);
    }
    out.factor_indices.insert(out.factor_indices.end(), c->factor_indices.begin(), c->factor_indices.end());
  }
  out.cliques.reserve(path_order.size());
  for (Clique* c : path_order) out.cliques.push_back(c->shared_from_this());
  for (const Clique::Ptr& c : out.cliques) {  // detach: the orphans and removed children
    c->children.clear();
    c->parent = nullptr;
  }
  roots_.erase(std::remove_if(roots_.begin(), roots_.end(),
                              [&](const Clique::Ptr& r) { return removed.count(r.get()) != 0; }),
               roots_.end());
  return out;
}

Clique::Ptr BayesTree::removeSubtree(Clique* top) {
  Clique::Ptr owned = top->shared_from_this();
  std::vector<Clique::Ptr>& siblings = top->parent ? top->parent->children : roots_;
  siblings.erase(std::find(siblings.begin(), siblings.end(), owned));
  top->parent = nullptr;
  std::vector<const Clique*> stack{top};
  while (!stack.empty()) {
    const Clique* c = stack.back();
    stack.pop_back();
    for (Key k : c->frontals) nodes_.erase(k);
    for (const auto& ch : c->children) stack.push_back(ch.get());
  }
  return owned;
}

namespace {

/// Joint covariance of one clique's variables (frontals, then separator) and where each
/// variable sits in it.
struct CliqueJoint {
  Matrix cov;
  std::unordered_map<Key, std::pair<int, int>> at;  // offset, dim
};

/// The clique's joint from its parent's (nullptr for a root): with the separator's joint
/// C_S read from the parent's, the conditional x_F = R^-1 d - G x_S, G = R^-1 S, gives
/// C_FF = R^-1 R^-T + G C_S G^T and C_FS = -G C_S (Kaess and Dellaert 2009).
CliqueJoint cliqueJoint(const Clique& c, const CliqueJoint* parent) {
  const GaussianConditional& cond = c.conditional;
  const int nf = cond.frontalDim();
  CliqueJoint j;
  int ns = 0;
  for (std::size_t p = 0; p < cond.parents().size(); ++p) {
    j.at[cond.parents()[p]] = {nf + ns, static_cast<int>(cond.S()[p].cols())};
    ns += static_cast<int>(cond.S()[p].cols());
  }
  Matrix cs(ns, ns);  // separator joint, read from the parent's
  if (ns > 0)
    for (const auto& [ka, pa] : j.at)
      for (const auto& [kb, pb] : j.at) {
        const auto qa = parent->at.at(ka), qb = parent->at.at(kb);
        cs.block(pa.first - nf, pb.first - nf, pa.second, pb.second) =
            parent->cov.block(qa.first, qb.first, qa.second, qb.second);
      }
  Matrix rinv = Matrix::Identity(nf, nf);
  cond.R().triangularView<Eigen::Upper>().solveInPlace(rinv);
  Matrix g(nf, ns);  // R^-1 S
  for (std::size_t p = 0, col = 0; p < cond.parents().size(); ++p) {
    g.middleCols(static_cast<Eigen::Index>(col), cond.S()[p].cols()) = cond.S()[p];
    col += static_cast<std::size_t>(cond.S()[p].cols());
  }
  // A root clique has no separator: g is empty and there is nothing to solve (Eigen's
  // triangular solve would take the address of the first coefficient of an empty matrix).
  if (ns > 0) cond.R().triangularView<Eigen::Upper>().solveInPlace(g);
  j.cov.resize(nf + ns, nf + ns);
  const Matrix gcs = g * cs;
  j.cov.topLeftCorner(nf, nf) = rinv * rinv.transpose() + gcs * g.transpose();
  j.cov.topRightCorner(nf, ns) = -gcs;
  j.cov.bottomLeftCorner(ns, nf) = -gcs.transpose();
  j.cov.bottomRightCorner(ns, ns) = cs;
  for (std::size_t i = 0; i < cond.frontals().size(); ++i)
    j.at[cond.frontals()[i]] = {cond.frontalOffset(i), cond.frontalDims()[i]};
  return j;
}

}  // namespace

std::unordered_map<Key, Matrix> BayesTree::marginalCovariances() const {
  std::unordered_map<Key, Matrix> out;
  out.reserve(nodes_.size());
  // Each clique's joint is kept until its last child has read its separator block from it.
  std::unordered_map<const Clique*, std::pair<CliqueJoint, std::size_t>> joints;  // joint, children left
  for (const Clique* c : cliquesTopDown()) {
    const CliqueJoint* parent = c->parent ? &joints.at(c->parent).first : nullptr;
    CliqueJoint j = cliqueJoint(*c, parent);
    if (c->parent && --joints.at(c->parent).second == 0) joints.erase(c->parent);
    const GaussianConditional& cond = c->conditional;
    for (std::size_t i = 0; i < cond.frontals().size(); ++i) {
      const int off = cond.frontalOffset(i), dim = cond.frontalDims()[i];
      out[cond.frontals()[i]] = j.cov.block(off, off, dim, dim);
    }
    if (!c->children.empty()) joints.emplace(c, std::make_pair(std::move(j), c->children.size()));
  }
  return out;
}

Matrix BayesTree::marginalCovariance(Key key) const {
  const Clique* target = clique(key);
  if (!target) throw std::out_of_range("marginalCovariance: no variable " + keyToString(key));
  std::vector<const Clique*> path;  // the key's clique up to its root
  for (const Clique* c = target; c; c = c->parent) path.push_back(c);
  CliqueJoint joint;
  for (auto it = path.rbegin(); it != path.rend(); ++it) joint = cliqueJoint(**it, it == path.rbegin() ? nullptr : &joint);
  const auto [off, dim] = joint.at.at(key);
  return joint.cov.block(off, off, dim, dim);
}

Matrix BayesTree::jointMarginalCovariance(const KeyVector& keys) const {
  // Cliques on the paths to the roots: a Bayes net over an ancestor-closed set of cliques,
  // whose joint density is the marginal on their variables.
  std::unordered_map<const Clique*, int> depth_of;
  for (Key k : keys) {
    const Clique* c = clique(k);
    if (!c) throw std::out_of_range("jointMarginalCovariance: no variable " + keyToString(k));
    for (; c && !depth_of.count(c); c = c->parent) depth_of[c] = 0;
  }
  std::vector<const Clique*> cliques;
  for (auto& [c, d] : depth_of) {
    int depth = 0;
    for (const Clique* p = c->parent; p; p = p->parent) ++depth;
    d = depth;
    cliques.push_back(c);
  }
  // Deeper cliques first: each conditional's parents then have larger column offsets,
  // making the stacked square-root information R upper triangular.
  std::sort(cliques.begin(), cliques.end(), [&](const Clique* a, const Clique* b) {
    return depth_of[a] != depth_of[b] ? depth_of[a] > depth_of[b] : a->frontals[0] < b->frontals[0];
  });
  std::unordered_map<Key, std::pair<int, int>> col;  // offset, dim
  int n = 0;
  for (const Clique* c : cliques) {
    const auto& cond = c->conditional;
    for (std::size_t i = 0; i < cond.frontals().size(); ++i)
      col[cond.frontals()[i]] = {n + cond.frontalOffset(i), cond.frontalDims()[i]};
    n += cond.frontalDim();
  }
  Matrix r = Matrix::Zero(n, n);
  for (const Clique* c : cliques) {
    const auto& cond = c->conditional;
    const int row = col.at(cond.frontals()[0]).first;
    const int nf = cond.frontalDim();
    r.block(row, row, nf, nf) = cond.R();
    for (std::size_t j = 0; j < cond.parents().size(); ++j) {
      const auto [off, dim] = col.at(cond.parents()[j]);
      r.block(row, off, nf, dim) = cond.S()[j];
    }
  }
  int m = 0;
  for (Key k : keys) m += col.at(k).second;
  Matrix e = Matrix::Zero(n, m);
  int c0 = 0;
  for (Key k : keys) {
    const auto [off, dim] = col.at(k);
    e.block(off, c0, dim, dim).setIdentity();
    c0 += dim;
  }
  // Sigma = R^-1 R^-T, so Sigma_sel = Y^T Y with R^T Y = E.
  r.transpose().triangularView<Eigen::Lower>().solveInPlace(e);
  return e.transpose() * e;
}

}  // namespace ppp::smoother
