// Bayes tree surgery on a small hand-built forest: BayesTree::removeTop (which cliques
// go, in which order, which subtrees become orphans, what stays consistent) and
// BayesTree::removeSubtree.
#include <gtest/gtest.h>

#include <algorithm>

#include "ppp_bayes_tree/smoother/bayes_tree.h"

using namespace ppp::smoother;

namespace {

// Clique with 1-dimensional frontal variables and a unit conditional (removeTop only
// looks at the structure).
Clique::Ptr makeClique(const KeyVector& frontals, const KeyVector& separator, std::vector<FactorIndex> factors) {
  auto c = std::make_shared<Clique>();
  c->frontals = frontals;
  c->separator = separator;
  const int n = static_cast<int>(frontals.size());
  c->conditional = GaussianConditional(frontals, std::vector<int>(frontals.size(), 1), separator,
                                       Matrix::Identity(n, n), std::vector<Matrix>(separator.size(), Matrix::Zero(n, 1)),
                                       Vector::Zero(n));
  c->factor_indices = std::move(factors);
  return c;
}

Key x(std::uint32_t i) { return symbolKey('x', i); }
Key y(std::uint32_t i) { return symbolKey('y', i); }

// Two trees:
//   R {x4,x5}                      S {y0}
//   +- A {x2,x3 | x4}              +- E {y1 | y0}
//   |  +- C {x0 | x2}
//   |  +- D {x1 | x3}
//   +- B {x6 | x5}
struct Forest {
  BayesTree tree;
  Clique::Ptr r, a, b, c, d, s, e;
  Forest() {
    r = makeClique({x(4), x(5)}, {}, {40, 41});
    a = makeClique({x(2), x(3)}, {x(4)}, {20});
    b = makeClique({x(6)}, {x(5)}, {60});
    c = makeClique({x(0)}, {x(2)}, {0});
    d = makeClique({x(1)}, {x(3)}, {10, 11});
    s = makeClique({y(0)}, {}, {100});
    e = makeClique({y(1)}, {y(0)}, {101});
    link(r, a);
    link(r, b);
    link(a, c);
    link(a, d);
    link(s, e);
    tree.mutableRoots() = {r, s};
    for (const Clique::Ptr& q : {r, a, b, c, d, s, e})
      for (Key k : q->frontals) tree.setClique(k, q.get());
  }
  static void link(const Clique::Ptr& parent, const Clique::Ptr& child) {
    child->parent = parent.get();
    parent->children.push_back(child);
  }
};

}  // namespace

TEST(SmootherBayesTree, HandBuiltForestIsConsistent) {
  Forest f;
  EXPECT_EQ(f.tree.checkInvariants(), "");
  EXPECT_EQ(f.tree.numCliques(), 7u);
  EXPECT_EQ(f.tree.depth(), 3u);
}

TEST(SmootherBayesTree, RemoveTopTakesThePathsToTheRootAndOrphansTheSubtreesBelow) {
  Forest f;
  // x1 sits in D: D, A and the root R go; x6 in B: B goes, its path stops at R (removed).
  const RemovedTop top = f.tree.removeTop({x(1), x(6)});
  ASSERT_EQ(top.cliques.size(), 4u);
  EXPECT_EQ(top.cliques[0], f.d);
  EXPECT_EQ(top.cliques[1], f.a);
  EXPECT_EQ(top.cliques[2], f.r);
  EXPECT_EQ(top.cliques[3], f.b);
  EXPECT_EQ(top.frontals, (KeyVector{x(1), x(2), x(3), x(4), x(5), x(6)}));
  EXPECT_EQ(top.factor_indices, (std::vector<FactorIndex>{10, 11, 20, 40, 41, 60}));
  // C hung below A and was not on a path: the only orphan, detached with its conditional.
  ASSERT_EQ(top.orphans.size(), 1u);
  EXPECT_EQ(top.orphans[0], f.c);
  EXPECT_EQ(f.c->parent, nullptr);
  EXPECT_EQ(f.c->separator, KeyVector{x(2)});
  // The removed cliques are detached from each other and from the orphans.
  for (const auto& q : top.cliques) {
    EXPECT_TRUE(q->children.empty());
    EXPECT_EQ(q->parent, nullptr);
  }
  // The removed variables left the node map; the orphan's stay; the other tree is untouched.
  for (Key k : top.frontals) EXPECT_FALSE(f.tree.contains(k)) << keyToString(k);
  EXPECT_EQ(f.tree.clique(x(0)), f.c.get());
  ASSERT_EQ(f.tree.roots().size(), 1u);
  EXPECT_EQ(f.tree.roots()[0], f.s);
  EXPECT_EQ(f.tree.clique(y(1)), f.e.get());
  EXPECT_EQ(f.e->parent, f.s.get());
  // Without the orphan's variable (it comes back when the orphan is re-attached), the rest
  // is a consistent tree.
  f.tree.eraseKey(x(0));
  EXPECT_EQ(f.tree.checkInvariants(), "");
  EXPECT_EQ(f.tree.numCliques(), 2u);
}

TEST(SmootherBayesTree, RemoveTopOfARootAloneOrphansAllItsChildren) {
  Forest f;
  const RemovedTop top = f.tree.removeTop({x(5)});
  ASSERT_EQ(top.cliques.size(), 1u);
  EXPECT_EQ(top.cliques[0], f.r);
  EXPECT_EQ(top.frontals, (KeyVector{x(4), x(5)}));
  EXPECT_EQ(top.orphans, (std::vector<Clique::Ptr>{f.a, f.b}));
  EXPECT_EQ(f.a->parent, nullptr);
  EXPECT_EQ(f.b->parent, nullptr);
  // The orphans keep their own subtrees.
  EXPECT_EQ(f.a->children.size(), 2u);
  EXPECT_EQ(f.c->parent, f.a.get());
  EXPECT_EQ(f.tree.numVariables(), 7u);  // x0..x3, x6 (orphans) and y0, y1
}

TEST(SmootherBayesTree, RemoveTopIgnoresUnknownKeysAndRepeatedPaths) {
  Forest f;
  const RemovedTop none = f.tree.removeTop({symbolKey('z', 9)});
  EXPECT_TRUE(none.cliques.empty());
  EXPECT_TRUE(none.orphans.empty());
  EXPECT_EQ(f.tree.checkInvariants(), "");
  EXPECT_EQ(f.tree.numCliques(), 7u);
  // y1 and y0 share the path: each clique is removed once; the tree of x is untouched.
  const RemovedTop top = f.tree.removeTop({y(1), y(0), symbolKey('z', 9)});
  ASSERT_EQ(top.cliques.size(), 2u);
  EXPECT_EQ(top.cliques[0], f.e);
  EXPECT_EQ(top.cliques[1], f.s);
  EXPECT_TRUE(top.orphans.empty());
  EXPECT_EQ(top.frontals, (KeyVector{y(1), y(0)}));
  EXPECT_EQ(f.tree.checkInvariants(), "");
  EXPECT_EQ(f.tree.numCliques(), 5u);
  EXPECT_EQ(f.tree.roots().size(), 1u);
}

TEST(SmootherBayesTree, RemoveSubtreeCutsALeafSubtreeAndLeavesAConsistentTree) {
  Forest f;
  const Clique::Ptr cut = f.tree.removeSubtree(f.a.get());
  EXPECT_EQ(cut, f.a);
  EXPECT_EQ(f.a->parent, nullptr);
  EXPECT_EQ(f.a->children.size(), 2u);  // the subtree stays whole
  EXPECT_EQ(f.r->children, (std::vector<Clique::Ptr>{f.b}));
  for (std::uint32_t i = 0; i < 4; ++i) EXPECT_FALSE(f.tree.contains(x(i)));
  EXPECT_EQ(f.tree.checkInvariants(), "");
  EXPECT_EQ(f.tree.numCliques(), 4u);
  EXPECT_EQ(f.tree.numVariables(), 5u);  // x4, x5, x6, y0, y1
  // A whole tree goes from the roots.
  f.tree.removeSubtree(f.s.get());
  EXPECT_EQ(f.tree.roots(), (std::vector<Clique::Ptr>{f.r}));
  EXPECT_EQ(f.tree.checkInvariants(), "");
  EXPECT_EQ(f.tree.numVariables(), 3u);
}
