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

// Cuts along sharp curves inside cube faces (issue 7): the cut blocks still tile the cube with
// positive Jacobian and keep its axes, conform face to face with equal element counts, every cut
// line on a surface face is an edge between two surface faces (C0 there), and the elements along
// an axis are spread over the intervals by length.
namespace {

using Cuts = std::array<std::vector<double>, 3>;

// Jacobian matrix J[d][a] = d x_d / d u_a of the trilinear block at uvw.
std::array<std::array<double, 3>, 3> jacobian(const std::array<Vec3, 8>& c, const Vec3& uvw) {
  std::array<std::array<double, 3>, 3> J{};
  for (std::size_t i = 0; i < 8; ++i)
    for (std::size_t a = 0; a < 3; ++a) {
      double w = 1;  // derivative of corner i's weight along a
      for (std::size_t e = 0; e < 3; ++e) {
        const bool bit = (i >> e) & 1;
        w *= e == a ? (bit ? 1.0 : -1.0) : (bit ? uvw[e] : 1 - uvw[e]);
      }
      for (std::size_t d = 0; d < 3; ++d) J[d][a] += w * c[i][d];
    }
  return J;
}

double det(const std::array<std::array<double, 3>, 3>& J) {
  return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

struct BlockFace {
  std::array<Vec3, 4> x;  // corners (0,0), (1,0), (0,1), (1,1) in the face's two block directions
  std::array<int, 2> n;   // element counts along them
  int flag = 0;
  std::size_t block = 0;
};

std::vector<BlockFace> block_faces(const std::vector<tmesh::Block>& blocks) {
  std::vector<BlockFace> out;
  for (std::size_t b = 0; b < blocks.size(); ++b)
    for (std::size_t a = 0; a < 3; ++a)
      for (std::size_t s = 0; s < 2; ++s) {
        const std::size_t u = (a + 1) % 3, v = (a + 2) % 3;
        BlockFace f;
        for (std::size_t k = 0; k < 4; ++k) f.x[k] = blocks[b].corners[(s << a) | ((k & 1) << u) | ((k >> 1) << v)];
        f.n = {blocks[b].elements[u], blocks[b].elements[v]};
        f.flag = blocks[b].boundary[2 * a + s];
        f.block = b;
        out.push_back(f);
      }
  return out;
}

bool same_point(const Vec3& p, const Vec3& q) {
  return std::abs(p[0] - q[0]) < 1e-12 && std::abs(p[1] - q[1]) < 1e-12 && std::abs(p[2] - q[2]) < 1e-12;
}

// Index in g of each corner of f, or -1 where g has no such corner.
std::array<int, 4> corner_match(const BlockFace& f, const BlockFace& g) {
  std::array<int, 4> m{-1, -1, -1, -1};
  for (std::size_t k = 0; k < 4; ++k)
    for (std::size_t l = 0; l < 4; ++l)
      if (same_point(f.x[k], g.x[l])) m[k] = static_cast<int>(l);
  return m;
}

// Element count of face f along its edge between corners p and q (an edge: they differ in one bit).
int edge_count(const BlockFace& f, int p, int q) { return (p ^ q) == 1 ? f.n[0] : f.n[1]; }

// Every block face lies on the cube's boundary (then no other block has it, and it is flagged iff
// that cube face is a surface face) or is the whole face of exactly one other block, unflagged,
// with the same element counts along its edges. Returns the area of the flagged faces.
double check_cut_conformity(const std::vector<tmesh::Block>& blocks, const std::array<int, 6>& boundary) {
  const auto faces = block_faces(blocks);
  double area = 0;
  for (const BlockFace& f : faces) {
    int on_cube = -1;  // cube face 2 d + s that holds all four corners
    for (std::size_t d = 0; d < 3; ++d)
      for (int s = 0; s < 2; ++s)
        if (std::all_of(f.x.begin(), f.x.end(), [&](const Vec3& p) { return std::abs(p[d] - s) < 1e-12; })) on_cube = static_cast<int>(2 * d) + s;
    int shared = 0;
    for (const BlockFace& g : faces) {
      if (g.block == f.block) continue;
      const auto m = corner_match(f, g);
      if (std::count(m.begin(), m.end(), -1) > 0) continue;
      ++shared;
      for (const auto& [p, q] : {std::pair{0, 1}, std::pair{2, 3}, std::pair{0, 2}, std::pair{1, 3}})
        EXPECT_EQ(edge_count(f, p, q), edge_count(g, m[static_cast<std::size_t>(p)], m[static_cast<std::size_t>(q)])) << "element counts differ across a shared face";
    }
    if (on_cube >= 0) {
      EXPECT_EQ(shared, 0) << "a face on the cube's boundary shared by another block";
      EXPECT_EQ(f.flag, boundary[static_cast<std::size_t>(on_cube)]);
    } else {
      EXPECT_EQ(shared, 1) << "an inner face that is not the whole face of exactly one other block";
      EXPECT_EQ(f.flag, 0);
    }
    if (f.flag) {  // an axis-aligned rectangle on the cube face
      double a = 1;
      for (std::size_t d = 0; d < 3; ++d) {
        const double ext = std::max({f.x[0][d], f.x[1][d], f.x[2][d], f.x[3][d]}) - std::min({f.x[0][d], f.x[1][d], f.x[2][d], f.x[3][d]});
        if (ext > 1e-12) a *= ext;
      }
      area += a;
    }
  }
  return area;
}

// Number of flagged block faces with p on one of their edges.
int flagged_faces_with_edge_through(const std::vector<tmesh::Block>& blocks, const Vec3& p) {
  int n = 0;
  for (const BlockFace& f : block_faces(blocks)) {
    if (!f.flag) continue;
    bool on = false;
    for (const auto& [i, j] : {std::pair{0, 1}, std::pair{2, 3}, std::pair{0, 2}, std::pair{1, 3}}) {
      const Vec3 &a = f.x[static_cast<std::size_t>(i)], &b = f.x[static_cast<std::size_t>(j)];
      double t = 0, len2 = 0;
      for (std::size_t d = 0; d < 3; ++d) t += (p[d] - a[d]) * (b[d] - a[d]), len2 += (b[d] - a[d]) * (b[d] - a[d]);
      t = std::clamp(t / len2, 0.0, 1.0);
      double dist2 = 0;
      for (std::size_t d = 0; d < 3; ++d) dist2 += std::pow(a[d] + t * (b[d] - a[d]) - p[d], 2);
      on = on || dist2 < 1e-24;
    }
    n += on;
  }
  return n;
}

const std::array<std::array<int, 6>, 4> kBoundaries = {{{1, 1, 1, 1, 1, 1}, {0, 0, 1, 1, 1, 1}, {1, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 0}}};
const std::array<std::array<int, 3>, 2> kElements = {{{8, 8, 8}, {3, 5, 4}}};
const std::array<Cuts, 5> kCuts = {{{},                                  // none
                                    {{{}, {}, {0.3}}},                   // one on one axis
                                    {{{0.3, 0.55}, {0.4, 0.8}, {}}},     // two on two axes
                                    {{{}, {0.41, 0.43, 0.45}, {}}},      // three close ones
                                    {{{0.2, 0.4, 0.6, 0.8}, {}, {0.5}}}}};  // more intervals than elements along axis 0

std::string describe(const std::array<int, 6>& boundary, const std::array<int, 3>& elements, int layers, std::size_t cuts) {
  std::string s = "boundary";
  for (const int b : boundary) s += " " + std::to_string(b);
  return s + ", elements " + std::to_string(elements[0]) + " " + std::to_string(elements[1]) + " " + std::to_string(elements[2]) +
         ", layers " + std::to_string(layers) + ", cuts #" + std::to_string(cuts);
}

// Runs `check` on every case of the family (boundary pattern, element counts, layers, cuts), traced.
template <class Check>
void for_each_case(const Check& check) {
  for (const auto& boundary : kBoundaries)
    for (const auto& elements : kElements)
      for (int layers = 0; layers <= 2; ++layers)
        for (std::size_t c = 0; c < kCuts.size(); ++c) {
          SCOPED_TRACE(describe(boundary, elements, layers, c));
          check(boundary, elements, layers, c);
        }
}

}  // namespace

TEST(PillowCuts, CutBlocksTileTheCubeWithPositiveJacobianAndTheCubesAxes) {
  for_each_case([&](const auto& boundary, const auto& elements, int layers, std::size_t c) {
    const auto blocks = tmesh::cube_blocks(boundary, elements, layers, kCuts[c]);
    std::size_t pieces = 1;
    for (const auto& cut : kCuts[c]) pieces *= cut.size() + 1;
    EXPECT_GE(blocks.size(), pieces);
    check_blocks(blocks, layers > 0);  // pillowed: a slab has one surface face, the core none
    // Volume: 2-point Gauss–Legendre per direction, exact for the trilinear Jacobian (degree 2 per variable).
    const double g[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
    double volume = 0;
    for (const auto& b : blocks)
      for (const double x : g)
        for (const double y : g)
          for (const double z : g) volume += det(jacobian(b.corners, {x, y, z})) / 8;
    EXPECT_NEAR(volume, 1.0, 1e-12);
    for (const auto& b : blocks)
      for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 4; ++j)
          for (int k = 0; k <= 4; ++k) {
            const auto J = jacobian(b.corners, {i / 4.0, j / 4.0, k / 4.0});
            EXPECT_GT(det(J), 0);
            for (std::size_t d = 0; d < 3; ++d) EXPECT_GT(J[d][d], 0) << "a block axis not along the cube's";
          }
  });
}

TEST(PillowCuts, BlocksConformFaceToFaceAndTheSurfaceFacesCoverTheCubesSurfaceFaces) {
  for_each_case([&](const auto& boundary, const auto& elements, int layers, std::size_t c) {
    const double area = check_cut_conformity(tmesh::cube_blocks(boundary, elements, layers, kCuts[c]), boundary);
    int faces = 0;
    for (const int b : boundary) faces += b;
    EXPECT_NEAR(area, faces, 1e-12);
  });
}

TEST(PillowCuts, EveryCutLineOnASurfaceFaceIsAnEdgeBetweenTwoSurfaceFaces) {
  // The washer's case: a torus cube, a crease around it at c = 0.3 on its faces b = 0 and b = 1.
  const auto torus = tmesh::cube_blocks({0, 0, 1, 1, 1, 1}, {8, 8, 8}, 1, Cuts{{{}, {}, {0.3}}});
  for (const double a : {0.05, 0.3, 0.5, 0.77, 0.95})
    for (const double b : {0.0, 1.0}) {
      EXPECT_EQ(flagged_faces_with_edge_through(torus, {a, b, 0.3}), 2) << "a = " << a << ", b = " << b;
      EXPECT_EQ(flagged_faces_with_edge_through(torus, {a, b, 0.2}), 0) << "no edge off the cut";
    }
  // Every case: on every surface face e = s, the line x_d = u of every cut.
  const double samples[] = {0.1234, 0.3777, 0.6021, 0.8765};  // none on a cut
  for (const auto& boundary : kBoundaries)
    for (int layers = 0; layers <= 2; ++layers)
      for (std::size_t c = 0; c < kCuts.size(); ++c) {
        SCOPED_TRACE(describe(boundary, {3, 5, 4}, layers, c));
        const auto blocks = tmesh::cube_blocks(boundary, {3, 5, 4}, layers, kCuts[c]);
        for (std::size_t d = 0; d < 3; ++d)
          for (const double u : kCuts[c][d])
            for (std::size_t e = 0; e < 3; ++e)
              for (int s = 0; s < 2; ++s) {
                if (e == d || !boundary[2 * e + static_cast<std::size_t>(s)]) continue;
                const std::size_t f = 3 - d - e;
                for (const double w : samples) {
                  Vec3 p;
                  p[d] = u, p[e] = s, p[f] = w;
                  EXPECT_EQ(flagged_faces_with_edge_through(blocks, p), 2) << "cut " << u << " along axis " << d << " on face " << 2 * e + s;
                }
              }
      }
}

TEST(PillowCuts, ElementsAreSpreadOverTheIntervalsByLength) {
  // Largest remainder: 8 over 0.3 + 0.7 is 2.4 + 5.6 -> 2 + 6; 5 over four intervals of which two
  // are slivers -> one each, the rest by length.
  auto counts = [](const std::vector<tmesh::Block>& blocks, std::size_t d) {
    std::map<std::pair<long long, long long>, int> at;  // core interval along d -> elements
    for (const auto& b : blocks) {
      if (b.pillow) continue;
      const double lo = std::min(b.corners[0][d], b.corners[7][d]), hi = std::max(b.corners[0][d], b.corners[7][d]);
      const auto [it, fresh] = at.emplace(std::pair{std::llround(lo * 1e9), std::llround(hi * 1e9)}, b.elements[d]);
      EXPECT_TRUE(fresh || it->second == b.elements[d]);
    }
    std::vector<std::pair<double, int>> out;  // (length, elements) in order
    for (const auto& [k, n] : at) out.emplace_back((k.second - k.first) * 1e-9, n);
    return out;
  };
  const auto two = counts(tmesh::cube_blocks({0, 0, 0, 0, 0, 0}, {8, 8, 8}, 0, Cuts{{{0.3}, {}, {}}}), 0);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].second, 2);
  EXPECT_EQ(two[1].second, 6);
  for_each_case([&](const auto& boundary, const auto& elements, int layers, std::size_t c) {
    const auto blocks = tmesh::cube_blocks(boundary, elements, layers, kCuts[c]);
    for (std::size_t d = 0; d < 3; ++d) {
      const auto iv = counts(blocks, d);
      ASSERT_EQ(iv.size(), kCuts[c][d].size() + 1);
      double length = 0;
      int total = 0;
      for (const auto& [len, n] : iv) length += len, total += n;
      EXPECT_EQ(total, std::max(elements[d], static_cast<int>(iv.size())));
      bool every_share_one = true;
      for (const auto& [len, n] : iv) every_share_one = every_share_one && elements[d] * len / length >= 1;
      for (const auto& [len, n] : iv) {
        EXPECT_GE(n, 1);
        if (every_share_one) {
          EXPECT_LE(std::abs(n - elements[d] * len / length), 1.0);
        }
      }
      // Slabs that span d follow the core: their counts along d are among the core's.
      for (const auto& b : blocks)
        if (b.pillow && !b.boundary[2 * d] && !b.boundary[2 * d + 1]) {
          EXPECT_TRUE(std::any_of(iv.begin(), iv.end(), [&](const auto& x) { return x.second == b.elements[d]; }));
        }
    }
  });
}

TEST(PillowCuts, NoCutsGiveTheUncutBlocksAndBadCutsAreRefused) {
  for (const auto& boundary : kBoundaries)
    for (int layers = 0; layers <= 2; ++layers) {
      const auto plain = tmesh::cube_blocks(boundary, {3, 5, 4}, layers);
      const auto cut = tmesh::cube_blocks(boundary, {3, 5, 4}, layers, Cuts{});
      ASSERT_EQ(plain.size(), cut.size());
      for (std::size_t i = 0; i < plain.size(); ++i) {
        EXPECT_EQ(plain[i].corners, cut[i].corners);
        EXPECT_EQ(plain[i].elements, cut[i].elements);
        EXPECT_EQ(plain[i].boundary, cut[i].boundary);
        EXPECT_EQ(plain[i].pillow, cut[i].pillow);
      }
    }
  for (const std::vector<double>& bad : std::vector<std::vector<double>>{
           {0.0}, {1.0}, {-0.2}, {1.5}, {0.5, 0.5}, {0.6, 0.4}, {std::nan("")}, {0.5, 0.5 + 1e-9}, {1e-8}, {1 - 1e-8}})
    for (std::size_t d = 0; d < 3; ++d) {
      Cuts cuts;
      cuts[d] = bad;
      EXPECT_THROW(tmesh::cube_blocks({1, 1, 1, 1, 1, 1}, {8, 8, 8}, 1, cuts), core::ConfigError) << bad[0] << " along axis " << d;
      EXPECT_THROW(tmesh::cube_blocks({0, 0, 0, 0, 0, 0}, {8, 8, 8}, 0, cuts), core::ConfigError);
    }
}

namespace {

// Elements of the surface faces of `blocks` on cube face f that have two or more edges on that
// face's outline (the cube face's four edges).
int elements_with_two_outline_edges(const std::vector<tmesh::Block>& blocks, int f) {
  const int a = f / 2, s = f % 2, u = (a + 1) % 3, v = (a + 2) % 3;
  auto on_line = [&](const Vec3& p, const Vec3& q) {
    for (const int d : {u, v})
      for (const double x : {0.0, 1.0})
        if (std::abs(p[d] - x) < 1e-12 && std::abs(q[d] - x) < 1e-12) return true;
    return false;
  };
  int bad = 0;
  for (const auto& b : blocks) {
    if (!b.boundary[static_cast<std::size_t>(f)]) continue;
    const int nu = b.elements[static_cast<std::size_t>(u)], nv = b.elements[static_cast<std::size_t>(v)];
    auto at = [&](int i, int j) {
      Vec3 w{0, 0, 0};
      w[static_cast<std::size_t>(a)] = s, w[static_cast<std::size_t>(u)] = double(i) / nu, w[static_cast<std::size_t>(v)] = double(j) / nv;
      return tmesh::block_point(b.corners, w);
    };
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        const Vec3 p00 = at(i, j), p10 = at(i + 1, j), p01 = at(i, j + 1), p11 = at(i + 1, j + 1);
        const int edges = on_line(p00, p10) + on_line(p01, p11) + on_line(p00, p01) + on_line(p10, p11);
        bad += edges >= 2;
      }
  }
  return bad;
}

// cube_blocks with the slabs under the faces in `rimmed` replaced by their rim pillows.
std::vector<tmesh::Block> rimmed_cube(const std::array<int, 6>& boundary, const std::array<int, 3>& elements, int layers,
                                      const std::vector<int>& rimmed) {
  std::vector<tmesh::Block> out;
  for (const auto& b : tmesh::cube_blocks(boundary, elements, layers)) {
    const bool rim = b.pillow && std::any_of(rimmed.begin(), rimmed.end(), [&](int f) { return b.boundary[static_cast<std::size_t>(f)] == 1; });
    if (!rim) {
      out.push_back(b);
      continue;
    }
    for (const auto& r : tmesh::rim_pillow(b, layers)) out.push_back(r);
  }
  return out;
}

}  // namespace

// The in-plane pillow of a slab's surface face (rim_pillow): the new blocks tile the slab with
// positive Jacobian, its neighbours conform unchanged, the surface is covered once, no block has
// two surface faces, and no element of a rimmed face has two edges on the face's outline (without
// the rim, the face's four corner elements do).
TEST(RimPillow, TilesTheSlabConformsWithItsNeighboursAndRingsItsSurfaceFace) {
  const std::array<std::array<int, 6>, 2> cases = {{{1, 1, 1, 1, 1, 1}, {0, 1, 1, 0, 1, 1}}};
  for (const auto& boundary : cases)
    for (int layers = 1; layers <= 2; ++layers)
      for (const std::vector<int>& rimmed : std::vector<std::vector<int>>{{5}, {4, 5}, {1, 2, 4, 5}}) {
        SCOPED_TRACE("layers " + std::to_string(layers) + ", rimmed faces " + std::to_string(rimmed.size()) + ", boundary face 0: " +
                     std::to_string(boundary[0]));
        const std::array<int, 3> n{4, 5, 6};
        const auto plain = tmesh::cube_blocks(boundary, n, layers);
        const auto blocks = rimmed_cube(boundary, n, layers, rimmed);
        // Each rimmed slab became six blocks (core, five sheets).
        EXPECT_EQ(blocks.size(), plain.size() + 5 * rimmed.size());
        double volume = 0, area = 0;
        for (const auto& b : blocks) {
          double min_det = 0;
          volume += block_volume(b.corners, &min_det);
          EXPECT_GT(min_det, 0);
          EXPECT_LE(std::count(b.boundary.begin(), b.boundary.end(), 1), 1);
        }
        EXPECT_NEAR(volume, 1.0, 1e-9);
        if (std::count(boundary.begin(), boundary.end(), 1) == 6) {  // check_conforming: every other face shared
          area = check_conforming(blocks);
          EXPECT_NEAR(area, 6.0, 1e-9);
        }
        for (int f = 0; f < 6; ++f) {
          if (!boundary[static_cast<std::size_t>(f)]) continue;
          const bool rim = std::find(rimmed.begin(), rimmed.end(), f) != rimmed.end();
          const int plain_bad = elements_with_two_outline_edges(plain, f), bad = elements_with_two_outline_edges(blocks, f);
          EXPECT_EQ(plain_bad, 4) << "face " << f << ": a plain slab's face has four corner elements";
          EXPECT_EQ(bad, rim ? 0 : 4) << "face " << f;
        }
      }
  EXPECT_THROW(tmesh::rim_pillow(tmesh::cube_blocks({1, 1, 1, 1, 1, 1}, {3, 3, 3}, 1)[0], 1), core::InvalidInputError) << "the core has no surface face";
  EXPECT_THROW(tmesh::rim_pillow(tmesh::cube_blocks({1, 1, 1, 1, 1, 1}, {3, 3, 3}, 1)[1], 0), core::ConfigError);
}

namespace {

// The cross section (a, b) squared: faces a = 0 and b = 0 become one smooth face (their edge is
// flattened, the 3D pillow's case), and on the flat faces c = 0 and c = 1 the corner a = b = 0
// turns 180 degrees while their edges with the smooth face stay sharp (90 degrees) — the rod's
// lensed connector end on the shank's round section.
Vec3 flattened_face_corner(const Vec3& abc) {
  const double u = abc[0], v = abc[1];
  return {u * u - v * v, 2 * u * v, abc[2]};
}

}  // namespace

// On the map above the plain pillow's slabs under c = 0 and c = 1 have a corner element whose
// face turns 180 degrees (scaled Jacobian 0); their rim pillows lift those faces to the level of
// the rest of the mesh, whose worst is the 3D pillow of the flattened edge a = b = 0 (untouched).
TEST(RimPillow, LiftsTheFlattenedCornerOfAFlatFace) {
  tmesh::Params p;
  p.level = 3;
  // Worst trilinear figure over the blocks with (on_c_faces) or without a surface face c = 0 or 1.
  auto worst = [&](const std::vector<int>& rimmed, bool on_c_faces) {
    tmesh::PolycubeMaps m = one_cube(flattened_face_corner);
    m.blocks = {rimmed_cube({1, 1, 1, 1, 1, 1}, {8, 8, 8}, 1, rimmed)};
    double w = 1;
    for (const auto& t : tmesh::build(m, p))
      if ((t.boundary[4] || t.boundary[5]) == on_c_faces) w = std::min(w, tmesh::min_element_scaled_jacobian(t));
    return w;
  };
  const double plain = worst({}, true), rimmed = worst({4, 5}, true), rest = worst({}, false);
  std::printf("worst scaled Jacobian on the flat faces: plain pillow %g, rim pillow %g; elsewhere %g\n", plain, rimmed, rest);
  EXPECT_LT(plain, 0.01);
  EXPECT_GT(rimmed, 0.15);
  EXPECT_GE(rimmed, rest);
  EXPECT_EQ(worst({4, 5}, false), rest) << "the rim pillow changes nothing off the rimmed slabs";
}

// A cube minus several parallel through holes (Liu et al. 2013 Fig. 1: a plate with four bolt
// holes, a cube with four virtual cylinders and the difference operation).
namespace {

using Hole = std::array<Vec3, 2>;
using Across = std::array<double, 4>;  // x0, x1, y0, y1: a hole's extents along cube axes (axis + 1) % 3, (axis + 2) % 3

std::vector<Hole> through(int axis, const std::vector<Across>& across) {
  const auto u = static_cast<std::size_t>((axis + 1) % 3), v = static_cast<std::size_t>((axis + 2) % 3);
  std::vector<Hole> out;
  for (const Across& a : across) {
    Hole h{Vec3{0, 0, 0}, Vec3{1, 1, 1}};
    h[0][u] = a[0], h[1][u] = a[1], h[0][v] = a[2], h[1][v] = a[3];
    out.push_back(h);
  }
  return out;
}

// No gap between a wall and the next wall or side is within 1e-3 of twice a pillow thickness
// layers / (elements + 2 layers) tried below, so whether the pillow fits is never a rounding question.
struct HoleFamily {
  const char* name;
  std::vector<Across> holes;
};
const std::vector<HoleFamily> kHoleFamilies = {
    {"two side by side", {{0.15, 0.38, 0.3, 0.7}, {0.63, 0.85, 0.3, 0.7}}},
    {"two diagonal", {{0.15, 0.4, 0.15, 0.4}, {0.55, 0.85, 0.62, 0.85}}},
    {"two staggered (a wall line of one crosses the other)", {{0.22, 0.5, 0.15, 0.4}, {0.35, 0.83, 0.62, 0.85}}},
    {"four bolt holes at (+-0.3, +-0.25) around the centre",
     {{0.14, 0.26, 0.19, 0.31}, {0.74, 0.86, 0.19, 0.31}, {0.14, 0.26, 0.69, 0.81}, {0.74, 0.86, 0.69, 0.81}}},
    {"three with shared lo and hi lines", {{0.25, 0.45, 0.22, 0.4}, {0.25, 0.6, 0.63, 0.82}, {0.7, 0.83, 0.22, 0.4}}},
};

// Whether a pillow of thickness t fits: along each cross axis, every hi wall or the side 0 lies more
// than 2t below every lo wall or the side 1 above it (the core lines, moved t toward the solid, keep
// their order).
bool pillow_fits(const std::vector<Across>& holes, double t) {
  for (std::size_t d = 0; d < 2; ++d) {
    std::vector<double> up{0.0}, down{1.0};  // lines whose core line moves up (+t), down (-t)
    for (const Across& a : holes) down.push_back(a[2 * d]), up.push_back(a[2 * d + 1]);
    for (const double p : up)
      for (const double m : down)
        if (p < m && !(m - p > 2 * t)) return false;
  }
  return true;
}

// Whether the quad x lies on the solid's boundary: on a side of the cube, or on a wall of a hole
// (in the wall's plane, within its extent); never inside a hole.
bool on_solid_boundary(const std::array<Vec3, 4>& x, int axis, const std::vector<Across>& holes) {
  auto all = [&](auto pred) { return std::all_of(x.begin(), x.end(), pred); };
  for (std::size_t d = 0; d < 3; ++d)
    for (const double s : {0.0, 1.0})
      if (all([&](const Vec3& p) { return std::abs(p[d] - s) < 1e-12; })) return true;
  const std::array<std::size_t, 2> c{static_cast<std::size_t>((axis + 1) % 3), static_cast<std::size_t>((axis + 2) % 3)};
  for (const Across& a : holes)
    for (std::size_t d = 0; d < 2; ++d)
      for (std::size_t s = 0; s < 2; ++s) {
        const double wall = a[2 * d + s], lo = a[2 * (1 - d)], hi = a[2 * (1 - d) + 1];
        if (all([&](const Vec3& p) { return std::abs(p[c[d]] - wall) < 1e-12 && p[c[1 - d]] > lo - 1e-12 && p[c[1 - d]] < hi + 1e-12; }))
          return true;
      }
  return false;
}

// Exact volume of a trilinear block (2-point Gauss-Legendre per direction: det J has degree 2 per variable).
double exact_volume(const std::array<Vec3, 8>& c) {
  const double g[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
  double v = 0;
  for (const double x : g)
    for (const double y : g)
      for (const double z : g) v += det(jacobian(c, {x, y, z})) / 8;
  return v;
}

// The TopologyError message of f(), or "" if it throws none.
template <class F>
std::string topology_error(const F& f) {
  try {
    f();
  } catch (const core::TopologyError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// Conformity, the boundary flags tiling the cube's surface and the walls, at most one boundary face
// per pillowed block, the volume of the cube minus the holes, element counts by length; or, where
// the pillow does not fit between the walls, a TopologyError.
TEST(DifferenceHoles, BlocksTileTheCubeMinusTheHolesConformingly) {
  for (const HoleFamily& family : kHoleFamilies) {
    int pillowed = 0;
    for (int axis = 0; axis < 3; ++axis)
      for (int layers = 0; layers <= 2; ++layers)
        for (const int elements : {4, 8, 16, 32}) {
          SCOPED_TRACE(std::string(family.name) + ", axis " + std::to_string(axis) + ", layers " + std::to_string(layers) + ", elements " +
                       std::to_string(elements));
          const std::vector<Hole> holes = through(axis, family.holes);
          const double h = 1.0 / (elements + 2 * layers);
          if (!pillow_fits(family.holes, layers * h)) {
            EXPECT_THROW(tmesh::difference_blocks(axis, holes, elements, layers), core::TopologyError);
            continue;
          }
          pillowed += layers > 0;
          const auto blocks = tmesh::difference_blocks(axis, holes, elements, layers);
          // (a) every face flagged or the whole face of exactly one other block, same element counts.
          const double area = check_conforming(blocks);
          // (b) the flagged faces: the cube's six sides and every wall, minus the openings.
          double want_area = 6, want_volume = 1;
          for (const Across& a : family.holes) {
            const double wx = a[1] - a[0], wy = a[3] - a[2];
            want_area += 2 * (wx + wy) - 2 * wx * wy;
            want_volume -= wx * wy;
          }
          EXPECT_NEAR(area, want_area, 1e-12);
          for (const BlockFace& f : block_faces(blocks))
            if (f.flag) {
              EXPECT_TRUE(on_solid_boundary(f.x, axis, family.holes)) << "a flagged face off the boundary, of block " << f.block;
            }
          // (c) pillowed: a frustum has one boundary face, a core column none; and positive Jacobian.
          check_blocks(blocks, layers > 0);
          // (d) volume.
          double volume = 0;
          for (const auto& b : blocks) {
            const double v = exact_volume(b.corners);
            EXPECT_GT(v, 0);
            volume += v;
          }
          EXPECT_NEAR(volume, want_volume, 1e-12);
          // Element counts: a column's interval across gets its length in elements of h, rounded, at
          // least one; along the axis `elements` (the core's length is elements h). A column is a box;
          // its parameter p runs from corner 0 to corner 2^p.
          for (const auto& b : blocks) {
            if (b.pillow) continue;
            for (std::size_t p = 0; p < 3; ++p) {
              const Vec3 &o = b.corners[0], &e = b.corners[std::size_t{1} << p];
              const double len = std::sqrt(std::pow(e[0] - o[0], 2) + std::pow(e[1] - o[1], 2) + std::pow(e[2] - o[2], 2)) / h;
              const bool along = std::abs(e[static_cast<std::size_t>(axis)] - o[static_cast<std::size_t>(axis)]) > 0;
              const long want = along ? elements : std::max(1L, std::lround(len));
              EXPECT_EQ(b.elements[p], want) << "length " << len << " h" << (along ? ", along the axis" : "");
            }
          }
        }
    EXPECT_GT(pillowed, 0) << family.name << ": no pillowed case fits";
  }
}

// Element counts per cube axis: the plate of the assembly (4 x 3 x 0.5, holes of radius 0.3 at
// (+-1.5, +-1)) in its cube's parameters, with counts proportional to its sides (the pillow then
// one physical thickness). Conforming, its volume, and every block's element size along each cube
// axis 1 / (n_a + 2 layers) of that axis, where a uniform count cannot fit the pillow at all.
TEST(DifferenceHoles, ElementCountsPerAxisFitAFlatPlate) {
  const std::vector<Across> bolts = {{0.05, 0.2, 0.2 / 3, 0.8 / 3}, {0.8, 0.95, 0.2 / 3, 0.8 / 3}, {0.05, 0.2, 2.2 / 3, 2.8 / 3}, {0.8, 0.95, 2.2 / 3, 2.8 / 3}};
  const std::vector<Hole> holes = through(2, bolts);
  EXPECT_THROW(tmesh::difference_blocks(2, holes, 8, 1), core::TopologyError);  // 1/10 of 4 is wider than the 0.2 beside a hole
  for (const std::array<int, 3> n : {std::array<int, 3>{64, 48, 8}, std::array<int, 3>{96, 72, 12}}) {
    for (const int layers : {1, 2}) {
      if (2.0 * layers / (n[0] + 2 * layers) >= 0.05) {  // two pillows in the 0.05 beside a hole
        EXPECT_THROW(tmesh::difference_blocks(2, holes, n, layers), core::TopologyError);
        continue;
      }
      SCOPED_TRACE("counts " + std::to_string(n[0]) + " " + std::to_string(n[1]) + " " + std::to_string(n[2]) + ", layers " + std::to_string(layers));
      const auto blocks = tmesh::difference_blocks(2, holes, n, layers);
      check_conforming(blocks);
      check_blocks(blocks, true);
      double volume = 0;
      for (const auto& b : blocks) volume += exact_volume(b.corners);
      double want = 1;
      for (const Across& a : bolts) want -= (a[1] - a[0]) * (a[3] - a[2]);
      EXPECT_NEAR(volume, want, 1e-12);
      // Columns are boxes: along cube axis a their length in elements of 1 / (n_a + 2 layers),
      // rounded (at least one), and n_2 along the holes.
      for (const auto& b : blocks) {
        if (b.pillow) continue;
        for (std::size_t p = 0; p < 3; ++p) {
          const Vec3 &o = b.corners[0], &e = b.corners[std::size_t{1} << p];
          const double len = std::abs(e[p] - o[p]) * (n[p] + 2 * layers);
          EXPECT_EQ(b.elements[p], p == 2 ? n[2] : std::max(1L, std::lround(len))) << "axis " << p << ", length " << len;
        }
      }
      // The pillow: the core spans [t_a, 1 - t_a] along cube axis a, t_a = layers / (n_a + 2 layers).
      for (std::size_t p = 0; p < 3; ++p) {
        double lo = 1, hi = 0;
        for (const auto& blk : blocks)
          if (!blk.pillow)
            for (const Vec3& c : blk.corners) lo = std::min(lo, c[p]), hi = std::max(hi, c[p]);
        EXPECT_NEAR(lo, layers / double(n[p] + 2 * layers), 1e-12) << "axis " << p;
        EXPECT_NEAR(hi, 1 - layers / double(n[p] + 2 * layers), 1e-12) << "axis " << p;
      }
    }
  }
}

TEST(DifferenceHoles, BadHolesAreRefusedNamingThem) {
  auto refused = [](int axis, const std::vector<Across>& across, int elements, int layers) {
    return topology_error([&] { tmesh::difference_blocks(axis, through(axis, across), elements, layers); });
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int layers = 0; layers <= 1; ++layers) {
      SCOPED_TRACE("axis " + std::to_string(axis) + ", layers " + std::to_string(layers));
      const Across a{0.2, 0.4, 0.25, 0.5}, far{0.6, 0.8, 0.3, 0.7};
      // Overlapping, touching along a wall, touching at a corner.
      EXPECT_NE(refused(axis, {a, far, {0.3, 0.5, 0.4, 0.7}}, 32, layers).find("holes 0 and 2"), std::string::npos);
      EXPECT_NE(refused(axis, {a, {0.4, 0.55, 0.3, 0.45}}, 32, layers).find("holes 0 and 1"), std::string::npos);
      EXPECT_NE(refused(axis, {a, {0.4, 0.55, 0.5, 0.7}}, 32, layers).find("holes 0 and 1"), std::string::npos);
      // Apart across, but the hi wall of one on the line of the lo wall of the other.
      EXPECT_NE(refused(axis, {{0.1, 0.3, 0.1, 0.3}, {0.3, 0.5, 0.6, 0.8}}, 32, layers).find("holes 0 and 1"), std::string::npos);
      // Not through the cube, or not strictly inside it across.
      std::vector<Hole> holes = through(axis, {a, far});
      holes[1][0][static_cast<std::size_t>(axis)] = 0.1;
      EXPECT_NE(topology_error([&] { tmesh::difference_blocks(axis, holes, 32, layers); }).find("hole 1"), std::string::npos);
      EXPECT_NE(refused(axis, {far, {0.0, 0.3, 0.3, 0.6}}, 32, layers).find("hole 1"), std::string::npos);
      EXPECT_NE(refused(axis, {far, {0.2, 0.1, 0.3, 0.6}}, 32, layers).find("hole 1"), std::string::npos);
    }
  // Too close for the pillow (2 t = 1/9 at 16 elements and one layer): side by side, apart across
  // (every grid line crosses the section), and to the cube's side; all fine without the pillow.
  const std::vector<std::vector<Across>> close = {{{0.2, 0.4, 0.3, 0.6}, {0.45, 0.7, 0.3, 0.6}},
                                                  {{0.2, 0.4, 0.1, 0.3}, {0.45, 0.7, 0.6, 0.8}},
                                                  {{0.6, 0.8, 0.3, 0.7}, {0.05, 0.3, 0.3, 0.6}}};
  const std::vector<std::string> names = {"holes 0 and 1", "holes 0 and 1", "hole 1 and the cube's side"};
  for (std::size_t i = 0; i < close.size(); ++i) {
    EXPECT_NE(refused(2, close[i], 16, 1).find(names[i]), std::string::npos) << names[i] << ": " << refused(2, close[i], 16, 1);
    EXPECT_EQ(refused(2, close[i], 16, 0), "");
    EXPECT_EQ(refused(2, close[i], 64, 1), "") << "thinner pillow (2 t = 1/33)";
  }
  EXPECT_THROW(tmesh::difference_blocks(2, std::vector<Hole>{}, 8, 1), core::TopologyError);
  EXPECT_THROW(tmesh::difference_blocks(3, through(2, {{0.2, 0.4, 0.2, 0.4}}), 8, 1), core::TopologyError);
  EXPECT_THROW(tmesh::difference_blocks(2, through(2, {{0.2, 0.4, 0.2, 0.4}}), 8, -1), core::ConfigError);
}
