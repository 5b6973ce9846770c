// Tests of h-refinement by knot insertion (tmesh.h h_refine): the refined T-mesh is the same
// spline — every block evaluates alike, every fine element is a piece of its parent with the same
// scaled Jacobian — on eight times the elements, its T-junctions still on their rows and its basis
// a partition of unity. The family: rings of 3–5 cubes of mixed levels, before and after the
// optimizer has moved their nodes.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "bezier/bezier_hex.h"
#include "bezier/bspline.h"
#include "core/errors.h"
#include "extract/extract.h"
#include "ring_cubes.h"
#include "tmesh/optimize.h"
#include "tmesh/pillow.h"
#include "tmesh/tmesh.h"

using namespace volts;
using namespace volts::test;

namespace {

// A ring whose inside is pushed along it (a map no spline reproduces, elements sheared), so the
// refined nets are not the coarse ones' linear interpolation.
tmesh::PolycubeMaps sheared_ring(int k) {
  tmesh::PolycubeMaps maps = ring(k);
  maps.physical = [k](int c, const Vec3& abh) {
    const double t = -2 * kPi * (c + abh[0]) / k, r = kInner + (kOuter - kInner) * abh[1];
    const double shift = 0.4 * 16 * abh[1] * (1 - abh[1]) * abh[2] * (1 - abh[2]) * std::sin(2 * t) / r;
    return Vec3{r * std::cos(t + shift), r * std::sin(t + shift), abh[2]};
  };
  return maps;
}

// A ring of k sectors whose section is a plus of five cells (tmesh::profile_blocks: the pillow
// wraps the section's concave edges through the centre cell's cut columns), bent as ring_point.
tmesh::PolycubeMaps plus_ring(int k, int elements) {
  const std::vector<std::array<int, 2>> cells = {{1, 1}, {0, 1}, {2, 1}, {1, 0}, {1, 2}};
  const auto blocks = tmesh::profile_blocks(cells, elements, 1);
  tmesh::PolycubeMaps m;
  for (int s = 0; s < k; ++s)
    for (std::size_t c = 0; c < cells.size(); ++c) m.boundary.push_back({0, 0, 0, 0, 0, 0}), m.blocks.push_back(blocks[c]);
  m.physical = m.polycube = [k, cells](int cube, const Vec3& x) {
    const auto& cell = cells[static_cast<std::size_t>(cube) % cells.size()];
    return ring_point(k, cube / static_cast<int>(cells.size()), {x[0], (cell[0] + x[1]) / 3, (cell[1] + x[2]) / 3});
  };
  return m;
}

// Every block's spans split `split` times along every axis (plain h-refinement).
std::vector<tmesh::SpanSplits> uniform_splits(const std::vector<tmesh::TMesh>& ts, int split) {
  std::vector<tmesh::SpanSplits> out(ts.size());
  for (std::size_t b = 0; b < ts.size(); ++b)
    for (std::size_t a = 0; a < 3; ++a) out[b][a].assign(bezier::element_intervals(ts[b].knots[a], ts[b].degree).size(), split);
  return out;
}

// Checks that `fine` is `coarse` h-refined `times` times with its spans split as `splits` says
// (parent: fine element -> coarse one); every `stride`-th fine element is compared with its parent
// point by point.
void expect_same_spline(const std::vector<tmesh::TMesh>& coarse, const std::vector<tmesh::TMesh>& fine, int times,
                        const std::vector<tmesh::SpanSplits>& splits, const std::vector<int>& parent, std::size_t stride = 1) {
  ASSERT_EQ(fine.size(), coarse.size());
  ASSERT_EQ(splits.size(), coarse.size());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  double gap = 0, scale = 0;
  std::vector<std::array<int, 3>> split_of;  // per coarse element, its splits along each axis
  for (std::size_t b = 0; b < coarse.size(); ++b) {
    EXPECT_EQ(fine[b].level, coarse[b].level + times);
    int children = 0;
    const auto& sp = splits[b];
    for (std::size_t k = 0; k < sp[2].size(); ++k)
      for (std::size_t j = 0; j < sp[1].size(); ++j)
        for (std::size_t i = 0; i < sp[0].size(); ++i) children += sp[0][i] * sp[1][j] * sp[2][k], split_of.push_back({sp[0][i], sp[1][j], sp[2][k]});
    EXPECT_EQ(fine[b].elements(), children);
    for (int s = 0; s < 40; ++s) {
      const Eigen::Vector3d x(u(rng), u(rng), u(rng));
      const Eigen::Vector3d a = bezier::evaluate(volume(coarse[b]), x), c = bezier::evaluate(volume(fine[b]), x);
      gap = std::max(gap, (a - c).norm()), scale = std::max(scale, a.norm());
    }
  }
  EXPECT_LE(gap, 1e-12 * scale) << "the refined blocks are another spline";
  // Every fine element is a piece of its parent: each of its corners is a point of the parent's
  // grid of local parameters k / split, where both have the same scaled Jacobian (it does not see
  // the parameters' scale).
  const auto hc = hexes(coarse), hf = hexes(fine);
  ASSERT_EQ(parent.size(), hf.size());
  ASSERT_EQ(split_of.size(), hc.size());
  std::vector<int> children(hc.size(), 0);
  double sj_gap = 0;
  for (std::size_t e = 0; e < hf.size(); ++e) {
    const int p = parent[e];
    ASSERT_GE(p, 0);
    ASSERT_LT(static_cast<std::size_t>(p), hc.size());
    ++children[static_cast<std::size_t>(p)];
    if (e % stride) continue;
    const std::array<int, 3> sp = split_of[static_cast<std::size_t>(p)];
    for (int corner = 0; corner < 8; ++corner) {
      Eigen::Matrix3d Jf;
      const Eigen::Vector3d y = bezier::evaluate(hf[e], Eigen::Vector3d(corner & 1, (corner >> 1) & 1, corner >> 2), &Jf);
      double best = std::numeric_limits<double>::infinity(), best_sj = 0;
      for (int i = 0; i <= sp[0]; ++i)
        for (int j = 0; j <= sp[1]; ++j)
          for (int k = 0; k <= sp[2]; ++k) {
            Eigen::Matrix3d Jc;
            const Eigen::Vector3d z = bezier::evaluate(hc[static_cast<std::size_t>(p)], Eigen::Vector3d(double(i) / sp[0], double(j) / sp[1], double(k) / sp[2]), &Jc);
            if ((z - y).norm() < best) best = (z - y).norm(), best_sj = bezier::scaled_jacobian(Jc);
          }
      EXPECT_LE(best, 1e-12 * scale) << "fine element " << e << " is not in its parent " << p;
      sj_gap = std::max(sj_gap, std::abs(best_sj - bezier::scaled_jacobian(Jf)));
    }
  }
  EXPECT_LE(sj_gap, 1e-9);
  for (std::size_t e = 0; e < hc.size(); ++e) EXPECT_EQ(children[e], split_of[e][0] * split_of[e][1] * split_of[e][2]);
  // T-junctions on their rows (global_basis checks each, 1e-12) and a partition of unity.
  const extract::GlobalBasis g = extract::global_basis(fine, hf);
  EXPECT_LE(g.partition_of_unity_error, 1e-12);
}

}  // namespace

TEST(HRefine, TheRefinedTMeshIsTheSameSplineOnEightTimesTheElements) {
  for (int k = 3; k <= 5; ++k) {
    SCOPED_TRACE("ring of " + std::to_string(k) + " cubes");
    const tmesh::PolycubeMaps maps = sheared_ring(k);
    tmesh::Params p;
    p.level = 1;
    std::vector<int> levels;
    for (int c = 0; c < k; ++c) levels.push_back(1 + c % 2);  // T-junctions between cubes and between slabs and cores
    const auto coarse = tmesh::build(maps, p, levels);
    std::vector<int> parent;
    const auto fine = tmesh::h_refine(maps, p, coarse, 1, &parent);
    expect_same_spline(coarse, fine, 1, uniform_splits(coarse, 2), parent);
    const tmesh::NodeCounts nc = tmesh::count_nodes(coarse), nf = tmesh::count_nodes(fine);
    EXPECT_GT(nf.t_junctions, nc.t_junctions);
    EXPECT_GT(nf.nodes - nf.t_junctions, nc.nodes - nc.t_junctions) << "refinement adds functions";
  }
}

// After the optimizer moved nodes (and T-junctions with them), twice refined.
TEST(HRefine, RefinesTheOptimizedSplineTwice) {
  const tmesh::PolycubeMaps maps = sheared_ring(4);
  tmesh::Params p;
  p.level = 1;
  auto ts = tmesh::build(maps, p, {1, 2, 1, 2});
  const auto start = ts;
  const tmesh::OptimizeResult r = tmesh::optimize(ts, test::running_rounds(1, 30));
  ASSERT_GT(r.nodes_moved + r.joint_rounds, 0);
  double moved = 0;
  for (std::size_t b = 0; b < ts.size(); ++b)
    for (std::size_t i = 0; i < ts[b].control_points.size(); ++i)
      for (int d = 0; d < 3; ++d) moved = std::max(moved, std::abs(ts[b].control_points[i][static_cast<std::size_t>(d)] - start[b].control_points[i][static_cast<std::size_t>(d)]));
  ASSERT_GT(moved, 1e-6) << "the optimizer moved nothing: the test would not see moved nodes";
  std::vector<int> parent;
  const auto fine = tmesh::h_refine(maps, p, ts, 2, &parent);
  expect_same_spline(ts, fine, 2, uniform_splits(ts, 4), parent, 13);
  // Stage-file round trip of the refined T-mesh (its rows are checked on reading).
  for (const auto& t : fine) EXPECT_NO_THROW(tmesh::from_json(tmesh::to_json(t), "refined"));
}

// The stage's "before" figure: each element split in 2^h per direction on the unrefined blocks
// gives the refined net's worst trilinear hex (the same spline at the same corners) without
// building it; rings of 3-5 sheared cubes of mixed levels, once and twice refined.
TEST(HRefine, SplitElementsGiveTheRefinedNetsTrilinearFigure) {
  for (int k = 3; k <= 5; ++k)
    for (int times = 1; times <= 2; ++times) {
      SCOPED_TRACE("ring of " + std::to_string(k) + " cubes, h_refine " + std::to_string(times));
      const tmesh::PolycubeMaps maps = sheared_ring(k);
      tmesh::Params p;
      p.level = 1;
      std::vector<int> levels;
      for (int c = 0; c < k; ++c) levels.push_back(1 + c % 2);
      const auto coarse = tmesh::build(maps, p, levels);
      const auto fine = tmesh::h_refine(maps, p, coarse, times);
      double split = std::numeric_limits<double>::infinity(), refined = split, unsplit = split;
      for (const auto& t : coarse) split = std::min(split, tmesh::min_element_scaled_jacobian(t, times)), unsplit = std::min(unsplit, tmesh::min_element_scaled_jacobian(t));
      for (const auto& t : fine) refined = std::min(refined, tmesh::min_element_scaled_jacobian(t));
      EXPECT_NEAR(split, refined, 1e-12);
      EXPECT_NE(split, unsplit) << "the split changes nothing on this family: the test would not see a missing split";
    }
  tmesh::Params p;
  p.level = 1;
  const auto ts = tmesh::build(sheared_ring(3), p, {1, 1, 1});
  EXPECT_THROW(tmesh::min_element_scaled_jacobian(ts.front(), 4), core::ConfigError);
  EXPECT_THROW(tmesh::min_element_scaled_jacobian(ts.front(), -1), core::ConfigError);
}

TEST(HRefine, RefusesWhatIsNotTheRefinementOfItsPolycube) {
  const tmesh::PolycubeMaps maps = sheared_ring(4);
  tmesh::Params p;
  p.level = 2;
  const auto ts = tmesh::build(maps, p, {2, 3, 2, 3});
  std::vector<int> parent;
  const auto same = tmesh::h_refine(maps, p, ts, 0, &parent);
  ASSERT_EQ(same.size(), ts.size());
  for (std::size_t b = 0; b < ts.size(); ++b) EXPECT_EQ(same[b].control_points, ts[b].control_points);
  EXPECT_EQ(static_cast<int>(parent.size()), [&] {
    int n = 0;
    for (const auto& t : ts) n += t.elements();
    return n;
  }());
  EXPECT_THROW(tmesh::h_refine(maps, p, ts, 4), core::ConfigError);
  EXPECT_THROW(tmesh::h_refine(maps, p, ts, -1), core::ConfigError);
  auto fewer = ts;
  fewer.pop_back();
  EXPECT_THROW(tmesh::h_refine(maps, p, fewer, 1), core::InvalidInputError);
  auto other_cube = ts;
  other_cube[0].corners[7] = {0.5, 0.5, 0.5};
  EXPECT_THROW(tmesh::h_refine(maps, p, other_cube, 1), core::InvalidInputError);
  // A node moved in one block only: the blocks part (not C0), which refinement must not hide.
  auto cracked = ts;
  for (std::size_t i = 0; i < cracked[0].control_points.size(); ++i) {
    const int id = cracked[0].function_ids[i];
    bool shared = false;
    for (std::size_t b = 1; b < cracked.size(); ++b)
      for (const int other : cracked[b].function_ids) shared = shared || other == id;
    if (!shared) continue;
    cracked[0].control_points[i][2] += 1e-3;
    break;
  }
  EXPECT_THROW(tmesh::h_refine(maps, p, cracked, 1), core::NumericalError);
}

// Boundary layers (tmesh.pillow_splits): the pillow slabs' spans across the surface split k more
// times, nothing else — the same spline, conforming, a partition of unity; rings of 3-5 sheared
// cubes of mixed levels (T-junctions between slabs of different levels), once refined and not.
TEST(HRefine, PillowSplitsRefineTheSlabsAcrossTheSurfaceAlone) {
  for (int k = 3; k <= 5; ++k)
    for (const int splits_across : {2, 3})
      for (const int times : {0, 1}) {
        SCOPED_TRACE("ring of " + std::to_string(k) + " cubes, pillow_splits " + std::to_string(splits_across) + ", h_refine " + std::to_string(times));
        const tmesh::PolycubeMaps maps = sheared_ring(k);
        tmesh::Params p;
        p.level = 1;
        p.pillow_splits = splits_across;
        std::vector<int> levels;
        for (int c = 0; c < k; ++c) levels.push_back(1 + c % 2);
        const auto coarse = tmesh::build(maps, p, levels);
        const auto splits = tmesh::refinement_splits(maps, p, coarse, times);
        const int base = 1 << times;
        int slabs = 0;
        for (std::size_t b = 0; b < coarse.size(); ++b) {
          int across = -1;  // the axis of the slab's surface face
          for (int f = 0; f < 6; ++f)
            if (coarse[b].boundary[static_cast<std::size_t>(f)]) across = f / 2;
          if (coarse[b].kind != "pillow") across = -1;
          slabs += across >= 0;
          for (int a = 0; a < 3; ++a)
            for (const int m : splits[b][static_cast<std::size_t>(a)]) EXPECT_EQ(m, a == across ? base * splits_across : base) << "block " << b << " axis " << a;
        }
        EXPECT_EQ(slabs, 4 * k) << "the ring's four slabs per cube";
        std::vector<int> parent;
        const auto fine = tmesh::h_refine(maps, p, coarse, times, &parent);
        expect_same_spline(coarse, fine, times, splits, parent, 3);
        // The stage's "before" figure: the coarse blocks split alike give the refined net's.
        double split = std::numeric_limits<double>::infinity(), refined = split;
        for (std::size_t b = 0; b < coarse.size(); ++b) split = std::min(split, tmesh::min_element_scaled_jacobian(coarse[b], splits[b]));
        for (const auto& t : fine) refined = std::min(refined, tmesh::min_element_scaled_jacobian(t));
        EXPECT_NEAR(split, refined, 1e-12);
        for (const auto& t : fine) EXPECT_NO_THROW(tmesh::from_json(tmesh::to_json(t), "split"));
      }
}

// Where the pillow wraps a concave edge of a plus-shaped section, the layer runs on through the
// centre cell's columns, which are no slabs: they are split too, and every face two refined
// blocks share carries the same control points on both sides (checked here by position,
// independently of h_refine's own check).
TEST(HRefine, PillowSplitsFollowTheLayerAroundConcaveEdges) {
  const tmesh::PolycubeMaps maps = plus_ring(3, 2);
  tmesh::Params p;
  p.level = 1;
  p.pillow_splits = 2;
  const auto coarse = tmesh::build(maps, p, std::vector<int>(maps.blocks.size(), 1));
  const auto splits = tmesh::refinement_splits(maps, p, coarse, 1);
  int wrapped = 0;  // blocks that are no slab but carry the layer
  for (std::size_t b = 0; b < coarse.size(); ++b) {
    bool any = false;
    for (const auto& axis : splits[b])
      for (const int m : axis) {
        EXPECT_TRUE(m == 2 || m == 4) << m;
        any = any || m == 4;
      }
    const bool slab = coarse[b].kind == "pillow" && std::any_of(coarse[b].boundary.begin(), coarse[b].boundary.end(), [](int f) { return f != 0; });
    wrapped += any && !slab;
  }
  EXPECT_GT(wrapped, 0) << "no block besides the slabs carries the layer: the plus would not test the wrap";
  std::vector<int> parent;
  const auto fine = tmesh::h_refine(maps, p, coarse, 1, &parent);
  expect_same_spline(coarse, fine, 1, splits, parent, 5);
  // Faces by their four corner points (1e-9 units): the control points on them agree.
  auto key = [](const Vec3& x) { return std::array<long long, 3>{std::llround(x[0] * 1e9), std::llround(x[1] * 1e9), std::llround(x[2] * 1e9)}; };
  std::map<std::array<std::array<long long, 3>, 4>, std::vector<std::set<std::array<long long, 3>>>> faces;
  for (const auto& t : fine)
    for (int f = 0; f < 6; ++f) {
      const int a = f / 2, u = (a + 1) % 3, v = (a + 2) % 3;
      std::array<int, 3> idx{};
      idx[static_cast<std::size_t>(a)] = f % 2 ? t.size[static_cast<std::size_t>(a)] - 1 : 0;
      std::set<std::array<long long, 3>> points;
      std::array<std::array<long long, 3>, 4> corners{};
      for (int j = 0; j < t.size[static_cast<std::size_t>(v)]; ++j)
        for (int i = 0; i < t.size[static_cast<std::size_t>(u)]; ++i) {
          idx[static_cast<std::size_t>(u)] = i, idx[static_cast<std::size_t>(v)] = j;
          const auto x = key(t.control_points[static_cast<std::size_t>(idx[0] + t.size[0] * (idx[1] + t.size[1] * idx[2]))]);
          points.insert(x);
          const bool iu = i == 0 || i == t.size[static_cast<std::size_t>(u)] - 1, jv = j == 0 || j == t.size[static_cast<std::size_t>(v)] - 1;
          if (iu && jv) corners[static_cast<std::size_t>((i > 0) + 2 * (j > 0))] = x;
        }
      std::sort(corners.begin(), corners.end());
      faces[corners].push_back(points);
    }
  int shared = 0;
  for (const auto& [corners, list] : faces)
    if (list.size() == 2) {
      ++shared;
      EXPECT_EQ(list[0], list[1]);
    }
  EXPECT_GT(shared, 100);
}

TEST(HRefine, PillowSplitsOutOfRangeOrThatCannotNestAreRefused) {
  const tmesh::PolycubeMaps maps = sheared_ring(3);
  tmesh::Params p;
  p.level = 1;
  const auto ts = tmesh::build(maps, p, {1, 1, 1});
  for (const int bad : {0, 9}) {
    p.pillow_splits = bad;
    EXPECT_THROW(tmesh::h_refine(maps, p, ts, 1), core::ConfigError) << bad;
    EXPECT_THROW(tmesh::refinement_splits(maps, p, ts, 1), core::ConfigError) << bad;
  }
  p.pillow_splits = 2;
  EXPECT_THROW(tmesh::refinement_splits(maps, p, ts, 4), core::ConfigError);
  tmesh::Params flat = p;
  flat.pillow_layers = 0;
  EXPECT_THROW(tmesh::refinement_splits(maps, flat, ts, 1), core::ConfigError);
  // A block with 3 spans along the ring where its neighbours across its faces have 2: no split
  // of both sides nests, which is refused, not written with a crack.
  auto odd = ts;
  odd[0].knots[0] = bezier::open_uniform_knots(3, odd[0].degree);
  EXPECT_THROW(tmesh::refinement_splits(maps, p, odd, 1), core::TopologyError);
  // A layer split count per span that does not fit the block's spans.
  tmesh::SpanSplits wrong;
  EXPECT_THROW(tmesh::min_element_scaled_jacobian(ts[0], wrong), core::ConfigError);
}
