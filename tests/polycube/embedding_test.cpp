// The torus embedding (Liu et al. §4.2, Fig. 5(b)) and the volume map onto it (§4.3): every surface
// vertex gets one point whichever patch it is read from, the embedded surface bounds the n-gon
// annulus, and the harmonic volume map onto it has no flipped tet after untangling, so every point
// of every cube's prism has a physical image.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "classify/classify.h"
#include "core/errors.h"
#include "models/models.h"
#include "polycube/embedding.h"
#include "polycube/rings.h"
#include "ring_map_check.h"
#include "split/split.h"
#include "volmap/volmap.h"

using namespace volts;

namespace {

surface::Mesh model(const std::string& name, int resolution = 16) {
  if (name.find('.') != std::string::npos) return surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/" + name);
  models::ModelParams p;
  p.name = name;
  p.resolution = resolution;
  return models::make_model(p);
}

void check(const std::string& name, int cubes) {
  const auto m = model(name);
  split::Params sp;
  sp.torus_cubes = cubes;
  const auto d = split::split(m, classify::classify(m, {}), sp);
  const auto maps = polycube::map_patches(d, {});
  const auto e = polycube::embed_torus(d, maps);
  EXPECT_LT(e.max_mismatch, 1e-12) << name;
  test::expect_inner_side_shortest(d.layout.points, e, name);
  // Every vertex on its annulus: radius in [1, 2], height in [0, 1].
  const double inner = 1.0;
  for (const auto& p : e.points) {
    ASSERT_TRUE(std::isfinite(p[0]));
    const double r = std::hypot(p[0], p[1]);
    EXPECT_GE(r, inner - 1e-12);
    EXPECT_LE(r, 2 + 1e-12);
    EXPECT_GE(p[2], -1e-12);
    EXPECT_LE(p[2], 1 + 1e-12);
  }
  // Tets of at most 1/1000 of the volume, the polycube stage's default (a polygonal ring with
  // TetGen's default sizes kept flipped tets at its reentrant inner edges).
  volmap::Params vp;
  vp.tetgen.max_volume_rel = 1e-3;
  const auto vm = volmap::harmonic_volume_map(split::layout_mesh(d.layout, false), e.points, vp);
  EXPECT_EQ(vm.flipped_tets, 0) << name << ": " << vm.flipped_tets_before_untangling << " flipped before untangling";
  std::printf("[ info ] %s, %d cubes: %zu tets, flipped %d before untangling, %d after, min volume ratio %.3g\n", name.c_str(), cubes,
              vm.tets.size(), vm.flipped_tets_before_untangling, vm.flipped_tets, vm.min_volume_ratio);
  // Random points of every cube's prism have a physical image.
  Eigen::Vector3d lo = vm.parameter.at(0), hi = lo;
  for (const auto& p : vm.parameter) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  EXPECT_LT(e.boundary_gap, 0.01) << "chords of the round ring";
  const volmap::Locator locate(vm, 2 * e.boundary_gap / (hi - lo).norm());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int missing = 0;
  for (int i = 0; i < 2000; ++i) {
    const int k = i % cubes;
    if (!locate.physical(polycube::cell_point(e, k, {u(rng), u(rng), u(rng)}))) ++missing;
  }
  EXPECT_EQ(missing, 0) << name;
  test::expect_ring_map_one_to_one(d, e, vm, 3, cubes);
}

}  // namespace

TEST(Embedding, GeneratedTorusMapsOntoItsRing) { check("torus", 4); }
TEST(Embedding, CinolibTorusMapsOntoItsRing) { check("cinolib_torus.obj", 4); }
TEST(Embedding, SixCubesPerRing) { check("torus", 6); }

TEST(Embedding, BoxIsNotATorus) {
  const auto m = model("box", 8);
  const auto d = split::split(m, classify::classify(m, {}), {});
  EXPECT_THROW(polycube::embed_torus(d, polycube::map_patches(d, {})), core::TopologyError);
}

TEST(Embedding, FacesOfSeveralPatchesAreMergedIntoOneQuadPatch) {
  // The washer: 12 sharp rings, 4 of them at cube edges, so its cube faces hold 3 patches each.
  const auto m = model("loopycuts_mechanical08_rem.obj");
  const auto d = split::split(m, classify::classify(m, {}), {});
  const auto r = polycube::merge_face_patches(d);
  std::size_t before = 0;
  for (const auto& c : d.components)
    for (int i = 0; i < 4; ++i) before = std::max(before, c.faces[static_cast<std::size_t>(i)].patches.size());
  ASSERT_GT(before, 1u);
  std::vector<int> covered(r.layout.triangles.size(), 0);
  for (const auto& c : r.components)
    for (int i = 0; i < 4; ++i) {
      const auto& f = c.faces[static_cast<std::size_t>(i)];
      ASSERT_EQ(f.patches.size(), 1u);
      const auto& p = r.layout.patches[static_cast<std::size_t>(f.patches[0])];
      // Corners are the face's; side k runs from corner k to corner k+1; the sides close the loop.
      for (int k = 0; k < 4; ++k) {
        EXPECT_NE(std::find(f.corners.begin(), f.corners.end(), p.corners[static_cast<std::size_t>(k)]), f.corners.end());
        EXPECT_EQ(p.sides[static_cast<std::size_t>(k)].front(), p.corners[static_cast<std::size_t>(k)]);
        EXPECT_EQ(p.sides[static_cast<std::size_t>(k)].back(), p.corners[static_cast<std::size_t>((k + 1) % 4)]);
      }
      for (const int t : p.triangles) ++covered[static_cast<std::size_t>(t)];
    }
  for (std::size_t t = 0; t < covered.size(); ++t) EXPECT_EQ(covered[t], 1) << "triangle " << t;
  // The merged decomposition maps with every vertex at one point and no flipped triangle.
  polycube::PatchMapParams square;
  square.profile = "square";
  const auto sm = polycube::map_torus_surface(d, square);
  EXPECT_EQ(sm.flipped_surface_triangles, 0);
  EXPECT_LT(sm.embedding.max_mismatch, 1e-12);
}

// The washer's default volume map: untangling parks one interior vertex on another (an edge whose
// link alternates with vertices of the planar top face); collapsing that edge leaves no flat tet.
// The washer's cross section is a plus sign (Liu et al. §4.2, a union of torus primitives): the
// profile embedding makes it 5 grid cells, every sharp ring at a corner of the polygon (on a cube
// edge, not inside a face), every surface vertex on the polygon's sides, the cells' widths those
// of the part (flange and hub about 0.2 wide each, so thirds).
TEST(Embedding, WasherCrossSectionIsAPlusOfFiveCells) {
  const auto m = model("loopycuts_mechanical08_rem.obj");
  const auto c = classify::classify(m, {});
  const auto d = split::split(m, c, {});
  std::string why;
  const auto e = polycube::embed_profile_ring(d, polycube::map_patches(d, {}), why);
  ASSERT_TRUE(e) << why;
  const auto& pr = e->profile;
  EXPECT_EQ(pr.concave_corners, 4);
  ASSERT_EQ(pr.polygon.size(), 12u);
  ASSERT_EQ(pr.b.size(), 4u);
  ASSERT_EQ(pr.c.size(), 4u);
  for (int k = 1; k < 3; ++k) {
    EXPECT_NEAR(pr.b[static_cast<std::size_t>(k)], k / 3.0, 0.03);
    EXPECT_NEAR(pr.c[static_cast<std::size_t>(k)], k / 3.0, 0.03);
  }
  std::set<std::array<int, 2>> cells(pr.cells.begin(), pr.cells.end());
  EXPECT_EQ(cells, (std::set<std::array<int, 2>>{{1, 0}, {0, 1}, {1, 1}, {2, 1}, {1, 2}}));
  EXPECT_LT(e->max_mismatch, 1e-12);
  // (b, c) of every embedded vertex; on a side of the polygon, and at a corner if on a sharp curve.
  auto bc = [&](const std::array<double, 3>& p) {
    return std::array<double, 2>{std::hypot(p[0], p[1]) - 1, e->mirrored ? 1 - p[2] : p[2]};
  };
  auto distance_to = [&](const std::array<double, 2>& x, bool corners_only) {
    double best = HUGE_VAL;
    for (std::size_t i = 0; i < pr.polygon.size(); ++i) {
      const auto &p = pr.polygon[i], &q = pr.polygon[(i + 1) % pr.polygon.size()];
      if (corners_only) {
        best = std::min(best, std::hypot(x[0] - p[0], x[1] - p[1]));
        continue;
      }
      const double t = std::clamp(((x[0] - p[0]) * (q[0] - p[0]) + (x[1] - p[1]) * (q[1] - p[1])) /
                                       ((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1])), 0.0, 1.0);
      best = std::min(best, std::hypot(x[0] - p[0] - t * (q[0] - p[0]), x[1] - p[1] - t * (q[1] - p[1])));
    }
    return best;
  };
  double off_side = 0, off_corner = 0;
  for (const auto& p : e->points) off_side = std::max(off_side, distance_to(bc(p), false));
  int sharp = 0;
  for (const auto& curve : c.curves)  // input vertex ids are layout ids
    for (const int v : curve.vertices) ++sharp, off_corner = std::max(off_corner, distance_to(bc(e->points.at(static_cast<std::size_t>(v))), true));
  EXPECT_LT(off_side, 1e-12);
  EXPECT_EQ(c.curves.size(), 12u);
  EXPECT_GE(sharp, 12 * 60);
  EXPECT_LT(off_corner, 1e-12);
  // Not a plus: a smooth torus has no concave corner and keeps the square.
  const auto t = model("torus");
  const auto dt = split::split(t, classify::classify(t, {}), {});
  EXPECT_FALSE(polycube::embed_profile_ring(dt, polycube::map_patches(dt, {}), why));
  EXPECT_TRUE(polycube::map_torus_surface(dt, {}).embedding.profile.empty());
}

TEST(Embedding, WasherVolumeMapIsOneToOne) {
  const auto m = model("loopycuts_mechanical08_rem.obj");
  const auto d = split::split(m, classify::classify(m, {}), {});
  const auto sm = polycube::map_torus_surface(d, {});
  ASSERT_EQ(sm.flipped_surface_triangles, 0);
  const auto vm = polycube::torus_volume_map(d, sm, {});
  std::printf("[ info ] washer: %zu tets, flipped %d before untangling, %d after, %d edges collapsed, min volume ratio %.3g\n",
              vm.tets.size(), vm.flipped_tets_before_untangling, vm.flipped_tets, vm.collapsed_edges, vm.min_volume_ratio);
  test::expect_ring_map_one_to_one(d, sm.embedding, vm, 5);
}

// Sharp curves inside faces on straight lines (PatchMapParams::sharp_lines): the washer's faces
// are strips of three patches; the two curves between them land on one height across the face in
// every cube, so tmesh can make them C0 block faces.
TEST(Embedding, WasherSharpCurvesInsideFacesLieOnStraightLines) {
  const auto m = model("loopycuts_mechanical08_rem.obj");
  const auto d = split::split(m, classify::classify(m, {}), {});
  auto on_lines = [&](const polycube::TorusSurfaceMap& sm, const std::array<std::vector<double>, 3>& cuts) {
    int n = 0;
    for (const auto& p : sm.embedding.points) {
      if (!std::isfinite(p[0])) continue;
      const double b = std::hypot(p[0], p[1]) - 1, c = sm.embedding.mirrored ? 1 - p[2] : p[2];
      const bool on_c_face = std::abs(c) < 1e-12 || std::abs(c - 1) < 1e-12, on_b_face = std::abs(b) < 1e-12 || std::abs(b - 1) < 1e-12;
      bool hit = false;
      for (double u : cuts[1]) hit = hit || (on_c_face && std::abs(b - u) < 1e-12);
      for (double u : cuts[2]) hit = hit || (on_b_face && std::abs(c - u) < 1e-12);
      n += hit;
    }
    return n;
  };
  polycube::PatchMapParams pp;
  pp.sharp_lines = true;
  pp.profile = "square";
  const auto sm = polycube::map_torus_surface(d, pp);
  EXPECT_EQ(sm.flipped_surface_triangles, 0);
  EXPECT_LT(sm.embedding.max_mismatch, 1e-12);
  EXPECT_TRUE(sm.cuts[0].empty());
  for (int axis = 1; axis < 3; ++axis) {
    ASSERT_EQ(sm.cuts[static_cast<std::size_t>(axis)].size(), 2u) << axis;
    for (double u : sm.cuts[static_cast<std::size_t>(axis)]) {
      EXPECT_GT(u, 0.05);
      EXPECT_LT(u, 0.95);
    }
  }
  // The 8 sharp rings inside faces have 61 edges each on the input mesh (more vertices after split's cuts).
  const int straight = on_lines(sm, sm.cuts);
  EXPECT_GE(straight, 8 * 61);
  // Off, the same heights hold (almost) no vertex: the lines are the straightening's doing.
  pp.sharp_lines = false;
  const auto merged = polycube::map_torus_surface(d, pp);
  EXPECT_TRUE(merged.cuts[1].empty() && merged.cuts[2].empty());
  EXPECT_LT(on_lines(merged, sm.cuts), straight / 10);
}
