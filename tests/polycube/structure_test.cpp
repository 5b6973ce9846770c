// The polycube structure (Liu et al. §4.2–4.3, Fig. 6): every union and difference case of Fig. 6,
// over families (the 24 rotations of each case, each cube in its own rotated and scaled frame).
// Properties checked on every valid structure: each face is tiled by its glued, boundary and
// virtual regions (areas add up to the face's); gluings are symmetric (a's glued regions map into
// b's and back, maps inverse of each other); a point of a shared face maps through the gluing to
// the same developed point (a torus's ring: shifted by one constant period); JSON round trip.
// Unrealizable inputs throw TopologyError naming the components; bad JSON InvalidInputError.
#include "polycube/structure.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "core/errors.h"

using namespace volts;
using polycube::AxisMap;
using polycube::Box;
using polycube::FaceRegion;
using polycube::Point;
using polycube::Rect;
using polycube::RegionKind;
using polycube::Structure;

namespace {

Box box(double x0, double y0, double z0, double x1, double y1, double z1) { return Box{{x0, y0, z0}, {x1, y1, z1}}; }
double area(const Rect& r) { return (r.hi[0] - r.lo[0]) * (r.hi[1] - r.lo[1]); }
bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::array<int, 2> face_axes(int f) { return {(f / 2 + 1) % 3, (f / 2 + 2) % 3}; }
Point on_face(const Box& b, int f, double s, double t) {
  Point p;
  p[f / 2] = f % 2 ? b.hi[f / 2] : b.lo[f / 2];
  p[face_axes(f)[0]] = s, p[face_axes(f)[1]] = t;
  return p;
}
std::array<double, 2> st(const Point& p, int f) { return {p[face_axes(f)[0]], p[face_axes(f)[1]]}; }
bool inside(const Rect& r, const std::array<double, 2>& p) { return r.lo[0] <= p[0] && p[0] <= r.hi[0] && r.lo[1] <= p[1] && p[1] <= r.hi[1]; }
bool same(const AxisMap& a, const AxisMap& b) { return a.axis == b.axis && a.scale == b.scale && a.offset == b.offset; }
bool same(const Box& a, const Box& b) { return a.lo == b.lo && a.hi == b.hi; }

// The 24 rotations of [0,1]^3 onto itself: signed axis permutations with det +1.
std::vector<AxisMap> rotations() {
  std::vector<AxisMap> out;
  std::array<int, 3> perm{0, 1, 2};
  do {
    for (int signs = 0; signs < 8; ++signs) {
      AxisMap m;
      m.axis = perm;
      int det = (perm[0] > perm[1]) + (perm[0] > perm[2]) + (perm[1] > perm[2]);
      for (int k = 0; k < 3; ++k) {
        m.scale[k] = signs >> k & 1 ? -1 : 1;
        m.offset[k] = signs >> k & 1 ? 1 : 0;
        det += signs >> k & 1;
      }
      if (det % 2 == 0) out.push_back(m);
    }
  } while (std::next_permutation(perm.begin(), perm.end()));
  return out;
}

// Cube c's own frame: `rot` of the unit cube its box is scaled onto (box sizes are dyadic, so exact).
AxisMap unit_frame(const Box& b, const AxisMap& rot) {
  AxisMap to_unit;
  for (int k = 0; k < 3; ++k) to_unit.scale[k] = 1 / (b.hi[k] - b.lo[k]), to_unit.offset[k] = -b.lo[k] / (b.hi[k] - b.lo[k]);
  return polycube::compose(rot, to_unit);
}

void expect_same(const Structure& a, const Structure& b) {
  ASSERT_EQ(a.cubes.size(), b.cubes.size());
  for (std::size_t i = 0; i < a.cubes.size(); ++i) {
    EXPECT_EQ(a.cubes[i].label, b.cubes[i].label);
    EXPECT_TRUE(same(a.cubes[i].box, b.cubes[i].box));
    EXPECT_EQ(a.cubes[i].primitive, b.cubes[i].primitive);
  }
  ASSERT_EQ(a.primitives.size(), b.primitives.size());
  for (std::size_t i = 0; i < a.primitives.size(); ++i) {
    EXPECT_EQ(a.primitives[i].label, b.primitives[i].label);
    EXPECT_EQ(a.primitives[i].torus, b.primitives[i].torus);
    EXPECT_EQ(a.primitives[i].cubes, b.primitives[i].cubes);
  }
  ASSERT_EQ(a.gluings.size(), b.gluings.size());
  for (std::size_t i = 0; i < a.gluings.size(); ++i) {
    const auto &x = a.gluings[i], &y = b.gluings[i];
    EXPECT_EQ(std::tie(x.a, x.fa, x.b, x.fb, x.closes_torus), std::tie(y.a, y.fa, y.b, y.fb, y.closes_torus));
    EXPECT_EQ(x.rect_a.lo, y.rect_a.lo);
    EXPECT_EQ(x.rect_a.hi, y.rect_a.hi);
    EXPECT_TRUE(same(x.map, y.map));
  }
  ASSERT_EQ(a.virtual_components.size(), b.virtual_components.size());
  for (std::size_t i = 0; i < a.virtual_components.size(); ++i) {
    const auto &x = a.virtual_components[i], &y = b.virtual_components[i];
    EXPECT_EQ(std::tie(x.label, x.cube, x.torus), std::tie(y.label, y.cube, y.torus));
    ASSERT_EQ(x.boxes.size(), y.boxes.size());
    for (std::size_t k = 0; k < x.boxes.size(); ++k) EXPECT_TRUE(same(x.boxes[k], y.boxes[k]));
  }
  ASSERT_EQ(a.contacts.size(), b.contacts.size());
  for (std::size_t i = 0; i < a.contacts.size(); ++i) {
    const auto &x = a.contacts[i], &y = b.contacts[i];
    EXPECT_EQ(std::tie(x.label, x.a, x.fa, x.b, x.fb), std::tie(y.label, y.a, y.fa, y.b, y.fb));
  }
}

// Area of cube c's regions of `kind`.
double kind_area(const Structure& s, int c, RegionKind kind) {
  double a = 0;
  for (const auto& r : polycube::boundary_regions(s, c))
    if (r.kind == kind) a += area(r.rect);
  return a;
}

// What every valid structure satisfies (file comment).
void expect_polycube(const Structure& s) {
  ASSERT_NO_THROW(polycube::check(s));
  const auto dev = polycube::develop(s);
  std::vector<std::vector<FaceRegion>> regions;
  for (std::size_t c = 0; c < s.cubes.size(); ++c) regions.push_back(polycube::boundary_regions(s, static_cast<int>(c)));
  for (std::size_t c = 0; c < s.cubes.size(); ++c)
    for (int f = 0; f < 6; ++f) {
      const Rect whole = polycube::face_rect(s.cubes[c].box, f);
      double glued = 0, boundary = 0, opening = 0;
      std::vector<Rect> mine;
      for (const auto& r : regions[c]) {
        if (r.face != f) continue;
        EXPECT_TRUE(inside(whole, r.rect.lo) && inside(whole, r.rect.hi));
        (r.kind == RegionKind::glued ? glued : r.kind == RegionKind::boundary ? boundary : opening) += area(r.rect);
        EXPECT_EQ(r.kind == RegionKind::glued, r.gluing >= 0 && r.virtual_component < 0);
        for (const auto& o : mine)
          EXPECT_TRUE(std::min(o.hi[0], r.rect.hi[0]) <= std::max(o.lo[0], r.rect.lo[0]) ||
                      std::min(o.hi[1], r.rect.hi[1]) <= std::max(o.lo[1], r.rect.lo[1]))
              << "regions overlap";
        mine.push_back(r.rect);
      }
      EXPECT_EQ(glued + boundary + opening, area(whole)) << "cube " << c << " face " << f;
    }
  for (std::size_t g = 0; g < s.gluings.size(); ++g) {
    const auto& x = s.gluings[g];
    SCOPED_TRACE("gluing " + std::to_string(g));
    const AxisMap back = polycube::inverse(x.map);
    EXPECT_TRUE(same(polycube::compose(x.map, back), AxisMap{}));
    EXPECT_TRUE(same(polycube::compose(back, x.map), AxisMap{}));
    // a's regions of this gluing land in b's and back; areas agree up to the map's scales.
    auto lands = [&](int from, int from_face, int to, int to_face, const AxisMap& m) {
      double a = 0;
      for (const auto& r : regions[from]) {
        if (r.gluing != static_cast<int>(g) || r.face != from_face) continue;
        EXPECT_EQ(r.neighbor, to);
        a += area(r.rect);
        for (const auto& p : {r.rect.lo, r.rect.hi, std::array<double, 2>{(r.rect.lo[0] + r.rect.hi[0]) / 2, (r.rect.lo[1] + r.rect.hi[1]) / 2}}) {
          const auto q = st(polycube::apply(m, on_face(s.cubes[from].box, from_face, p[0], p[1])), to_face);
          EXPECT_TRUE(std::any_of(regions[to].begin(), regions[to].end(), [&](const FaceRegion& o) {
            return o.gluing == static_cast<int>(g) && o.face == to_face && inside(o.rect, q);
          }));
        }
      }
      return a;
    };
    const auto [ub, vb] = face_axes(x.fb);
    const double area_a = lands(x.a, x.fa, x.b, x.fb, x.map), area_b = lands(x.b, x.fb, x.a, x.fa, back);
    EXPECT_GT(area_a, 0);
    EXPECT_EQ(area_a * std::abs(x.map.scale[ub] * x.map.scale[vb]), area_b);
    // The same developed point on both sides (a torus's closing gluing: one constant period).
    std::vector<Point> shift;
    const Rect& r = x.rect_a;
    for (const auto& p : {r.lo, r.hi, std::array<double, 2>{r.lo[0], r.hi[1]}, std::array<double, 2>{(r.lo[0] + r.hi[0]) / 2, r.lo[1]}}) {
      const Point on_a = on_face(s.cubes[x.a].box, x.fa, p[0], p[1]);
      const Point from_a = polycube::apply(dev[x.a], on_a), from_b = polycube::apply(dev[x.b], polycube::apply(x.map, on_a));
      shift.push_back({from_b[0] - from_a[0], from_b[1] - from_a[1], from_b[2] - from_a[2]});
    }
    for (const auto& d : shift) EXPECT_EQ(d, shift[0]);
    if (x.closes_torus < 0)
      EXPECT_EQ(shift[0], (Point{0, 0, 0}));
    else
      EXPECT_NE(shift[0], (Point{0, 0, 0}));
  }
  const Structure back = polycube::structure_from_json(core::Json::parse(polycube::to_json(s).dump()), "round.json");
  expect_same(s, back);
  EXPECT_EQ(polycube::to_json(back), polycube::to_json(s));
}

std::string topology_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const core::TopologyError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no TopologyError";
  return {};
}

// Fig. 6(a): cube B on face x = 1 of the unit cube A.
struct UnionCase {
  const char* name;
  Box b;
  double glued;
};
const UnionCase union_cases[] = {
    {"equal faces", box(1, 0, 0, 2, 1, 1), 1},
    {"smaller inside the face", box(1, 0.25, 0.25, 1.5, 0.75, 0.75), 0.25},
    {"flush with one edge", box(1, 0, 0.25, 1.5, 0.5, 0.75), 0.25},
    {"partial, flush with a corner", box(1, 0.5, 0.5, 2, 1.5, 1.5), 0.25},
};

}  // namespace

TEST(structure, MapsComposeInvertAndMapFaces) {
  for (const auto& r : rotations())
    for (const auto& q : rotations()) {
      const AxisMap rq = polycube::compose(r, q);
      const Point x{0.25, 0.5, 0.875};
      EXPECT_EQ(polycube::apply(rq, x), polycube::apply(r, polycube::apply(q, x)));
      EXPECT_TRUE(same(polycube::compose(rq, polycube::inverse(rq)), AxisMap{}));
      for (int f = 0; f < 6; ++f) {  // the face's centre goes to the centre of the face map_face names
        const Point c = polycube::apply(rq, on_face(box(0, 0, 0, 1, 1, 1), f, 0.5, 0.5));
        EXPECT_EQ(c, on_face(box(0, 0, 0, 1, 1, 1), polycube::map_face(rq, f), 0.5, 0.5));
      }
    }
  EXPECT_EQ(rotations().size(), 24u);
}

TEST(structure, Fig6aUnionOfTwoCubesInEveryPositionAndRotation) {
  for (const auto& cs : union_cases)
    for (const auto& rot : rotations()) {
      SCOPED_TRACE(cs.name);
      Structure s;
      const int a = polycube::add_cube(s, "A", polycube::apply(rot, box(0, 0, 0, 1, 1, 1)));
      const int b = polycube::add_cube(s, "B", polycube::apply(rot, cs.b));
      const auto g = polycube::unite(s, a, b);
      ASSERT_EQ(g.size(), 1u);
      EXPECT_EQ(s.gluings[g[0]].fa, polycube::map_face(rot, 1));
      EXPECT_EQ(s.gluings[g[0]].fb, polycube::map_face(rot, 0));
      expect_polycube(s);
      EXPECT_EQ(kind_area(s, 0, RegionKind::glued), cs.glued);
      EXPECT_EQ(kind_area(s, 1, RegionKind::glued), cs.glued);
      EXPECT_EQ(kind_area(s, 0, RegionKind::boundary), 6 - cs.glued);
      EXPECT_EQ(kind_area(s, 0, RegionKind::virtual_opening), 0);
    }
}

// The same unions with each cube in its own frame (unit cube, any rotation): the gluing maps carry
// scales and rotations, and the development puts every cube back where it was.
TEST(structure, Fig6aUnionWithEveryCubeInItsOwnRotatedScaledFrame) {
  const auto rots = rotations();
  for (const auto& cs : union_cases)
    for (std::size_t i = 0; i < rots.size(); ++i) {
      Structure s;
      const int a = polycube::add_cube(s, "A", box(0, 0, 0, 1, 1, 1));
      const int b = polycube::add_cube(s, "B", cs.b);
      polycube::unite(s, a, b);
      polycube::reframe(s, 0, rots[i]);
      polycube::reframe(s, 1, unit_frame(cs.b, rots[(7 * i + 3) % rots.size()]));
      EXPECT_TRUE(same(s.cubes[1].box, box(0, 0, 0, 1, 1, 1)));
      expect_polycube(s);
      const auto dev = polycube::develop(s);
      EXPECT_TRUE(same(polycube::apply(polycube::compose(polycube::inverse(rots[i]), dev[1]), s.cubes[1].box), cs.b)) << cs.name;
      EXPECT_EQ(kind_area(s, 0, RegionKind::glued), cs.glued);
      const double sx = cs.b.hi[1] - cs.b.lo[1], sz = cs.b.hi[2] - cs.b.lo[2];
      EXPECT_EQ(kind_area(s, 1, RegionKind::glued), cs.glued / (sx * sz)) << cs.name;
    }
}

TEST(structure, Fig6aThreeCubesAndARingOfCubes) {
  // An L of three cubes, one of them glued on two faces.
  Structure l;
  const int a = polycube::add_cube(l, "A", box(0, 0, 0, 1, 1, 1));
  const int b = polycube::add_cube(l, "B", box(1, 0, 0, 2, 1, 1));
  const int c = polycube::add_cube(l, "C", box(0, 1, 0, 1, 2, 1));
  polycube::unite(l, a, b);
  polycube::unite(l, a, c);
  expect_polycube(l);
  EXPECT_EQ(kind_area(l, 0, RegionKind::glued), 2);
  // A pinwheel ring of four boxes around a square hole (dyadic sizes: exact frames): a cycle whose maps compose to the identity.
  Structure ring;
  const std::vector<Box> boxes{box(0, 0, 0, 2, 1, 1), box(2, 0, 0, 3, 2, 1), box(1, 2, 0, 3, 3, 1), box(0, 1, 0, 1, 3, 1)};
  for (std::size_t i = 0; i < 4; ++i) polycube::add_cube(ring, "P" + std::to_string(i), boxes[i]);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(polycube::unite(ring, i, (i + 1) % 4).size(), 1u);
  expect_polycube(ring);
  const auto rots = rotations();
  for (int i = 0; i < 4; ++i) polycube::reframe(ring, i, unit_frame(boxes[i], rots[5 * i + 2]));
  expect_polycube(ring);
}

TEST(structure, Fig6bDifferenceHolesNotchesAndInnerBoxes) {
  struct Case {
    std::string name;
    Box hole;
    std::vector<int> faces;  // the host faces it opens
    double opening, walls;
  };
  std::vector<Case> cases;
  for (int ax = 0; ax < 3; ++ax) {
    Box through = box(0.25, 0.25, 0.25, 0.75, 0.75, 0.75);
    through.lo[ax] = -1, through.hi[ax] = 2;  // clipped to the cube
    cases.push_back({"through hole along " + std::to_string(ax), through, {2 * ax, 2 * ax + 1}, 0.5, 2});
    for (int side = 0; side < 2; ++side) {
      Box blind = box(0.25, 0.25, 0.25, 0.75, 0.75, 0.75);
      (side ? blind.hi : blind.lo)[ax] = side;
      (side ? blind.lo : blind.hi)[ax] = 0.5;
      cases.push_back({"blind hole into face " + std::to_string(2 * ax + side), blind, {2 * ax + side}, 0.25, 1.25});
    }
    for (int su = 0; su < 2; ++su)
      for (int sv = 0; sv < 2; ++sv) {  // a notch along an edge parallel to ax
        const int u = (ax + 1) % 3, v = (ax + 2) % 3;
        Box notch = box(0, 0, 0, 1, 1, 1);
        (su ? notch.lo : notch.hi)[u] = 0.5;
        (sv ? notch.lo : notch.hi)[v] = 0.5;
        cases.push_back({"notch at an edge along " + std::to_string(ax), notch, {2 * ax, 2 * ax + 1, 2 * u + su, 2 * v + sv}, 1.5, 1});
      }
  }
  cases.push_back({"box inside", box(0.25, 0.25, 0.25, 0.75, 0.75, 0.75), {}, 0, 1.5});
  for (const auto& cs : cases) {
    SCOPED_TRACE(cs.name);
    Structure s;
    polycube::add_cube(s, "host", box(0, 0, 0, 1, 1, 1));
    polycube::add_cube(s, "other", box(-1, 0, 0, 0, 1, 1));
    polycube::unite(s, 0, 1);
    const int v = polycube::subtract(s, 0, "hole", {cs.hole});
    expect_polycube(s);
    std::vector<int> opened;
    double opening = 0;
    for (const auto& r : polycube::boundary_regions(s, 0))
      if (r.kind == RegionKind::virtual_opening) {
        EXPECT_EQ(r.virtual_component, v);
        opening += area(r.rect);
        if (std::find(opened.begin(), opened.end(), r.face) == opened.end()) opened.push_back(r.face);
      }
    std::sort(opened.begin(), opened.end());
    auto expected = cs.faces;
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(opened, expected);
    EXPECT_EQ(opening, cs.opening);
    // Face 0 is glued to `other`: an opening there stays glued (the other side keeps its face).
    double glued_face0 = 0;
    for (const auto& r : polycube::boundary_regions(s, 0))
      if (r.face == 0) {
        EXPECT_EQ(r.gluing, 0);
        glued_face0 += area(r.rect);
      }
    EXPECT_EQ(glued_face0, 1);
    EXPECT_EQ(kind_area(s, 1, RegionKind::glued), 1);
    // Walls and openings close the removed box: their signed areas cancel per axis.
    double walls = 0;
    std::array<double, 3> flux{};
    for (const auto& w : polycube::virtual_walls(s, v)) {
      walls += area(w.rect);
      flux[w.face / 2] += (w.face % 2 ? 1 : -1) * area(w.rect);
    }
    for (const auto& r : polycube::boundary_regions(s, 0))
      if (r.kind == RegionKind::virtual_opening) flux[r.face / 2] += (r.face % 2 ? 1 : -1) * area(r.rect);
    EXPECT_EQ(walls, cs.walls);
    EXPECT_EQ(flux, (std::array<double, 3>{0, 0, 0}));
  }
}

TEST(structure, Fig6cCubeUnitedWithATorusOnItsRepresentativeCube) {
  struct Case {
    const char* name;
    Box cube;
    int gluings;
    double glued;
  };
  const Case cases[] = {
      {"on top of the representative", box(0, 0, 1, 1, 1, 2), 1, 1},
      {"smaller, inside its top face", box(0.25, 0.25, 1, 0.75, 0.75, 1.5), 1, 0.25},
      {"beside it", box(0, 1, 0, 1, 2, 1), 1, 1},
      {"across two of the ring's cubes", box(0.5, 0, 1, 1.5, 1, 2), 2, 1},
  };
  for (const auto& cs : cases) {
    SCOPED_TRACE(cs.name);
    Structure s;
    const int t = polycube::add_torus(s, "T", box(0, 0, 0, 1, 1, 1), 0);
    const int c = polycube::add_cube(s, "C", cs.cube);
    const auto g = polycube::unite(s, c, t);
    ASSERT_EQ(g.size(), static_cast<std::size_t>(cs.gluings));
    EXPECT_EQ(s.gluings[g[0]].b, s.primitives[t].cubes[0]) << "the representative cube";
    expect_polycube(s);
    EXPECT_EQ(kind_area(s, 4, RegionKind::glued), cs.glued);
    double torus_glued = 0;
    for (int k = 0; k < 4; ++k) torus_glued += kind_area(s, k, RegionKind::glued);
    EXPECT_EQ(torus_glued, 8 + cs.glued) << "each ring cube glued on two whole faces, plus the cube";
  }
}

// The ring's four maps compose to a translation by the period, whatever frame each cube is in.
TEST(structure, TorusRingComposesToItsPeriodInAnyFrames) {
  const auto rots = rotations();
  for (int ring_axis = 0; ring_axis < 3; ++ring_axis)
    for (std::size_t i = 0; i < rots.size(); ++i) {
      Structure s;
      const int t = polycube::add_torus(s, "T", box(0, 0, 0, 0.5, 0.5, 0.5), ring_axis);
      for (int k = 0; k < 4; ++k) polycube::reframe(s, k, unit_frame(s.cubes[k].box, rots[(i + 5 * k) % rots.size()]));
      expect_polycube(s);
      // Around the ring, starting in cube 0's frame.
      AxisMap around;
      int at = s.primitives[t].cubes[0];
      for (int step = 0; step < 4; ++step) {
        const auto g = std::find_if(s.gluings.begin(), s.gluings.end(), [&](const polycube::Gluing& x) { return x.a == at; });
        ASSERT_NE(g, s.gluings.end());
        around = polycube::compose(g->map, around);
        at = g->b;
      }
      EXPECT_EQ(at, s.primitives[t].cubes[0]);
      EXPECT_EQ(around.axis, (std::array<int, 3>{0, 1, 2}));
      EXPECT_EQ(around.scale, (Point{1, 1, 1}));
      std::array<double, 3> period = around.offset;
      std::sort(period.begin(), period.end(), [](double x, double y) { return std::abs(x) < std::abs(y); });
      EXPECT_EQ(period[0], 0);
      EXPECT_EQ(period[1], 0);
      EXPECT_EQ(std::abs(period[2]), 4) << "four unit cubes";
    }
}

TEST(structure, Fig6dCubeMinusATorus) {
  struct Case {
    const char* name;
    double z0, z1, opening, walls;
  };
  // Ring between [1/8, 7/8]^2 and [3/8, 5/8]^2: 0.5 of area across; lateral perimeters 3 + 1.
  const Case cases[] = {{"inside the cube", 0.25, 0.75, 0, 4 * 0.5 + 2 * 0.5}, {"a groove in the top face", 0.5, 1, 0.5, 4 * 0.5 + 0.5}};
  for (const auto& cs : cases) {
    SCOPED_TRACE(cs.name);
    Structure s;
    polycube::add_cube(s, "host", box(0, 0, 0, 1, 1, 1));
    const int v = polycube::subtract_ring(s, 0, "ring", box(0.125, 0.125, cs.z0, 0.875, 0.875, cs.z1), box(0.375, 0.375, cs.z0, 0.625, 0.625, cs.z1), 2);
    EXPECT_TRUE(s.virtual_components[v].torus);
    ASSERT_EQ(s.virtual_components[v].boxes.size(), 4u);
    double volume = 0;
    for (const auto& b : s.virtual_components[v].boxes) volume += (b.hi[0] - b.lo[0]) * (b.hi[1] - b.lo[1]) * (b.hi[2] - b.lo[2]);
    EXPECT_EQ(volume, 0.5 * (cs.z1 - cs.z0));
    expect_polycube(s);
    EXPECT_EQ(kind_area(s, 0, RegionKind::virtual_opening), cs.opening);
    double walls = 0;
    for (const auto& w : polycube::virtual_walls(s, v)) walls += area(w.rect);
    EXPECT_EQ(walls, cs.walls);
  }
  Structure through;
  polycube::add_cube(through, "host", box(0, 0, 0, 1, 1, 1));
  const auto msg = topology_error([&] {
    polycube::subtract_ring(through, 0, "ring", box(0.125, 0.125, 0, 0.875, 0.875, 1), box(0.375, 0.375, 0, 0.625, 0.625, 1), 2);
  });
  EXPECT_TRUE(has(msg, "'ring'") && has(msg, "'host'") && has(msg, "2 pieces")) << msg;
  EXPECT_TRUE(through.virtual_components.empty());
}

TEST(structure, FaceGluedTwiceIsATopologyErrorNamingTheCubes) {
  Structure s;
  polycube::add_cube(s, "A", box(0, 0, 0, 1, 1, 1));
  polycube::add_cube(s, "B", box(1, 0, 0, 2, 1, 1));
  polycube::add_cube(s, "C", box(0, 0, 0, 1, 1, 1));  // its own frame
  polycube::unite(s, 0, 1);
  AxisMap shift;
  shift.offset[0] = -1;
  const auto msg = topology_error([&] { polycube::glue(s, 0, 1, 2, 0, Rect{{0, 0.5}, {0.5, 1}}, shift); });
  EXPECT_TRUE(has(msg, "'A'") && has(msg, "'B'") && has(msg, "'C'") && has(msg, "glued twice")) << msg;
  EXPECT_EQ(s.gluings.size(), 1u) << "the failed gluing is undone";
  // Written by hand past glue(): check() finds it.
  s.gluings.push_back(polycube::Gluing{0, 1, 2, 0, Rect{{0, 0.5}, {0.5, 1}}, shift, -1});
  const auto again = topology_error([&] { polycube::check(s); });
  EXPECT_TRUE(has(again, "'B'") && has(again, "'C'")) << again;
}

TEST(structure, OverlappingCubesAreATopologyErrorNamingThem) {
  Structure s;
  polycube::add_cube(s, "A", box(0, 0, 0, 1, 1, 1));
  polycube::add_cube(s, "B", box(1, 0, 0, 2, 1, 1));
  polycube::add_cube(s, "C", box(0, 0, 1, 1, 1, 2));
  polycube::add_cube(s, "D", box(1, 0, 0.5, 2, 1, 1.5));
  polycube::unite(s, 0, 1);
  polycube::unite(s, 0, 2);
  polycube::unite(s, 2, 3);
  auto msg = topology_error([&] { polycube::check(s); });
  EXPECT_TRUE(has(msg, "'B'") && has(msg, "'D'") && has(msg, "overlap")) << msg;
  msg = topology_error([&] { polycube::unite(s, 1, 3); });
  EXPECT_TRUE(has(msg, "'B'") && has(msg, "'D'") && has(msg, "overlap")) << msg;
}

TEST(structure, InconsistentCyclesAreATopologyErrorNamingTheCycle) {
  // Three unit cubes, each in its own frame, glued in a row that closes on itself.
  Structure row;
  for (const char* n : {"A", "B", "C"}) polycube::add_cube(row, n, box(0, 0, 0, 1, 1, 1));
  AxisMap shift;
  shift.offset[0] = -1;
  for (int i = 0; i < 3; ++i) polycube::glue(row, i, 1, (i + 1) % 3, 0, Rect{{0, 0}, {1, 1}}, shift);
  auto msg = topology_error([&] { polycube::check(row); });
  EXPECT_TRUE(has(msg, "'A'") && has(msg, "'B'") && has(msg, "'C'") && has(msg, "identity")) << msg;

  // The pinwheel ring in rotated frames, one gluing turned half a turn about its face's centre.
  const std::vector<Box> boxes{box(0, 0, 0, 2, 1, 1), box(2, 0, 0, 3, 2, 1), box(1, 2, 0, 3, 3, 1), box(0, 1, 0, 1, 3, 1)};
  const auto rots = rotations();
  for (std::size_t r = 0; r < rots.size(); r += 5) {
    Structure s;
    for (int i = 0; i < 4; ++i) polycube::add_cube(s, "P" + std::to_string(i), boxes[i]);
    for (int i = 0; i < 4; ++i) polycube::unite(s, i, (i + 1) % 4);
    for (int i = 0; i < 4; ++i) polycube::reframe(s, i, unit_frame(boxes[i], rots[(r + 3 * i) % rots.size()]));
    polycube::Gluing& g = s.gluings[2];
    const Rect rb = polycube::face_rect(polycube::apply(g.map, Box{on_face(s.cubes[g.a].box, g.fa, g.rect_a.lo[0], g.rect_a.lo[1]),
                                                                   on_face(s.cubes[g.a].box, g.fa, g.rect_a.hi[0], g.rect_a.hi[1])}),
                                        g.fb);
    AxisMap half;  // about b's face normal, through the glued rectangle's centre
    const auto [u, v] = face_axes(g.fb);
    half.scale[u] = half.scale[v] = -1;
    half.offset[u] = rb.lo[0] + rb.hi[0], half.offset[v] = rb.lo[1] + rb.hi[1];
    g.map = polycube::compose(half, g.map);
    msg = topology_error([&] { polycube::check(s); });
    EXPECT_TRUE(has(msg, "'P0'") && has(msg, "'P1'") && has(msg, "'P2'") && has(msg, "'P3'")) << msg;
  }

  // A torus whose ring closes with a quarter turn.
  Structure t;
  polycube::add_torus(t, "T", box(0, 0, 0, 1, 1, 1), 0);
  auto closing = std::find_if(t.gluings.begin(), t.gluings.end(), [](const polycube::Gluing& g) { return g.closes_torus == 0; });
  AxisMap quarter;  // about the x axis through (·, 1/2, 1/2)
  quarter.axis = {0, 2, 1};
  quarter.scale = {1, -1, 1};
  quarter.offset = {0, 1, 0};
  closing->map = polycube::compose(quarter, closing->map);
  msg = topology_error([&] { polycube::check(t); });
  EXPECT_TRUE(has(msg, "torus 'T'") && has(msg, "'T/0'") && has(msg, "'T/3'") && has(msg, "translation")) << msg;
}

TEST(structure, AlmostEqualCoordinatesAreATopologyErrorNotAContact) {
  const Box almost[] = {box(1 + 1e-13, 0, 0, 2, 1, 1), box(1, 1e-14, 0.25, 1.5, 0.5, 0.75), box(1, 0.25, 0.25, 1.5, 0.75, 1 - 1e-12),
                        box(1 - 1e-13, 0, 0, 2, 1, 1)};
  for (const auto& b : almost) {
    Structure s;
    polycube::add_cube(s, "A", box(0, 0, 0, 1, 1, 1));
    polycube::add_cube(s, "B", b);
    const auto msg = topology_error([&] { polycube::unite(s, 0, 1); });
    EXPECT_TRUE(has(msg, "'A'") && has(msg, "'B'") && has(msg, "almost")) << msg;
    EXPECT_TRUE(s.gluings.empty());
  }
  Structure s;
  polycube::add_cube(s, "A", box(0, 0, 0, 1, 1, 1));
  polycube::add_cube(s, "B", box(0, 0, 0, 1, 1, 1));
  AxisMap near;
  near.offset[0] = -1 + 1e-15;
  auto msg = topology_error([&] { polycube::glue(s, 0, 1, 1, 0, Rect{{0, 0}, {1, 1}}, near); });
  EXPECT_TRUE(has(msg, "'A'") && has(msg, "'B'") && has(msg, "almost")) << msg;
  msg = topology_error([&] { polycube::subtract(s, 0, "hole", {box(0.25, 0.25, 1e-12, 0.75, 0.75, 1)}); });
  EXPECT_TRUE(has(msg, "'hole'") && has(msg, "'A'") && has(msg, "almost")) << msg;
}

TEST(structure, OtherUnrealizableStructuresNameTheirComponents) {
  Structure s;
  polycube::add_cube(s, "A", box(0, 0, 0, 1, 1, 1));
  polycube::add_cube(s, "B", box(3, 0, 0, 4, 1, 1));
  auto msg = topology_error([&] { polycube::unite(s, 0, 1); });
  EXPECT_TRUE(has(msg, "'A'") && has(msg, "'B'") && has(msg, "no face")) << msg;
  msg = topology_error([&] { polycube::check(s); });
  EXPECT_TRUE(has(msg, "'A'") && has(msg, "'B'") && has(msg, "not connected")) << msg;
  // y and z swapped: a mirror image.
  msg = topology_error([&] { polycube::glue(s, 0, 1, 1, 0, Rect{{0, 0}, {1, 1}}, AxisMap{{0, 2, 1}, {1, 1, 1}, {2, 0, 0}}); });
  EXPECT_TRUE(has(msg, "'A'") && has(msg, "'B'") && has(msg, "mirrors")) << msg;
  msg = topology_error([&] { polycube::glue(s, 0, 1, 1, 1, Rect{{0, 0}, {1, 1}}, AxisMap{{0, 1, 2}, {1, 1, 1}, {3, 0, 0}}); });
  EXPECT_TRUE(has(msg, "same side")) << msg;
  msg = topology_error([&] { polycube::glue(s, 0, 1, 1, 0, Rect{{0, 0}, {1, 1.5}}, AxisMap{{0, 1, 2}, {1, 1, 1}, {2, 0, 0}}); });
  EXPECT_TRUE(has(msg, "not inside its face")) << msg;

  // A crack: B and D touch in the development but nothing glues them.
  Structure crack;
  for (const auto& [n, b] : {std::pair{"A", box(0, 0, 0, 1, 1, 1)}, {"B", box(1, 0, 0, 2, 1, 1)}, {"C", box(0, 1, 0, 1, 2, 1)}, {"D", box(1, 1, 0, 2, 2, 1)}})
    polycube::add_cube(crack, n, b);
  polycube::unite(crack, 0, 1);
  polycube::unite(crack, 0, 2);
  polycube::unite(crack, 2, 3);
  msg = topology_error([&] { polycube::check(crack); });
  EXPECT_TRUE(has(msg, "'B'") && has(msg, "'D'") && has(msg, "not glued")) << msg;
  polycube::unite(crack, 1, 3);
  expect_polycube(crack);

  // A torus missing a ring gluing.
  Structure t;
  polycube::add_torus(t, "T", box(0, 0, 0, 1, 1, 1), 2);
  t.gluings.erase(t.gluings.begin() + 1);
  msg = topology_error([&] { polycube::check(t); });
  EXPECT_TRUE(has(msg, "torus 'T'") && has(msg, "'T/1'") && has(msg, "'T/2'")) << msg;

  // Virtual components that are no difference of a cube.
  Structure h;
  polycube::add_cube(h, "H", box(0, 0, 0, 1, 1, 1));
  msg = topology_error([&] { polycube::subtract(h, 0, "slot", {box(0.25, -1, -1, 0.75, 2, 2)}); });
  EXPECT_TRUE(has(msg, "'slot'") && has(msg, "'H'") && has(msg, "pieces")) << msg;
  msg = topology_error([&] { polycube::subtract(h, 0, "all", {box(-1, -1, -1, 2, 2, 2)}); });
  EXPECT_TRUE(has(msg, "'all'") && has(msg, "removes all")) << msg;
  msg = topology_error([&] { polycube::subtract(h, 0, "away", {box(2, 2, 2, 3, 3, 3)}); });
  EXPECT_TRUE(has(msg, "'away'") && has(msg, "misses")) << msg;
  polycube::subtract(h, 0, "first", {box(0.25, 0.25, 0.5, 0.75, 0.75, 1)});
  msg = topology_error([&] { polycube::subtract(h, 0, "second", {box(0.5, 0.5, 0.25, 0.625, 0.625, 0.75)}); });
  EXPECT_TRUE(has(msg, "'first'") && has(msg, "'second'") && has(msg, "overlap")) << msg;
  EXPECT_EQ(h.virtual_components.size(), 1u);
}

TEST(structure, JsonRoundTripAndBadJson) {
  Structure s;
  const int t = polycube::add_torus(s, "T", box(0, 0, 0, 1, 1, 1), 0);
  const int c = polycube::add_cube(s, "C", box(0, 0, 1, 1, 1, 2));
  polycube::unite(s, c, t);
  polycube::subtract(s, 4, "hole", {box(0.25, 0.25, 1.5, 0.75, 0.75, 2)});
  polycube::reframe(s, 2, unit_frame(s.cubes[2].box, rotations()[7]));
  expect_polycube(s);
  EXPECT_EQ(polycube::report_figures(s), (core::Json{{"cubes", 5}, {"tori", 1}, {"virtual_components", 1}, {"gluings", 5}, {"contacts", 0}}));

  const core::Json good = polycube::to_json(s);
  struct Bad {
    const char* member;
    std::function<void(core::Json&)> edit;
  };
  const std::vector<Bad> bad{
      {"structure: must be an object", [](core::Json& j) { j = core::Json::array(); }},
      {"structure.cubes: missing", [](core::Json& j) { j.erase("cubes"); }},
      {"structure.gluings: must be an array", [](core::Json& j) { j["gluings"] = 3; }},
      {"structure.cubes[1].lo", [](core::Json& j) { j["cubes"][1]["lo"] = {0, 0}; }},
      {"structure.cubes[1]: lo < hi", [](core::Json& j) { j["cubes"][1]["hi"][0] = -5; }},
      {"structure.cubes[0].label", [](core::Json& j) { j["cubes"][0]["label"] = 7; }},
      {"structure.cubes[4].primitive", [](core::Json& j) { j["cubes"][4]["primitive"] = 9; }},
      {"structure.primitives[0].cubes", [](core::Json& j) { j["primitives"][0]["cubes"] = {0, 1, 2}; }},
      {"structure.primitives[1].cubes", [](core::Json& j) { j["primitives"][1]["cubes"] = {3}; }},
      {"structure.gluings[0].fa", [](core::Json& j) { j["gluings"][0]["fa"] = 6; }},
      {"structure.gluings[0].b", [](core::Json& j) { j["gluings"][0]["b"] = -1; }},
      {"structure.gluings[2].a", [](core::Json& j) { j["gluings"][2]["a"] = 2.5; }},
      {"structure.gluings[0]: axis/scale", [](core::Json& j) { j["gluings"][0]["axis"] = {0, 0, 1}; }},
      {"structure.gluings[0]: axis/scale", [](core::Json& j) { j["gluings"][0]["scale"][1] = 0; }},
      {"structure.gluings[0].offset", [](core::Json& j) { j["gluings"][0]["offset"] = "x"; }},
      {"structure.gluings[0]: rect_lo < rect_hi", [](core::Json& j) { j["gluings"][0]["rect_hi"] = {0, 0}; }},
      {"structure.gluings[0].closes_torus", [](core::Json& j) { j["gluings"][0]["closes_torus"] = 1; }},
      {"structure.virtual_components[0].cube", [](core::Json& j) { j["virtual_components"][0]["cube"] = 5; }},
      {"structure.virtual_components[0].boxes", [](core::Json& j) { j["virtual_components"][0]["boxes"] = core::Json::array(); }},
      {"structure.virtual_components[0].boxes[0].hi", [](core::Json& j) { j["virtual_components"][0]["boxes"][0].erase("hi"); }},
      {"structure.virtual_components[0].torus", [](core::Json& j) { j["virtual_components"][0]["torus"] = "no"; }},
  };
  for (const auto& b : bad) {
    core::Json j = good;
    b.edit(j);
    try {
      polycube::structure_from_json(j, "bad.json");
      ADD_FAILURE() << "accepted: " << b.member;
    } catch (const core::InvalidInputError& e) {
      EXPECT_TRUE(has(e.what(), "bad.json: ") && has(e.what(), b.member)) << e.what();
    }
  }
}

TEST(structure, ParaViewFileHoldsOneHexPerCubeAndVirtualBox) {
  Structure s;
  const int t = polycube::add_torus(s, "T", box(0, 0, 0, 1, 1, 1), 0);
  const int c = polycube::add_cube(s, "C", box(0, 0, 1, 1, 1, 2));
  polycube::unite(s, c, t);
  polycube::subtract_ring(s, 4, "ring", box(0.125, 0.125, 1.5, 0.875, 0.875, 2), box(0.375, 0.375, 1.5, 0.625, 0.625, 2), 2);
  const auto path = std::filesystem::temp_directory_path() / ("volts_structure_" + std::to_string(::getpid()) + ".vtu");
  polycube::write_structure_vtu(path.string(), s);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string vtu = text.str();
  EXPECT_TRUE(has(vtu, "NumberOfPoints=\"72\"") && has(vtu, "NumberOfCells=\"9\"")) << "5 cubes + 4 ring boxes";
  for (const char* field : {"\"cube_id\"", "\"primitive_id\"", "\"torus\"", "\"virtual\"", "\"virtual_component\""}) EXPECT_TRUE(has(vtu, field)) << field;
  std::filesystem::remove(path);
}

// split makes tori of 4..16 cubes (split.torus_cubes): rings of n cubes in any frames close with
// a translation by n widths; fewer than four cubes is no torus.
TEST(structure, TorusOfNCubesAsSplitMakesThem) {
  const auto rots = rotations();
  for (int n : {4, 5, 8, 16})
    for (int ring_axis = 0; ring_axis < 3; ++ring_axis) {
      SCOPED_TRACE(std::to_string(n) + " cubes along " + std::to_string(ring_axis));
      Structure s;
      const int t = polycube::add_torus(s, "T", box(0, 0, 0, 0.5, 0.5, 0.5), ring_axis, n);
      ASSERT_EQ(s.primitives[t].cubes.size(), static_cast<std::size_t>(n));
      EXPECT_EQ(s.cubes.back().label, "T/" + std::to_string(n - 1));
      EXPECT_EQ(polycube::report_figures(s), (core::Json{{"cubes", n}, {"tori", 1}, {"virtual_components", 0}, {"gluings", n}, {"contacts", 0}}));
      expect_polycube(s);
      for (int k = 0; k < n; ++k) polycube::reframe(s, k, unit_frame(s.cubes[k].box, rots[(3 * n + 5 * k + ring_axis) % rots.size()]));
      expect_polycube(s);
      AxisMap around;
      int at = s.primitives[t].cubes[0];
      for (int step = 0; step < n; ++step) {
        const auto g = std::find_if(s.gluings.begin(), s.gluings.end(), [&](const polycube::Gluing& x) { return x.a == at; });
        ASSERT_NE(g, s.gluings.end());
        around = polycube::compose(g->map, around);
        at = g->b;
      }
      EXPECT_EQ(at, s.primitives[t].cubes[0]);
      EXPECT_EQ(around.scale, (Point{1, 1, 1}));
      std::array<double, 3> period = around.offset;
      std::sort(period.begin(), period.end(), [](double x, double y) { return std::abs(x) < std::abs(y); });
      EXPECT_EQ(period[0], 0);
      EXPECT_EQ(period[1], 0);
      EXPECT_EQ(std::abs(period[2]), n) << "n unit cubes (cube 0's frame)";
    }
  Structure three;
  auto msg = topology_error([&] { polycube::add_torus(three, "R", box(0, 0, 0, 1, 1, 1), 0, 3); });
  EXPECT_TRUE(has(msg, "torus 'R'") && has(msg, "at least 4")) << msg;
  EXPECT_TRUE(three.cubes.empty());
  // A torus primitive cut down to three cubes by hand: check() and the JSON reader refuse it.
  Structure s;
  polycube::add_torus(s, "T", box(0, 0, 0, 1, 1, 1), 0, 4);
  core::Json j = polycube::to_json(s);
  s.primitives[0].cubes.pop_back();
  s.cubes.pop_back();
  msg = topology_error([&] { polycube::check(s); });
  EXPECT_TRUE(has(msg, "torus 'T'") && has(msg, "at least 4")) << msg;
  j["primitives"][0]["cubes"] = {0, 1, 2};
  try {
    polycube::structure_from_json(j, "three.json");
    ADD_FAILURE() << "a torus of three cubes was read";
  } catch (const core::InvalidInputError& e) {
    EXPECT_TRUE(has(e.what(), "three.json: structure.primitives[0].cubes: a torus has at least 4 cubes")) << e.what();
  }
  // A second gluing that claims to close the ring: the message names the cubes of both.
  Structure two;
  polycube::add_torus(two, "T", box(0, 0, 0, 1, 1, 1), 0, 6);
  two.gluings[2].closes_torus = 0;
  msg = topology_error([&] { polycube::check(two); });
  EXPECT_TRUE(has(msg, "2 gluings close its ring") && has(msg, "'T/2' to 'T/3'") && has(msg, "'T/5' to 'T/0'")) << msg;
}

// Two tori that touch on a region inside a face of each (split's genus-2 disk): a non-conforming
// contact joins the solid without a gluing; each torus stays in a frame of its own.
TEST(structure, TwoToriJoinedByANonConformingContact) {
  Structure s;
  const int t0 = polycube::add_torus(s, "A", box(0, 0, 0, 1, 1, 1), 0, 4);
  const int t1 = polycube::add_torus(s, "B", box(0, 0, 0, 1, 1, 1), 0, 6);  // the same coordinates: no common frame
  auto msg = topology_error([&] { polycube::check(s); });
  EXPECT_TRUE(has(msg, "not connected") && has(msg, "'B/0'") && has(msg, "'A/0'") && !has(msg, "contacts")) << msg;
  const int a = s.primitives[t0].cubes[1], b = s.primitives[t1].cubes[2];
  EXPECT_EQ(polycube::add_contact(s, "disk", a, 5, b, 4), 0);
  expect_polycube(s);  // JSON round trip with the contact included
  EXPECT_EQ(polycube::report_figures(s), (core::Json{{"cubes", 10}, {"tori", 2}, {"virtual_components", 0}, {"gluings", 10}, {"contacts", 1}}));
  EXPECT_EQ(polycube::to_json(s)["contacts"][0],
            (core::Json{{"label", "disk"}, {"a", a}, {"fa", 5}, {"b", b}, {"fb", 4}, {"conforming", false}}));
  // The contact glues nothing: both faces stay boundary; each ring is developed in its own frame.
  EXPECT_EQ(kind_area(s, a, RegionKind::boundary), 4);
  EXPECT_EQ(kind_area(s, b, RegionKind::boundary), 4);
  const auto dev = polycube::develop(s);
  EXPECT_TRUE(same(polycube::apply(dev[b], s.cubes[b].box), s.cubes[b].box));

  // A contact on a cross section (glued all over), between cubes of one ring, or out of range.
  Structure bad = s;
  msg = topology_error([&] { polycube::add_contact(bad, "section", a, 1, b, 4); });
  EXPECT_TRUE(has(msg, "contact 'section'") && has(msg, "'A/1'") && has(msg, "holds no boundary")) << msg;
  msg = topology_error([&] { polycube::add_contact(bad, "self", a, 5, a, 4); });
  EXPECT_TRUE(has(msg, "contact 'self'") && has(msg, "itself")) << msg;
  msg = topology_error([&] { polycube::add_contact(bad, "far", a, 5, 99, 4); });
  EXPECT_TRUE(has(msg, "contact 'far'") && has(msg, "no cube 99")) << msg;
  EXPECT_EQ(bad.contacts.size(), 1u) << "refused contacts are not kept";
  bad.contacts.push_back(polycube::Contact{"inside", s.primitives[t0].cubes[0], 2, s.primitives[t0].cubes[2], 2});
  msg = topology_error([&] { polycube::check(bad); });
  EXPECT_TRUE(has(msg, "contact 'inside'") && has(msg, "'A/0'") && has(msg, "'A/2'") && has(msg, "must be a gluing")) << msg;

  // JSON: a conforming contact is a gluing; an index out of range; no contacts member at all.
  const core::Json good = polycube::to_json(s);
  for (const auto& [member, edit] : std::vector<std::pair<std::string, std::function<void(core::Json&)>>>{
           {"structure.contacts[0].conforming: must be false", [](core::Json& j) { j["contacts"][0]["conforming"] = true; }},
           {"structure.contacts[0].fb", [](core::Json& j) { j["contacts"][0]["fb"] = 6; }},
           {"structure.contacts[0].b", [](core::Json& j) { j["contacts"][0]["b"] = 10; }},
           {"structure.contacts[0].label", [](core::Json& j) { j["contacts"][0].erase("label"); }},
           {"structure.contacts: must be an array", [](core::Json& j) { j["contacts"] = 1; }}}) {
    core::Json j = good;
    edit(j);
    try {
      polycube::structure_from_json(j, "bad.json");
      ADD_FAILURE() << "accepted: " << member;
    } catch (const core::InvalidInputError& e) {
      EXPECT_TRUE(has(e.what(), "bad.json: ") && has(e.what(), member)) << e.what();
    }
  }
  core::Json old = good;
  old.erase("contacts");
  const Structure without = polycube::structure_from_json(old, "old.json");
  EXPECT_TRUE(without.contacts.empty());
  msg = topology_error([&] { polycube::check(without); });
  EXPECT_TRUE(has(msg, "not connected")) << msg;

  // ParaView: one hex per cube, the second ring drawn beside the first (field `part`).
  const auto path = std::filesystem::temp_directory_path() / ("volts_structure_parts_" + std::to_string(::getpid()) + ".vtu");
  polycube::write_structure_vtu(path.string(), s);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_TRUE(has(text.str(), "NumberOfCells=\"10\"") && has(text.str(), "\"part\""));
  std::filesystem::remove(path);
}
