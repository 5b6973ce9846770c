// Tests of octree/octree.h over families of refinements (sphere surface, points, random predicates
// with fixed seeds): after balance() the leaves tile the root and are 2:1 balanced across faces and
// edges, balance() is the coarsest such refinement and idempotent, and the queries (face
// neighbours, T-junctions, nodes) agree with brute force over all leaves.
#include "octree/octree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <set>
#include <string>
#include <tuple>

#include "core/errors.h"
#include "octree/refine.h"

using namespace volts;
using namespace volts::octree;

namespace {

using Key = std::tuple<int, int, int, int>;  // level, lo
Key key_of(const Cell& c) { return {c.level, c.lo[0], c.lo[1], c.lo[2]}; }

std::set<Key> leaf_set(const Octree& t) {
  std::set<Key> s;
  for (const Cell& c : t.leaves()) s.insert(key_of(c));
  return s;
}

// Dimension of the intersection of two closed boxes (-1: disjoint).
int contact_dim(const Cell& x, const Cell& y) {
  int dim = 0;
  for (int a = 0; a < 3; ++a) {
    const int len = std::min(x.hi()[a], y.hi()[a]) - std::max(x.lo[a], y.lo[a]);
    if (len < 0) return -1;
    dim += len > 0;
  }
  return dim;
}

// Unbalanced (fine, coarse, edge only) pairs by brute force over all pairs of leaves.
std::set<std::tuple<int, int, bool>> brute_unbalanced(const Octree& t) {
  std::set<std::tuple<int, int, bool>> out;
  const auto& L = t.leaves();
  for (int i = 0; i < int(L.size()); ++i)
    for (int j = 0; j < int(L.size()); ++j) {
      const int dim = contact_dim(L[i], L[j]);
      if ((dim == 2 || dim == 1) && L[i].level > L[j].level + 1) out.insert({i, j, dim == 1});
    }
  return out;
}

std::set<std::tuple<int, int, bool>> reported_unbalanced(const CheckResult& r) {
  std::set<std::tuple<int, int, bool>> out;
  for (const auto& u : r.unbalanced) out.insert({u.fine, u.coarse, u.edge_only});
  return out;
}

// Independent tiling check: every unit cell of the root is in exactly one leaf.
void expect_tiles_by_cells(const Octree& t) {
  const int n = t.root_side();
  std::vector<int> cover(std::size_t(n) * n * n, 0);
  for (const Cell& c : t.leaves())
    for (int z = c.lo[2]; z < c.hi()[2]; ++z)
      for (int y = c.lo[1]; y < c.hi()[1]; ++y)
        for (int x = c.lo[0]; x < c.hi()[0]; ++x) ++cover[(std::size_t(z) * n + y) * n + x];
  EXPECT_TRUE(std::all_of(cover.begin(), cover.end(), [](int k) { return k == 1; }));
}

// The node of a T-junction lies strictly inside the face or edge `index` of its leaf, decoded from
// the numbering documented in octree.h.
bool strictly_on(const TJunction& tj, const Cell& c) {
  const Index3 hi = c.hi();
  auto inside = [&](int a) { return tj.node[a] > c.lo[a] && tj.node[a] < hi[a]; };
  auto at = [&](int a, int side) { return tj.node[a] == (side ? hi[a] : c.lo[a]); };
  if (tj.on == TJunction::On::face) {
    if (tj.index < 0 || tj.index > 5) return false;
    const int a = tj.index / 2;
    return at(a, tj.index % 2) && inside((a + 1) % 3) && inside((a + 2) % 3);
  }
  if (tj.index < 0 || tj.index > 11) return false;
  const int a = tj.index / 4;
  return inside(a) && at((a + 1) % 3, tj.index & 1) && at((a + 2) % 3, (tj.index >> 1) & 1);
}

std::vector<Index3> corners(const Cell& c) {
  std::vector<Index3> out;
  for (int k = 0; k < 8; ++k) out.push_back({c.lo[0] + (k & 1) * c.side, c.lo[1] + ((k >> 1) & 1) * c.side, c.lo[2] + ((k >> 2) & 1) * c.side});
  return out;
}

// Queries against brute force and invariants that hold whether or not the tree is balanced.
// `brute`: also the O(leaves^2) comparisons (small trees only).
void expect_queries(const Octree& t, bool brute) {
  const auto& L = t.leaves();
  const CheckResult r = check(t);
  EXPECT_TRUE(r.tiles()) << "volume " << r.volume << " of " << r.root_volume << ", overlaps " << r.overlaps;
  EXPECT_EQ(r.volume, r.root_volume);

  // Nodes: sorted, unique, exactly the leaf corners.
  const auto nodes = t.nodes();
  EXPECT_TRUE(std::adjacent_find(nodes.begin(), nodes.end(), [](const Index3& a, const Index3& b) { return !(a < b); }) == nodes.end());
  std::set<Index3> corner_set;
  for (const Cell& c : L)
    for (const Index3& p : corners(c)) corner_set.insert(p);
  EXPECT_EQ(std::set<Index3>(nodes.begin(), nodes.end()), corner_set);

  // T-junctions: on the named face/edge, and a vertex of a deeper leaf.
  std::set<std::pair<Index3, int>> deep_corner;  // (corner, level)
  for (const Cell& c : L)
    for (const Index3& p : corners(c)) deep_corner.insert({p, c.level});
  const auto tjs = t.t_junctions();
  // Leaves of two levels share a face somewhere, and the finer face has a corner off the coarser's
  // corners: hanging nodes exist iff the refinement is not uniform.
  const bool uniform = std::all_of(L.begin(), L.end(), [&](const Cell& c) { return c.level == L[0].level; });
  EXPECT_EQ(tjs.empty(), uniform);
  for (const TJunction& tj : tjs) {
    ASSERT_GE(tj.leaf, 0);
    ASSERT_LT(tj.leaf, int(L.size()));
    EXPECT_TRUE(strictly_on(tj, L[tj.leaf]));
    bool deeper = false;
    for (int l = L[tj.leaf].level + 1; l <= t.max_level() && !deeper; ++l) deeper = deep_corner.count({tj.node, l}) > 0;
    EXPECT_TRUE(deeper);
  }

  // Locate: the leaf returned holds the unit cell.
  for (const Cell& c : L) {
    const int found = t.locate(c.lo);
    ASSERT_GE(found, 0);
    EXPECT_EQ(key_of(L[found]), key_of(c));
  }
  EXPECT_EQ(t.locate({-1, 0, 0}), -1);
  EXPECT_EQ(t.locate({0, 0, t.root_side()}), -1);

  if (!brute) return;
  EXPECT_EQ(reported_unbalanced(r), brute_unbalanced(t));
  // Every (node, leaf) with the node strictly inside a face or edge of the leaf is reported.
  std::set<std::tuple<Index3, int, int, int>> want, got;
  for (const Index3& p : nodes)
    for (int i = 0; i < int(L.size()); ++i)
      for (int on = 0; on < 2; ++on)
        for (int idx = 0; idx < (on ? 12 : 6); ++idx) {
          const TJunction tj{p, i, on ? TJunction::On::edge : TJunction::On::face, idx};
          if (strictly_on(tj, L[i])) want.insert({p, i, on, idx});
        }
  for (const TJunction& tj : tjs) got.insert({tj.node, tj.leaf, tj.on == TJunction::On::edge, tj.index});
  EXPECT_EQ(got, want);
  EXPECT_EQ(got.size(), tjs.size());  // no duplicates
  // Face neighbours: exactly the leaves with a positive-area contact across that face.
  for (int i = 0; i < int(L.size()); ++i)
    for (int f = 0; f < 6; ++f) {
      const int a = f / 2;
      const int plane = f % 2 ? L[i].hi()[a] : L[i].lo[a];
      std::vector<int> expect;
      for (int j = 0; j < int(L.size()); ++j)
        if (contact_dim(L[i], L[j]) == 2 && (f % 2 ? L[j].lo[a] == plane : L[j].hi()[a] == plane)) expect.push_back(j);
      EXPECT_EQ(t.face_neighbours(i, f), expect);
    }
  expect_tiles_by_cells(t);
}

// Invariants of a balanced tree.
void expect_balanced(const Octree& t) {
  const CheckResult r = check(t);
  EXPECT_TRUE(r.ok()) << r.unbalanced.size() << " unbalanced pairs";
  const auto& L = t.leaves();
  // Hanging nodes sit at face centres and edge midpoints only.
  for (const TJunction& tj : t.t_junctions()) {
    const Cell& c = L[tj.leaf];
    int at_mid = 0;
    for (int a = 0; a < 3; ++a) at_mid += 2 * tj.node[a] == 2 * c.lo[a] + c.side;
    EXPECT_EQ(at_mid, tj.on == TJunction::On::face ? 2 : 1);
  }
  // A face sees one neighbour of the same level or one coarser, or four one level finer.
  for (int i = 0; i < int(L.size()); ++i)
    for (int f = 0; f < 6; ++f) {
      const auto nb = t.face_neighbours(i, f);
      const int a = f / 2;
      const bool boundary = f % 2 ? L[i].hi()[a] == t.root_side() : L[i].lo[a] == 0;
      if (boundary) {
        EXPECT_TRUE(nb.empty());
      } else if (nb.size() == 1) {
        EXPECT_TRUE(L[nb[0]].level == L[i].level || L[nb[0]].level == L[i].level - 1);
      } else {
        ASSERT_EQ(nb.size(), 4u);
        for (int j : nb) EXPECT_EQ(L[j].level, L[i].level + 1);
      }
    }
}

// Balance by the definition: split the coarse leaf of every unbalanced pair check() reports until
// none is left. Every such split is forced, so this is the coarsest balanced refinement.
std::set<Key> naive_balance(Octree t) {
  for (int round = 0; round < 100; ++round) {
    const CheckResult r = check(t);
    if (r.unbalanced.empty()) break;
    std::set<Key> coarse;
    for (const auto& u : r.unbalanced) coarse.insert(key_of(t.leaves()[u.coarse]));
    t.refine([&](const Cell& c) { return coarse.count(key_of(c)) > 0; });
  }
  EXPECT_TRUE(check(t).ok());
  return leaf_set(t);
}

// The whole contract on one refined tree: queries before and after balance, balance minimal and
// idempotent, the balanced leaves refine the original ones.
void expect_balance_contract(Octree t, bool brute) {
  expect_queries(t, brute);
  const auto before = leaf_set(t);
  const auto naive = brute ? naive_balance(t) : std::set<Key>{};
  const int splits = t.balance();
  EXPECT_GE(splits, 0);
  EXPECT_EQ(t.leaves().size(), before.size() + 7 * std::size_t(splits));
  if (brute) {
    EXPECT_EQ(leaf_set(t), naive);
  }
  // Each old leaf is now a union of leaves: every new leaf lies in an old one.
  for (const Cell& c : t.leaves()) {
    bool inside = false;
    for (int l = c.level; l >= 0 && !inside; --l) {
      const int s = 1 << (t.max_level() - l);
      inside = before.count({l, c.lo[0] / s * s, c.lo[1] / s * s, c.lo[2] / s * s}) > 0;
    }
    EXPECT_TRUE(inside);
  }
  expect_queries(t, brute);
  expect_balanced(t);
  EXPECT_EQ(t.balance(), 0);
}

}  // namespace

TEST(Octree, ParamsOutOfRangeThrow) {
  EXPECT_THROW(Octree(OctreeParams{-1}), core::ConfigError);
  EXPECT_THROW(Octree(OctreeParams{17}), core::ConfigError);
  EXPECT_NO_THROW(Octree(OctreeParams{0}));
  EXPECT_NO_THROW(Octree(OctreeParams{16}));
  EXPECT_EQ(OctreeParams{}.max_level, 6);
}

TEST(Octree, RootOnly) {
  for (int max_level : {0, 3}) {
    Octree t(OctreeParams{max_level});
    ASSERT_EQ(t.leaves().size(), 1u);
    EXPECT_EQ(t.leaves()[0].side, t.root_side());
    EXPECT_EQ(t.refine([&](const Cell&) { return max_level == 0; }), 0);  // level 0 = max: no split
    EXPECT_TRUE(check(t).ok());
    EXPECT_TRUE(t.t_junctions().empty());
    EXPECT_EQ(t.nodes().size(), 8u);
    for (int f = 0; f < 6; ++f) EXPECT_TRUE(t.face_neighbours(0, f).empty());
  }
}

TEST(Octree, UniformRefinementHasNoTJunctions) {
  for (int level = 0; level <= 4; ++level) {
    Octree t(OctreeParams{5});
    const int splits = t.refine([&](const Cell& c) { return c.level < level; });
    EXPECT_EQ(t.leaves().size(), std::size_t(1) << (3 * level));
    EXPECT_EQ(t.leaves().size(), 1 + 7 * std::size_t(splits));
    for (const Cell& c : t.leaves()) EXPECT_EQ(c.level, level);
    EXPECT_TRUE(t.t_junctions().empty());
    const std::size_t n = (std::size_t(1) << level) + 1;
    EXPECT_EQ(t.nodes().size(), n * n * n);
    EXPECT_TRUE(check(t).ok());
    EXPECT_EQ(t.balance(), 0);
    expect_queries(t, level <= 2);
  }
}

TEST(Octree, RefineStopsAtMaxLevel) {
  for (int max_level : {1, 3, 16}) {
    Octree t(OctreeParams{max_level});
    t.refine([](const Cell& c) { return c.lo == Index3{0, 0, 0}; });  // always true toward the origin
    int deepest = 0;
    for (const Cell& c : t.leaves()) {
      deepest = std::max(deepest, c.level);
      EXPECT_EQ(c.side, 1 << (max_level - c.level));
      for (int a = 0; a < 3; ++a) EXPECT_DOUBLE_EQ(c.unit_hi[a] - c.unit_lo[a], double(c.side) / t.root_side());
    }
    EXPECT_EQ(deepest, max_level);
    EXPECT_TRUE(check(t).tiles());
  }
}

TEST(Octree, UnbalancedRefinementIsDetected) {
  // Toward points just inside the faces x = 1/2 (and y = 3/4) of coarse cells, to the last level,
  // without balance: the deepest leaves touch those faces, across which the leaves are level 1 or 2.
  // (Toward a single root corner the refinement is graded by itself: that case is in PointFamily.)
  for (const Vec3& q : {Vec3{0.49, 0.3, 0.3}, Vec3{0.499, 0.749, 0.26}}) {
    Octree t(OctreeParams{5});
    refine_toward_point(t, q);
    const CheckResult r = check(t);
    EXPECT_TRUE(r.tiles());
    EXPECT_FALSE(r.ok());
    EXPECT_FALSE(r.unbalanced.empty());
    for (const auto& u : r.unbalanced) EXPECT_GT(t.leaves()[u.fine].level, t.leaves()[u.coarse].level + 1);
    expect_balance_contract(t, true);
  }
}

TEST(Octree, EdgeOnlyImbalanceIsDetectedAndBalanced) {
  // Level-3 leaves along the edge x = y = 4, z in [0, 2] whose face neighbours across x = 4 and
  // y = 4 are level 2, but whose diagonal neighbour across the edge is the level-1 leaf
  // [4,8]x[4,8]x[0,4]: balanced across faces (all CGAL's grade() looks at), not across edges.
  Octree t(OctreeParams{3});
  t.refine([](const Cell& c) {
    if (c.level == 0) return true;
    if (c.level == 1) return c.lo == Index3{0, 0, 0} || c.lo == Index3{4, 0, 0} || c.lo == Index3{0, 4, 0};
    return c.level == 2 && c.lo == Index3{2, 2, 0};
  });
  const CheckResult r = check(t);
  EXPECT_TRUE(r.tiles());
  ASSERT_FALSE(r.unbalanced.empty());
  for (const auto& u : r.unbalanced) {
    EXPECT_TRUE(u.edge_only);
    EXPECT_EQ(key_of(t.leaves()[u.coarse]), Key(1, 4, 4, 0));
    EXPECT_EQ(contact_dim(t.leaves()[u.fine], t.leaves()[u.coarse]), 1);
  }
  expect_balance_contract(t, true);
}

TEST(Octree, SphereSurfaceFamily) {
  // Small trees against brute force, then the default level.
  for (const auto& [level, radius] : {std::pair{3, 0.3}, std::pair{4, 0.21}, std::pair{4, 0.45}, std::pair{6, 0.35}}) {
    const int max_level = level;
    const double r = radius;
    SCOPED_TRACE("max_level " + std::to_string(max_level) + " r " + std::to_string(r));
    const Vec3 centre{0.52, 0.47, 0.5};
    Octree t(OctreeParams{max_level});
    refine_toward_sphere(t, centre, r);
    // The deepest leaves are the ones the sphere crosses; leaves of other levels miss it.
    for (const Cell& c : t.leaves())
      if (c.level < max_level) {
        EXPECT_FALSE(crosses_sphere(c, centre, r));
      }
    expect_balance_contract(t, max_level <= 4);
  }
}

TEST(Octree, PointFamily) {
  for (const Vec3& q : {Vec3{1, 1, 1}, Vec3{0, 0.5, 1}, Vec3{0.5, 0.5, 0.5}, Vec3{0.13, 0.81, 0.4}}) {
    Octree t(OctreeParams{4});
    refine_toward_point(t, q);
    expect_balance_contract(t, true);
  }
}

TEST(Octree, RandomPredicates) {
  int unbalanced = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const int max_level = 3 + int(seed % 2);
    Octree t(OctreeParams{max_level});
    t.refine([&](const Cell& c) { return random_split(c, seed, c.level == 0 ? 1.0 : 0.35); });
    unbalanced += !check(t).ok();
    expect_balance_contract(t, true);
  }
  EXPECT_GT(unbalanced, 0);  // the family exercises balance()
  // Larger ones, without the quadratic brute force.
  for (std::uint64_t seed = 100; seed < 103; ++seed) {
    Octree t(OctreeParams{6});
    t.refine([&](const Cell& c) { return random_split(c, seed, 0.3); });
    expect_balance_contract(t, false);
  }
}

TEST(Octree, RefineAfterBalanceKeepsContract) {
  // Refinement is incremental: refine, balance, refine elsewhere, balance again.
  Octree t(OctreeParams{5});
  refine_toward_point(t, {0.1, 0.1, 0.1});
  t.balance();
  refine_toward_point(t, {0.9, 0.2, 0.75});
  expect_balance_contract(t, false);
}
