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
constexpr double kConeRadius = 1.0;
constexpr double kConeBase = -0.5;
constexpr double kConeApex = 1.0;

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

Mesh make_torus(const ModelParams& p) {
  const int nv = p.resolution;                                                // around the minor circle
  const int nu = std::max(3, rounded(p.resolution * kTorusMajor / kTorusMinor));  // around the axis
  Soup soup;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const auto u = unit_circle(i, nu), v = unit_circle(j, nv);
      const double rho = kTorusMajor + kTorusMinor * v[0];
      soup.add(Point(rho * u[0], rho * u[1], kTorusMinor * v[1]));
    }
  const auto id = [&](int i, int j) -> std::size_t { return (i % nu) * nv + j % nv; };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) soup.quad(id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
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

/// A ring of `count` vertices on the circle of `radius` about the z axis at height z, at angles
/// 2 pi k / count (counter-clockwise about +z).
std::vector<std::size_t> add_ring(Soup& soup, int count, double radius, double z) {
  std::vector<std::size_t> ring(count);
  for (int k = 0; k < count; ++k) {
    const auto [c, s] = unit_circle(k, count);
    ring[k] = soup.add(Point(radius * c, radius * s, z));
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

/// Splits each of the 12 edges of the cube [-1,1]^3 in `mesh` (corner to corner, untouched by the Boolean)
/// into `segments` equal parts and triangulates the faces beside them.
void split_cube_edges(Mesh& mesh, int segments) {
  std::vector<Mesh::Halfedge_index> cube_edges;
  for (const auto e : mesh.edges()) {
    const Point &a = mesh.point(mesh.vertex(e, 0)), &b = mesh.point(mesh.vertex(e, 1));
    int same = 0, corners = 0;
    for (int i = 0; i < 3; ++i) {
      same += a[i] == b[i];
      corners += std::abs(a[i]) == 1 && std::abs(b[i]) == 1;
    }
    if (corners == 3 && same == 2) cube_edges.push_back(mesh.halfedge(e));
  }
  for (const auto h : cube_edges) {
    const Point a = mesh.point(mesh.source(h)), b = mesh.point(mesh.target(h));
    const int axis = a.x() != b.x() ? 0 : a.y() != b.y() ? 1 : 2;
    for (int k = 1; k < segments; ++k) {  // h keeps its target: each split inserts after the last point
      std::array<double, 3> x = {a.x(), a.y(), a.z()};
      x[axis] = lattice_coordinate(a[axis] < 0 ? k : segments - k, segments, 1.0);
      mesh.point(mesh.target(CGAL::Euler::split_edge(h, mesh))) = Point(x[0], x[1], x[2]);
    }
  }
  PMP::triangulate_faces(mesh);
}

/// Isotropic remeshing of the cube with a hole to edge length h. Constrained edges: the sharp ones, between
/// faces of different cube planes or of a plane and the wall (told exactly by coordinates, where dihedral
/// angles of thin triangles are not reliable), and the vertical creases of the hole's prism (else the
/// remeshed wall would cut across them and shrink the hole). Their ends, the cube's and the rims' corners,
/// join three constrained edges, so the remesher keeps them in place: corners, cube edges and rim polygons
/// stay exact, and the volume stays that of the cube minus the prism.
void remesh_cube_with_hole(Mesh& mesh, double h) {
  const auto plane_of = [&](Mesh::Face_index f) {
    for (int a = 0; a < 3; ++a)
      for (const double side : {-1.0, 1.0}) {
        bool on = true;
        for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) on = on && mesh.point(v)[a] == side;
        if (on) return 2 * a + (side > 0);
      }
    return -1;  // the hole's wall
  };
  auto constrained = mesh.add_property_map<Mesh::Edge_index, bool>("e:constrained", false).first;
  for (const auto e : mesh.edges()) {
    const int p0 = plane_of(mesh.face(mesh.halfedge(e, 0))), p1 = plane_of(mesh.face(mesh.halfedge(e, 1)));
    const Point &a = mesh.point(mesh.vertex(e, 0)), &b = mesh.point(mesh.vertex(e, 1));
    put(constrained, e, p0 != p1 || (p0 == -1 && a.x() == b.x() && a.y() == b.y()));
  }
  PMP::isotropic_remeshing(faces(mesh), h, mesh,
                           CGAL::parameters::number_of_iterations(5)
                               .edge_is_constrained_map(constrained)
                               .protect_constraints(false));
  mesh.remove_property_map(constrained);
  mesh.collect_garbage();
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
  Soup cylinder_soup;
  std::vector<std::size_t> below;
  for (int k = -1; k <= n + 1; ++k) {
    const double z = lattice_coordinate(k, n, 1.0);
    const auto ring = add_ring(cylinder_soup, nc, kHoleRadius, z);
    if (k == -1)
      add_fan(cylinder_soup, cylinder_soup.add(Point(0, 0, z)), ring, true);
    else
      add_band(cylinder_soup, below, ring, true);  // lower ring as "inner": flip to face outward
    below = ring;
  }
  add_fan(cylinder_soup, cylinder_soup.add(Point(0, 0, lattice_coordinate(n + 1, n, 1.0))), below, false);
  Mesh cylinder = cylinder_soup.to_mesh("cylinder of model 'cube-with-hole'");

  Mesh difference;
  if (!PMP::corefine_and_compute_difference(cube, cylinder, difference))
    throw core::NumericalError("model 'cube-with-hole': the Boolean difference of cube and cylinder failed");
  Mesh result = canonical(difference, "Boolean difference of model 'cube-with-hole'");

  // The remesher halves constrained edges longer than 4/3 h: split the cube's edges into the odd part of n
  // (few thin triangles, fast) and it halves them down to exactly n segments.
  int odd = n;
  while (odd % 2 == 0) odd /= 2;
  split_cube_edges(result, odd);
  remesh_cube_with_hole(result, h);
  return canonical(result, "model 'cube-with-hole'");
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
