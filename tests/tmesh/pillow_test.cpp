// Pillowing (Liu et al. §5.2, Fig. 9) and the block-structured control mesh: the blocks tile the
// cube, no element has two faces on the surface, shared control points have one id and one
// position, affine maps are reproduced, and the pillow removes the degenerate elements along cube
// edges that a map flattens (a cube onto a solid cylinder, Fig. 9(a-b)).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "core/errors.h"
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

// Every block has positive Jacobian; pillowed, a slab has exactly one surface face and a core
// block none. Returns the blocks' total volume.
double check_blocks(const std::vector<tmesh::Block>& blocks, bool pillowed) {
  double total = 0;
  for (const auto& b : blocks) {
    double min_det = 0;
    total += block_volume(b.corners, &min_det);
    EXPECT_GT(min_det, 0);
    int on = 0;
    for (const int x : b.boundary) on += x;
    if (pillowed) {
      EXPECT_EQ(on, b.pillow ? 1 : 0);
    }
    for (const int n : b.elements) EXPECT_GE(n, 1);
  }
  return total;
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
      EXPECT_NEAR(check_blocks(blocks, true), 1.0, 1e-9);
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

namespace {

// Every block face is either on the surface (flagged, and no other block's face) or the whole face
// of exactly one other block with the same element count along each of its edges. Returns the
// total area of the flagged faces.
double check_conforming(const std::vector<tmesh::Block>& blocks) {
  using Key = std::array<std::array<long long, 3>, 4>;
  auto round = [](const Vec3& p) {
    return std::array<long long, 3>{std::llround(p[0] * 1e9), std::llround(p[1] * 1e9), std::llround(p[2] * 1e9)};
  };
  struct Seen {
    int count = 0, boundary = 0;
    std::map<std::pair<std::array<long long, 3>, std::array<long long, 3>>, int> edges;
  };
  std::map<Key, Seen> faces;
  double area = 0;
  for (const auto& b : blocks)
    for (int a = 0; a < 3; ++a)
      for (int s = 0; s < 2; ++s) {
        const int u = (a + 1) % 3, v = (a + 2) % 3;
        std::array<std::array<long long, 3>, 4> c;  // corners (0,0), (1,0), (0,1), (1,1) in (u, v)
        std::array<Vec3, 4> x;
        for (int k = 0; k < 4; ++k) {
          const int i = (s << a) | ((k & 1) << u) | ((k >> 1) << v);
          x[static_cast<std::size_t>(k)] = b.corners[static_cast<std::size_t>(i)];
          c[static_cast<std::size_t>(k)] = round(x[static_cast<std::size_t>(k)]);
        }
        Key key = c;
        std::sort(key.begin(), key.end());
        Seen& f = faces[key];
        ++f.count;
        f.boundary += b.boundary[static_cast<std::size_t>(2 * a + s)];
        auto edge = [&](int p, int q, int n) {
          auto e = std::minmax(c[static_cast<std::size_t>(p)], c[static_cast<std::size_t>(q)]);
          const auto [it, fresh] = f.edges.emplace(std::make_pair(e.first, e.second), n);
          EXPECT_TRUE(fresh || it->second == n) << "element counts differ across a shared face";
        };
        edge(0, 1, b.elements[static_cast<std::size_t>(u)]), edge(2, 3, b.elements[static_cast<std::size_t>(u)]);
        edge(0, 2, b.elements[static_cast<std::size_t>(v)]), edge(1, 3, b.elements[static_cast<std::size_t>(v)]);
        if (b.boundary[static_cast<std::size_t>(2 * a + s)]) {  // planar quads here: |diagonal cross product| / 2
          Vec3 d1, d2;
          for (int k = 0; k < 3; ++k) d1[k] = x[3][k] - x[0][k], d2[k] = x[2][k] - x[1][k];
          area += 0.5 * std::sqrt(std::pow(d1[1] * d2[2] - d1[2] * d2[1], 2) + std::pow(d1[2] * d2[0] - d1[0] * d2[2], 2) +
                                  std::pow(d1[0] * d2[1] - d1[1] * d2[0], 2));
        }
      }
  for (const auto& [key, f] : faces) {
    if (f.boundary) {
      EXPECT_EQ(f.count, 1) << "a surface face shared by another block";
    } else {
      EXPECT_EQ(f.count, 2) << "an inner face that is not the whole face of exactly one other block";
    }
  }
  return area;
}

}  // namespace

// A cube minus a through hole (Liu et al. §4.2 difference; §5.2 pillow around virtual cylinders):
// the blocks tile the cube minus the hole with positive Jacobian, conform face to face, their
// surface faces cover the solid's boundary once, and with a pillow no block has two surface faces.
TEST(Pillow, DifferenceBlocksTileTheCubeMinusTheHoleConformingly) {
  for (int axis = 0; axis < 3; ++axis)
    for (int layers = 0; layers <= 2; ++layers) {
      SCOPED_TRACE("axis " + std::to_string(axis) + ", layers " + std::to_string(layers));
      Vec3 lo{0.3, 0.25, 0.4}, hi{0.6, 0.7, 0.55};
      lo[static_cast<std::size_t>(axis)] = 0, hi[static_cast<std::size_t>(axis)] = 1;
      const auto blocks = tmesh::difference_blocks(axis, lo, hi, 16, layers);
      EXPECT_EQ(blocks.size(), layers ? 40u : 8u);
      const double volume = check_blocks(blocks, layers > 0);
      const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      const double wx = hi[a1] - lo[a1], wy = hi[a2] - lo[a2];
      EXPECT_NEAR(volume, 1 - wx * wy, 1e-9);
      EXPECT_NEAR(check_conforming(blocks), 4 + 2 * (1 - wx * wy) + 2 * (wx + wy), 1e-9) << "surface faces: 4 sides, 2 annuli, 4 walls";
    }
  // The single cube's pillow conforms too.
  EXPECT_NEAR(check_conforming(tmesh::cube_blocks({1, 1, 1, 1, 1, 1}, {4, 5, 6}, 1)), 6.0, 1e-9);
  // A hole too close to the side for the pillow, or not through the cube, is refused.
  EXPECT_THROW(tmesh::difference_blocks(2, {0.05, 0.3, 0}, {0.5, 0.6, 1}, 8, 1), core::TopologyError);
  EXPECT_THROW(tmesh::difference_blocks(2, {0.3, 0.3, 0.1}, {0.6, 0.6, 1}, 8, 1), core::TopologyError);
}
