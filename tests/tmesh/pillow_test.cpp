// Pillowing (Liu et al. §5.2, Fig. 9) and the block-structured control mesh: the blocks tile the
// cube, no element has two faces on the surface, shared control points have one id and one
// position, affine maps are reproduced, and the pillow removes the degenerate elements along cube
// edges that a map flattens (a cube onto a solid cylinder, Fig. 9(a-b)).
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "tmesh/pillow.h"
#include "tmesh/tmesh.h"

using namespace volts;
using tmesh::Vec3;

namespace {

// Volume of a trilinear block (Gauss–Legendre 3 points per direction; exact for trilinear maps).
double block_volume(const std::array<Vec3, 8>& c, double* min_det) {
  const double g[3] = {0.5 - std::sqrt(0.15), 0.5, 0.5 + std::sqrt(0.15)}, w[3] = {5.0 / 18, 8.0 / 18, 5.0 / 18};
  double v = 0;
  *min_det = 1e300;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        const Vec3 u{g[i], g[j], g[k]};
        double J[3][3];
        for (int a = 0; a < 3; ++a) {
          Vec3 lo = u, hi = u;
          lo[a] -= 1e-6, hi[a] += 1e-6;
          const Vec3 p = tmesh::block_point(c, hi), q = tmesh::block_point(c, lo);
          for (int d = 0; d < 3; ++d) J[d][a] = (p[d] - q[d]) / 2e-6;
        }
        const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                           J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
        *min_det = std::min(*min_det, det);
        v += w[i] * w[j] * w[k] * det;
      }
  return v;
}

// The cube's cross section (b, c) squared as a complex number: conformal except at the edge
// b = c = 0, whose 90° angle it flattens to 180° — what the polycube's volume map does at a cube
// edge on a smooth part of the surface (the torus's longitudinal cube edges).
Vec3 flattened_edge(const Vec3& abc) {
  const double u = abc[1], v = abc[2];
  return {abc[0], u * u - v * v, 2 * u * v};
}

tmesh::PolycubeMaps one_cube(const std::function<Vec3(const Vec3&)>& f, std::array<int, 6> boundary = {1, 1, 1, 1, 1, 1}) {
  tmesh::PolycubeMaps m;
  m.boundary = {boundary};
  m.physical = [f](int, const Vec3& abc) { return f(abc); };
  m.polycube = [](int, const Vec3& abc) { return abc; };
  return m;
}

double min_net_sj(const std::vector<tmesh::TMesh>& ts) {
  double s = 1;
  for (const auto& t : ts) s = std::min(s, tmesh::min_element_scaled_jacobian(t));
  return s;
}

}  // namespace

TEST(Pillow, BlocksTileTheCubeWithPositiveJacobianAndOneSurfaceFaceEach) {
  const std::array<std::array<int, 6>, 3> cases = {{{1, 1, 1, 1, 1, 1}, {0, 0, 1, 1, 1, 1}, {1, 0, 0, 1, 1, 0}}};
  for (const auto& boundary : cases)
    for (int layers = 1; layers <= 2; ++layers) {
      const auto blocks = tmesh::cube_blocks(boundary, {4, 5, 6}, layers);
      int faces = 0;
      for (const int b : boundary) faces += b;
      ASSERT_EQ(static_cast<int>(blocks.size()), 1 + faces);
      double total = 0;
      for (const auto& b : blocks) {
        double min_det = 0;
        total += block_volume(b.corners, &min_det);
        EXPECT_GT(min_det, 0);
        int on = 0;
        for (const int x : b.boundary) on += x;
        EXPECT_EQ(on, b.pillow ? 1 : 0);
      }
      EXPECT_NEAR(total, 1.0, 1e-9);
    }
}

TEST(Pillow, WithoutLayersTheCubeIsOneBlock) {
  const auto blocks = tmesh::cube_blocks({1, 1, 1, 1, 1, 1}, {3, 3, 3}, 0);
  ASSERT_EQ(blocks.size(), 1u);
  EXPECT_EQ(blocks[0].corners[7], (Vec3{1, 1, 1}));
  EXPECT_THROW(tmesh::cube_blocks({1, 1, 1, 1, 1, 1}, {3, 3, 3}, -1), std::exception);
}

TEST(Pillow, SharedControlPointsHaveOneIdAndOnePositionAndAffineMapsAreReproduced) {
  // An affine map: the spline reproduces it, so every control point is the map at its Greville point.
  auto affine = [](const Vec3& x) { return Vec3{2 * x[0] + 0.3 * x[1], x[1] - 0.2 * x[2], 0.5 * x[2] + 0.1 * x[0]}; };
  tmesh::Params p;
  p.level = 2;
  for (int layers = 0; layers <= 2; ++layers) {
    p.pillow_layers = layers;
    const auto ts = tmesh::build(one_cube(affine), p);
    std::map<int, Vec3> at;
    double err = 0;
    for (const auto& t : ts) {
      ASSERT_EQ(t.function_ids.size(), t.control_points.size());
      for (std::size_t i = 0; i < t.control_points.size(); ++i) {
        const Vec3 want = affine(tmesh::block_point(t.corners, t.parameters[i]));
        for (int d = 0; d < 3; ++d) err = std::max(err, std::abs(t.control_points[i][d] - want[d]));
        const auto [it, fresh] = at.emplace(t.function_ids[i], t.control_points[i]);
        if (!fresh) {
          EXPECT_EQ(it->second, t.control_points[i]);  // bitwise: conforming elements
        }
      }
    }
    EXPECT_LT(err, 1e-12);
    // Nodes: each block's points minus those counted twice on shared faces.
    const tmesh::NodeCounts n = tmesh::count_nodes(ts);
    EXPECT_EQ(n.nodes, static_cast<int>(at.size()));
    if (layers == 0) {
      EXPECT_EQ(n.irregular_interior, 0);
      EXPECT_EQ(n.irregular_surface, 8);  // the cube's corners: three surface neighbours
    } else {
      EXPECT_GT(n.irregular_interior, 0);  // the core's corners and edges
    }
  }
}

TEST(Pillow, PillowRemovesTheElementsDegeneratedByAFlattenedCubeEdge) {
  tmesh::Params p;
  p.level = 3;
  p.pillow_layers = 0;
  const double plain = min_net_sj(tmesh::build(one_cube(flattened_edge, {0, 0, 1, 1, 1, 1}), p));
  p.pillow_layers = 1;
  const auto pillowed = tmesh::build(one_cube(flattened_edge, {0, 0, 1, 1, 1, 1}), p);
  const double with = min_net_sj(pillowed);
  std::printf("min scaled Jacobian: plain %g, pillowed %g\n", plain, with);
  // The cube as a torus cube sees it: the a faces are cross sections, the others on the surface.
  EXPECT_LT(plain, 0.05);
  EXPECT_GT(with, 0.3);
  int elements = 0;
  for (const auto& t : pillowed) elements += t.elements();
  EXPECT_EQ(elements, 8 * 8 * 8 + 4 * 8 * 8);
}
