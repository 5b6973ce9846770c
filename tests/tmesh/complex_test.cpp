// Pillowing of a glued cube complex (tmesh/complex.h): on a lone cube and a ring it is the per-cube
// pillow of cube_blocks; on a cube standing on the middle of a row of three (a connector on a
// ring sector: concave edges that end on convex ones) the blocks tile the solid, conform face to
// face with equal element counts, have positive Jacobians, leave no element with two surface
// faces, and the corners of the shared face get the five-block pillow edge of a valence-5 surface
// vertex. Frames of the glued cubes may be rotated: the blocks are the same in space.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <vector>

#include "core/errors.h"
#include "tmesh/complex.h"
#include "tmesh/pillow.h"

using namespace volts;
using tmesh::AxisMap;
using tmesh::Block;
using tmesh::Vec3;

namespace {

AxisMap shift(double a, double b, double c) {
  AxisMap m;
  m.t = {a, b, c};
  return m;
}

// A cube's blocks placed in space (corners through `to_space`).
struct Placed {
  std::array<Vec3, 8> x;
  Block b;
};

double det3(const Vec3& u, const Vec3& v, const Vec3& w) {
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

// Volume and the smallest Jacobian determinant of a trilinear hex (3^3 Gauss points and corners).
double volume(const std::array<Vec3, 8>& c, double* min_det) {
  const double g[3] = {0.5 - std::sqrt(0.15), 0.5, 0.5 + std::sqrt(0.15)}, w[3] = {5.0 / 18, 8.0 / 18, 5.0 / 18};
  auto jac = [&](const Vec3& u) {
    std::array<Vec3, 3> d{};
    for (int i = 0; i < 8; ++i) {
      const double f[3] = {i & 1 ? u[0] : 1 - u[0], (i >> 1) & 1 ? u[1] : 1 - u[1], (i >> 2) & 1 ? u[2] : 1 - u[2]};
      const double s[3] = {i & 1 ? 1.0 : -1.0, (i >> 1) & 1 ? 1.0 : -1.0, (i >> 2) & 1 ? 1.0 : -1.0};
      for (int a = 0; a < 3; ++a) {
        double coef = s[a];
        for (int b = 0; b < 3; ++b)
          if (b != a) coef *= f[b];
        for (int k = 0; k < 3; ++k) d[a][k] += coef * c[i][k];
      }
    }
    return det3(d[0], d[1], d[2]);
  };
  double v = 0;
  *min_det = 1e300;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        const double dt = jac({g[i], g[j], g[k]});
        v += w[i] * w[j] * w[k] * dt;
        *min_det = std::min(*min_det, dt);
      }
  for (int i = 0; i < 8; ++i) *min_det = std::min(*min_det, jac({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)}));
  return v;
}

using FaceKey = std::array<std::array<long long, 3>, 4>;
FaceKey face_key(const std::array<Vec3, 8>& x, int f) {
  const int d = f / 2, side = f % 2;
  FaceKey k{};
  int n = 0;
  for (int i = 0; i < 8; ++i)
    if (((i >> d) & 1) == side)
      for (int a = 0; a < 3; ++a) k[n][a] = std::llround(x[i][a] * 1e9), n += a == 2;
  std::sort(k.begin(), k.end());
  return k;
}

// Blocks placed in space by `place` (cube, its parameters -> space); checks the properties in the
// header comment (tiling: the volume; conforming: every inner block face is the whole face of
// exactly one other block with the same element counts; positive Jacobians; a pillow has exactly
// one surface face, a core none) and returns the placed blocks.
// `key` maps a placed point to where faces are compared (a ring's development folded back onto
// itself; volumes and Jacobians are measured before it).
std::vector<Placed> check_blocks(const std::vector<std::vector<Block>>& blocks, const std::function<Vec3(std::size_t, const Vec3&)>& place,
                                 double want_volume, double want_surface, const std::function<Vec3(Vec3)>& key = [](Vec3 x) { return x; }) {
  std::vector<Placed> all;
  double total = 0, surface = 0;
  std::map<FaceKey, std::vector<std::array<int, 2>>> faces;  // -> (placed block, face)
  for (std::size_t c = 0; c < blocks.size(); ++c)
    for (const Block& b : blocks[c]) {
      Placed p{{}, b};
      for (int i = 0; i < 8; ++i) p.x[i] = place(c, b.corners[i]);
      double min_det = 0;
      total += volume(p.x, &min_det);
      EXPECT_GT(min_det, 1e-6) << "cube " << c;
      int on = 0;
      std::array<Vec3, 8> folded;
      for (int i = 0; i < 8; ++i) folded[i] = key(p.x[i]);
      for (int f = 0; f < 6; ++f) {
        on += b.boundary[f];
        faces[face_key(folded, f)].push_back({static_cast<int>(all.size()), f});
      }
      EXPECT_EQ(on, b.pillow ? 1 : 0);
      all.push_back(p);
    }
  EXPECT_NEAR(total, want_volume, 1e-9);
  for (const auto& [key, list] : faces) {
    const Placed& p = all[static_cast<std::size_t>(list[0][0])];
    const int f = list[0][1];
    if (p.b.boundary[f]) {
      EXPECT_EQ(list.size(), 1u);
      // Surface area of the (planar, in these tests) outer face.
      const int d = f / 2, side = f % 2;
      std::vector<Vec3> q;
      for (int i = 0; i < 8; ++i)
        if (((i >> d) & 1) == side) q.push_back(p.x[i]);
      Vec3 e1, e2, e3;
      for (int a = 0; a < 3; ++a) e1[a] = q[1][a] - q[0][a], e2[a] = q[2][a] - q[0][a], e3[a] = q[3][a] - q[0][a];
      auto cross_norm = [](const Vec3& u, const Vec3& v) {
        const Vec3 c{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        return std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
      };
      surface += 0.5 * cross_norm(e1, e3) + 0.5 * cross_norm(Vec3{e3[0] - e2[0], e3[1] - e2[1], e3[2] - e2[2]},
                                                              Vec3{e1[0] - e2[0], e1[1] - e2[1], e1[2] - e2[2]});
      continue;
    }
    EXPECT_EQ(list.size(), 2u) << "an inner block face not shared by exactly two blocks";
    if (list.size() != 2) continue;
    const Placed& o = all[static_cast<std::size_t>(list[1][0])];
    EXPECT_EQ(o.b.boundary[list[1][1]], 0);
    std::array<int, 2> n1{p.b.elements[(f / 2 + 1) % 3], p.b.elements[(f / 2 + 2) % 3]};
    std::array<int, 2> n2{o.b.elements[(list[1][1] / 2 + 1) % 3], o.b.elements[(list[1][1] / 2 + 2) % 3]};
    std::sort(n1.begin(), n1.end()), std::sort(n2.begin(), n2.end());
    EXPECT_EQ(n1, n2);
  }
  EXPECT_NEAR(surface, want_surface, 1e-9);
  return all;
}

// The blocks of the complex placed in space through each cube's map.
std::vector<Placed> check_complex(const tmesh::CubeComplex& k, const std::vector<AxisMap>& to_space, double want_volume,
                                  double want_surface, int elements, int layers) {
  const auto blocks = tmesh::complex_blocks(k, elements, layers);
  EXPECT_EQ(blocks.size(), k.glue.size());
  return check_blocks(blocks, [&](std::size_t c, const Vec3& x) { return to_space[c](x); }, want_volume, want_surface);
}

std::vector<std::array<Vec3, 8>> sorted_corners(const std::vector<Block>& blocks) {
  std::vector<std::array<Vec3, 8>> v;
  for (const Block& b : blocks) v.push_back(b.corners);
  std::sort(v.begin(), v.end());
  return v;
}

void expect_same_blocks(const std::vector<Block>& a, const std::vector<Block>& b) {
  const auto x = sorted_corners(a), y = sorted_corners(b);
  ASSERT_EQ(x.size(), y.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    for (int j = 0; j < 8; ++j)
      for (int d = 0; d < 3; ++d) EXPECT_NEAR(x[i][j][d], y[i][j][d], 1e-12);
}

}  // namespace

TEST(CubeComplex, LoneCubeIsThePerCubePillow) {
  tmesh::CubeComplex k;
  k.glue.resize(1);
  const auto blocks = tmesh::complex_blocks(k, 8, 1);
  expect_same_blocks(blocks[0], tmesh::cube_blocks({1, 1, 1, 1, 1, 1}, {8, 8, 8}, 1));
  check_complex(k, {AxisMap{}}, 1, 6, 8, 1);
}

TEST(CubeComplex, RingCubesAreThePerCubePillow) {
  // Four cubes in a row along a, the last glued to the first (a ring: no surface across a).
  tmesh::CubeComplex k;
  k.glue.resize(4);
  for (int c = 0; c < 4; ++c) tmesh::glue_faces(k, c, 1, (c + 1) % 4, 0, shift(-1, 0, 0));
  const auto blocks = tmesh::complex_blocks(k, 8, 2);
  for (const auto& b : blocks) expect_same_blocks(b, tmesh::cube_blocks({0, 0, 1, 1, 1, 1}, {8, 8, 8}, 2));
}

namespace {

// A row of three cubes along a (cubes 0, 1, 2 at a = -1, 0, 1) and cube 3 standing on the middle
// one (c from 1 to 2), glued with `frame`: cube 1's parameters -> cube 3's.
tmesh::CubeComplex t_junction(const AxisMap& frame, std::vector<AxisMap>& to_space) {
  tmesh::CubeComplex k;
  k.glue.resize(4);
  tmesh::glue_faces(k, 0, 1, 1, 0, shift(-1, 0, 0));
  tmesh::glue_faces(k, 1, 1, 2, 0, shift(-1, 0, 0));
  const Vec3 top = frame.linear({0, 0, 1});
  int face = 0;
  while (top[face / 2] == 0) face += 2;
  face += top[face / 2] > 0 ? 0 : 1;  // cube 3's face across cube 1's top: its inward normal is +c of cube 1
  tmesh::glue_faces(k, 1, 5, 3, face, frame);
  to_space = {shift(-1, 0, 0), AxisMap{}, shift(1, 0, 0), frame.inverse()};
  return k;
}

}  // namespace

TEST(CubeComplex, CubeOnARowTilesConformsAndHasFivePillowsAtTheSharedFacesCorners) {
  for (int rotated = 0; rotated < 2; ++rotated) {
    SCOPED_TRACE(rotated ? "cube 3 in a rotated frame" : "cube 3 in cube 1's frame");
    AxisMap frame = shift(0, 0, -1);
    if (rotated) {
      // Cube 3's (a, b, c) = (c - 1, a, b) of cube 1: a cyclic permutation, right-handed.
      frame.P = {{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}};
      frame.t = {-1, 0, 0};
    }
    std::vector<AxisMap> to_space;
    const tmesh::CubeComplex k = t_junction(frame, to_space);
    // Three cubes in a row (area 14) less the shared face, plus the standing cube's five faces.
    const auto all = check_complex(k, to_space, 4, 14 - 1 + 5, 8, 1);
    // The shared face's corner (0, 0, 1), where five surface faces meet (the row's front and top,
    // the standing cube's front and side, the middle cube's front): its inner copy (p, p, 1 - p)
    // is a corner of the five pillows on those faces and of no core.
    const double p = 1.0 / 10;
    auto has = [](const Placed& q, const Vec3& x) {
      for (const auto& y : q.x)
        if (std::abs(y[0] - x[0]) < 1e-12 && std::abs(y[1] - x[1]) < 1e-12 && std::abs(y[2] - x[2]) < 1e-12) return true;
      return false;
    };
    int pillows = 0, cores = 0;
    for (const Placed& q : all)
      if (has(q, {0, 0, 1}) && has(q, {p, p, 1 - p})) (q.b.pillow ? pillows : cores) += 1;
    EXPECT_EQ(pillows, 5);
    EXPECT_EQ(cores, 0);
  }
}

// A pillow of one thickness in the solid (physical_pillow): on the cube standing on a row, with
// every cube 4 long along the row, 1 across it and 2 high (in cube 1's frame), the axis classes
// get p0 / 4, p0 and p0 / 2; glued faces agree on every axis, so the blocks still tile the solid,
// conform and have positive Jacobians; lengths that are not positive are refused.
TEST(CubeComplex, PhysicalPillowIsOneThicknessInTheSolidAndStillConforms) {
  for (int rotated = 0; rotated < 2; ++rotated) {
    SCOPED_TRACE(rotated ? "cube 3 in a rotated frame" : "cube 3 in cube 1's frame");
    AxisMap frame = shift(0, 0, -1);
    if (rotated) frame.P = {{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}}, frame.t = {-1, 0, 0};
    std::vector<AxisMap> to_space;
    const tmesh::CubeComplex k = t_junction(frame, to_space);
    const Vec3 along{4, 1, 2};  // lengths along cube 1's axes
    std::vector<std::array<double, 3>> length(4, along);
    for (int d = 0; d < 3; ++d) {  // cube 3's axis d is cube 1's axis e
      Vec3 u{0, 0, 0};
      u[static_cast<std::size_t>(d)] = 1;
      const Vec3 w = frame.inverse().linear(u);
      for (int e = 0; e < 3; ++e)
        if (w[static_cast<std::size_t>(e)] != 0) length[3][static_cast<std::size_t>(d)] = along[static_cast<std::size_t>(e)];
    }
    const double p0 = 1.0 / 10;
    // Lengths that differ within a class (cube 0 longer along the row): one thickness per class.
    for (const double first : {4.0, 6.0}) {
      length[0][0] = first;
      const auto p = tmesh::physical_pillow(k, 8, 1, length);
      if (first == 4.0) {
        for (std::size_t c = 0; c < 4; ++c)
          for (std::size_t d = 0; d < 3; ++d) EXPECT_NEAR(p[c][d], p0 * 1.0 / length[c][d], 1e-15) << "cube " << c << " axis " << d;
      } else {
        EXPECT_NEAR(p[0][0], p0 * 1.0 / 4.5, 1e-15);  // the row's class: (6 + 4 + 4 + 4) / 4
      }
      for (std::size_t c = 0; c < 4; ++c)
        for (int f = 0; f < 6; ++f) {
          const auto& g = k.glue[c][static_cast<std::size_t>(f)];
          if (!g) continue;
          for (int t = 0; t < 3; ++t)
            for (int a = 0; a < 3; ++a)
              if (g->map.P[a][t] != 0) {
                EXPECT_EQ(p[c][static_cast<std::size_t>(t)], p[static_cast<std::size_t>(g->cube)][static_cast<std::size_t>(a)]);
              }
        }
      const auto blocks = tmesh::complex_blocks(k, std::vector<std::array<int, 3>>(4, {8, 8, 8}), 1, p);
      check_blocks(blocks, [&](std::size_t c, const Vec3& x) { return to_space[c](x); }, 4, 14 - 1 + 5);
    }
  }
  std::vector<AxisMap> to_space;
  const tmesh::CubeComplex k = t_junction(shift(0, 0, -1), to_space);
  EXPECT_THROW(tmesh::physical_pillow(k, 8, 1, std::vector<std::array<double, 3>>(4, {1, 0, 1})), core::ConfigError);
  EXPECT_THROW(tmesh::physical_pillow(k, 8, 1, std::vector<std::array<double, 3>>(3, {1, 1, 1})), core::ConfigError);
  EXPECT_THROW(tmesh::physical_pillow(k, 8, 0, std::vector<std::array<double, 3>>(4, {1, 1, 1})), core::ConfigError);
}

TEST(CubeComplex, LocateCarriesPointsAcrossGluedFacesOnly) {
  std::vector<AxisMap> to_space;
  AxisMap frame;
  frame.P = {{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}};
  frame.t = {-1, 0, 0};
  const tmesh::CubeComplex k = t_junction(frame, to_space);
  // From cube 0 past its a = 1 face into cube 1.
  auto r = tmesh::locate(k, 0, {1.1, 0.5, 0.9});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->first, 1);
  EXPECT_NEAR(r->second[0], 0.1, 1e-12);
  // From cube 3 below its bottom (a < 0 in its frame) into cube 1: (a, b, c) = (b3, c3, 1 + a3).
  r = tmesh::locate(k, 3, {-0.1, 0.2, 0.3});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->first, 1);
  EXPECT_NEAR(r->second[0], 0.2, 1e-12);
  EXPECT_NEAR(r->second[1], 0.3, 1e-12);
  EXPECT_NEAR(r->second[2], 0.9, 1e-12);
  // Out through a surface face.
  EXPECT_FALSE(tmesh::locate(k, 0, {-0.1, 0.5, 0.5}));
  EXPECT_FALSE(tmesh::locate(k, 1, {0.5, -0.2, 0.5}));
}

TEST(CubeComplex, BadInputIsRejected) {
  tmesh::CubeComplex k;
  k.glue.resize(2);
  EXPECT_THROW(tmesh::complex_blocks(k, 8, 0), core::ConfigError);
  // A map that does not take face 1 of cube 0 onto face 0 of cube 1.
  EXPECT_THROW(tmesh::glue_faces(k, 0, 1, 1, 0, shift(0, 0, 0)), core::TopologyError);
  tmesh::glue_faces(k, 0, 1, 1, 0, shift(-1, 0, 0));
  EXPECT_THROW(tmesh::glue_faces(k, 0, 1, 1, 0, shift(-1, 0, 0)), core::TopologyError);
  // Per-cube counts and thicknesses: glued faces must agree along their shared axes (b here).
  const std::vector<std::array<double, 3>> p(2, {0.1, 0.1, 0.1});
  try {
    tmesh::complex_blocks(k, {{8, 8, 8}, {8, 6, 8}}, 1, p);
    ADD_FAILURE() << "counts that differ across a glued face accepted";
  } catch (const core::TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("cube 0 face 1 has 8 elements along axis 1"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(tmesh::complex_blocks(k, {{8, 8, 8}, {3, 8, 8}}, 1, p));  // along a, across the face: free
  EXPECT_EQ(tmesh::element_counts(k, {{8, 8, 8}, {3, 6, 9}}), (std::vector<std::array<int, 3>>{{8, 8, 9}, {3, 8, 9}}));
  EXPECT_THROW(tmesh::complex_blocks(k, {{8, 8, 8}, {8, 8, 8}}, 1, {{0.1, 0.1, 0.1}, {0.1, 0.5, 0.1}}), core::ConfigError);
  EXPECT_THROW(tmesh::complex_blocks(k, {{8, 8, 8}}, 1, p), core::ConfigError);
  EXPECT_THROW(tmesh::element_counts(k, {{8, 8, 8}, {8, 0, 8}}), core::ConfigError);
}

// ------------------------------------------------------------------------------------------------
// Boxes of one frame (BoxLayout): faces of different sizes meeting in part become whole faces of
// sub-boxes; the pillowed blocks of the result tile the boxes and conform.

namespace {

tmesh::BoxLayout::Closure closure(int a, int fa, int b, int fb, const Vec3& shift) {
  tmesh::BoxLayout::Closure c;
  c.a = a, c.fa = fa, c.b = b, c.fb = fb, c.shift = shift;
  return c;
}

// Pillowed blocks of a box complex with `elements` per unit of frame length along every axis (at
// least one), the pillow 0.1 thick in the frame, checked in the frame (`wrap` folds a ring's
// development back onto itself).
std::vector<Placed> check_boxes(const tmesh::BoxComplex& bc, double want_volume, double want_surface,
                                const std::function<Vec3(Vec3)>& wrap = [](Vec3 x) { return x; }) {
  std::vector<std::array<int, 3>> wanted(bc.extent.size());
  for (std::size_t c = 0; c < wanted.size(); ++c)
    for (int d = 0; d < 3; ++d) wanted[c][d] = std::max(1, static_cast<int>(std::lround(8 * (bc.extent[c][1][d] - bc.extent[c][0][d]))));
  const auto counts = tmesh::element_counts(bc.complex, wanted);
  const auto blocks = tmesh::complex_blocks(bc.complex, counts, 1, bc.pillow(0.1));
  return check_blocks(blocks, [&](std::size_t c, const Vec3& x) { return bc.to_frame(static_cast<int>(c), x); }, want_volume, want_surface, wrap);
}

}  // namespace

TEST(BoxComplex, UnitBoxesGiveTheGluedComplexsBlocks) {
  // The row of three with a cube on the middle one, as boxes of one frame and as glued cubes.
  tmesh::BoxLayout L;
  L.boxes = {{Vec3{-1, 0, 0}, Vec3{0, 1, 1}}, {Vec3{0, 0, 0}, Vec3{1, 1, 1}}, {Vec3{1, 0, 0}, Vec3{2, 1, 1}}, {Vec3{0, 0, 1}, Vec3{1, 1, 2}}};
  const tmesh::BoxComplex bc = tmesh::box_complex(L);
  ASSERT_EQ(bc.extent.size(), 4u);
  std::vector<AxisMap> to_space;
  const auto glued = check_complex(t_junction(shift(0, 0, -1), to_space), to_space, 4, 18, 8, 1);
  const auto boxed = check_boxes(bc, 4, 18);
  ASSERT_EQ(glued.size(), boxed.size());
  auto corners = [](const std::vector<Placed>& v) {
    std::vector<std::array<Vec3, 8>> c;
    for (const Placed& p : v) c.push_back(p.x);
    std::sort(c.begin(), c.end());
    return c;
  };
  const auto a = corners(glued), b = corners(boxed);
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int j = 0; j < 8; ++j)
      for (int d = 0; d < 3; ++d) EXPECT_NEAR(a[i][j][d], b[i][j][d], 1e-12);
}

TEST(BoxComplex, ACubeOnPartOfAFaceCutsTheFaceAndConforms) {
  // A unit cube on the middle third of a 3 x 1 x 1 bar's top: the bar is cut at x = 1 and 2.
  tmesh::BoxLayout L;
  L.boxes = {{Vec3{0, 0, 0}, Vec3{3, 1, 1}}, {Vec3{1, 0, 1}, Vec3{2, 1, 2}}};
  const tmesh::BoxComplex bc = tmesh::box_complex(L);
  ASSERT_EQ(bc.extent.size(), 4u);
  EXPECT_EQ(std::count(bc.box.begin(), bc.box.end(), 0), 3);
  check_boxes(bc, 3 + 1, 2 * (3 + 3 + 1) - 1 + 5);
}

TEST(BoxComplex, AThinBoxOnTheMiddleOfAnEndFaceMakesShouldersOfOtherSizes) {
  // The rod's small end: a 4 x 1 x 1 shank whose end x = 4 carries a 1 x 1 x 0.4 box on its
  // middle strip z in [0.3, 0.7]; the rest of the end face (the shoulders) is surface. The shank
  // is cut at z = 0.3 and 0.7 into boxes 0.3, 0.4 and 0.3 high, whose pillows are as thick as
  // the others in the frame (0.1) so that the inner copies of their shared vertices coincide.
  tmesh::BoxLayout L;
  L.boxes = {{Vec3{0, 0, 0}, Vec3{4, 1, 1}}, {Vec3{4, 0, 0.3}, Vec3{5, 1, 0.7}}};
  const tmesh::BoxComplex bc = tmesh::box_complex(L);
  ASSERT_EQ(bc.extent.size(), 4u);
  std::vector<double> heights;
  for (std::size_t c = 0; c < bc.extent.size(); ++c)
    if (bc.box[c] == 0) heights.push_back(bc.extent[c][1][2] - bc.extent[c][0][2]);
  ASSERT_EQ(heights.size(), 3u);
  EXPECT_NEAR(heights[0], 0.3, 1e-15);
  EXPECT_NEAR(heights[1], 0.4, 1e-15);
  EXPECT_NEAR(heights[2], 0.3, 1e-15);
  const double shank = 2 * (4 + 4 + 1), box = 2 * (1 * 1 + 1 * 0.4 + 1 * 0.4);
  check_boxes(bc, 4 + 0.4, shank + box - 2 * 0.4);
}

TEST(BoxComplex, CutsTravelAroundARingThroughItsClosure) {
  // A ring of four unit boxes developed along x (box 3's face x = 4 is box 0's x = 0), and a box
  // on the middle half (in y) of box 1's top: its sides cut box 1 at y = 0.25 and 0.75, and the
  // cuts go on through boxes 0 and 2 and, across the closure, box 3.
  tmesh::BoxLayout L;
  for (int i = 0; i < 4; ++i) L.boxes.push_back({Vec3{double(i), 0, 0}, Vec3{double(i + 1), 1, 1}});
  L.boxes.push_back({Vec3{1, 0.25, 1}, Vec3{2, 0.75, 2}});
  L.closures = {closure(3, 1, 0, 0, {-4, 0, 0})};
  const tmesh::BoxComplex bc = tmesh::box_complex(L);
  for (int b = 0; b < 4; ++b) EXPECT_EQ(std::count(bc.box.begin(), bc.box.end(), b), 3) << "ring box " << b;
  EXPECT_EQ(std::count(bc.box.begin(), bc.box.end(), 4), 1);
  // The sub-boxes at x = 4 are glued to those at x = 0 (no surface there).
  for (std::size_t c = 0; c < bc.extent.size(); ++c) {
    if (bc.box[c] != 3) continue;
    EXPECT_TRUE(bc.complex.glue[c][1].has_value()) << c;
  }
  auto wrap = [](Vec3 x) {
    if (x[0] > 4 - 1e-12) x[0] -= 4;
    return x;
  };
  check_boxes(bc, 4 + 0.5, 16 - 0.5 + (0.5 + 2 * 1 + 2 * 0.5), wrap);
  // locate: a point past the closing face (a pillow corner reaching across it) lands in box 0.
  const auto at = bc.locate({4.05, 0.5, 0.5});
  ASSERT_TRUE(at);
  EXPECT_EQ(bc.box[static_cast<std::size_t>(at->first)], 0);
  EXPECT_NEAR(at->second[0], 0.05, 1e-12);
  EXPECT_FALSE(bc.locate({0.5, 0.5, 1.5}));  // above box 0: outside the solid
}

// A ring laid out with a gap (the assembly's: the foot cube on the plate, the others in a row
// beyond it): box 0 at [0, 1], boxes 1 and 2 at [-3, -2] and [-5, -3], box 0's face x = 0 closed
// onto box 1's x = -2. A point just past box 1's closing face is carried into box 0, not by the
// shift the other way into box 2 (which it reaches too); a point past no closing face stays out.
TEST(BoxComplex, LocateCrossesAClosureOnlyFromItsFaceIntoItsBox) {
  tmesh::BoxLayout L;
  L.boxes = {{Vec3{0, 0, 0}, Vec3{1, 1, 1}}, {Vec3{-3, 0, 0}, Vec3{-2, 1, 1}}, {Vec3{-5, 0, 0}, Vec3{-3, 1, 1}}};
  L.closures = {closure(0, 0, 1, 1, {-2, 0, 0})};
  const tmesh::BoxComplex bc = tmesh::box_complex(L);
  const auto at = bc.locate({-1.9, 0.5, 0.5});
  ASSERT_TRUE(at);
  EXPECT_EQ(bc.box[static_cast<std::size_t>(at->first)], 0);
  EXPECT_NEAR(at->second[0], 0.1, 1e-12);
  const auto back = bc.locate({-0.1, 0.5, 0.5});  // past box 0's closing face: into box 1
  ASSERT_TRUE(back);
  EXPECT_EQ(bc.box[static_cast<std::size_t>(back->first)], 1);
  EXPECT_NEAR(back->second[0], 0.9, 1e-12);
  EXPECT_FALSE(bc.locate({-1.9, 1.5, 0.5}));  // beside the face, not past it
}

TEST(BoxComplex, BadLayoutsAreRefusedNamingTheBoxes) {
  tmesh::BoxLayout L;
  L.boxes = {{Vec3{0, 0, 0}, Vec3{1, 1, 1}}, {Vec3{0.5, 0, 0}, Vec3{1.5, 1, 1}}};
  try {
    tmesh::box_complex(L);
    ADD_FAILURE() << "overlapping boxes accepted";
  } catch (const core::TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("box 0 and box 1 overlap"), std::string::npos) << e.what();
  }
  L.boxes = {{Vec3{0, 0, 0}, Vec3{1, 1, 1}}, {Vec3{1, 0, 0}, Vec3{2, 1, 1}}};
  L.closures = {closure(1, 1, 0, 0, {-1.5, 0, 0})};
  EXPECT_THROW(tmesh::box_complex(L), core::TopologyError);  // the shift misses the face
  L.closures = {closure(1, 1, 0, 2, {-2, 0, 0})};
  EXPECT_THROW(tmesh::box_complex(L), core::TopologyError);  // faces of different axes
  L.closures.clear();
  EXPECT_THROW(tmesh::box_complex(L, {{std::vector<double>{1.5}, {}, {}}, {}}), core::ConfigError);  // cut outside box 0
  L.boxes = {{Vec3{0, 0, 0}, Vec3{0, 1, 1}}};
  EXPECT_THROW(tmesh::box_complex(L), core::TopologyError);  // empty
}

namespace {

// Two rings of four cubes and a connector cube between them in frames turned against each other
// (the eight's and the rod's complex): ring 0 cubes 0-3, ring 1 cubes 4-7, the connector 8 on
// ring 0 cube 0's face b = 1 and ring 1 cube 4's face b = 0.
tmesh::CubeComplex two_rings_and_a_connector() {
  tmesh::CubeComplex k;
  k.glue.resize(9);
  for (int r = 0; r < 2; ++r)
    for (int i = 0; i < 4; ++i) tmesh::glue_faces(k, 4 * r + i, 1, 4 * r + (i + 1) % 4, 0, shift(-1, 0, 0));
  AxisMap to_connector;  // ring 0 cube 0 (A, B, C) -> connector (a, b, c) = (B - 1, C, A)
  to_connector.P = {{{0, 1, 0}, {0, 0, 1}, {1, 0, 0}}};
  to_connector.t = {-1, 0, 0};
  tmesh::glue_faces(k, 0, 3, 8, 0, to_connector);
  AxisMap to_ring1;  // connector (a, b, c) -> ring 1 cube 4 (A, B, C) = (c, a - 1, b)
  to_ring1.P = {{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}};
  to_ring1.t = {0, -1, 0};
  tmesh::glue_faces(k, 8, 1, 4, 2, to_ring1);
  return k;
}

}  // namespace

TEST(BoxComplex, DevelopedComplexGivesTheSameBlocksInEachCubesParameters) {
  std::vector<AxisMap> unused;
  AxisMap turned;
  turned.P = {{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}};
  turned.t = {-1, 0, 0};
  AxisMap quarter;  // a quarter turn about c: cube 3's (a, b, c) = (1 - b, a, c - 1) of cube 1
  quarter.P = {{{0, -1, 0}, {1, 0, 0}, {0, 0, 1}}};
  quarter.t = {1, 0, -1};
  for (const tmesh::CubeComplex& k : {t_junction(turned, unused), t_junction(quarter, unused), two_rings_and_a_connector()}) {
    SCOPED_TRACE(std::to_string(k.glue.size()) + " cubes");
    tmesh::BoxLayout L;
    const std::vector<AxisMap> frame = tmesh::develop(k, L);
    ASSERT_EQ(L.boxes.size(), k.glue.size());
    const tmesh::BoxComplex bc = tmesh::box_complex(L);
    ASSERT_EQ(bc.extent.size(), k.glue.size());  // unit cubes meeting in whole faces: nothing to cut
    const auto in_frame = tmesh::complex_blocks(bc.complex, std::vector<std::array<int, 3>>(bc.extent.size(), {8, 8, 8}), 1, bc.pillow(0.1));
    const auto got = tmesh::blocks_in_cubes(bc, frame, in_frame), want = tmesh::complex_blocks(k, 8, 1);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t c = 0; c < want.size(); ++c) {
      ASSERT_EQ(got[c].size(), want[c].size()) << "cube " << c;
      for (std::size_t b = 0; b < want[c].size(); ++b) {
        EXPECT_EQ(got[c][b].pillow, want[c][b].pillow);
        EXPECT_EQ(got[c][b].elements, want[c][b].elements);
        EXPECT_EQ(got[c][b].boundary, want[c][b].boundary) << "cube " << c << " block " << b;
        for (int i = 0; i < 8; ++i)
          for (int d = 0; d < 3; ++d) EXPECT_NEAR(got[c][b].corners[i][d], want[c][b].corners[i][d], 1e-12) << "cube " << c << " block " << b;
      }
    }
  }
  // The two rings become two closures (each ring cut open at one gluing).
  tmesh::BoxLayout L;
  tmesh::develop(two_rings_and_a_connector(), L);
  EXPECT_EQ(L.closures.size(), 2u);
  // A ring closed with a turn has no single frame.
  tmesh::CubeComplex twisted;
  twisted.glue.resize(4);
  for (int i = 0; i < 3; ++i) tmesh::glue_faces(twisted, i, 1, i + 1, 0, shift(-1, 0, 0));
  AxisMap turn;
  turn.P = {{{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}};
  turn.t = {-1, 1, 0};
  tmesh::glue_faces(twisted, 3, 1, 0, 0, turn);
  EXPECT_THROW(tmesh::develop(twisted, L), core::TopologyError);
}

// The rod's small end in the frame (develop()): ring 1's boxes narrowed to the middle strip of the
// connector's end face, the rest of that face a lens on each side. Where a lens meets the next
// sector of the ring the development puts both faces in one plane facing opposite ways (in the
// solid the ring turns away there): refused by default; with OppositePlanes::in_plane every block
// corner stays inside the frame's solid, the blocks tile it without inverted corners (some are
// flat there) and conform. blocks_in_cubes gives them back in each cube's own parameters through
// the narrowed boxes.
TEST(BoxComplex, ALensBesideTheNextRingSectorIsPillowedInThePlaneOfBoth) {
  const tmesh::CubeComplex k = two_rings_and_a_connector();
  tmesh::BoxLayout L;
  const std::vector<AxisMap> frame = tmesh::develop(k, L);
  // Connector axis b (ring 1's A is the connector's c): the strip [0.3, 0.7] of it.
  int F = -1;
  for (int f = 0; f < 3; ++f)
    if (frame[8].P[f][1] != 0) F = f;
  ASSERT_GE(F, 0);
  const double x0 = tmesh::cube_to_frame(frame[8], L.boxes[8], Vec3{1, 0.3, 0.5})[F], x1 = tmesh::cube_to_frame(frame[8], L.boxes[8], Vec3{1, 0.7, 0.5})[F];
  for (int c = 4; c < 8; ++c) L.boxes[c][0][F] = std::min(x0, x1), L.boxes[c][1][F] = std::max(x0, x1);
  const tmesh::BoxComplex bc = tmesh::box_complex(L);
  std::vector<std::array<int, 3>> wanted(bc.extent.size());
  for (std::size_t c = 0; c < wanted.size(); ++c)
    for (int d = 0; d < 3; ++d) wanted[c][d] = std::max(1, static_cast<int>(std::lround(8 * (bc.extent[c][1][d] - bc.extent[c][0][d]))));
  const auto counts = tmesh::element_counts(bc.complex, wanted);
  EXPECT_THROW(tmesh::complex_blocks(bc.complex, counts, 1, bc.pillow(0.1)), core::TopologyError);
  const auto blocks = tmesh::complex_blocks(bc.complex, counts, 1, bc.pillow(0.1), tmesh::OppositePlanes::in_plane);
  double want_volume = 0;
  for (const auto& b : L.boxes) want_volume += (b[1][0] - b[0][0]) * (b[1][1] - b[0][1]) * (b[1][2] - b[0][2]);
  auto inside = [&](const Vec3& x) {
    for (const auto& b : L.boxes) {
      bool in = true;
      for (int d = 0; d < 3; ++d) in = in && x[d] > b[0][d] - 1e-12 && x[d] < b[1][d] + 1e-12;
      if (in) return true;
    }
    return false;
  };
  // Faces across a ring's closure compared where they meet: a point on a closing face moved by its shift.
  auto fold = [&](Vec3 x) {
    for (const auto& cl : L.closures) {
      const auto& b = L.boxes[static_cast<std::size_t>(cl.a)];
      const int d = cl.fa / 2;
      bool on = std::abs(x[d] - b[cl.fa % 2][d]) < 1e-12;
      for (int e = 0; e < 3; ++e) on = on && (e == d || (x[e] > b[0][e] - 1e-12 && x[e] < b[1][e] + 1e-12));
      if (on) {
        for (int e = 0; e < 3; ++e) x[e] += cl.shift[e];
        return x;
      }
    }
    return x;
  };
  double total = 0;
  int flat = 0;
  std::map<FaceKey, int> inner_faces;
  for (std::size_t c = 0; c < blocks.size(); ++c)
    for (const Block& b : blocks[c]) {
      std::array<Vec3, 8> x;
      for (int i = 0; i < 8; ++i) {
        x[i] = bc.to_frame(static_cast<int>(c), b.corners[i]);
        EXPECT_TRUE(inside(x[i])) << "sub-box " << c << ": a block corner outside the solid";
      }
      double min_det = 0;
      total += volume(x, &min_det);
      EXPECT_GT(min_det, -1e-12) << "sub-box " << c;
      flat += min_det < 1e-9;
      std::array<Vec3, 8> folded;
      for (int i = 0; i < 8; ++i) folded[i] = fold(x[i]);
      for (int f = 0; f < 6; ++f)
        if (!b.boundary[f]) ++inner_faces[face_key(folded, f)];
    }
  EXPECT_NEAR(total, want_volume, 1e-9);
  EXPECT_GT(flat, 0);  // the lens's corners beside the ring's next sector
  for (const auto& [key, n] : inner_faces) EXPECT_EQ(n, 2) << "an inner block face not shared by exactly two blocks";
  // Back in each cube's parameters: the same frame corners through its (narrowed) box.
  const auto in_cubes = tmesh::blocks_in_cubes(bc, frame, blocks);
  std::vector<std::array<Vec3, 8>> a, b;
  for (std::size_t c = 0; c < blocks.size(); ++c)
    for (const Block& q : blocks[c]) {
      std::array<Vec3, 8> x;
      for (int i = 0; i < 8; ++i) x[i] = bc.to_frame(static_cast<int>(c), q.corners[i]);
      std::sort(x.begin(), x.end());
      a.push_back(x);
    }
  for (std::size_t c = 0; c < in_cubes.size(); ++c)
    for (const Block& q : in_cubes[c]) {
      std::array<Vec3, 8> x;
      for (int i = 0; i < 8; ++i) {
        x[i] = tmesh::cube_to_frame(frame[c], L.boxes[c], q.corners[i]);
        const Vec3 back = tmesh::frame_to_cube(frame[c], L.boxes[c], x[i]);
        for (int d = 0; d < 3; ++d) EXPECT_NEAR(back[d], q.corners[i][d], 1e-12);
      }
      std::sort(x.begin(), x.end());
      b.push_back(x);
    }
  std::sort(a.begin(), a.end()), std::sort(b.begin(), b.end());
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int j = 0; j < 8; ++j)
      for (int d = 0; d < 3; ++d) EXPECT_NEAR(a[i][j][d], b[i][j][d], 1e-12);
  // An unstretched cube's box is its develop() map.
  for (int i = 0; i < 8; ++i) {
    const Vec3 u{0.1 + 0.1 * i, 0.9 - 0.1 * i, 0.25};
    const Vec3 p = tmesh::cube_to_frame(frame[0], L.boxes[0], u), q = frame[0](u);
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(p[d], q[d], 1e-12);
  }
}

// A ring's foot on a plate, straight as development lays it out: cube 0 (the plate cell under
// the foot) and cube 1 beside it in a row, cube 2 (the foot cube) on cube 0, cube 3 (the ring's
// next cube) glued to cube 2's side. Cubes 1 and 3 touch back to back without being glued (in
// the solid the ring rises off the plate there): a crack. Refused by default, naming it; with
// OppositePlanes::in_plane the inner copy of the crack's root moves away from it in its plane
// (every cube finds the same point: (1 - p, p, 1) of cube 0 at the root's front end), and the
// blocks tile the four cubes with no inverted corner (the two slabs at the root are flat there).
TEST(CubeComplex, ACrackBesideAFootIsPillowedAwayFromItInItsPlane) {
  tmesh::CubeComplex k;
  k.glue.resize(4);
  tmesh::glue_faces(k, 0, 1, 1, 0, shift(-1, 0, 0));
  tmesh::glue_faces(k, 0, 5, 2, 4, shift(0, 0, -1));
  tmesh::glue_faces(k, 2, 1, 3, 0, shift(-1, 0, 0));
  const std::vector<Vec3> at{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {1, 0, 1}};  // each cube's place
  try {
    tmesh::complex_blocks(k, 4, 1);
    ADD_FAILURE() << "a crack was not refused";
  } catch (const core::TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("not glued"), std::string::npos) << e.what();
  }
  const double p = 0.1;
  const auto blocks = tmesh::complex_blocks(k, std::vector<std::array<int, 3>>(4, {4, 4, 4}), 1,
                                            std::vector<std::array<double, 3>>(4, {p, p, p}), tmesh::OppositePlanes::in_plane);
  ASSERT_EQ(blocks.size(), 4u);
  double total = 0;
  int flat = 0, root_copies = 0;
  for (std::size_t c = 0; c < 4; ++c)
    for (const Block& b : blocks[c]) {
      std::array<Vec3, 8> x;
      for (int i = 0; i < 8; ++i) {
        for (int d = 0; d < 3; ++d) x[i][d] = at[c][d] + b.corners[i][d];
        // No block reaches across the crack: cube 3's stay above it, cube 1's below.
        const bool right = x[i][0] > 1 + 1e-12, below = x[i][2] < 1 - 1e-12, above = x[i][2] > 1 + 1e-12;
        EXPECT_FALSE((c == 3 && right && below) || (c == 1 && right && above)) << "cube " << c;
        EXPECT_TRUE(x[i][0] > -1e-12 && x[i][0] < 2 + 1e-12 && x[i][1] > -1e-12 && x[i][1] < 1 + 1e-12 && x[i][2] > -1e-12 && x[i][2] < 2 + 1e-12);
        root_copies += std::abs(x[i][0] - (1 - p)) < 1e-12 && std::abs(x[i][1] - p) < 1e-12 && std::abs(x[i][2] - 1) < 1e-12;
      }
      double min_det = 0;
      total += volume(x, &min_det);
      EXPECT_GT(min_det, -1e-12) << "cube " << c;
      flat += min_det < 1e-9;
    }
  EXPECT_NEAR(total, 4, 1e-9);
  EXPECT_GT(flat, 0);
  // The root's inner copy is a corner of the four cores and of the slabs of cubes 1 and 3 on the
  // crack and of the front faces (y = 0) of all four.
  EXPECT_GE(root_copies, 4 + 2 + 4);
}
