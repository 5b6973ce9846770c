#include "models/models.h"

#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/polygon_mesh_to_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>

#include "core/errors.h"

namespace volts::models {
namespace {

using surface::Mesh;
using surface::Point;
using Vector = surface::Kernel::Vector_3;
namespace PMP = CGAL::Polygon_mesh_processing;

constexpr double kPi = 3.14159265358979323846;
constexpr int kMinResolution = 4;
constexpr int kMaxResolution = 512;
constexpr double kMaxBulge = 0.35;  // beyond it the box edges' dihedral deviation nears the 30 degree feature angle

constexpr std::array<double, 3> kBoxHalf = {1.0, 0.75, 0.5};
constexpr double kTorusMajor = 2.0;
constexpr double kTorusMinor = 0.75;
constexpr double kHoleRadius = 0.7;  // 0.35 x the cube side 2
constexpr std::array<double, 3> kPlateHalf = {2.0, 1.5, 0.25};  // assembly (Liu et al. 2013, Fig. 1)
constexpr std::array<double, 2> kPlateHoleCentre = {1.5, 1.0};   // the holes are at (+-1.5, +-1)
constexpr double kPlateHoleRadius = 0.3;
constexpr double kRingMajor = 0.8;     // the ring: a torus in the plane y = 0 (axis along y)
constexpr double kRingMinor = 0.3;
constexpr double kRingCentreZ = 0.95;  // its tube's centre circle dips 0.1 below the plate's top face
constexpr double kConeRadius = 1.0;
constexpr double kConeBase = -0.5;
constexpr double kConeApex = 1.0;

/// A cross section in the (r, z) half-plane: its corners, counter-clockwise (r to the right, z up).
using Profile = std::vector<std::array<double, 2>>;
/// washer: a plus sign, flange r in [0.7, 1.3], |z| <= 0.1, union hub r in [0.9, 1.1], |z| <= 0.3.
const Profile kWasherProfile = {{0.7, -0.1}, {0.9, -0.1}, {0.9, -0.3}, {1.1, -0.3}, {1.1, -0.1}, {1.3, -0.1},
                                {1.3, 0.1},  {1.1, 0.1},  {1.1, 0.3},  {0.9, 0.3},  {0.9, 0.1},  {0.7, 0.1}};
/// flanged-ring: an L, tube wall r in [1, 1.2], z in [0, 0.6], union flange r in [1, 1.6], z in [0, 0.2].
const Profile kFlangedRingProfile = {{1.0, 0.0}, {1.6, 0.0}, {1.6, 0.2}, {1.2, 0.2}, {1.2, 0.6}, {1.0, 0.6}};
constexpr int kMinRevolutionSegments = 16;     // sectors turn 22.5 degrees at most: below the 30 degree feature angle
constexpr double kMaxRimToSideRatio = 2.7;     // atan(1 / 2.7) = 20.3 degrees: the smallest triangle angle

/// sin(pi j / n), exactly 0 at j = 0 and j = n (so box edges stay exactly straight) and symmetric in j.
double sin_pi_fraction(int j, int n) {
  const int m = std::min(j, n - j);
  return m == 0 ? 0.0 : std::sin(kPi * m / n);
}

/// (cos, sin) of 2 pi j / n, exact on the axes and exactly symmetric about the diagonals, so that points
/// there meet the cube's grid lines and diagonals exactly.
std::array<double, 2> unit_circle(int j, int n) {
  const int quadrant = 4 * j / n, r = 4 * j - quadrant * n;  // angle = (quadrant + r / n) pi / 2
  double c = 1.0, s = 0.0;
  if (2 * r == n) {
    c = s = std::sqrt(0.5);
  } else if (2 * r > n) {
    c = std::sin(kPi / 2 * (n - r) / n);
    s = std::cos(kPi / 2 * (n - r) / n);
  } else if (r > 0) {
    c = std::cos(kPi / 2 * r / n);
    s = std::sin(kPi / 2 * r / n);
  }
  switch (quadrant % 4) {
    case 0: return {c, s};
    case 1: return {-s, c};
    case 2: return {-c, -s};
    default: return {s, -c};
  }
}

int rounded(double x) { return static_cast<int>(std::lround(x)); }

/// A triangle soup. Vertices shared by patches are welded through integer keys, never by comparing
/// coordinates, so seams are exact.
class Soup {
 public:
  using Key = std::array<int, 4>;

  std::size_t size() const { return points_.size(); }
  std::size_t add(const Point& p) {
    points_.push_back(p);
    return points_.size() - 1;
  }
  std::size_t weld(const Key& key, const Point& p) {
    const auto [it, inserted] = keys_.try_emplace(key, points_.size());
    if (inserted) points_.push_back(p);
    return it->second;
  }
  void triangle(std::size_t a, std::size_t b, std::size_t c, bool flip = false) {
    if (flip) std::swap(b, c);
    triangles_.push_back({a, b, c});
  }
  /// Counter-clockwise quad a b c d, split along its shorter diagonal (the better triangles).
  void quad(std::size_t a, std::size_t b, std::size_t c, std::size_t d) {
    if (CGAL::squared_distance(points_[a], points_[c]) <= CGAL::squared_distance(points_[b], points_[d]) * (1.0 + 1e-12)) {
      triangle(a, b, c);
      triangle(a, c, d);
    } else {
      triangle(a, b, d);
      triangle(b, c, d);
    }
  }
  /// Validates the soup (a generator bug must not pass silently) and builds the mesh.
  Mesh to_mesh(const std::string& source) const {
    surface::validate_soup(points_, triangles_, source);
    Mesh mesh;
    PMP::polygon_soup_to_polygon_mesh(points_, triangles_, mesh);
    return mesh;
  }

 private:
  std::vector<Point> points_;
  std::vector<std::vector<std::size_t>> triangles_;
  std::map<Key, std::size_t> keys_;
};

using Lattice = std::array<int, 3>;

/// Boundary of the lattice box [0,n0] x [0,n1] x [0,n2]: six grids of quads, outward for a position
/// map that preserves orientation.
void add_lattice_box(Soup& soup, const Lattice& n, const std::function<Point(const Lattice&)>& position) {
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;  // e_b x e_c = e_a
    for (int side = 0; side < 2; ++side) {
      std::vector<std::size_t> id((n[b] + 1) * (n[c] + 1));
      const auto at = [&](int u, int v) -> std::size_t& { return id[u * (n[c] + 1) + v]; };
      for (int u = 0; u <= n[b]; ++u)
        for (int v = 0; v <= n[c]; ++v) {
          Lattice ijk{};
          ijk[a] = side * n[a];
          ijk[b] = u;
          ijk[c] = v;
          at(u, v) = soup.weld({ijk[0], ijk[1], ijk[2], 0}, position(ijk));
        }
      for (int u = 0; u < n[b]; ++u)
        for (int v = 0; v < n[c]; ++v) {
          if (side == 1)
            soup.quad(at(u, v), at(u + 1, v), at(u + 1, v + 1), at(u, v + 1));
          else
            soup.quad(at(u, v), at(u, v + 1), at(u + 1, v + 1), at(u + 1, v));
        }
    }
  }
}

/// Segments per edge of a box of half-sizes `half` with `resolution` segments along its longest edge.
Lattice box_segments(const std::array<double, 3>& half, int resolution) {
  const double longest = *std::max_element(half.begin(), half.end());
  Lattice n{};
  for (int a = 0; a < 3; ++a) n[a] = std::max(1, rounded(resolution * half[a] / longest));
  return n;
}

/// Lattice coordinate i of n mapped to [-half, half], exactly symmetric.
double lattice_coordinate(int i, int n, double half) { return half * (2 * i - n) / n; }

Mesh make_bulged_box(const ModelParams& p, double bulge) {
  const Lattice n = box_segments(kBoxHalf, p.resolution);
  Soup soup;
  add_lattice_box(soup, n, [&](const Lattice& ijk) {
    std::array<double, 3> x{};
    for (int a = 0; a < 3; ++a) x[a] = lattice_coordinate(ijk[a], n[a], kBoxHalf[a]);
    for (int a = 0; a < 3; ++a) {
      if (ijk[a] != 0 && ijk[a] != n[a]) continue;
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      const double amplitude = bulge * std::min(kBoxHalf[b], kBoxHalf[c]);
      const double d = amplitude * sin_pi_fraction(ijk[b], n[b]) * sin_pi_fraction(ijk[c], n[c]);
      x[a] += ijk[a] == 0 ? -d : d;
    }
    return Point(x[0], x[1], x[2]);
  });
  return soup.to_mesh("model '" + p.name + "'");
}

Mesh make_box(const ModelParams& p) { return make_bulged_box(p, 0.0); }

/// Equiangular cube grid projected onto the unit sphere: near-uniform cells, no poles.
Mesh make_sphere(const ModelParams& p) {
  const int m = std::max(1, rounded(p.resolution / 4.0));  // the equator has 4m segments
  Soup soup;
  add_lattice_box(soup, {m, m, m}, [&](const Lattice& ijk) {
    const auto q = [&](int i) { return std::tan(kPi / 4 * (2 * i - m) / m); };
    const Vector v(q(ijk[0]), q(ijk[1]), q(ijk[2]));
    return CGAL::ORIGIN + v / std::sqrt(v.squared_length());
  });
  return soup.to_mesh("model 'sphere'");
}

/// Torus about the z axis through the origin: nu segments around the axis, nv around the tube, vertex (i, j)
/// at the angles 2 pi i / nu and 2 pi j / nv (interpolated: on the exact surface), moved into place by
/// `place` (a rotation and translation of (x, y, z), so the torus stays outward).
void add_torus(Soup& soup, double major, double minor, int nu, int nv,
               const std::function<Point(double x, double y, double z)>& place) {
  const std::size_t first = soup.size();
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const auto u = unit_circle(i, nu), v = unit_circle(j, nv);
      const double rho = major + minor * v[0];
      soup.add(place(rho * u[0], rho * u[1], minor * v[1]));
    }
  const auto id = [&](int i, int j) -> std::size_t { return first + (i % nu) * nv + j % nv; };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) soup.quad(id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
}

Mesh make_torus(const ModelParams& p) {
  const int nv = p.resolution;                                                // around the minor circle
  const int nu = std::max(3, rounded(p.resolution * kTorusMajor / kTorusMinor));  // around the axis
  Soup soup;
  add_torus(soup, kTorusMajor, kTorusMinor, nu, nv, [](double x, double y, double z) { return Point(x, y, z); });
  return soup.to_mesh("model 'torus'");
}

Mesh make_tetrahedron(const ModelParams& p) {
  const int n = p.resolution;  // segments per edge
  const std::array<Point, 4> corner = {Point(1, 1, 1), Point(1, -1, -1), Point(-1, 1, -1), Point(-1, -1, 1)};
  // Faces opposite each corner, ordered counter-clockwise seen from outside.
  const std::array<std::array<int, 3>, 4> faces = {{{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}}};
  Soup soup;
  for (const auto& f : faces) {
    // Vertex (i, j) of the face grid is corner f0 + i/n (f1 - f0) + j/n (f2 - f0), keyed by its weights.
    const auto id = [&](int i, int j) {
      Soup::Key w{};
      w[f[0]] = n - i - j;
      w[f[1]] = i;
      w[f[2]] = j;
      Vector sum = CGAL::NULL_VECTOR;
      for (int k = 0; k < 4; ++k) sum = sum + (corner[k] - CGAL::ORIGIN) * w[k];
      return soup.weld(w, CGAL::ORIGIN + sum / n);
    };
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        soup.triangle(id(i, j), id(i + 1, j), id(i, j + 1));
        if (i + j < n - 1) soup.triangle(id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
      }
  }
  return soup.to_mesh("model 'tetrahedron'");
}

/// A ring of `count` vertices on the circle of `radius` about the vertical axis through `centre` (x, y) at
/// height z, at angles 2 pi k / count (counter-clockwise about +z).
std::vector<std::size_t> add_ring(Soup& soup, int count, double radius, double z,
                                  const std::array<double, 2>& centre = {0.0, 0.0}) {
  std::vector<std::size_t> ring(count);
  for (int k = 0; k < count; ++k) {
    const auto [c, s] = unit_circle(k, count);
    ring[k] = soup.add(Point(centre[0] + radius * c, centre[1] + radius * s, z));
  }
  return ring;
}

/// Triangles between two rings (both counter-clockwise about +z, starting at angle 0), advancing on
/// whichever ring's next vertex comes first; counter-clockwise seen from +z unless `flip`.
void add_band(Soup& soup, const std::vector<std::size_t>& inner, const std::vector<std::size_t>& outer, bool flip) {
  const std::size_t na = inner.size(), nb = outer.size();
  std::size_t i = 0, j = 0;
  while (i < na || j < nb) {
    if (j < nb && (i == na || (j + 1) * na <= (i + 1) * nb)) {
      soup.triangle(inner[i % na], outer[j], outer[(j + 1) % nb], flip);
      ++j;
    } else {
      soup.triangle(inner[i], outer[j % nb], inner[(i + 1) % na], flip);
      ++i;
    }
  }
}

void add_fan(Soup& soup, std::size_t centre, const std::vector<std::size_t>& ring, bool flip) {
  for (std::size_t k = 0; k < ring.size(); ++k) soup.triangle(centre, ring[k], ring[(k + 1) % ring.size()], flip);
}

/// Disc-like patch of revolution about z from a centre vertex to `rim` through m rings: ring k has about
/// rim.size() k / m vertices (at least 3), so triangles keep their shape up to the centre, and lies at
/// (radius, z) = radius_z(k / m); the centre at radius_z(0).
void add_polar_patch(Soup& soup, const std::vector<std::size_t>& rim, int m,
                     const std::function<std::array<double, 2>(double t)>& radius_z, bool flip) {
  const int n = static_cast<int>(rim.size());
  std::vector<std::size_t> inner;
  for (int k = 1; k <= m; ++k) {
    const double t = static_cast<double>(k) / m;
    const auto [radius, z] = radius_z(t);
    const auto ring = k == m ? rim : add_ring(soup, std::max(3, rounded(n * t)), radius, z);
    if (k == 1)
      add_fan(soup, soup.add(Point(0, 0, radius_z(0)[1])), ring, flip);
    else
      add_band(soup, inner, ring, flip);
    inner = ring;
  }
}

Mesh make_cone(const ModelParams& p) {
  const int n = p.resolution;  // around the base circle
  const double h = 2 * kPi * kConeRadius / n;
  const double height = kConeApex - kConeBase;
  const double slant = std::hypot(kConeRadius, height);
  Soup soup;
  const auto rim = add_ring(soup, n, kConeRadius, kConeBase);
  add_polar_patch(soup, rim, std::max(1, rounded(slant / h)), [&](double t) {
    return std::array<double, 2>{kConeRadius * t, kConeApex - height * t};
  }, false);
  add_polar_patch(soup, rim, std::max(1, rounded(kConeRadius / h)), [&](double t) {
    return std::array<double, 2>{kConeRadius * t, kConeBase};
  }, true);
  return soup.to_mesh("model 'cone'");
}

/// Segments around the axis of the solid of revolution of `profile`: the multiple of 4 at least
/// `resolution` and 16, and enough that the outermost rim's segment is at most kMaxRimToSideRatio times the
/// shortest profile side (a side of one segment then leaves no triangle angle below 20 degrees).
int revolution_segments(const Profile& profile, int resolution) {
  double r_out = 0.0, shortest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < profile.size(); ++k) {
    const auto &a = profile[k], &b = profile[(k + 1) % profile.size()];
    r_out = std::max(r_out, a[0]);
    shortest = std::min(shortest, std::hypot(b[0] - a[0], b[1] - a[1]));
  }
  int n = 4 * ((std::max(resolution, kMinRevolutionSegments) + 3) / 4);
  while (2 * r_out * std::sin(kPi / n) > kMaxRimToSideRatio * shortest) n += 4;
  return n;
}

/// The solid of revolution about z of `profile` (corners counter-clockwise in the (r, z) half-plane, r > 0):
/// revolution_segments(profile, resolution) sectors at the angles 2 pi i / n, each profile side split into
/// equal segments of about the innermost rim's segment length (at least one). Vertices lie on the exact
/// surface; every face is a planar quad (the sides are vertical or horizontal) split in two, outward.
Mesh make_revolved_profile(const ModelParams& p, const Profile& profile) {
  const int n = revolution_segments(profile, p.resolution);
  double r_in = std::numeric_limits<double>::infinity();
  for (const auto& c : profile) r_in = std::min(r_in, c[0]);
  const double h = 2 * r_in * std::sin(kPi / n);
  Profile points;  // the profile's corners and the points between them, counter-clockwise
  for (std::size_t k = 0; k < profile.size(); ++k) {
    const auto &a = profile[k], &b = profile[(k + 1) % profile.size()];
    const int m = std::max(1, rounded(std::hypot(b[0] - a[0], b[1] - a[1]) / h));
    for (int j = 0; j < m; ++j) {
      const double t = static_cast<double>(j) / m;
      points.push_back({a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t});
    }
  }
  const int np = static_cast<int>(points.size());
  Soup soup;
  for (int i = 0; i < n; ++i)
    for (const auto& [r, z] : points) {
      const auto [c, s] = unit_circle(i, n);
      soup.add(Point(r * c, r * s, z));
    }
  // Around the axis (d/d angle) then along the counter-clockwise profile: the outward normal.
  const auto id = [&](int i, int k) -> std::size_t { return static_cast<std::size_t>((i % n) * np + k % np); };
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < np; ++k) soup.quad(id(i, k), id(i + 1, k), id(i + 1, k + 1), id(i, k + 1));
  return soup.to_mesh("model '" + p.name + "'");
}

Mesh make_washer(const ModelParams& p) { return make_revolved_profile(p, kWasherProfile); }

Mesh make_flanged_ring(const ModelParams& p) { return make_revolved_profile(p, kFlangedRingProfile); }

/// Validates `mesh` and returns it with its vertices in lexicographic order and its faces sorted: the same
/// geometry then always gives the same mesh, whatever order an algorithm produced it in (the Boolean's
/// order depends on memory addresses).
Mesh canonical(const Mesh& mesh, const std::string& source) {
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> faces;
  PMP::polygon_mesh_to_polygon_soup(mesh, points, faces);
  surface::validate_soup(points, faces, source);
  std::vector<std::size_t> order(points.size()), rank(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return points[a] < points[b]; });
  std::vector<Point> sorted(points.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    rank[order[k]] = k;
    sorted[k] = points[order[k]];
  }
  for (auto& f : faces) {
    for (auto& v : f) v = rank[v];
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());  // keeps the orientation
  }
  std::sort(faces.begin(), faces.end());
  Mesh out;
  PMP::polygon_soup_to_polygon_mesh(sorted, faces, out);
  return out;
}

/// Splits every edge of `mesh` lying on one of the 12 edges of the box [-half, half] (two coordinates at
/// +-half on both ends; the Boolean leaves them alone) into segments(length) equal parts, exactly symmetric,
/// and triangulates the faces beside them.
void split_box_edges(Mesh& mesh, const std::array<double, 3>& half, const std::function<int(double)>& segments) {
  std::vector<Mesh::Halfedge_index> box_edges;
  for (const auto e : mesh.edges()) {
    const Point &a = mesh.point(mesh.vertex(e, 0)), &b = mesh.point(mesh.vertex(e, 1));
    int on = 0;
    for (int i = 0; i < 3; ++i) on += a[i] == b[i] && std::abs(a[i]) == half[i];
    if (on == 2) box_edges.push_back(mesh.halfedge(e));
  }
  for (const auto h : box_edges) {
    const Point a = mesh.point(mesh.source(h)), b = mesh.point(mesh.target(h));
    const int axis = a.x() != b.x() ? 0 : a.y() != b.y() ? 1 : 2;
    const double mid = (a[axis] + b[axis]) / 2, half_length = std::abs(b[axis] - a[axis]) / 2;
    const int m = segments(2 * half_length);
    for (int k = 1; k < m; ++k) {  // h keeps its target: each split inserts after the last point
      std::array<double, 3> x = {a.x(), a.y(), a.z()};
      x[axis] = mid + lattice_coordinate(a[axis] < b[axis] ? k : m - k, m, half_length);
      mesh.point(mesh.target(CGAL::Euler::split_edge(h, mesh))) = Point(x[0], x[1], x[2]);
    }
  }
  PMP::triangulate_faces(mesh);
}

/// The odd part of the number of segments of length about h in `length`: the remesher halves constrained
/// edges longer than 4/3 h, so an edge split into the odd part (few thin triangles, fast) ends in exactly
/// that many segments.
int odd_segments(double length, double h) {
  int n = std::max(1, rounded(length / h));
  while (n % 2 == 0) n /= 2;
  return n;
}

/// Which plane of the box [-half, half] the face lies on (2 axis + (side > 0)), or -1, told exactly by
/// coordinates (dihedral angles of thin triangles are not reliable).
int box_plane_of(const Mesh& mesh, Mesh::Face_index f, const std::array<double, 3>& half) {
  for (int a = 0; a < 3; ++a)
    for (const double side : {-half[a], half[a]}) {
      bool on = true;
      for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) on = on && mesh.point(v)[a] == side;
      if (on) return 2 * a + (side > 0);
    }
  return -1;
}

/// Isotropic remeshing to edge length h of a solid whose faces fall into parts (part(f): a box plane, a
/// hole's wall, ...). Constrained edges: those between faces of different parts (the sharp ones) and, in
/// part -1 (the walls of vertical prisms), the vertical edges (the prism's creases: else the remeshed wall
/// would cut across them and shrink the hole). Constrained edges may be split and collapsed along
/// themselves; a vertex joining three of them (a box corner, a rim corner) stays in place, so box edges
/// and rim polygons stay exact. With `project_per_part`, moved vertices are projected back onto their own
/// part only (else a vertex beside a concave crease may land on the other surface).
void remesh_keeping_creases(Mesh& mesh, double h, const std::function<int(Mesh::Face_index)>& part,
                            bool project_per_part) {
  auto part_map = mesh.add_property_map<Mesh::Face_index, int>("f:part", -1).first;
  for (const auto f : mesh.faces()) put(part_map, f, part(f));
  auto constrained = mesh.add_property_map<Mesh::Edge_index, bool>("e:constrained", false).first;
  for (const auto e : mesh.edges()) {
    const int p0 = part_map[mesh.face(mesh.halfedge(e, 0))], p1 = part_map[mesh.face(mesh.halfedge(e, 1))];
    const Point &a = mesh.point(mesh.vertex(e, 0)), &b = mesh.point(mesh.vertex(e, 1));
    put(constrained, e, p0 != p1 || (p0 == -1 && a.x() == b.x() && a.y() == b.y()));
  }
  const auto np =
      CGAL::parameters::number_of_iterations(5).edge_is_constrained_map(constrained).protect_constraints(false);
  if (project_per_part)
    PMP::isotropic_remeshing(faces(mesh), h, mesh, np.face_patch_map(part_map));
  else
    PMP::isotropic_remeshing(faces(mesh), h, mesh, np);
  mesh.remove_property_map(constrained);
  mesh.remove_property_map(part_map);
  mesh.collect_garbage();
}

/// Lawson flips in the planes of the box [-half, half]: an edge between two faces of one plane whose
/// opposite angles sum to more than 180 degrees is flipped until none is, so each plane's triangulation
/// is the Delaunay one of its vertices, which has the largest smallest angle (the remesher flips for
/// valence, and leaves angles below 20 degrees beside rims close to a plate edge). Box edges, rims and
/// other constrained edges lie between different parts and are never flipped.
void make_planes_delaunay(Mesh& mesh, const std::array<double, 3>& half) {
  const auto cot = [&](Mesh::Vertex_index apex, Mesh::Vertex_index p, Mesh::Vertex_index q) {
    const Vector u = mesh.point(p) - mesh.point(apex), v = mesh.point(q) - mesh.point(apex);
    return (u * v) / std::sqrt(CGAL::cross_product(u, v).squared_length());
  };
  for (bool flipped = true; flipped;) {
    flipped = false;
    for (const auto e : mesh.edges()) {
      const auto h = mesh.halfedge(e), o = mesh.opposite(h);
      const int plane = box_plane_of(mesh, mesh.face(h), half);
      if (plane < 0 || box_plane_of(mesh, mesh.face(o), half) != plane) continue;
      const auto a = mesh.source(h), c = mesh.target(h);
      const auto b = mesh.target(mesh.next(h)), d = mesh.target(mesh.next(o));
      if (cot(b, c, a) + cot(d, a, c) >= -1e-12 || mesh.halfedge(b, d) != Mesh::null_halfedge()) continue;
      CGAL::Euler::flip_edge(h, mesh);
      flipped = true;
    }
  }
}

/// Closed prism inscribed in the vertical cylinder of `radius` about `centre` (x, y): `sides` sides (a
/// multiple of 4 puts corners on the axis lines through the centre), rings at z = lattice_coordinate(k,
/// segments, half_height) for k = -1 .. segments + 1, so the rings at z = +-half_height are its own
/// polygons and the prism reaches one segment beyond.
Mesh make_prism(const std::array<double, 2>& centre, double radius, int sides, int segments, double half_height,
                const std::string& source) {
  Soup soup;
  std::vector<std::size_t> below;
  for (int k = -1; k <= segments + 1; ++k) {
    const double z = lattice_coordinate(k, segments, half_height);
    const auto ring = add_ring(soup, sides, radius, z, centre);
    if (k == -1)
      add_fan(soup, soup.add(Point(centre[0], centre[1], z)), ring, true);
    else
      add_band(soup, below, ring, true);  // lower ring as "inner": flip to face outward
    below = ring;
  }
  add_fan(soup, soup.add(Point(centre[0], centre[1], lattice_coordinate(segments + 1, segments, half_height))), below,
          false);
  return soup.to_mesh(source);
}

enum class BooleanOp { kUnion, kDifference };

/// a op b by corefinement (both are corefined in place), in canonical order.
/// Throws core::NumericalError "model 'NAME': the Boolean WHAT failed".
Mesh boolean(Mesh& a, Mesh& b, BooleanOp op, const std::string& model, const std::string& what) {
  Mesh out;
  const bool ok = op == BooleanOp::kUnion ? PMP::corefine_and_compute_union(a, b, out)
                                          : PMP::corefine_and_compute_difference(a, b, out);
  if (!ok) throw core::NumericalError("model '" + model + "': the Boolean " + what + " failed");
  return canonical(out, "Boolean " + std::string(op == BooleanOp::kUnion ? "union" : "difference") + " of model '" +
                            model + "'");
}

/// Cube [-1,1]^3 minus the prism inscribed in the cylinder of radius kHoleRadius along z, by
/// corefinement, then remeshed to the segment length with its sharp edges kept in place.
Mesh make_cube_with_hole(const ModelParams& p) {
  const int n = p.resolution;
  const double h = 2.0 / n;
  // The cube as 12 triangles: its top and bottom diagonals (x = y) then pass exactly through two corners
  // of each rim polygon, so the Boolean creates no vertex on a rim (such vertices, arbitrarily close to
  // the rim's corners, would leave slivers no remeshing removes).
  Soup cube_soup;
  add_lattice_box(cube_soup, {1, 1, 1}, [](const Lattice& ijk) {
    return Point(2 * ijk[0] - 1, 2 * ijk[1] - 1, 2 * ijk[2] - 1);
  });
  Mesh cube = cube_soup.to_mesh("cube of model 'cube-with-hole'");

  // Cylinder with the segment length, through the cube and one segment beyond, with rings exactly at
  // z = -1 and 1: the rims are its own polygons. A multiple of 8 segments (corners on the diagonals), at
  // least 16 (the hole's vertical edges must stay below the 30 degree feature angle).
  const int nc = 8 * std::max(2, rounded(2 * kPi * kHoleRadius / h / 8));
  Mesh cylinder = make_prism({0.0, 0.0}, kHoleRadius, nc, n, 1.0, "cylinder of model 'cube-with-hole'");
  Mesh result = boolean(cube, cylinder, BooleanOp::kDifference, "cube-with-hole", "difference of cube and cylinder");

  // Each cube edge is split into the odd part of n; the remesher halves it down to exactly n segments.
  const std::array<double, 3> half = {1.0, 1.0, 1.0};
  split_box_edges(result, half, [&](double length) { return odd_segments(length, h); });
  remesh_keeping_creases(result, h, [&](Mesh::Face_index f) { return box_plane_of(result, f, half); }, false);
  return canonical(result, "model 'cube-with-hole'");
}

/// The assembly's plate [-half, half] as a soup. Its top and bottom faces are cut by the lines x = 0,
/// +-1.5 and y = 0, +-1 (through the hole centres) into 16 rectangles, each with one hole centre as a
/// corner and split along the diagonal that misses it (at least 0.35 from it, beyond the hole's radius):
/// the only top edges crossing a rim are the axis lines through its centre, which meet it exactly at
/// corners of the rim polygon, so the Boolean puts no vertex near a rim corner. The ring's foot (|x| <
/// 0.85, |y| < 0.29) is crossed by the lines x = 0 and y = 0 only.
Mesh make_plate() {
  const std::array<double, 5> xs = {-kPlateHalf[0], -kPlateHoleCentre[0], 0.0, kPlateHoleCentre[0], kPlateHalf[0]};
  const std::array<double, 5> ys = {-kPlateHalf[1], -kPlateHoleCentre[1], 0.0, kPlateHoleCentre[1], kPlateHalf[1]};
  const std::array<double, 2> zs = {-kPlateHalf[2], kPlateHalf[2]};
  Soup soup;
  const auto id = [&](int i, int j, int k) { return soup.weld({i, j, k, 0}, Point(xs[i], ys[j], zs[k])); };
  const auto hole_centre = [&](int i, int j) { return (i == 1 || i == 3) && (j == 1 || j == 3); };
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        const bool flip = k == 0;  // counter-clockwise seen from outside: from below on the bottom
        const auto p00 = id(i, j, k), p10 = id(i + 1, j, k), p11 = id(i + 1, j + 1, k), p01 = id(i, j + 1, k);
        if (hole_centre(i, j) || hole_centre(i + 1, j + 1)) {
          soup.triangle(p00, p10, p01, flip);
          soup.triangle(p10, p11, p01, flip);
        } else {
          soup.triangle(p00, p10, p11, flip);
          soup.triangle(p00, p11, p01, flip);
        }
      }
  for (int m = 0; m < 4; ++m) {
    soup.quad(id(4, m, 0), id(4, m + 1, 0), id(4, m + 1, 1), id(4, m, 1));  // x = +2
    soup.quad(id(0, m + 1, 0), id(0, m, 0), id(0, m, 1), id(0, m + 1, 1));  // x = -2
    soup.quad(id(m + 1, 4, 0), id(m, 4, 0), id(m, 4, 1), id(m + 1, 4, 1));  // y = +1.5
    soup.quad(id(m, 0, 0), id(m + 1, 0, 0), id(m + 1, 0, 1), id(m, 0, 1));  // y = -1.5
  }
  return soup.to_mesh("plate of model 'assembly'");
}

/// The assembly's plate minus its four holes: prisms of `sides` sides and segments of about h.
Mesh plate_minus_holes(int sides, double h, const std::string& name) {
  Mesh result = make_plate();
  const int segments = std::max(1, rounded(2 * kPlateHalf[2] / h));
  for (const double sx : {-1.0, 1.0})
    for (const double sy : {-1.0, 1.0}) {
      Mesh prism = make_prism({sx * kPlateHoleCentre[0], sy * kPlateHoleCentre[1]}, kPlateHoleRadius, sides, segments,
                              kPlateHalf[2], "hole of model '" + name + "'");
      result = boolean(result, prism, BooleanOp::kDifference, name, "difference of plate and hole");
    }
  return result;
}

/// The number of sides of a prism of about the segment length h around a circle of `length`: a
/// multiple of 4 (the plate's axis lines meet its rim at corners).
int sides_of_4(double length, double h) { return 4 * std::max(1, rounded(length / h / 4)); }

/// The assembly's base alone (genus 4): the plate minus the assembly's four holes, remeshed to the
/// segment length 2 / resolution with the plate's edges and the rims kept.
Mesh make_plate_with_holes(const ModelParams& p) {
  const std::string name = "plate";
  const double h = 2.0 / p.resolution;
  Mesh result = plate_minus_holes(sides_of_4(2 * kPi * kPlateHoleRadius, h), h, name);
  split_box_edges(result, kPlateHalf, [&](double length) { return odd_segments(length, h); });
  // Parts: the plate's six planes and the holes' walls (-1, vertical prisms).
  remesh_keeping_creases(result, h, [&](Mesh::Face_index f) { return box_plane_of(result, f, kPlateHalf); }, true);
  make_planes_delaunay(result, kPlateHalf);
  return canonical(result, "model '" + name + "'");
}

/// Liu et al. 2013, Fig. 1: the plate minus four prisms (the holes) union a torus standing on the plate
/// (the ring), by corefinement, then remeshed to the segment length 2 / resolution with the plate's edges,
/// the rims, the holes' prism creases and the ring's foot kept.
Mesh make_assembly(const ModelParams& p) {
  const std::string name = "assembly";
  const double h = 2.0 / p.resolution;
  const auto multiple_of_4 = [&](double length) { return sides_of_4(length, h); };

  Mesh result = plate_minus_holes(multiple_of_4(2 * kPi * kPlateHoleRadius), h, name);

  // The ring: a torus about the y axis through (0, 0, kRingCentreZ), segments of about h.
  Soup ring_soup;
  const int nv = multiple_of_4(2 * kPi * kRingMinor);
  const int nu = 4 * std::max(1, rounded(nv * kRingMajor / kRingMinor / 4));
  add_torus(ring_soup, kRingMajor, kRingMinor, nu, nv,
            [](double x, double y, double z) { return Point(x, -z, kRingCentreZ + y); });  // a rotation about x
  Mesh ring = ring_soup.to_mesh("ring of model 'assembly'");
  result = boolean(result, ring, BooleanOp::kUnion, name, "union of plate and ring");

  split_box_edges(result, kPlateHalf, [&](double length) { return odd_segments(length, h); });
  // Parts: the plate's six planes, the ring (above the top face), the holes' walls (-1, vertical prisms).
  remesh_keeping_creases(
      result, h,
      [&](Mesh::Face_index f) {
        const int plane = box_plane_of(result, f, kPlateHalf);
        if (plane >= 0) return plane;
        for (const auto v : CGAL::vertices_around_face(result.halfedge(f), result))
          if (result.point(v).z() > kPlateHalf[2]) return 6;
        return -1;
      },
      true);
  make_planes_delaunay(result, kPlateHalf);
  return canonical(result, "model '" + name + "'");
}

struct Model {
  const char* name;
  const char* description;
  Mesh (*make)(const ModelParams&);
};

Mesh make_bulged_box_from_params(const ModelParams& p) { return make_bulged_box(p, p.bulge); }

const std::vector<Model>& models() {
  static const std::vector<Model> table = {
      {"box", "box [-1,1]x[-0.75,0.75]x[-0.5,0.5], faces gridded (genus 0, 12 sharp edges)", make_box},
      {"bulged-box", "the box with each face bulged out smoothly; edges stay straight and sharp (genus 0)",
       make_bulged_box_from_params},
      {"torus", "torus about z, radii 2 and 0.75 (genus 1, smooth)", make_torus},
      {"cube-with-hole", "cube [-1,1]^3 minus a through hole of radius 0.7 along z (genus 1; Liu et al. 2013, Fig. 3)",
       make_cube_with_hole},
      {"sphere", "unit sphere, projected cube grid (genus 0, smooth)", make_sphere},
      {"tetrahedron", "regular tetrahedron with corners (1,1,1),(1,-1,-1),(-1,1,-1),(-1,-1,1) (genus 0)",
       make_tetrahedron},
      {"cone", "cone about z, base radius 1 at z=-0.5, apex at z=1 (genus 0, sharp rim and apex)", make_cone},
      {"plate",
       "plate [-2,2]x[-1.5,1.5]x[-0.25,0.25] with four through holes of radius 0.3 along z at (+-1.5, +-1) "
       "(genus 4; the base of Liu et al. 2013, Fig. 1)",
       make_plate_with_holes},
      {"assembly",
       "plate [-2,2]x[-1.5,1.5]x[-0.25,0.25] with four through holes of radius 0.3 and a ring (radii 0.8, 0.3) "
       "standing on it (genus 5; Liu et al. 2013, Fig. 1)",
       make_assembly},
      {"washer",
       "ring about z, plus-shaped cross section: flange r 0.7..1.3, |z|<=0.1, hub r 0.9..1.1, |z|<=0.3 "
       "(genus 1, 12 sharp rings)",
       make_washer},
      {"flanged-ring",
       "ring about z, L-shaped cross section: wall r 1..1.2, z 0..0.6, flange r 1..1.6, z 0..0.2 "
       "(genus 1, 6 sharp rings)",
       make_flanged_ring},
  };
  return table;
}

const Model& find_model(const std::string& name) {
  for (const auto& m : models())
    if (name == m.name) return m;
  std::ostringstream msg;
  msg << "unknown model '" << name << "'; known: ";
  for (std::size_t k = 0; k < models().size(); ++k) msg << (k ? ", " : "") << models()[k].name;
  throw core::ConfigError(msg.str());
}

}  // namespace

std::vector<std::string> model_names() {
  std::vector<std::string> names;
  for (const auto& m : models()) names.emplace_back(m.name);
  return names;
}

std::string model_description(const std::string& name) { return find_model(name).description; }

surface::Mesh make_model(const ModelParams& params) {
  const Model& model = find_model(params.name);
  if (params.resolution < kMinResolution || params.resolution > kMaxResolution)
    throw core::ConfigError("model resolution " + std::to_string(params.resolution) + " is out of range [" +
                            std::to_string(kMinResolution) + ", " + std::to_string(kMaxResolution) + "]");
  if (!(params.bulge >= 0.0 && params.bulge <= kMaxBulge)) {
    std::ostringstream msg;
    msg << "model bulge " << params.bulge << " is out of range [0, " << kMaxBulge << "]";
    throw core::ConfigError(msg.str());
  }
  return model.make(params);
}

}  // namespace volts::models
