// A difference (Liu et al. §4.2, Fig. 6; §4.3): a cube minus through holes, mapped onto the unit
// cube minus a box per hole. Checked on the generated cube-with-hole (a round hole), the shared square ring
// vhacd_tube1 (a square hole) and that ring with its hole moved off centre: no flipped surface triangle, every vertex on the polycube's
// boundary, no flipped tet after untangling, the parameter volume that of the polycube, and the map
// is one-to-one (random parameter points in exactly one mapped tet, mapped inside the solid). And
// on the generated plate (four parallel bolt holes): the boxes where the holes are, the stage
// file's "holes", refusals naming the holes.
#include <gtest/gtest.h>

#include <CGAL/Side_of_triangle_mesh.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include "classify/classify.h"
#include "common/test_util.h"
#include "core/errors.h"
#include "models/models.h"
#include "polycube/cube_frame.h"
#include "polycube/difference.h"
#include "polycube/embedding.h"
#include "polycube/rings.h"
#include "ring_map_check.h"
#include "split/split.h"
#include "volmap/volmap.h"

using namespace volts;

namespace {

// "shifted-tube": vhacd_tube1 (a 120 x 40 x 120 block with a centred 40 x 40 square hole along y)
// with x' = x + 0.3 (1 - u^2) 60, u = (x - centre) / 60: monotone, it keeps every face planar and
// moves the hole 0.15 of the block off centre (to [0.47, 0.8] across x).
surface::Mesh shifted_tube() {
  surface::Mesh m = surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/vhacd_tube1.off");
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (auto v : m.vertices()) lo = std::min(lo, m.point(v).x()), hi = std::max(hi, m.point(v).x());
  const double c = (lo + hi) / 2, half = (hi - lo) / 2;
  for (auto v : m.vertices()) {
    const auto& p = m.point(v);
    const double u = (p.x() - c) / half;
    m.point(v) = surface::Point(p.x() + 0.3 * (1 - u * u) * half, p.y(), p.z());
  }
  return m;
}

surface::Mesh model(const std::string& name) {
  if (name == "shifted-tube") return shifted_tube();
  if (name == "plate") return test::generated_model(name, 24);
  if (name.find('.') != std::string::npos) return surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/" + name);
  models::ModelParams p;
  p.name = name;
  p.resolution = 24;
  return models::make_model(p);
}

struct Mapped {
  split::Decomposition d;
  polycube::DifferenceMap m;
};

const Mapped& mapped(const std::string& name) {
  static std::map<std::string, Mapped> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  const surface::Mesh mesh = model(name);
  Mapped x;
  x.d = split::split(mesh, classify::classify(mesh, {}), {});
  x.m = polycube::map_difference_surface(x.d, {});
  return cache.emplace(name, std::move(x)).first->second;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class Difference : public ::testing::TestWithParam<const char*> {};

}  // namespace

TEST_P(Difference, SurfaceMapPutsEveryVertexOnThePolycubeWithoutFlips) {
  const Mapped& x = mapped(GetParam());
  const auto& m = x.m;
  ASSERT_EQ(m.holes.size(), 1u);
  EXPECT_EQ(m.holes[0].virtual_component, 1);
  const auto& hole_lo = m.holes[0].lo;
  const auto& hole_hi = m.holes[0].hi;
  EXPECT_EQ(m.flipped_surface_triangles, 0);
  EXPECT_LT(m.max_mismatch, 1e-12) << "a vertex got different points from two patches";
  ASSERT_EQ(static_cast<int>(m.points.size()), m.solid_vertices);
  // The hole runs through the cube along its axis, inside the cube, 0.25 from its sides; centred
  // where the hole is (the symmetric models), moved where it is not. The tube's cube corners are the
  // midpoints of the block's sides (split's choice on this 48-vertex mesh), so its cube axes are
  // diagonal in x-z, and the hole moved along x moves the box along both (measured: 0.069 each,
  // unclamped; the 0.25 margin would allow 0.083).
  std::vector<double> off_centre;
  for (int a = 0; a < 3; ++a) {
    if (a == m.axis) {
      EXPECT_EQ(hole_lo[a], 0.0);
      EXPECT_EQ(hole_hi[a], 1.0);
    } else {
      EXPECT_GE(hole_lo[a], 0.25 - 1e-12);
      EXPECT_LE(hole_hi[a], 0.75 + 1e-12);
      off_centre.push_back(std::abs(hole_lo[a] + hole_hi[a] - 1) / 2);
    }
  }
  for (const double o : off_centre) {
    if (std::string(GetParam()) == "shifted-tube")
      EXPECT_GT(o, 0.05);
    else
      EXPECT_LT(o, 1e-3);
  }
  // Every vertex on a face of the cube or of the hole's box, never inside the hole.
  int off = 0, in_hole = 0;
  for (const auto& p : m.points) {
    double face = 1;
    bool inside_box = true;
    for (int a = 0; a < 3; ++a) {
      face = std::min({face, std::abs(p[a]), std::abs(p[a] - 1)});
      if (a != m.axis) {
        const bool within = p[a] >= hole_lo[a] - 1e-12 && p[a] <= hole_hi[a] + 1e-12;
        if (within && (std::abs(p[a] - hole_lo[a]) < 1e-12 || std::abs(p[a] - hole_hi[a]) < 1e-12)) {
          const int b = 3 - a - m.axis;
          if (p[b] >= hole_lo[b] - 1e-12 && p[b] <= hole_hi[b] + 1e-12) face = 0;  // on a wall
        }
        inside_box = inside_box && p[a] > hole_lo[a] + 1e-9 && p[a] < hole_hi[a] - 1e-9;
      }
    }
    off += face > 1e-12;
    in_hole += inside_box && p[m.axis] > 1e-9 && p[m.axis] < 1 - 1e-9;
  }
  EXPECT_EQ(off, 0) << "vertices off the polycube's boundary";
  EXPECT_EQ(in_hole, 0);
}

TEST_P(Difference, VolumeMapIsOneToOneOntoTheCubeMinusTheHole) {
  const Mapped& x = mapped(GetParam());
  const auto& m = x.m;
  ASSERT_EQ(m.holes.size(), 1u);
  const auto& hole_lo = m.holes[0].lo;
  const auto& hole_hi = m.holes[0].hi;
  const volmap::VolumeMap vm = polycube::difference_volume_map(x.d, m, {});
  EXPECT_EQ(vm.flipped_tets, 0) << vm.flipped_tets_before_untangling << " before untangling, stopped: " << vm.untangle_stop;
  EXPECT_GT(vm.min_volume_ratio, 0);
  EXPECT_EQ(vm.surface_vertices, m.solid_vertices);
  const int a1 = (m.axis + 1) % 3, a2 = (m.axis + 2) % 3;
  const double hole = (hole_hi[a1] - hole_lo[a1]) * (hole_hi[a2] - hole_lo[a2]);
  EXPECT_NEAR(vm.parameter_volume, 1 - hole, 1e-9) << "the boundary lies on the polycube's planar faces";

  const volmap::Locator locate(vm);
  const surface::Mesh solid = polycube::difference_solid(x.d, m);
  CGAL::Side_of_triangle_mesh<surface::Mesh, surface::Kernel> inside(solid);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.01, 0.99);
  test::LocateCounts c;
  for (int tried = 0; tried < 2000;) {
    const std::array<double, 3> p{u(rng), u(rng), u(rng)};
    bool in_box = true;
    for (int a : {a1, a2}) in_box = in_box && p[a] > hole_lo[a] - 0.01 && p[a] < hole_hi[a] + 0.01;
    if (in_box) continue;
    ++tried;
    test::locate_point(locate, inside, p, c);
  }
  test::expect_all_located(c);
  // A point inside the hole is outside the domain.
  std::array<double, 3> centre{0.5, 0.5, 0.5};
  EXPECT_FALSE(locate.physical(centre).has_value());
}

TEST_P(Difference, StageFilePayloadRoundTrips) {
  const auto& m = mapped(GetParam()).m;
  const polycube::DifferenceMap r = polycube::difference_from_json(polycube::to_json(m), "polycube.stage.json");
  EXPECT_EQ(r.axis, m.axis);
  ASSERT_EQ(r.holes.size(), 1u);
  EXPECT_EQ(r.holes[0].virtual_component, m.holes[0].virtual_component);
  EXPECT_EQ(r.holes[0].lo, m.holes[0].lo);
  EXPECT_EQ(r.holes[0].hi, m.holes[0].hi);
  EXPECT_EQ(r.points, m.points);
  // One hole: the one-hole format (virtual_component, hole_lo, hole_hi), no "holes".
  const core::Json j = polycube::to_json(m);
  EXPECT_FALSE(j.contains("holes"));
  EXPECT_EQ((j["hole_lo"].get<std::array<double, 3>>()), m.holes[0].lo);
  core::Json bad = polycube::to_json(m);
  bad["hole_lo"][static_cast<std::size_t>((m.axis + 1) % 3)] = 0.0;  // the hole would touch the cube's side
  EXPECT_THROW(polycube::difference_from_json(bad, "p.json"), core::InvalidInputError);
}

INSTANTIATE_TEST_SUITE_P(Models, Difference, ::testing::Values("cube-with-hole", "vhacd_tube1.off", "shifted-tube"), [](const auto& info) {
  std::string s = info.param;
  s = s.substr(0, s.find('.'));
  std::replace(s.begin(), s.end(), '-', '_');
  return s;
});

// Component graphs that are not one cube minus through holes are topology errors naming them.
TEST(DifferenceGraph, UnrealizableComponentGraphsNameTheComponents) {
  const split::Decomposition& d = mapped("vhacd_tube1.off").d;
  auto message = [](const split::Decomposition& x) {
    try {
      polycube::map_difference_surface(x, {});
    } catch (const core::TopologyError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  {
    split::Decomposition x = d;  // a second cube
    x.components.push_back(x.components[0]);
    const std::string s = message(x);
    EXPECT_TRUE(has(s, "the components are 0 (cube), 1 (virtual), 2 (cube)")) << s;
  }
  {
    split::Decomposition x = d;  // two virtual components, each meeting the cube on one fill (two blind holes)
    x.components.push_back(x.components[1]);
    (x.contacts[1].a == 1 ? x.contacts[1].a : x.contacts[1].b) = 2;
    const std::string s = message(x);
    EXPECT_TRUE(has(s, "hole 0 (virtual component 1) meets the cube 0 on 1 filled patches") && has(s, "blind")) << s;
  }
  {
    split::Decomposition x = d;  // a blind hole: one fill
    x.contacts.pop_back();
    const std::string s = message(x);
    EXPECT_TRUE(has(s, "on 1 filled patches") && has(s, "blind")) << s;
  }
  {
    split::Decomposition x = d;  // meeting on a cross section
    x.contacts[0].via = "internal_face";
    const std::string s = message(x);
    EXPECT_TRUE(has(s, "components 0 and 1 meet via internal_face")) << s;
  }
}

// The cube frame from a cube's edge graph, whatever the corners' numbering: every edge joins
// corners whose codes differ in one bit, and the 8 codes are distinct. Other graphs are refused.
TEST(CubeFrame, AnyNumberingOfACubeGraphGivesACubeFrame) {
  std::mt19937 rng(3);
  std::array<int, 8> perm{0, 1, 2, 3, 4, 5, 6, 7};
  for (int trial = 0; trial < 500; ++trial) {
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<std::set<int>> adj(8);
    for (int c = 0; c < 8; ++c)
      for (int bit : {1, 2, 4}) adj[static_cast<std::size_t>(perm[c])].insert(perm[c ^ bit]);
    const std::vector<int> code = polycube::detail::cube_codes(adj);
    EXPECT_EQ(std::set<int>(code.begin(), code.end()).size(), 8u);
    for (int v = 0; v < 8; ++v)
      for (int w : adj[static_cast<std::size_t>(v)]) {
        const int x = code[static_cast<std::size_t>(v)] ^ code[static_cast<std::size_t>(w)];
        ASSERT_TRUE(x == 1 || x == 2 || x == 4) << "trial " << trial;
      }
  }
  std::vector<std::set<int>> ring(8);  // an 8-cycle is not a cube
  for (int c = 0; c < 8; ++c) ring[static_cast<std::size_t>(c)] = {(c + 1) % 8, (c + 7) % 8};
  EXPECT_THROW(polycube::detail::cube_codes(ring), core::TopologyError);
}


namespace {

// The plate's frame: cube corner (0,0,0) at `origin`, cube axis a along `edge[a]` (physical), from
// the solid vertices mapped onto the cube's corners.
struct Frame {
  std::array<double, 3> origin{};
  std::array<std::array<double, 3>, 3> edge{};
};

Frame cube_frame(const Mapped& x) {
  const auto& m = x.m;
  auto vertex_at = [&](const std::array<double, 3>& q) {
    for (std::size_t v = 0; v < m.points.size(); ++v)
      if (m.points[v] == q) return x.d.layout.points[v];
    ADD_FAILURE() << "no vertex at a cube corner";
    return std::array<double, 3>{0, 0, 0};
  };
  Frame f;
  f.origin = vertex_at({0, 0, 0});
  for (int a = 0; a < 3; ++a) {
    std::array<double, 3> e{0, 0, 0};
    e[static_cast<std::size_t>(a)] = 1;
    const auto p = vertex_at(e);
    for (int k = 0; k < 3; ++k) f.edge[static_cast<std::size_t>(a)][static_cast<std::size_t>(k)] = p[static_cast<std::size_t>(k)] - f.origin[static_cast<std::size_t>(k)];
  }
  return f;
}

double dot3(const std::array<double, 3>& p, const std::array<double, 3>& q) { return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]; }

// Triangles of the holed faces (all three points on the cube face axis = 0 or 1) that turn against
// the majority of their face in the cube's cross coordinates, or are degenerate.
int flipped_on_holed_faces(const Mapped& x) {
  const auto& m = x.m;
  const auto& L = x.d.layout;
  const int a1 = (m.axis + 1) % 3, a2 = (m.axis + 2) % 3;
  int flipped = 0;
  for (const double face : {0.0, 1.0}) {
    int positive = 0, negative = 0;
    for (std::size_t t = 0; t < L.triangles.size(); ++t) {
      if (L.filled[t]) continue;
      const auto& tr = L.triangles[t];
      bool on = true;
      for (int v : tr) on = on && m.points[static_cast<std::size_t>(v)][static_cast<std::size_t>(m.axis)] == face;
      if (!on) continue;
      const auto& p = m.points[static_cast<std::size_t>(tr[0])];
      const auto& q = m.points[static_cast<std::size_t>(tr[1])];
      const auto& r = m.points[static_cast<std::size_t>(tr[2])];
      const double area = (q[a1] - p[a1]) * (r[a2] - p[a2]) - (q[a2] - p[a2]) * (r[a1] - p[a1]);
      (area > 0 ? positive : negative) += 1;
    }
    flipped += std::min(positive, negative);
  }
  return flipped;
}

}  // namespace

// The plate, [-2,2] x [-1.5,1.5] x [-0.25,0.25] minus four cylinders of radius 0.3 along z at
// (+-1.5, +-1): split makes it a cube minus four virtual components; each gets its box where its
// hole is. The plate's faces are planar, so the rims' bilinear coordinates are affine in space:
// the boxes are the holes' extents in the plate's bounding box (measured: exact to rounding, e.g.
// [0.05, 0.2] x [0.0667, 0.2667] for the hole at (-1.5, -1)).
TEST(DifferencePlate, FourParallelHolesGetTheirBoxesWhereTheHolesAre) {
  const Mapped& x = mapped("plate");
  const auto& m = x.m;
  ASSERT_EQ(m.holes.size(), 4u);
  EXPECT_LT(m.max_mismatch, 1e-9);
  ASSERT_EQ(static_cast<int>(m.points.size()), m.solid_vertices);
  for (const auto& p : m.points)
    for (const double c : p) ASSERT_TRUE(c >= 0 && c <= 1) << "a point outside [0,1]^3";
  const int a1 = (m.axis + 1) % 3, a2 = (m.axis + 2) % 3;
  for (std::size_t h = 0; h < 4; ++h) {
    EXPECT_EQ(m.holes[h].virtual_component, static_cast<int>(h) + 1) << "one hole per virtual component, in component order";
    EXPECT_EQ(m.holes[h].lo[static_cast<std::size_t>(m.axis)], 0.0);
    EXPECT_EQ(m.holes[h].hi[static_cast<std::size_t>(m.axis)], 1.0);
  }
  // The cube's axes in space: the holes' axis along z, the cross axes along x and y.
  const Frame f = cube_frame(x);
  EXPECT_NEAR(std::abs(f.edge[static_cast<std::size_t>(m.axis)][2]), 0.5, 1e-12);
  for (const int a : {a1, a2}) {
    const auto& e = f.edge[static_cast<std::size_t>(a)];
    EXPECT_NEAR(e[2], 0, 1e-12);
    EXPECT_NEAR(std::abs(e[0]) * std::abs(e[1]), 0, 1e-12) << "a cross axis is not along x or y";
  }
  // Each physical hole matches one box: centre within 0.02 of the hole's in cube units, size the
  // square of the rim's length: pi/4 of the diameter (a 24-gon's perimeter: 0.786), within 0.01.
  std::set<std::size_t> matched;
  std::vector<std::array<double, 2>> centres;  // per hole (box order): its physical centre
  centres.resize(4);
  for (const double cx : {-1.5, 1.5})
    for (const double cy : {-1.0, 1.0}) {
      const std::array<double, 3> c{cx - f.origin[0], cy - f.origin[1], 0};
      std::array<double, 2> want{}, size{};
      for (int b = 0; b < 2; ++b) {
        const auto& e = f.edge[static_cast<std::size_t>(b == 0 ? a1 : a2)];
        want[static_cast<std::size_t>(b)] = dot3(c, e) / dot3(e, e);
        size[static_cast<std::size_t>(b)] = 0.6 * 3.14159265358979323846 / 4 / std::sqrt(dot3(e, e));
      }
      std::size_t best = 4;
      double best_d = HUGE_VAL;
      for (std::size_t h = 0; h < 4; ++h) {
        const auto& H = m.holes[h];
        const double d = std::hypot((H.lo[static_cast<std::size_t>(a1)] + H.hi[static_cast<std::size_t>(a1)]) / 2 - want[0],
                                    (H.lo[static_cast<std::size_t>(a2)] + H.hi[static_cast<std::size_t>(a2)]) / 2 - want[1]);
        if (d < best_d) best_d = d, best = h;
      }
      ASSERT_LT(best, 4u);
      EXPECT_TRUE(matched.insert(best).second) << "two holes on one box";
      centres[best] = {cx, cy};
      const auto& H = m.holes[best];
      for (int b = 0; b < 2; ++b) {
        const auto a = static_cast<std::size_t>(b == 0 ? a1 : a2);
        EXPECT_NEAR((H.lo[a] + H.hi[a]) / 2, want[static_cast<std::size_t>(b)], 0.02) << "hole at (" << cx << ", " << cy << ")";
        EXPECT_NEAR(H.hi[a] - H.lo[a], size[static_cast<std::size_t>(b)], 0.01) << "hole at (" << cx << ", " << cy << ")";
      }
    }
  // Disjoint boxes, and holes in one row or column share their grid lines exactly (snapped).
  for (std::size_t h = 0; h < 4; ++h)
    for (std::size_t g = h + 1; g < 4; ++g) {
      bool apart = false;
      for (const int a : {a1, a2}) {
        const auto k = static_cast<std::size_t>(a);
        apart = apart || m.holes[h].hi[k] < m.holes[g].lo[k] || m.holes[g].hi[k] < m.holes[h].lo[k];
        const auto& e = f.edge[k];
        const int phys = std::abs(e[0]) > std::abs(e[1]) ? 0 : 1;
        if (centres[h][static_cast<std::size_t>(phys)] == centres[g][static_cast<std::size_t>(phys)]) {
          EXPECT_EQ(m.holes[h].lo[k], m.holes[g].lo[k]) << "holes " << h << " and " << g << " along cube axis " << a;
          EXPECT_EQ(m.holes[h].hi[k], m.holes[g].hi[k]) << "holes " << h << " and " << g << " along cube axis " << a;
        }
      }
      EXPECT_TRUE(apart) << "boxes " << h << " and " << g << " overlap or touch";
    }
  // Each hole's rim vertices lie on its box's boundary, on the holed faces.
  for (const auto& c : x.d.contacts) {
    ASSERT_EQ(c.via, "filled_patch");
    const auto& H = m.holes[static_cast<std::size_t>(std::max(c.a, c.b) - 1)];
    int off = 0, n = 0;
    for (const auto& side : x.d.layout.patches[static_cast<std::size_t>(c.index)].sides)
      for (const int v : side) {
        ASSERT_LT(v, m.solid_vertices);
        const auto& p = m.points[static_cast<std::size_t>(v)];
        const auto k1 = static_cast<std::size_t>(a1), k2 = static_cast<std::size_t>(a2);
        auto at = [](double y, double z) { return std::abs(y - z) < 1e-12; };
        auto in = [](double y, double lo, double hi) { return y >= lo - 1e-12 && y <= hi + 1e-12; };
        const bool on = (at(p[k1], H.lo[k1]) || at(p[k1], H.hi[k1])) ? in(p[k2], H.lo[k2], H.hi[k2])
                        : (at(p[k2], H.lo[k2]) || at(p[k2], H.hi[k2])) && in(p[k1], H.lo[k1], H.hi[k1]);
        const double w = p[static_cast<std::size_t>(m.axis)];
        off += !on || (w != 0 && w != 1);
        ++n;
      }
    EXPECT_GT(n, 8);
    EXPECT_EQ(off, 0) << "rim vertices of fill patch " << c.index << " off hole " << std::max(c.a, c.b) - 1 << "'s box";
  }
  // No flipped triangle: the bilinear patches (outer faces, walls), and the holed faces' harmonic
  // map with its rims on boxes of the rims' length (on their bounding squares, 10 flipped at the
  // boxes' corners: the circle's diagonal points went 1.41 radii out).
  const int holed = flipped_on_holed_faces(x);
  EXPECT_EQ(holed, 0);
  EXPECT_EQ(m.flipped_surface_triangles, holed) << "flipped triangles off the holed faces";
}

// Holes along different cube axes, and boxes within 1e-3 of the cube's sides, are refused naming
// the holes.
TEST(DifferencePlate, HolesAlongDifferentAxesAreRefused) {
  const split::Decomposition& d = mapped("plate").d;
  split::Decomposition x = d;
  // Virtual component 2's contacts moved onto the cube's faces x = -2 and x = +2 (as if its fills
  // lay there): that hole would run along x, the others along z.
  const auto& L = x.layout;
  auto face_patch = [&](double px) {
    for (int p : x.components[0].patches) {
      bool on = true;
      for (int v : L.patches[static_cast<std::size_t>(p)].corners) on = on && L.points[static_cast<std::size_t>(v)][0] == px;
      if (on) return p;
    }
    ADD_FAILURE() << "no cube face on x = " << px;
    return -1;
  };
  int moved = 0;
  for (auto& c : x.contacts)
    if (std::max(c.a, c.b) == 2) c.index = face_patch(moved++ == 0 ? -2.0 : 2.0);
  ASSERT_EQ(moved, 2);
  try {
    polycube::map_difference_surface(x, {});
    ADD_FAILURE() << "no error";
  } catch (const core::TopologyError& e) {
    const std::string s = e.what();
    EXPECT_TRUE(has(s, "hole 1 (virtual component 2) runs along cube axis") && has(s, "hole 0 (virtual component 1) along axis")) << s;
  }
}

// The stage file's payload with four holes: "holes", no one-hole keys; read back bitwise, also
// through text; malformed hole lists are refused naming the file.
TEST(DifferencePlate, StageFilePayloadWithFourHolesRoundTrips) {
  const auto& m = mapped("plate").m;
  const core::Json j = polycube::to_json(m);
  EXPECT_FALSE(j.contains("virtual_component") || j.contains("hole_lo") || j.contains("hole_hi"));
  ASSERT_TRUE(j.contains("holes"));
  ASSERT_EQ(j["holes"].size(), 4u);
  for (std::size_t h = 0; h < 4; ++h) {
    EXPECT_EQ(j["holes"][h]["virtual_component"], m.holes[h].virtual_component);
    EXPECT_EQ((j["holes"][h]["hole_lo"].get<std::array<double, 3>>()), m.holes[h].lo);
    EXPECT_EQ((j["holes"][h]["hole_hi"].get<std::array<double, 3>>()), m.holes[h].hi);
  }
  for (const core::Json& k : {j, core::Json::parse(j.dump())}) {
    const polycube::DifferenceMap r = polycube::difference_from_json(k, "polycube.stage.json");
    EXPECT_EQ(r.cube, m.cube);
    EXPECT_EQ(r.axis, m.axis);
    EXPECT_EQ(r.mirrored, m.mirrored);
    ASSERT_EQ(r.holes.size(), 4u);
    for (std::size_t h = 0; h < 4; ++h) {
      EXPECT_EQ(r.holes[h].virtual_component, m.holes[h].virtual_component);
      EXPECT_EQ(r.holes[h].lo, m.holes[h].lo);
      EXPECT_EQ(r.holes[h].hi, m.holes[h].hi);
    }
    EXPECT_EQ(r.points, m.points);
    EXPECT_EQ(polycube::to_json(r), j);
  }
  auto refused = [](const core::Json& bad, const std::string& part) {
    try {
      polycube::difference_from_json(bad, "p.json");
    } catch (const core::InvalidInputError& e) {
      const std::string s = e.what();
      EXPECT_TRUE(has(s, "p.json") && has(s, part)) << s;
      return;
    }
    ADD_FAILURE() << "accepted, expected an error with " << part;
  };
  const auto a1 = static_cast<std::size_t>((m.axis + 1) % 3);
  core::Json bad = j;
  bad["holes"][1]["hole_lo"] = bad["holes"][0]["hole_lo"], bad["holes"][1]["hole_hi"] = bad["holes"][0]["hole_hi"];
  refused(bad, "overlap");
  bad = j;
  bad["holes"][2]["hole_hi"][a1] = 1.0;  // through the cube's side
  refused(bad, "polycube.holes[2]");
  bad = j;
  bad["holes"][3]["virtual_component"] = m.holes[0].virtual_component;
  refused(bad, "same virtual component");
  bad = j;
  bad["hole_lo"] = j["holes"][0]["hole_lo"];
  refused(bad, "both");
  bad = j;
  bad["holes"] = core::Json::array();
  refused(bad, "holes");
  bad = j;
  bad["holes"][0].erase("hole_hi");
  refused(bad, "hole_hi");
}

// A one-hole payload as stage files have always held it reads as one hole and writes back as it was.
TEST(DifferenceJson, ReadsTheOneHoleFormat) {
  const core::Json j{{"kind", "difference"},
                     {"cube", 0},
                     {"virtual_component", 1},
                     {"axis", 2},
                     {"hole_lo", {0.25, 0.375, 0.0}},
                     {"hole_hi", {0.75, 0.625, 1.0}},
                     {"mirrored", false},
                     {"solid_vertices", 4},
                     {"points", {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}},
                     {"flipped_surface_triangles", 0},
                     {"max_angle_distortion_deg", 1.5},
                     {"max_mismatch", 0.0}};
  const polycube::DifferenceMap m = polycube::difference_from_json(j, "polycube.stage.json");
  ASSERT_EQ(m.holes.size(), 1u);
  EXPECT_EQ(m.holes[0].virtual_component, 1);
  EXPECT_EQ(m.holes[0].lo, (std::array<double, 3>{0.25, 0.375, 0.0}));
  EXPECT_EQ(m.holes[0].hi, (std::array<double, 3>{0.75, 0.625, 1.0}));
  EXPECT_EQ(m.points.size(), 4u);
  EXPECT_EQ(polycube::to_json(m), j);
  EXPECT_EQ(polycube::to_json(m).dump(), j.dump());
}

// The assembly (Liu et al. 2013, Fig. 1): split's union of the plate minus four holes and a ring
// standing on its foot, as two pieces. The ring is a closed torus of its four cubes with the foot
// as a whole patch; the base is the plate closed by the foot (the foot's triangles not fills),
// mapped as a difference whose foot is a rectangle of its top face: apart from the holes' boxes,
// where the foot lies (the plate's centre), every foot vertex on it, no flipped triangle (at 16
// the kernel unfolding takes 3 flips beside the rectangle's corners away; at 24 one is left that
// only fixing the corners' fans takes away).
TEST(DifferenceFoot, AssemblysRingStandsOnARectangleOfThePlatesTopFace) {
  for (const int res : {16, 24}) {
    SCOPED_TRACE("resolution " + std::to_string(res));
    const surface::Mesh mesh = test::generated_model("assembly", res);
    const split::Decomposition d = split::split(mesh, classify::classify(mesh, {}), {});
    const polycube::TorusOnCube pieces = polycube::torus_on_cube(d);
    EXPECT_EQ(pieces.ring.component, (std::vector<int>{5, 6, 7, 8}));
    EXPECT_EQ(pieces.base.component, (std::vector<int>{0, 1, 2, 3, 4}));
    const auto& B = pieces.base.decomposition.layout;
    ASSERT_EQ(pieces.foot_patch, static_cast<int>(B.patches.size()) - 1);
    for (int t : B.patches[static_cast<std::size_t>(pieces.foot_patch)].triangles) EXPECT_EQ(B.filled[static_cast<std::size_t>(t)], 0);
    EXPECT_GT(std::count(B.filled.begin(), B.filled.end(), 1), 0) << "the holes' fills stay fills";
    const polycube::TorusSurfaceMap ring = polycube::map_torus_surface(pieces.ring.decomposition, {});
    EXPECT_EQ(ring.flipped_surface_triangles, 0);

    const polycube::DifferenceMap m = polycube::map_difference_surface(pieces.base.decomposition, {}, pieces.foot_patch);
    EXPECT_EQ(m.flipped_surface_triangles, 0);
    EXPECT_LT(m.max_mismatch, 1e-9);
    ASSERT_EQ(m.holes.size(), 4u);
    ASSERT_TRUE(m.foot.has_value());
    const auto& F = *m.foot;
    const int ax = m.axis, a1 = (ax + 1) % 3, a2 = (ax + 2) % 3;
    EXPECT_EQ(F.lo[ax], F.hi[ax]);
    // The foot (|x| <= 0.85, |y| <= 0.3 on the 4 x 3 plate) is about the middle of its face.
    for (const int a : {a1, a2}) EXPECT_NEAR((F.lo[a] + F.hi[a]) / 2, 0.5, 0.05);
    for (const auto& H : m.holes) {
      bool apart = false;
      for (const int a : {a1, a2}) apart = apart || H.hi[a] < F.lo[a] || F.hi[a] < H.lo[a];
      EXPECT_TRUE(apart);
    }
    std::set<std::pair<double, double>> corners;
    const auto& P = B.patches[static_cast<std::size_t>(pieces.foot_patch)];
    for (int t : P.triangles)
      for (int v : B.triangles[static_cast<std::size_t>(t)]) {
        const auto& q = m.points[static_cast<std::size_t>(v)];
        EXPECT_EQ(q[ax], F.lo[ax]);
        for (const int a : {a1, a2}) {
          EXPECT_GE(q[a], F.lo[a] - 1e-12);
          EXPECT_LE(q[a], F.hi[a] + 1e-12);
        }
      }
    for (int v : P.corners) corners.insert({m.points[static_cast<std::size_t>(v)][a1], m.points[static_cast<std::size_t>(v)][a2]});
    EXPECT_EQ(corners, (std::set<std::pair<double, double>>{{F.lo[a1], F.lo[a2]}, {F.hi[a1], F.lo[a2]}, {F.hi[a1], F.hi[a2]}, {F.lo[a1], F.hi[a2]}}));
    // The stage file's form.
    const polycube::DifferenceMap back = polycube::difference_from_json(polycube::to_json(m), "test");
    ASSERT_TRUE(back.foot.has_value());
    EXPECT_EQ(back.foot->patch, F.patch);
    EXPECT_EQ(back.foot->lo, F.lo);
    EXPECT_EQ(back.foot->hi, F.hi);
    core::Json bad = polycube::to_json(m);
    bad["foot"]["lo"] = m.holes[0].lo;
    bad["foot"]["hi"] = m.holes[0].hi;
    bad["foot"]["lo"][static_cast<std::size_t>(ax)] = bad["foot"]["hi"][static_cast<std::size_t>(ax)] = F.lo[ax];
    EXPECT_THROW(polycube::difference_from_json(bad, "test"), core::InvalidInputError);
  }
  // Two tori are no torus on a cube.
  const surface::Mesh eight = surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/cfwen_eight.off");
  try {
    polycube::torus_on_cube(split::split(eight, classify::classify(eight, {}), {}));
    ADD_FAILURE() << "no error";
  } catch (const core::TopologyError& e) {
    EXPECT_TRUE(has(e.what(), "2 tori")) << e.what();
  }
}
