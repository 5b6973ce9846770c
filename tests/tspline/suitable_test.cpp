// Tests of tspline/suitable.h: after make_partition_of_unity (slab rule + check-and-repair) every
// tree of the families (refinement toward a point, a plane, a sphere surface, random predicates
// with fixed seeds; max levels 3–5) has Σ N = 1 and Greville control points reproduce the identity
// (polynomial and rational) to 1e-12; the rules only split (every new leaf inside an old one) and
// keep the tree 2:1 balanced. Also the findings behind the rule: one level of refinement of a box
// sums to one only for a slab spanning the root, and graded balance does not fix it.
#include "tspline/suitable.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>

#include "common/octree_families.h"
#include "core/errors.h"
#include "octree/refine.h"

using namespace volts;
using namespace volts::tspline;
using octree::Cell;
using octree::Octree;

namespace {

constexpr double kTol = 1e-12;

using test::toward_plane;
using test::toward_point;
using test::toward_sphere;

struct Case {
  std::string name;
  int max_level;
  std::function<bool(const Cell&)> split;
};

std::vector<Case> cases() {
  std::vector<Case> out = {{"point", 3, toward_point},   {"point", 4, toward_point},   {"point", 5, toward_point},
                           {"plane", 3, toward_plane},   {"sphere", 3, toward_sphere},
                           {"sphere", 4, toward_sphere}};
  for (std::uint64_t seed = 1; seed <= 6; ++seed)
    out.push_back({"random" + std::to_string(seed), seed <= 3 ? 3 : 4,
                   [seed](const Cell& c) { return c.level == 0 || octree::random_split(c, seed, seed <= 3 ? 0.4 : 0.2); }});
  return out;
}

Octree build(const Case& c) {
  Octree t(octree::OctreeParams{c.max_level});
  t.refine(c.split);
  t.balance();
  return t;
}

// Every leaf of `fine` lies inside a leaf of `coarse` at most as deep (dyadic boxes nest).
void expect_refines(const Octree& coarse, const Octree& fine, const std::string& name) {
  for (const Cell& c : fine.leaves()) {
    const int l = coarse.locate(c.lo);
    ASSERT_GE(l, 0) << name;
    const Cell& o = coarse.leaves()[l];
    EXPECT_LE(o.level, c.level) << name;
    for (int a = 0; a < 3; ++a) EXPECT_TRUE(o.lo[a] <= c.lo[a] && c.hi()[a] <= o.hi()[a]) << name;
  }
}

// One level of refinement (max level 4) of the box [lo, hi) of level-3 cells in a uniform level-3 tree.
double block_pou_error(const octree::Index3& lo, const octree::Index3& hi) {
  Octree t(octree::OctreeParams{4});
  t.refine([&](const Cell& c) {
    if (c.level < 3) return true;
    for (int a = 0; a < 3; ++a)
      if (c.lo[a] / 2 < lo[a] || c.lo[a] / 2 >= hi[a]) return false;
    return true;
  });
  return TSpline(t).partition_of_unity_error();
}

}  // namespace

TEST(Suitable, MakePartitionOfUnityOnEveryFamily) {
  std::printf("%-8s %2s %6s %6s %4s %8s %10s %10s\n", "tree", "L", "before", "after", "axis", "repairs", "PoU before",
              "PoU after");
  for (const Case& c : cases()) {
    const std::string name = c.name + " L" + std::to_string(c.max_level);
    const Octree before = build(c);
    const double pou_before = TSpline(before).partition_of_unity_error();
    Octree t = before;
    SuitableReport rep;
    const int splits = make_partition_of_unity(t, {}, &rep);
    EXPECT_EQ(splits, rep.splits) << name;
    EXPECT_EQ(splits > 0, t.leaves().size() > before.leaves().size()) << name;
    EXPECT_TRUE(octree::check(t).ok()) << name;
    expect_refines(before, t, name);
    const TSpline ts(t);
    EXPECT_LE(ts.partition_of_unity_error(), kTol) << name;
    EXPECT_EQ(ts.partition_of_unity_error(), rep.pou_error) << name;
    EXPECT_LE(greville_identity_error(ts), kTol) << name;
    const auto [poly, rat] = test::random_identity_errors(ts, 25, 3);
    EXPECT_LE(poly, kTol) << name;
    EXPECT_LE(rat, kTol) << name;
    EXPECT_TRUE(non_unity_leaves(ts, kTol).empty()) << name;
    std::printf("%-8s %2d %6zu %6zu %4d %8d %10.2g %10.2g\n", c.name.c_str(), c.max_level, before.leaves().size(),
                t.leaves().size(), rep.axis, rep.repair_iterations, pou_before, rep.pou_error);
  }
}

TEST(Suitable, FixedAxisAndRepairRuleAlsoConverge) {
  for (const Case& c : cases()) {
    if (c.max_level > 3) continue;
    const Octree before = build(c);
    for (int variant = 0; variant < 4; ++variant) {
      Octree t = before;
      SuitableParams p;
      if (variant < 3) p.axis = variant;
      else p.rule = SuitableRule::repair;
      SuitableReport rep;
      make_partition_of_unity(t, p, &rep);
      EXPECT_EQ(rep.axis, variant < 3 ? variant : -1);
      EXPECT_TRUE(octree::check(t).ok()) << c.name;
      expect_refines(before, t, c.name);
      const TSpline ts(t);
      EXPECT_LE(ts.partition_of_unity_error(), kTol) << c.name << " variant " << variant;
      EXPECT_LE(greville_identity_error(ts), kTol) << c.name << " variant " << variant;
    }
  }
}

// The slab rule's level depends on one coordinate only, and it is idempotent.
TEST(Suitable, SlabClosureMakesTheLevelAFunctionOfOneCoordinate) {
  for (const Case& c : cases()) {
    if (c.max_level > 3) continue;
    for (int axis = 0; axis < 3; ++axis) {
      Octree t = build(c);
      slab_closure(t, axis);
      EXPECT_TRUE(octree::check(t).ok());
      std::vector<int> level(std::size_t(t.root_side()), -1);
      for (const Cell& cell : t.leaves())
        for (int x = cell.lo[axis]; x < cell.lo[axis] + cell.side; ++x) {
          if (level[x] < 0) level[x] = cell.level;
          EXPECT_EQ(level[x], cell.level) << c.name << " axis " << axis;
        }
      EXPECT_EQ(slab_closure(t, axis), 0);
      EXPECT_EQ(make_partition_of_unity(t, {SuitableRule::slab, axis}), 0) << c.name << " axis " << axis;
    }
  }
}

// The finding behind the rule: one level of refinement of a box of cells sums to one only when the
// box is a slab spanning the root in two directions (no edge of the refined region in the interior).
TEST(Suitable, OnlySlabRefinementsOfABoxArePartitionsOfUnity) {
  EXPECT_LE(block_pou_error({0, 3, 0}, {8, 5, 8}), kTol);  // slab
  EXPECT_LE(block_pou_error({0, 0, 3}, {8, 8, 5}), kTol);
  EXPECT_LE(block_pou_error({0, 0, 0}, {8, 4, 8}), kTol);  // half space
  EXPECT_GT(block_pou_error({2, 2, 2}, {6, 6, 6}), 0.01);  // cube
  EXPECT_GT(block_pou_error({3, 3, 3}, {5, 5, 5}), 0.01);
  EXPECT_GT(block_pou_error({2, 2, 0}, {6, 6, 8}), 0.01);  // column spanning z
  EXPECT_GT(block_pou_error({0, 2, 2}, {8, 6, 6}), 0.01);  // bar spanning x
  EXPECT_GT(block_pou_error({1, 1, 0}, {7, 7, 8}), 0.01);
}

// Candidate (b): graded balance over a neighbourhood refines and keeps the tree balanced, but the
// basis still does not sum to one (printed).
TEST(Suitable, GradedBalanceIsNotEnough) {
  int still_failing = 0, trees = 0;
  for (const Case& c : cases()) {
    if (c.max_level > 4) continue;
    for (int radius = 1; radius <= 2; ++radius) {
      const Octree before = build(c);
      Octree t = before;
      balance_neighbourhood(t, radius);
      EXPECT_TRUE(octree::check(t).ok());
      expect_refines(before, t, c.name);
      EXPECT_EQ(balance_neighbourhood(t, radius), 0);
      // No leaf has a leaf two levels deeper within `radius` of its sides.
      for (const Cell& a : t.leaves())
        for (const Cell& b : t.leaves()) {
          if (b.level <= a.level + 1) continue;
          bool near = true;
          for (int d = 0; d < 3; ++d)
            near = near && b.lo[d] < a.hi()[d] + radius * a.side && a.lo[d] - radius * a.side < b.hi()[d];
          EXPECT_FALSE(near) << c.name << " radius " << radius;
        }
      ++trees;
      still_failing += TSpline(t).partition_of_unity_error() > kTol;
    }
  }
  std::printf("graded balance (radius 1, 2): %d of %d trees still have Σ N != 1\n", still_failing, trees);
  EXPECT_GT(still_failing, 0);
}

TEST(Suitable, TypedErrors) {
  Octree t(octree::OctreeParams{3});
  EXPECT_THROW(make_partition_of_unity(t, {SuitableRule::slab, 3}), core::InvalidInputError);
  EXPECT_THROW(make_partition_of_unity(t, {SuitableRule::slab, -2}), core::InvalidInputError);
  EXPECT_THROW(make_partition_of_unity(t, {SuitableRule::slab, -1, 0.0}), core::InvalidInputError);
  EXPECT_THROW(slab_closure(t, 3), core::InvalidInputError);
  EXPECT_THROW(balance_neighbourhood(t, 0), core::InvalidInputError);
  EXPECT_THROW(repair_partition_of_unity(t, -1.0, 4), core::InvalidInputError);
  // Repair with no rounds allowed on a defective tree: NumericalError.
  Octree p(octree::OctreeParams{3});
  p.refine(toward_point);
  EXPECT_THROW(repair_partition_of_unity(p, kTol, 0), core::NumericalError);
}
