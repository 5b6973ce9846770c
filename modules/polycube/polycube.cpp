#include "polycube/polycube.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>

#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "core/errors.h"
#include "polycube/cube_frame.h"
#include "surface/mesh_json.h"
#include "viz/viz.h"

namespace volts::polycube {

using surface::Mesh;
using K = surface::Kernel;
using Vec3 = std::array<double, 3>;
constexpr double kPi = 3.14159265358979323846;

namespace {

double dist(const surface::Point& a, const surface::Point& b) { return std::sqrt(CGAL::squared_distance(a, b)); }

double corner_angle(const Vec3& p, const Vec3& q, const Vec3& r) {  // angle at p in triangle pqr
  double a[3], b[3];
  for (int k = 0; k < 3; ++k) a[k] = q[k] - p[k], b[k] = r[k] - p[k];
  const double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), lb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
  if (la == 0 || lb == 0) return 0;
  return std::acos(std::clamp(d / (la * lb), -1.0, 1.0));
}

Vec3 to_vec(const surface::Point& p) { return {p.x(), p.y(), p.z()}; }

std::vector<int> cube_codes(const classify::Classification& c) {
  std::map<int, int> corner_of_vertex;
  for (std::size_t i = 0; i < c.corners.size(); ++i) corner_of_vertex[c.corners[i]] = static_cast<int>(i);
  std::vector<std::set<int>> adj(c.corners.size());
  for (const auto& k : c.curves) {
    const int a = corner_of_vertex.at(k.vertices.front()), b = corner_of_vertex.at(k.vertices.back());
    adj[a].insert(b);
    adj[b].insert(a);
  }
  return detail::cube_codes(adj);
}

}  // namespace

Polycube map_surface(const Mesh& mesh, const classify::Classification& c, const split::Decomposition& d,
                     const Params& params) {
  if (params.weights != "mean-value" && params.weights != "uniform")
    throw core::ConfigError("polycube.weights must be 'mean-value' or 'uniform', not '" + params.weights + "'");
  if (d.components.size() != 1 || d.components[0].type != split::ComponentType::cube)
    throw core::TopologyError("polycube: only a single cube component is supported yet (issue 6); this decomposition has " +
                              std::to_string(d.components.size()) + " components — set `route: tet` to mesh it");

  Polycube pc;
  const std::vector<int> code = cube_codes(c);
  std::map<int, int> corner_of_vertex;
  for (std::size_t i = 0; i < c.corners.size(); ++i) {
    corner_of_vertex[c.corners[i]] = static_cast<int>(i);
    pc.corner_cube_coords.push_back({code[i] & 1, (code[i] >> 1) & 1, (code[i] >> 2) & 1});
  }

  // Faces of the patches: the one coordinate shared by all corners of the patch.
  std::vector<int> and_code(c.patches, 7), or_code(c.patches, 0);
  for (const auto& k : c.curves)
    for (int v : {k.vertices.front(), k.vertices.back()})
      for (int p : {k.patch_left, k.patch_right}) {
        and_code[p] &= code[corner_of_vertex.at(v)];
        or_code[p] |= code[corner_of_vertex.at(v)];
      }
  pc.patch_face.assign(c.patches, -1);
  std::set<int> used;
  for (int p = 0; p < c.patches; ++p) {
    const int const1 = and_code[p], const0 = ~or_code[p] & 7;
    const int bits = const1 | const0;
    if (bits != 1 && bits != 2 && bits != 4)
      throw core::TopologyError("polycube: patch " + std::to_string(p) + " does not lie on one face of the cube");
    const int axis = bits == 1 ? 0 : bits == 2 ? 1 : 2;
    pc.patch_face[p] = 2 * axis + (const1 ? 1 : 0);
    used.insert(pc.patch_face[p]);
  }
  if (used.size() != 6) throw core::TopologyError("polycube: two patches map to the same cube face");

  // Curves onto cube edges by arc length: both neighbouring patches see the same boundary map.
  const std::size_t nv = mesh.number_of_vertices();
  pc.vertex_uvw.assign(nv, {0, 0, 0});
  std::vector<char> fixed(nv, 0);
  for (const auto& k : c.curves) {
    const auto& vs = k.vertices;
    std::vector<double> s(vs.size(), 0.0);
    for (std::size_t i = 1; i < vs.size(); ++i)
      s[i] = s[i - 1] + dist(mesh.point(Mesh::Vertex_index(vs[i - 1])), mesh.point(Mesh::Vertex_index(vs[i])));
    const auto& a = pc.corner_cube_coords[corner_of_vertex.at(vs.front())];
    const auto& b = pc.corner_cube_coords[corner_of_vertex.at(vs.back())];
    for (std::size_t i = 0; i < vs.size(); ++i) {
      const double t = s[i] / s.back();
      for (int ax = 0; ax < 3; ++ax) pc.vertex_uvw[vs[i]][ax] = a[ax] + t * (b[ax] - a[ax]);
      fixed[vs[i]] = 1;
    }
  }

  // Interior of each patch: one sparse solve per patch for its two free coordinates.
  std::vector<int> vertex_patch(nv, -1);
  for (auto f : mesh.faces())
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      if (!fixed[v]) vertex_patch[v] = c.face_patch[f];
  for (int p = 0; p < c.patches; ++p) {
    const int axis = pc.patch_face[p] / 2, side = pc.patch_face[p] % 2;
    std::vector<int> index(nv, -1), unknowns;
    for (auto v : mesh.vertices())
      if (vertex_patch[v] == p) index[v] = static_cast<int>(unknowns.size()), unknowns.push_back(static_cast<int>(v));
    for (int v : unknowns) pc.vertex_uvw[v][axis] = side;
    if (unknowns.empty()) continue;
    const int n = static_cast<int>(unknowns.size());
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 2);
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int row = 0; row < n; ++row) {
      const Mesh::Vertex_index vi(unknowns[row]);
      std::map<int, double> w;  // ordered: deterministic assembly
      for (auto h : CGAL::halfedges_around_source(vi, mesh)) {
        const auto vj = mesh.target(h), vk = mesh.target(mesh.next(h));
        if (params.weights == "uniform") {
          w[static_cast<int>(vj)] += 1.0;
          continue;
        }
        const double theta = corner_angle(to_vec(mesh.point(vi)), to_vec(mesh.point(vj)), to_vec(mesh.point(vk)));
        const double t = std::tan(theta / 2);
        w[static_cast<int>(vj)] += t / dist(mesh.point(vi), mesh.point(vj));
        w[static_cast<int>(vk)] += t / dist(mesh.point(vi), mesh.point(vk));
      }
      double sum = 0;
      for (const auto& [j, wij] : w) {
        sum += wij;
        if (index[j] >= 0) trip.emplace_back(row, index[j], -wij);
        else rhs(row, 0) += wij * pc.vertex_uvw[j][a1], rhs(row, 1) += wij * pc.vertex_uvw[j][a2];
      }
      trip.emplace_back(row, row, sum);
    }
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(trip.begin(), trip.end());
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
    lu.compute(A);
    if (lu.info() != Eigen::Success) throw core::NumericalError("polycube: disk map of patch " + std::to_string(p) + " is singular");
    const Eigen::MatrixXd x = lu.solve(rhs);
    for (int row = 0; row < n; ++row) {
      pc.vertex_uvw[unknowns[row]][a1] = x(row, 0);
      pc.vertex_uvw[unknowns[row]][a2] = x(row, 1);
    }
  }

  // The cube frame is chosen combinatorially; mirror it if it came out left-handed, so that the
  // volume map is orientation-preserving.
  double vol = 0;
  for (auto f : mesh.faces()) {
    std::vector<Vec3> q;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) q.push_back(pc.vertex_uvw[v]);
    vol += (q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1]) - q[0][1] * (q[1][0] * q[2][2] - q[1][2] * q[2][0]) +
            q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0])) / 6.0;
  }
  if (vol < 0) {
    for (auto& u : pc.vertex_uvw) std::swap(u[0], u[1]);
    for (auto& cc : pc.corner_cube_coords) std::swap(cc[0], cc[1]);
    for (auto& f : pc.patch_face) {
      const int axis = f / 2, side = f % 2;
      f = 2 * (axis == 0 ? 1 : axis == 1 ? 0 : 2) + side;
    }
  }

  // Flipped triangles by CGAL's exact orientation predicate in the face plane.
  for (auto f : mesh.faces()) {
    const int face = pc.patch_face[c.face_patch[f]], axis = face / 2, side = face % 2;
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    std::vector<K::Point_2> q;
    std::vector<Vec3> phys, cube;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      q.emplace_back(pc.vertex_uvw[v][a1], pc.vertex_uvw[v][a2]);
      phys.push_back(to_vec(mesh.point(v)));
      cube.push_back(pc.vertex_uvw[v]);
    }
    const auto o = CGAL::orientation(q[0], q[1], q[2]);
    if (o != (side == 1 ? CGAL::POSITIVE : CGAL::NEGATIVE)) ++pc.flipped_surface_triangles;
    for (int i = 0; i < 3; ++i) {
      const double a = corner_angle(phys[i], phys[(i + 1) % 3], phys[(i + 2) % 3]);
      const double b = corner_angle(cube[i], cube[(i + 1) % 3], cube[(i + 2) % 3]);
      pc.max_angle_distortion_deg = std::max(pc.max_angle_distortion_deg, std::abs(a - b) * 180.0 / kPi);
    }
  }
  return pc;
}

// ---------------------------------------------------------------------------------------------
// Volume map

struct VolumeMap::Impl {
  using Triangle = K::Triangle_3;
  using Primitive = CGAL::AABB_triangle_primitive<K, std::vector<Triangle>::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
  struct Face {
    std::vector<Triangle> triangles;           // (s, t, 0) images of the patch's triangles
    std::vector<std::array<Vec3, 3>> physical;  // their physical corners
    std::unique_ptr<Tree> tree;
  };
  std::array<Face, 6> faces;

  Vec3 on_face(int face, double s, double t) const {
    const Face& f = faces[face];
    const K::Point_3 q(s, t, 0);
    const auto hit = f.tree->closest_point_and_primitive(q);
    const std::size_t i = static_cast<std::size_t>(hit.second - f.triangles.begin());
    const Triangle& tri = f.triangles[i];
    // Barycentric coordinates of the closest point in the (s, t) triangle.
    const double x = hit.first.x(), y = hit.first.y();
    const double x0 = tri[0].x(), y0 = tri[0].y(), x1 = tri[1].x(), y1 = tri[1].y(), x2 = tri[2].x(), y2 = tri[2].y();
    const double det = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    double b1 = ((x - x0) * (y2 - y0) - (x2 - x0) * (y - y0)) / det;
    double b2 = ((x1 - x0) * (y - y0) - (x - x0) * (y1 - y0)) / det;
    double b0 = 1 - b1 - b2;
    Vec3 r{};
    for (int k = 0; k < 3; ++k) r[k] = b0 * f.physical[i][0][k] + b1 * f.physical[i][1][k] + b2 * f.physical[i][2][k];
    return r;
  }
};

VolumeMap::VolumeMap(const Mesh& mesh, const classify::Classification& c, const Polycube& p) : impl_(std::make_unique<Impl>()) {
  for (auto f : mesh.faces()) {
    const int face = p.patch_face[c.face_patch[f]], axis = face / 2;
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    std::vector<K::Point_3> q;
    std::array<Vec3, 3> phys;
    int i = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      q.emplace_back(p.vertex_uvw[v][a1], p.vertex_uvw[v][a2], 0.0);
      phys[i++] = to_vec(mesh.point(v));
    }
    impl_->faces[face].triangles.emplace_back(q[0], q[1], q[2]);
    impl_->faces[face].physical.push_back(phys);
  }
  for (int f = 0; f < 6; ++f) {
    auto& F = impl_->faces[f];
    if (F.triangles.empty()) throw core::TopologyError("polycube: cube face " + std::to_string(f) + " has no triangles");
    F.tree = std::make_unique<Impl::Tree>(F.triangles.cbegin(), F.triangles.cend());
    F.tree->accelerate_distance_queries();
  }
}
VolumeMap::~VolumeMap() = default;
VolumeMap::VolumeMap(VolumeMap&&) noexcept = default;

std::array<double, 3> VolumeMap::on_face(int face, double s, double t) const { return impl_->on_face(face, s, t); }

std::array<double, 3> VolumeMap::operator()(const std::array<double, 3>& x) const {
  // Coons (Boolean-sum) transfinite interpolation: faces - edges + corners.
  auto L = [&](int axis, int side) { return side ? x[axis] : 1.0 - x[axis]; };
  auto face_at = [&](int axis, int side, const Vec3& y) { return on_face(2 * axis + side, y[(axis + 1) % 3], y[(axis + 2) % 3]); };
  Vec3 r{0, 0, 0};
  auto acc = [&](double w, const Vec3& v) {
    for (int k = 0; k < 3; ++k) r[k] += w * v[k];
  };
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s) acc(L(a, s), face_at(a, s, x));
  for (int a = 0; a < 3; ++a) {  // edges parallel to axis a
    const int b = (a + 1) % 3, cc = (a + 2) % 3;
    for (int sb = 0; sb < 2; ++sb)
      for (int sc = 0; sc < 2; ++sc) {
        Vec3 y = x;
        y[b] = sb, y[cc] = sc;
        acc(-L(b, sb) * L(cc, sc), face_at(b, sb, y));
      }
  }
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 y{double(corner & 1), double((corner >> 1) & 1), double((corner >> 2) & 1)};
    acc(L(0, corner & 1) * L(1, (corner >> 1) & 1) * L(2, (corner >> 2) & 1), face_at(0, corner & 1, y));
  }
  return r;
}

// ---------------------------------------------------------------------------------------------

core::Json to_json(const Polycube& p) {
  std::vector<double> uvw;
  uvw.reserve(3 * p.vertex_uvw.size());
  for (const auto& u : p.vertex_uvw) uvw.insert(uvw.end(), u.begin(), u.end());
  return core::Json{{"corner_cube_coords", p.corner_cube_coords}, {"patch_face", p.patch_face}, {"vertex_uvw", uvw},
                    {"flipped_surface_triangles", p.flipped_surface_triangles},
                    {"max_angle_distortion_deg", p.max_angle_distortion_deg}};
}

Polycube from_json(const core::Json& j, const std::string& file) {
  Polycube p;
  try {
    p.corner_cube_coords = core::require(j, "corner_cube_coords", file).get<std::vector<std::array<int, 3>>>();
    p.patch_face = core::require(j, "patch_face", file).get<std::vector<int>>();
    const auto uvw = core::require(j, "vertex_uvw", file).get<std::vector<double>>();
    if (uvw.size() % 3) throw core::InvalidInputError(file + ": vertex_uvw needs 3 values per vertex");
    for (std::size_t i = 0; i < uvw.size(); i += 3) p.vertex_uvw.push_back({uvw[i], uvw[i + 1], uvw[i + 2]});
    p.flipped_surface_triangles = core::require(j, "flipped_surface_triangles", file).get<int>();
    p.max_angle_distortion_deg = core::require(j, "max_angle_distortion_deg", file).get<double>();
  } catch (const core::Json::exception& e) {
    throw core::InvalidInputError(file + ": malformed polycube: " + e.what());
  }
  for (int f : p.patch_face)
    if (f < 0 || f > 5) throw core::InvalidInputError(file + ": patch_face out of range");
  return p;
}

core::Json report_figures(const Polycube& p, const split::Decomposition& d) {
  int cubes = 0, virt = 0;
  for (const auto& k : d.components) {
    cubes += k.type != split::ComponentType::virtual_component;
    virt += k.type == split::ComponentType::virtual_component;
  }
  return core::Json{{"cubes", cubes}, {"tori", 0}, {"virtual_components", virt},
                    {"flipped_surface_triangles", p.flipped_surface_triangles},
                    {"max_angle_distortion_deg", p.max_angle_distortion_deg}};
}

namespace {
viz::PolyData polycube_polydata(const Mesh& mesh, const classify::Classification& c, const Polycube& p) {
  viz::PolyData d;
  d.points = surface::vertex_array(mesh);
  d.polys = surface::triangle_array(mesh);
  viz::Field uvw{"uvw", 3, {}}, face{"cube_face", 1, {}};
  for (const auto& u : p.vertex_uvw) uvw.values.insert(uvw.values.end(), u.begin(), u.end());
  for (auto f : mesh.faces()) face.values.push_back(p.patch_face[c.face_patch[f]]);
  d.point_fields = {uvw};
  d.cell_fields = {face};
  return d;
}
}  // namespace

void write_vtp(const std::string& path, const Mesh& mesh, const classify::Classification& c, const Polycube& p) {
  viz::write_vtp(path, polycube_polydata(mesh, c, p));
}

void write_mapped_vtp(const std::string& path, const Mesh& mesh, const classify::Classification& c, const Polycube& p) {
  viz::PolyData d = polycube_polydata(mesh, c, p);
  viz::Field xyz{"xyz", 3, {}};  // the physical position, so a user can colour the cube by it
  for (const auto& q : d.points) xyz.values.insert(xyz.values.end(), q.begin(), q.end());
  d.point_fields.push_back(xyz);
  d.points = p.vertex_uvw;
  viz::write_vtp(path, d);
}

}  // namespace volts::polycube
