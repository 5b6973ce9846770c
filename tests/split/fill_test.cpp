// Filling the openings of a cut surface (split/layout.h: fill_opening_in_plane, fill_openings):
// open prisms over a family of simple polygons, convex and not, closed by the fills.
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <set>
#include <vector>

#include "split/layout.h"
#include "surface/surface.h"

namespace {

using volts::surface::Mesh;
using volts::surface::Point;
namespace PMP = CGAL::Polygon_mesh_processing;

struct Polygon {
  const char* name;
  std::vector<std::array<double, 2>> xy;  // counter-clockwise
};

double area(const Polygon& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.xy.size(); ++i) {
    const auto& u = p.xy[i];
    const auto& v = p.xy[(i + 1) % p.xy.size()];
    a += 0.5 * (u[0] * v[1] - v[0] * u[1]);
  }
  return a;
}

// Edges subdivided so that the rim is fine (as a cut loop is) and the fills need interior points.
Polygon refined(const Polygon& p, double h) {
  Polygon r{p.name, {}};
  for (std::size_t i = 0; i < p.xy.size(); ++i) {
    const auto& u = p.xy[i];
    const auto& v = p.xy[(i + 1) % p.xy.size()];
    const int n = std::max(1, static_cast<int>(std::ceil(std::hypot(v[0] - u[0], v[1] - u[1]) / h)));
    for (int k = 0; k < n; ++k) r.xy.push_back({u[0] + (v[0] - u[0]) * k / n, u[1] + (v[1] - u[1]) * k / n});
  }
  return r;
}

std::vector<Polygon> family() {
  std::vector<Polygon> out = {
      {"square", {{0, 0}, {1, 0}, {1, 1}, {0, 1}}},
      {"L", {{0, 0}, {1, 0}, {1, 0.3}, {0.3, 0.3}, {0.3, 1}, {0, 1}}},
      // An I-beam's cross section (the rod's shank): two notches a 3D hole filling may bridge.
      {"I-beam", {{0, 0}, {1, 0}, {1, 0.2}, {0.6, 0.2}, {0.6, 0.8}, {1, 0.8}, {1, 1}, {0, 1}, {0, 0.8}, {0.4, 0.8}, {0.4, 0.2}, {0, 0.2}}},
  };
  Polygon star{"star", {}};
  for (int i = 0; i < 14; ++i) {
    const double r = i % 2 ? 0.35 : 1.0, t = 2 * M_PI * i / 14;
    star.xy.push_back({r * std::cos(t), r * std::sin(t)});
  }
  out.push_back(star);
  for (auto& p : out) p = refined(p, 0.05);
  return out;
}

// The side walls of a prism of height `height` over p, open at both ends; `wave` lifts the rims
// off their planes by wave * sin(3θ) (θ: the angle of a rim point about the origin).
Mesh open_prism(const Polygon& p, double height, double wave = 0) {
  Mesh m;
  const std::size_t n = p.xy.size();
  const int rings = 4;
  std::vector<std::vector<Mesh::Vertex_index>> v(rings + 1);
  for (int k = 0; k <= rings; ++k)
    for (const auto& q : p.xy) {
      const double lift = (k == 0 || k == rings) ? wave * std::sin(3 * std::atan2(q[1], q[0])) : 0.0;
      v[k].push_back(m.add_vertex(Point(q[0], q[1], height * k / rings + lift)));
    }
  for (int k = 0; k < rings; ++k)
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = (i + 1) % n;
      m.add_face(v[k][i], v[k][j], v[k + 1][j]);
      m.add_face(v[k][i], v[k + 1][j], v[k + 1][i]);
    }
  return m;
}

std::vector<Mesh::Halfedge_index> borders(const Mesh& m) {
  std::vector<Mesh::Halfedge_index> out;
  std::set<std::size_t> seen;
  for (auto h : m.halfedges()) {
    if (!m.is_border(h) || seen.count(static_cast<std::size_t>(h))) continue;
    out.push_back(h);
    for (auto g : CGAL::halfedges_around_face(h, m)) seen.insert(static_cast<std::size_t>(g));
  }
  return out;
}

bool closed(const Mesh& m) {
  for (auto h : m.halfedges())
    if (m.is_border(h)) return false;
  return true;
}

TEST(Fill, PlanarFillsCloseAPrismExactlyOverSimplePolygonsConvexOrNot) {
  for (const Polygon& p : family()) {
    SCOPED_TRACE(p.name);
    Mesh m = open_prism(p, 0.7);
    const std::size_t rim_vertices = m.number_of_vertices();
    const auto open = borders(m);
    ASSERT_EQ(open.size(), 2u);
    for (auto h : open) ASSERT_TRUE(volts::split::detail::fill_opening_in_plane(m, h, 0.1));
    EXPECT_TRUE(closed(m));
    EXPECT_TRUE(CGAL::is_valid_polygon_mesh(m));
    EXPECT_FALSE(PMP::does_self_intersect(m));
    // Interior points were added (the rims are fine, the polygons are not), none on a rim.
    EXPECT_GT(m.number_of_vertices(), rim_vertices + 8);
    for (auto v : m.vertices()) {
      if (static_cast<std::size_t>(v) < rim_vertices) continue;
      const double z = m.point(v).z();
      EXPECT_TRUE(std::abs(z) < 1e-12 || std::abs(z - 0.7) < 1e-12) << "interior fill point off the rim's plane: z = " << z;
    }
    // The fills cover each polygon once, oriented outward: the enclosed volume is area × height.
    EXPECT_NEAR(volts::surface::signed_volume(m), area(p) * 0.7, 1e-12 * area(p));
  }
}

TEST(Fill, InteriorHeightsOfAWavyRimStayWithinTheRimsHeights) {
  for (const Polygon& p : family()) {
    SCOPED_TRACE(p.name);
    const double wave = 0.02;
    Mesh m = open_prism(p, 0.7, wave);
    const std::size_t rim_vertices = m.number_of_vertices();
    for (auto h : borders(m)) ASSERT_TRUE(volts::split::detail::fill_opening_in_plane(m, h, 0.1));
    EXPECT_TRUE(closed(m));
    EXPECT_FALSE(PMP::does_self_intersect(m));
    // Harmonic heights obey the maximum principle; the least-squares plane of a rim lifted by
    // sin(3θ) is tilted slightly, so allow for that tilt's share.
    int lifted = 0;
    for (auto v : m.vertices()) {
      if (static_cast<std::size_t>(v) < rim_vertices) continue;
      const double z = m.point(v).z(), off = std::min(std::abs(z), std::abs(z - 0.7));
      EXPECT_LE(off, 1.5 * wave);
      lifted += off > 1e-6 ? 1 : 0;
    }
    EXPECT_GT(lifted, 0);
  }
}

TEST(Fill, APlanarFillRefusesARimThatIsNotASimplePlanarLoop) {
  // Far off its plane: a rim lifted by half the polygon's size.
  Mesh m = open_prism(family()[0], 0.7, 0.5);
  const Mesh before = m;
  for (auto h : borders(m)) EXPECT_FALSE(volts::split::detail::fill_opening_in_plane(m, h, 0.1));
  EXPECT_EQ(m.number_of_faces(), before.number_of_faces());
  EXPECT_EQ(m.number_of_vertices(), before.number_of_vertices());
  // A bow tie: its projection crosses itself.
  Polygon bow{"bow tie", {{0, 0}, {1, 1}, {1, 0}, {0, 1}}};
  Mesh b = open_prism(refined(bow, 0.1), 0.5);
  for (auto h : borders(b)) EXPECT_FALSE(volts::split::detail::fill_opening_in_plane(b, h, 0.1));
}

TEST(Fill, FillOpeningsClosesTheSubmeshAndAppendsTheFillToTheLayout) {
  for (const Polygon& p : family()) {
    SCOPED_TRACE(p.name);
    volts::split::detail::Submesh s;
    s.mesh = open_prism(p, 0.7);
    volts::split::Layout layout;
    for (auto v : s.mesh.vertices()) {
      s.layout_vertex.push_back(static_cast<int>(layout.points.size()));
      const auto& q = s.mesh.point(v);
      layout.points.push_back({q.x(), q.y(), q.z()});
    }
    for (auto f : s.mesh.faces()) {
      std::array<int, 3> t{};
      int k = 0;
      for (auto v : CGAL::vertices_around_face(s.mesh.halfedge(f), s.mesh)) t[k++] = static_cast<int>(v);
      s.layout_triangle.push_back(static_cast<int>(layout.triangles.size()));
      layout.triangles.push_back(t);
      layout.filled.push_back(0);
    }
    const std::size_t walls = layout.triangles.size();
    const std::vector<int> fill = volts::split::detail::fill_openings(s, layout, true);
    EXPECT_TRUE(closed(s.mesh));
    EXPECT_FALSE(PMP::does_self_intersect(s.mesh));
    EXPECT_EQ(fill.size(), layout.triangles.size() - walls);
    EXPECT_EQ(s.layout_triangle.size(), layout.triangles.size());
    EXPECT_EQ(s.layout_vertex.size(), layout.points.size());
    for (const int t : fill) EXPECT_EQ(layout.filled[static_cast<std::size_t>(t)], 1);
    EXPECT_NEAR(volts::surface::signed_volume(s.mesh), area(p) * 0.7, 1e-9);
  }
}

}  // namespace
