// The surface the joint rounds slide nodes along: closest points with their triangle's normal, and
// the distance to the nearest sharp edge (a cube's 12 edges are sharp, its face diagonals are not).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "core/errors.h"
#include "tmesh/optimize.h"
#include "tmesh/slide_surface.h"
#include "tmesh/tmesh.h"
#include "unit_cube_blocks.h"

using namespace volts;
using tmesh::Vec3;

namespace {

tmesh::SlideSurface unit_cube() {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i) v.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  // Two outward triangles per face.
  const std::vector<std::array<int, 3>> t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                             {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return tmesh::SlideSurface(v, t);
}

// The unit cube with its faces sheared within their planes: delta_i = alpha sin(pi x_i) sin^2(pi x_j)
// cos(pi x_k) for (i, j, k) cyclic. delta_i vanishes on the faces x_i = 0, 1, so every face stays
// in its plane, and all three vanish on every edge, so the edges and corners stay. The shear is
// what only sliding surface nodes can undo: interior nodes alone cannot.
Vec3 sheared(const Vec3& x, double alpha) {
  Vec3 y = x;
  for (int i = 0; i < 3; ++i) {
    const double a = x[static_cast<std::size_t>(i)], b = x[static_cast<std::size_t>((i + 1) % 3)], c = x[static_cast<std::size_t>((i + 2) % 3)];
    y[static_cast<std::size_t>(i)] += alpha * std::sin(M_PI * a) * std::pow(std::sin(M_PI * b), 2) * std::cos(M_PI * c);
  }
  return y;
}

std::vector<tmesh::TMesh> sheared_blocks(int pillow, double alpha) {
  return tmesh::testing::unit_cube_blocks([alpha](const Vec3& abc) { return sheared(abc, alpha); }, pillow);
}

// The joint rounds alone on the paper's sample (corners + Gauss points), toward a target out of
// reach: every round runs to its own stopping rule.
tmesh::OptimizeParams joint_rounds_alone() {
  tmesh::OptimizeParams op;
  op.gauss_points = 2, op.grid_points = 2, op.target = 0.99;
  op.sweeps = 1, op.max_nodes_per_sweep = 0, op.trilinear_sweeps = 0;  // no per-node moves, no trilinear pass
  return op;
}

// Which faces of the cube control point i of block t lies on (bit 2a + s), from the block's flags.
int faces_of(const tmesh::TMesh& t, std::size_t i) {
  const int n = static_cast<int>(i);
  const int idx[3] = {n % t.size[0], (n / t.size[0]) % t.size[1], n / (t.size[0] * t.size[1])};
  int faces = 0;
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s)
      if (t.boundary[static_cast<std::size_t>(2 * a + s)] && idx[a] == (s ? t.size[static_cast<std::size_t>(a)] - 1 : 0)) faces |= 1 << (2 * a + s);
  return faces;
}

}  // namespace

TEST(SlideSurface, ClosestPointsAndNormalsOfACube) {
  const tmesh::SlideSurface s = unit_cube();
  Vec3 n;
  const Vec3 c = s.closest({0.3, 0.6, 1.7}, &n);
  EXPECT_NEAR(c[0], 0.3, 1e-12);
  EXPECT_NEAR(c[1], 0.6, 1e-12);
  EXPECT_NEAR(c[2], 1.0, 1e-12);
  EXPECT_NEAR(std::abs(n[2]), 1.0, 1e-12);
  const Vec3 inside = s.closest({0.5, 0.5, 0.1});
  EXPECT_NEAR(inside[2], 0.0, 1e-12);
}

TEST(SlideSurface, OnlyTheCubesEdgesAreSharp) {
  const tmesh::SlideSurface s = unit_cube();
  EXPECT_EQ(s.sharp_edges(), 12);  // the 6 face diagonals are flat
  EXPECT_NEAR(s.sharp_distance({0.5, 0.5, 1.0}), 0.5, 1e-12);   // a face's centre: half a side from its edges
  EXPECT_NEAR(s.sharp_distance({0.3, 0.3, 1.0}), 0.3, 1e-12);   // on a diagonal, which does not count
  EXPECT_NEAR(s.sharp_distance({1.0, 0.4, 1.0}), 0.0, 1e-12);
}

TEST(SlideSurface, ClosestSharpPointsTangentsAndCornersOfACube) {
  const tmesh::SlideSurface s = unit_cube();
  EXPECT_EQ(s.sharp_corners(), 8);  // three sharp edges meet at each corner
  Vec3 t;
  const Vec3 q = s.closest_sharp({0.3, 0.5, 1.1}, &t);  // the edge x = 0, z = 1 is nearest
  EXPECT_NEAR(q[0], 0.0, 1e-12);
  EXPECT_NEAR(q[1], 0.5, 1e-12);
  EXPECT_NEAR(q[2], 1.0, 1e-12);
  EXPECT_NEAR(std::abs(t[1]), 1.0, 1e-12);
  EXPECT_NEAR(s.sharp_corner_distance({0.5, 0.5, 1.0}), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(s.sharp_corner_distance({1.0, 1.0, 0.25}), 0.25, 1e-12);
  // A closed smooth sharp loop has no corner: a prism over a regular 24-gon, open at both ends,
  // has two sharp rims (boundary edges) whose turns (15 degrees) are below the sharp angle.
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> tri;
  const int n = 24;
  for (int h = 0; h < 2; ++h)
    for (int i = 0; i < n; ++i) v.push_back({std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), double(h)});
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    tri.push_back({i, j, n + j}), tri.push_back({i, n + j, n + i});
  }
  const tmesh::SlideSurface tube(v, tri);
  EXPECT_EQ(tube.sharp_edges(), 2 * n);
  EXPECT_EQ(tube.sharp_corners(), 0);
  EXPECT_TRUE(std::isinf(tube.sharp_corner_distance({0, 0, 0.5})));
}

TEST(SlideSurface, RefusesAnEmptyMeshAndIndicesOutOfRange) {
  EXPECT_THROW(tmesh::SlideSurface({}, {}), core::InvalidInputError);
  EXPECT_THROW(tmesh::SlideSurface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 3}}), core::InvalidInputError);
}

// The joint rounds with the input surface (Liu et al. §5.2, node types): on a cube whose faces are
// sheared in their planes, over shears and with and without a pillow layer, surface nodes slide and
// stay in their face's plane, nodes on the cube's edges and corners (sharp) stay exactly where they
// are, shared nodes move together, the worst figure and the certified count never get worse, and
// without a pillow sliding ends higher than the same rounds with the surface nodes fixed. Nodes
// on the cube's edges (sharp curves) slide along them only with slide_sharp_curves, and stay on
// them; the corners (sharp corners) never move.
TEST(SlideSurface, JointRoundsSlideSurfaceNodesInTheirFacesAndKeepSharpOnes) {
  const tmesh::SlideSurface cube = unit_cube();
  EXPECT_EQ(cube.sharp_corners(), 8);
  int moved_on_edges_total = 0;
  for (const double alpha : {0.1, 0.14, 0.2})
    for (int pillow = 0; pillow <= 1; ++pillow)
      for (const bool from_start : {false, true})
        for (const bool curves : {false, true}) {
      tmesh::OptimizeParams op = joint_rounds_alone();  // the figures below were measured on it
      op.slide_from = from_start ? tmesh::OptimizeParams::SlideFrom::start : tmesh::OptimizeParams::SlideFrom::stall;
      op.slide_sharp_curves = curves;
      std::vector<tmesh::TMesh> slid = sheared_blocks(pillow, alpha), fixed = slid;
      const std::vector<tmesh::TMesh> start = slid;
      const tmesh::OptimizeResult rs = tmesh::optimize(slid, op, &cube);
      const tmesh::OptimizeResult rf = tmesh::optimize(fixed, op);
      std::printf("alpha %.2f pillow %d from %s, curves %d: worst %.4f -> sliding %.4f (%d nodes slid, %d rounds), fixed surface %.4f\n", alpha, pillow,
                  from_start ? "start" : "stall", curves ? 1 : 0, rs.min_before, rs.min_after, rs.surface_nodes_slid, rs.joint_rounds, rf.min_after);
      EXPECT_GT(rs.surface_nodes_slid, 0);
      EXPECT_GE(rs.min_after, rs.min_before);
      EXPECT_LE(rs.invalid_after, rs.invalid_before);
      // Sliding once the fixed rounds stop goes on from their result.
      if (!from_start) {
        EXPECT_GE(rs.min_after, rf.min_after);
      }
      if (pillow == 0) {
        EXPECT_GT(rs.min_after, rf.min_after + 0.03);  // what sliding is for (measured +0.035 to +0.14)
      } else {
        // Pillowed, both end at the pillow's corner elements' 1/sqrt(3) (measured 0.5764-0.5773),
        // a limit of the layout that no node move lifts: sliding must not cost more than noise.
        EXPECT_NEAR(rs.min_after, 1 / std::sqrt(3.0), 0.005);
        EXPECT_GT(rs.min_after, rf.min_after - 0.002);
      }
      std::map<int, Vec3> at;
      int moved_on_faces = 0, moved_on_edges = 0;
      for (std::size_t b = 0; b < slid.size(); ++b) {
        const tmesh::TMesh& t = slid[b];
        for (std::size_t i = 0; i < t.control_points.size(); ++i) {
          const Vec3& p = t.control_points[i];
          const Vec3& p0 = start[b].control_points[i];
          const int faces = faces_of(t, i);
          int on = 0;
          for (int f = 0; f < 6; ++f)
            if (faces >> f & 1) {
              ++on;
              // Offset from the face's plane kept (it starts at rounding level).
              EXPECT_NEAR(p[static_cast<std::size_t>(f / 2)], p0[static_cast<std::size_t>(f / 2)], 1e-12) << "left its face";
            }
          if (on == 3 || (on == 2 && !curves)) {
            EXPECT_EQ(p, p0) << "a node on a sharp corner, or on a sharp edge without slide_sharp_curves, moved";
          }
          if (on == 2) moved_on_edges += p != p0;  // on its edge: both face planes checked above
          if (on == 1) moved_on_faces += p != p0;
          const auto [it, fresh] = at.emplace(t.function_ids[i], p);
          if (!fresh) {
            EXPECT_EQ(it->second, p) << "a shared control point moved in one block only";
          }
        }
      }
      EXPECT_GT(moved_on_faces, 0);
      moved_on_edges_total += moved_on_edges;
    }
  EXPECT_GT(moved_on_edges_total, 0);  // curve sliding is not a no-op on this family
}

// OptimizeParams::sweep_slide: the per-node sweeps alone (no joint rounds) undo more of the shear
// when surface nodes slide; they stay in their faces' planes, nodes on sharp edges and corners stay.
TEST(SlideSurface, SweepsSlideSurfaceNodesWhenAsked) {
  const tmesh::SlideSurface cube = unit_cube();
  for (const double alpha : {0.1, 0.2, 0.3}) {
    tmesh::OptimizeParams op;
    op.joint_rounds = 0;
    op.gauss_points = 2;
    // The paper's sample (corners + Gauss): with a 5^3 grid as well the greedy sweeps end within
    // noise of each other (alpha 0.2: sliding 0.787, interior 0.797), which says nothing of sliding.
    op.grid_points = 2;
    op.target = 0.99;
    op.sweeps = 6;
    op.trilinear_sweeps = 0;
    std::vector<tmesh::TMesh> slid = sheared_blocks(0, alpha), fixed = slid;
    const std::vector<tmesh::TMesh> start = slid;
    op.sweep_slide = true;
    const tmesh::OptimizeResult rs = tmesh::optimize(slid, op, &cube);
    op.sweep_slide = false;
    const tmesh::OptimizeResult rf = tmesh::optimize(fixed, op, &cube);
    std::printf("alpha %.2f: worst %.4f -> sliding sweeps %.4f (%d moves slid), interior sweeps %.4f (%d slid)\n", alpha, rs.min_before,
                rs.min_after, rs.surface_nodes_slid, rf.min_after, rf.surface_nodes_slid);
    EXPECT_GT(rs.surface_nodes_slid, 0);
    EXPECT_EQ(rf.surface_nodes_slid, 0);
    // Measured: equal at alpha 0.1 (0.9159 / 0.9160), +0.008 to +0.025 from 0.14 to 0.3: greedy
    // single-node moves; the joint rounds slide further.
    EXPECT_GT(rs.min_after, rf.min_after - 0.001);
    if (alpha >= 0.2) {
      EXPECT_GT(rs.min_after, rf.min_after + 0.015);
    }
    EXPECT_EQ(rs.invalid_after, 0);
    std::map<int, Vec3> at;
    for (std::size_t b = 0; b < slid.size(); ++b)
      for (std::size_t i = 0; i < slid[b].control_points.size(); ++i) {
        const Vec3& p = slid[b].control_points[i];
        const Vec3& p0 = start[b].control_points[i];
        const int faces = faces_of(slid[b], i);
        int on = 0;
        for (int f = 0; f < 6; ++f)
          if (faces >> f & 1) {
            ++on;
            EXPECT_NEAR(p[static_cast<std::size_t>(f / 2)], p0[static_cast<std::size_t>(f / 2)], 1e-12) << "left its face";
          }
        if (on >= 2) {
          EXPECT_EQ(p, p0) << "a node on a sharp edge or corner moved";
        }
        const auto [it, fresh] = at.emplace(slid[b].function_ids[i], p);
        if (!fresh) {
          EXPECT_EQ(it->second, p) << "a shared control point moved in one block only";
        }
      }
  }
}

// OptimizeParams::slide_from = valid: with every element certified valid at the start it is
// `start` (every round slides), bit for bit; on a folded start the rounds first run with the
// surface fixed, so it need not end where `start` does, but never with more elements not
// certified valid or a lower worst figure than it started with.
TEST(SlideSurface, SlidingFromValidIsFromTheStartOnAValidStart) {
  const tmesh::SlideSurface cube = unit_cube();
  int valid_starts = 0, folded_starts = 0;
  // (alpha, pillow): two valid starts and a folded one (the folded pillowed start at 0.35 takes
  // 20 s; there `valid` ends at -0.02 as `stall` does, `start` at 0.54).
  for (const auto& [alpha, pillow] : std::vector<std::pair<double, int>>{{0.1, 0}, {0.1, 1}, {0.35, 0}}) {
      tmesh::OptimizeParams op = joint_rounds_alone();
      std::vector<tmesh::TMesh> from_valid = sheared_blocks(pillow, alpha), from_start = from_valid;
      op.slide_from = tmesh::OptimizeParams::SlideFrom::valid;
      const tmesh::OptimizeResult rv = tmesh::optimize(from_valid, op, &cube);
      op.slide_from = tmesh::OptimizeParams::SlideFrom::start;
      const tmesh::OptimizeResult rs = tmesh::optimize(from_start, op, &cube);
      std::printf("alpha %.2f pillow %d: not valid at start %d; from valid %.4f, from start %.4f\n", alpha, pillow, rv.invalid_before, rv.min_after, rs.min_after);
      EXPECT_GE(rv.min_after, rv.min_before);
      EXPECT_LE(rv.invalid_after, rv.invalid_before);
      if (rv.invalid_before == 0) {
        ++valid_starts;
        EXPECT_EQ(rv.min_after, rs.min_after);
        for (std::size_t b = 0; b < from_valid.size(); ++b) EXPECT_EQ(from_valid[b].control_points, from_start[b].control_points);
      } else {
        ++folded_starts;
      }
    }
  EXPECT_GT(valid_starts, 0);
  EXPECT_GT(folded_starts, 0);
}

// OptimizeParams::fold_retry: where sliding from `valid` leaves folds, the optimization runs again
// from the start sliding from the first round and keeps that end if it is better; that second
// run is a `start` run, bit for bit. Where the first run ends all valid, nothing runs again.
TEST(SlideSurface, FoldsLeftRunTheOptimizationAgainSlidingFromTheStart) {
  const tmesh::SlideSurface cube = unit_cube();
  // Measured (joint rounds alone, target out of reach): 0.45 unpillowed, `valid` leaves 12 folds
  // (-0.0125) and `start` 38, so the first end stays; 0.4 pillowed, both 24 folds and `start` higher
  // (-0.8898 against -0.8902), so the second is kept; 0.1 ends all valid, no second run.
  int ran = 0, kept = 0;
  for (const auto& [alpha, pillow] : std::vector<std::pair<double, int>>{{0.45, 0}, {0.4, 1}, {0.1, 0}}) {
    tmesh::OptimizeParams op = joint_rounds_alone();
    std::vector<tmesh::TMesh> once = sheared_blocks(pillow, alpha), retried = once, from_start = once;
    op.slide_from = tmesh::OptimizeParams::SlideFrom::valid;
    op.fold_retry = false;
    const tmesh::OptimizeResult r1 = tmesh::optimize(once, op, &cube);
    op.fold_retry = true;
    const tmesh::OptimizeResult r2 = tmesh::optimize(retried, op, &cube);
    op.slide_from = tmesh::OptimizeParams::SlideFrom::start;
    const tmesh::OptimizeResult rs = tmesh::optimize(from_start, op, &cube);
    std::printf("alpha %.2f pillow %d: valid once %d folds, %.4f; retried %d folds, %.4f (ran %d, kept %d); start %d folds, %.4f\n", alpha, pillow,
                r1.invalid_after, r1.min_after, r2.invalid_after, r2.min_after, r2.retry.ran ? 1 : 0, r2.retry.kept ? 1 : 0, rs.invalid_after, rs.min_after);
    EXPECT_FALSE(r1.retry.ran);
    EXPECT_FALSE(rs.retry.ran);  // nothing else to try
    EXPECT_EQ(r2.retry.ran, r1.invalid_after > 0);
    if (!r2.retry.ran) {
      for (std::size_t b = 0; b < once.size(); ++b) EXPECT_EQ(once[b].control_points, retried[b].control_points);
      continue;
    }
    // The second run is the `start` run.
    EXPECT_EQ(r2.retry.invalid_after, rs.invalid_after);
    EXPECT_EQ(r2.retry.min_after, rs.min_after);
    // The better end is kept, with its figures.
    const bool second = rs.invalid_after < r1.invalid_after || (rs.invalid_after == r1.invalid_after && rs.min_after_checked > r1.min_after_checked);
    EXPECT_EQ(r2.retry.kept, second);
    ++ran, kept += second ? 1 : 0;
    const std::vector<tmesh::TMesh>& kept = second ? from_start : once;
    for (std::size_t b = 0; b < once.size(); ++b) EXPECT_EQ(retried[b].control_points, kept[b].control_points);
    EXPECT_EQ(r2.invalid_after, std::min(r1.invalid_after, rs.invalid_after));
    EXPECT_EQ(r2.min_before, r1.min_before);
  }
  EXPECT_EQ(ran, 2);  // both ends of the choice are exercised
  EXPECT_EQ(kept, 1);
}

namespace {

// The unit sphere as a latitude-longitude mesh (poles as single vertices), outward triangles.
tmesh::SlideSurface unit_sphere(int slices, int stacks) {
  std::vector<Vec3> v{{0, 0, -1}};
  for (int i = 1; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const double th = M_PI * i / stacks, ph = 2 * M_PI * j / slices;
      v.push_back({std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), -std::cos(th)});
    }
  v.push_back({0, 0, 1});
  const int top = static_cast<int>(v.size()) - 1;
  auto at = [slices](int ring, int j) { return 1 + ring * slices + (j % slices); };
  std::vector<std::array<int, 3>> t;
  for (int j = 0; j < slices; ++j) t.push_back({0, at(0, j + 1), at(0, j)});
  for (int r = 0; r + 1 < stacks - 1; ++r)
    for (int j = 0; j < slices; ++j) t.push_back({at(r, j), at(r, j + 1), at(r + 1, j + 1)}), t.push_back({at(r, j), at(r + 1, j + 1), at(r + 1, j)});
  for (int j = 0; j < slices; ++j) t.push_back({top, at(stacks - 2, j), at(stacks - 2, j + 1)});
  return tmesh::SlideSurface(v, t);
}

// The unit cube onto the unit ball: its faces onto the sphere exactly (the usual cube-to-sphere
// map, scaled inside), so the cube's corners and edges are no features of the surface.
Vec3 ball(const Vec3& abc) {
  Vec3 c;
  for (int i = 0; i < 3; ++i) c[static_cast<std::size_t>(i)] = 2 * abc[static_cast<std::size_t>(i)] - 1;
  Vec3 y;
  for (int i = 0; i < 3; ++i) {
    const double a = c[static_cast<std::size_t>(i)], b = c[static_cast<std::size_t>((i + 1) % 3)], d = c[static_cast<std::size_t>((i + 2) % 3)];
    y[static_cast<std::size_t>(i)] = a * std::sqrt(1 - b * b / 2 - d * d / 2 + b * b * d * d / 3);
  }
  return y;
}

}  // namespace

// OptimizeParams::max_boundary_deviation on a curved surface, a ball's sphere (where a flat face
// cannot show it: sliding within a plane keeps the boundary in it). Sliding nodes stay on the
// sphere, yet the spline's boundary between them moves: on the pillowed ball (folded at the start,
// sliding once valid) the rounds without a bound take it from 1.2e-3 to 7.5e-3 of the radius.
// With a bound above the start no boundary face ends farther out than the bound (sampled on the
// guard's grid), and the rounds end as high as without it (measured 0.7694-0.7697 against 0.7695
// at 1.5-3 times the start). Unpillowed, the cube's corner elements have three faces on the
// sphere and only sliding far lifts them (every bounded round is refused): that case says nothing
// of the bound.
TEST(SlideSurface, TheDeviationBoundHoldsTheSplinesBoundaryOnACurvedSurface) {
  const tmesh::SlideSurface sphere = unit_sphere(96, 48);
  EXPECT_EQ(sphere.sharp_edges(), 0);
  const int points = 6;
  auto deviation = [&](const std::vector<tmesh::TMesh>& t) {
    const std::vector<double> d = tmesh::boundary_deviation(t, [&](const Vec3& x) {
      const Vec3 c = sphere.closest(x);
      return std::hypot(x[0] - c[0], x[1] - c[1], x[2] - c[2]);
    }, points);
    return *std::max_element(d.begin(), d.end());
  };
  tmesh::OptimizeParams op;
  op.gauss_points = 2;
  op.grid_points = 3;
  op.target = 0.99;  // out of reach: every round runs to its own stopping rule
  op.sweeps = 1;
  op.max_nodes_per_sweep = 0;  // the joint rounds alone
  op.trilinear_sweeps = 0;
  op.deviation_points = points;
  // As measured (session 41): at the default since session 42 (100) the free rounds end at 2.3
  // times the start, short of the 3x bound.
  op.joint_evaluations = 300;
  const std::vector<tmesh::TMesh> start = tmesh::testing::unit_cube_blocks(ball, 1);
  const double d0 = deviation(start);
  std::vector<tmesh::TMesh> free = start;
  const tmesh::OptimizeResult rf = tmesh::optimize(free, op, &sphere);
  const double df = deviation(free);
  EXPECT_GT(d0, 0);
  EXPECT_GT(rf.invalid_before, 0);
  EXPECT_EQ(rf.invalid_after, 0);
  for (const double times : {1.5, 2.0, 3.0}) {
    const double bound = times * d0;
    op.max_boundary_deviation = bound;
    std::vector<tmesh::TMesh> bounded = start;
    const tmesh::OptimizeResult rb = tmesh::optimize(bounded, op, &sphere);
    const double db = deviation(bounded);
    std::printf("bound %.1f x start: deviation %.3e -> bounded %.3e (worst %.4f -> %.4f, %d slid), free %.3e (worst %.4f, %d slid)\n", times, d0, db,
                rb.min_before, rb.min_after, rb.surface_nodes_slid, df, rf.min_after, rf.surface_nodes_slid);
    EXPECT_LE(db, bound * (1 + 1e-12));
    EXPECT_GT(df, bound * 1.01);  // without the bound the boundary goes past it
    EXPECT_GT(rb.surface_nodes_slid, 0);
    EXPECT_EQ(rb.invalid_after, 0);
    EXPECT_GT(rb.min_after, rf.min_after - 0.05);
  }
}

TEST(SlideSurface, TheDeviationBoundRefusesBadValues) {
  const tmesh::SlideSurface sphere = unit_sphere(24, 12);
  std::vector<tmesh::TMesh> t = tmesh::testing::unit_cube_blocks(ball, 0);
  tmesh::OptimizeParams op;
  op.max_boundary_deviation = -1;
  EXPECT_THROW(tmesh::optimize(t, op, &sphere), core::ConfigError);
  op.max_boundary_deviation = std::nan("");
  EXPECT_THROW(tmesh::optimize(t, op, &sphere), core::ConfigError);
  op.max_boundary_deviation = 0.01;
  op.deviation_points = 1;
  EXPECT_THROW(tmesh::optimize(t, op, &sphere), core::ConfigError);
}
