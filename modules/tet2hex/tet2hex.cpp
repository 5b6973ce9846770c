#include "tet2hex/tet2hex.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "bezier/bernstein.h"
#include "bezier/bernstein_poly.h"
#include "bezier/vtk_bezier.h"
#include "core/errors.h"
#include "core/log.h"
#include "extract/extract.h"
#include "extract/point_index.h"
#include "quality/quality.h"
#include "surface/mesh_json.h"
#include "surface/remesh.h"
#include "tet2hex/convert.h"
#include "tmesh/optimize.h"

namespace volts::tet2hex {
namespace {

using surface::Mesh;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<surface::Kernel, Primitive>>;

void check_params(const Params& p) {
  if (p.degree < 1 || p.degree > 4) throw core::ConfigError("tet2hex.degree must be in [1, 4]");
  if (p.gauss_points < 0 || p.gauss_points > 10) throw core::ConfigError("tet2hex.gauss_points must be in [0, 10]");
  if (p.boundary_samples < 2 || p.boundary_samples > 64) throw core::ConfigError("tet2hex.boundary_samples must be in [2, 64]");
  if (!(p.remesh_edge_rel >= 0 && p.remesh_edge_rel <= 0.5)) throw core::ConfigError("tet2hex.remesh_edge_rel must be in [0, 0.5]");
  if (p.optimize_cycles < 0 || p.optimize_cycles > 100) throw core::ConfigError("tet2hex.optimize_cycles must be in [0, 100]");
  if (!(p.optimize_target > 0 && p.optimize_target <= 1)) throw core::ConfigError("tet2hex.optimize_target must be in (0, 1]");
  if (p.optimize_grid_points < 2 || p.optimize_grid_points > 8) throw core::ConfigError("tet2hex.optimize_grid_points must be in [2, 8]");
}

// The tet vertex each hex axis of sub-hex c runs towards (from subdomain_corners): the boundary
// face of hex c opposite to that vertex is its face "axis = 0".
int axis_towards(int c, int x) {
  const auto corners = subdomain_corners(c);
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Vector4d e = 2 * corners[1 << axis] - corners[0];  // the vertex the edge runs to
    if (e[x] > 0.5) return axis;
  }
  return -1;
}

Eigen::Vector3d closest(const Tree& tree, const Eigen::Vector3d& x) {
  const surface::Point q = tree.closest_point(surface::Point(x[0], x[1], x[2]));
  return {q.x(), q.y(), q.z()};
}

// Key of a control point of tet with global vertices g and multi-index a: the (vertex, exponent)
// pairs with exponent > 0, sorted by vertex. Equal on every tet sharing the point's entity.
using PointKey = std::vector<std::pair<int, int>>;
using EntityKey = std::vector<int>;
PointKey point_key(const std::array<int, 4>& g, const std::array<int, 4>& a) {
  PointKey k;
  for (int v = 0; v < 4; ++v)
    if (a[v] > 0) k.push_back({g[v], a[v]});
  std::sort(k.begin(), k.end());
  return k;
}
EntityKey entity_of(const PointKey& k) {
  EntityKey e;
  for (const auto& p : k) e.push_back(p.first);
  return e;
}

// Curved control points of the boundary edges and faces: interpolation of the closest surface
// points at the Lagrange nodes (uniform in barycentric coordinates). Edges first; faces then solve
// only for their interior points, so shared edges are bit-identical.
std::map<PointKey, Eigen::Vector3d> curved_points(const tetmesh::TetMesh& mesh, const std::vector<std::array<int, 2>>& bfaces, const Tree& tree, int n) {
  std::map<PointKey, Eigen::Vector3d> cp;
  if (n < 2) return cp;
  std::set<std::array<int, 2>> edges;
  std::vector<std::array<int, 3>> faces;
  for (const auto& bf : bfaces) {
    std::array<int, 3> f;
    for (int j = 0, m = 0; j < 4; ++j)
      if (j != bf[1]) f[m++] = mesh.tets[bf[0]][j];
    std::sort(f.begin(), f.end());
    faces.push_back(f);
    edges.insert({f[0], f[1]}), edges.insert({f[0], f[2]}), edges.insert({f[1], f[2]});
  }
  // Edge: B (n+1)^2 interpolation matrix at t = m/n; ends fixed at the vertices.
  Eigen::MatrixXd B(n + 1, n + 1);
  for (int m = 0; m <= n; ++m) B.row(m) = bezier::bernstein_basis(n, double(m) / n).transpose();
  const Eigen::PartialPivLU<Eigen::MatrixXd> Blu(B);
  for (const auto& e : edges) {
    const Eigen::Vector3d& p0 = mesh.points[e[0]];
    const Eigen::Vector3d& p1 = mesh.points[e[1]];
    Eigen::MatrixXd rhs(n + 1, 3);
    for (int m = 0; m <= n; ++m) {
      const Eigen::Vector3d x = p0 + (p1 - p0) * (double(m) / n);
      rhs.row(m) = (m == 0 || m == n ? x : closest(tree, x)).transpose();
    }
    const Eigen::MatrixXd c = Blu.solve(rhs);
    for (int m = 1; m < n; ++m) cp[{{e[0], n - m}, {e[1], m}}] = c.row(m).transpose();
  }
  if (n < 3) return cp;
  // Face: the triangle's interior control points from the interior nodes, edges known.
  const auto tri = bezier::simplex_multi_indices(2, n);  // {a0, a1, a2, 0}
  std::vector<int> inner, outer;
  for (int i = 0; i < static_cast<int>(tri.size()); ++i) (tri[i][0] > 0 && tri[i][1] > 0 && tri[i][2] > 0 ? inner : outer).push_back(i);
  auto basis = [&](const std::array<int, 4>& cpi, const std::array<int, 4>& node) {
    double b = bezier::binomial(n, cpi[1]) * bezier::binomial(n - cpi[1], cpi[2]);
    for (int v = 0; v < 3; ++v) b *= std::pow(double(node[v]) / n, cpi[v]);
    return b;
  };
  Eigen::MatrixXd Mi(inner.size(), inner.size()), Mo(inner.size(), outer.size());
  for (std::size_t r = 0; r < inner.size(); ++r) {
    for (std::size_t c = 0; c < inner.size(); ++c) Mi(r, c) = basis(tri[inner[c]], tri[inner[r]]);
    for (std::size_t c = 0; c < outer.size(); ++c) Mo(r, c) = basis(tri[outer[c]], tri[inner[r]]);
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> Milu(Mi);
  for (const auto& f : faces) {
    auto key = [&](const std::array<int, 4>& a) {
      return point_key({f[0], f[1], f[2], -1}, {a[0], a[1], a[2], 0});
    };
    Eigen::MatrixXd known(outer.size(), 3), rhs(inner.size(), 3);
    for (std::size_t c = 0; c < outer.size(); ++c) {
      const auto& a = tri[outer[c]];
      const int corner = a[0] == n ? 0 : a[1] == n ? 1 : a[2] == n ? 2 : -1;
      known.row(c) = (corner >= 0 ? mesh.points[f[corner]] : cp.at(key(a))).transpose();
    }
    for (std::size_t r = 0; r < inner.size(); ++r) {
      const auto& a = tri[inner[r]];
      const Eigen::Vector3d x = (a[0] * mesh.points[f[0]] + a[1] * mesh.points[f[1]] + a[2] * mesh.points[f[2]]) / n;
      rhs.row(r) = closest(tree, x).transpose();
    }
    const Eigen::MatrixXd c = Milu.solve(rhs - Mo * known);
    for (std::size_t r = 0; r < inner.size(); ++r) cp[key(tri[inner[r]])] = c.row(r).transpose();
  }
  return cp;
}

bezier::BezierTet build_tet(const tetmesh::TetMesh& mesh, int t, int n, const std::map<PointKey, Eigen::Vector3d>& curved,
                            const std::set<EntityKey>& flat) {
  const auto& g = mesh.tets[t];
  bezier::BezierTet tet;
  tet.degree = n;
  for (const auto& a : bezier::simplex_multi_indices(3, n)) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int v = 0; v < 4; ++v) x += a[v] * mesh.points[g[v]];
    x /= n;
    const PointKey k = point_key(g, a);
    if (k.size() == 2 || k.size() == 3) {
      const auto it = curved.find(k);
      if (it != curved.end() && !flat.count(entity_of(k))) x = it->second;
    }
    tet.points.push_back(x);
  }
  return tet;
}

// 1 if all four hexes are certified valid.
bool convert_certify(const bezier::BezierTet& tet, const bezier::CertifyParams& cp, bezier::BezierHex* hexes, int* status) {
  const auto h = four_hexes(tet);
  bool ok = true;
  for (int c = 0; c < 4; ++c) {
    hexes[c] = h[c];
    status[c] = static_cast<int>(bezier::certify(h[c], cp).status);
    ok = ok && status[c] == static_cast<int>(bezier::Validity::valid);
  }
  return ok;
}

Mesh remesh(const Mesh& in, double edge_rel) {
  surface::RemeshParams p;
  p.edge_length = edge_rel * surface::bbox_diagonal(in);
  return surface::remesh_isotropic(in, p).mesh;
}

// The corners of the tets as a TetMesh (points welded by exact position), for .vtu input.
tetmesh::TetMesh corner_mesh(const std::vector<bezier::BezierTet>& tets) {
  tetmesh::TetMesh m;
  std::map<std::array<double, 3>, int> id;
  for (const auto& t : tets) {
    const int n = t.degree;
    std::array<int, 4> c;
    const int idx[4] = {0, bezier::simplex_index(3, n, n, 0, 0), bezier::simplex_index(3, n, 0, n, 0), bezier::simplex_index(3, n, 0, 0, n)};
    for (int v = 0; v < 4; ++v) {
      const Eigen::Vector3d& p = t.points[idx[v]];
      const auto ins = id.emplace(std::array<double, 3>{p[0], p[1], p[2]}, static_cast<int>(m.points.size()));
      if (ins.second) m.points.push_back(p);
      c[v] = ins.first->second;
    }
    m.tets.push_back(c);
  }
  return m;
}

// The boundary triangles as a closed, outward surface (faces opposite vertex x of a positive tet
// are outward as listed).
Mesh boundary_surface(const tetmesh::TetMesh& m, const std::vector<std::array<int, 2>>& bfaces) {
  const auto& face = tetmesh::kOutwardFace;
  Mesh s;
  std::map<int, Mesh::Vertex_index> vid;
  auto vertex = [&](int g) {
    auto it = vid.find(g);
    if (it != vid.end()) return it->second;
    const auto v = s.add_vertex(surface::Point(m.points[g][0], m.points[g][1], m.points[g][2]));
    vid[g] = v;
    return v;
  };
  for (const auto& bf : bfaces) {
    const auto& t = m.tets[bf[0]];
    const auto f = s.add_face(vertex(t[face[bf[1]][0]]), vertex(t[face[bf[1]][1]]), vertex(t[face[bf[1]][2]]));
    if (f == Mesh::null_face()) throw core::InvalidInputError("the boundary of the tets is not a manifold surface");
  }
  if (!CGAL::is_closed(s)) throw core::InvalidInputError("the boundary of the tets is not closed");
  return s;
}

}  // namespace

std::vector<bezier::BezierTet> bezier_tets(const tetmesh::TetMesh& mesh, const Mesh& surface, const Params& params, Result& r) {
  check_params(params);
  const int n = params.degree;
  const auto bfaces = tetmesh::boundary_faces(mesh);
  r.degree = n;
  r.boundary_faces = static_cast<int>(bfaces.size());
  std::map<PointKey, Eigen::Vector3d> curved;
  if (params.curve_boundary && n >= 2) {
    core::LogSection s("curve the boundary onto the surface");
    Tree tree(faces(surface).first, faces(surface).second, surface);
    tree.accelerate_distance_queries();
    curved = curved_points(mesh, bfaces, tree, n);
  }
  const int nt = static_cast<int>(mesh.tets.size());
  std::set<EntityKey> flat;
  std::vector<bezier::BezierTet> tets(nt);
  r.hexes.assign(4 * nt, {});
  r.validity.assign(4 * nt, 0);
  std::vector<int> todo(nt);
  for (int t = 0; t < nt; ++t) todo[t] = t;
  core::LogSection s("Bézier tets → 4 hexes (Theorem 3), certified");
  core::Progress progress("tets", nt);
  for (int round = 0; !todo.empty(); ++round) {
    std::set<EntityKey> newly_flat;
    for (std::size_t i = 0; i < todo.size(); ++i) {
      const int t = todo[i];
      tets[t] = build_tet(mesh, t, n, curved, flat);
      const bool ok = convert_certify(tets[t], params.certify, &r.hexes[4 * t], &r.validity[4 * t]);
      if (round == 0) progress.step(i + 1);
      if (ok || curved.empty()) continue;
      // Put this tet's curved boundary entities back flat.
      for (const auto& a : bezier::simplex_multi_indices(3, n)) {
        const PointKey k = point_key(mesh.tets[t], a);
        if ((k.size() == 2 || k.size() == 3) && curved.count(k) && !flat.count(entity_of(k))) newly_flat.insert(entity_of(k));
      }
    }
    if (round == 0) progress.finish();
    if (newly_flat.empty()) break;
    flat.insert(newly_flat.begin(), newly_flat.end());
    todo.clear();
    for (int t = 0; t < nt; ++t)
      for (const auto& a : bezier::simplex_multi_indices(3, n)) {
        const PointKey k = point_key(mesh.tets[t], a);
        if ((k.size() == 2 || k.size() == 3) && newly_flat.count(entity_of(k))) {
          todo.push_back(t);
          break;
        }
      }
    core::log_verbose("revert round " + std::to_string(round + 1) + ": " + std::to_string(newly_flat.size()) + " boundary edges/faces flat again, " +
                      std::to_string(todo.size()) + " tets redone");
  }
  if (!curved.empty()) {
    // A boundary face counts as curved if its interior (n >= 3) or any of its edges is curved.
    for (const auto& bf : bfaces) {
      EntityKey f;
      for (int j = 0; j < 4; ++j)
        if (j != bf[1]) f.push_back(mesh.tets[bf[0]][j]);
      std::sort(f.begin(), f.end());
      const EntityKey edges[3] = {{f[0], f[1]}, {f[0], f[2]}, {f[1], f[2]}};
      bool reverted = flat.count(f) > 0;
      for (const auto& e : edges) reverted = reverted || flat.count(e) > 0;
      (reverted ? r.boundary_faces_reverted : r.boundary_faces_curved)++;
    }
  }
  r.tets = tets;
  return tets;
}

namespace {

// Params::optimize_cycles: the hexes as blocks of the tmesh optimizer. A hex is a clamped B-spline
// of one span per direction (its Bézier points are its control points); points within 1e-12 of
// the diagonal of each other are one node (extract's rule for the global basis); a hex face on a
// boundary tet face is a boundary face of its block (surface nodes: they slide or stay). The
// optimizer's Jacobians are polynomial: rational hexes (weighted tets given as .vtu) are left as
// they are.
void optimize_hexes(Result& r, const Mesh& surface, const std::vector<std::array<int, 2>>& bfaces, const Params& params, int gauss_points) {
  if (std::any_of(r.hexes.begin(), r.hexes.end(), [](const bezier::BezierHex& h) { return h.is_rational(); })) {
    core::log_warning("tet2hex.optimize_cycles: the hexes are rational (weighted tets); not optimized");
    r.optimization_stop = "rational_hexes";
    r.min_scaled_before_optimization = 0;
    return;
  }
  const int n = r.degree;
  Eigen::AlignedBox3d box;
  for (const auto& h : r.hexes)
    for (const auto& x : h.points) box.extend(x);
  extract::PointIndex index(box, 1e-12 * box.diagonal().norm());
  std::vector<double> knots(2 * static_cast<std::size_t>(n) + 2, 0.0);
  std::fill(knots.begin() + n + 1, knots.end(), 1.0);
  std::vector<tmesh::TMesh> blocks(r.hexes.size());
  for (std::size_t e = 0; e < r.hexes.size(); ++e) {
    tmesh::TMesh& t = blocks[e];
    t.degree = n;
    t.knots = {knots, knots, knots};
    t.size = {n + 1, n + 1, n + 1};
    t.boundary = {0, 0, 0, 0, 0, 0};
    t.kind = "hex";
    for (std::size_t i = 0; i < r.hexes[e].points.size(); ++i) {
      const std::array<int, 3> ijk = r.hexes[e].ijk(static_cast<int>(i));
      const int id = index.find_or_add(r.hexes[e].points[i]);
      // One position per node, its first point's (the conversion computes a shared face's points
      // in each tet: equal to roundoff), so the hexes share their points bit for bit, moved or not.
      const Eigen::Vector3d& x = index.points()[static_cast<std::size_t>(id)];
      t.control_points.push_back({x.x(), x.y(), x.z()});
      t.parameters.push_back({static_cast<double>(ijk[0]) / n, static_cast<double>(ijk[1]) / n, static_cast<double>(ijk[2]) / n});
      t.function_ids.push_back(id);
    }
  }
  for (const auto& bf : bfaces)
    for (int c = 0; c < 4; ++c)
      if (c != bf[1]) blocks[static_cast<std::size_t>(4 * bf[0] + c)].boundary[static_cast<std::size_t>(2 * axis_towards(c, bf[1]))] = 1;
  const tmesh::SlideSurface slide(surface::vertex_array(surface), surface::triangle_triples(surface));
  tmesh::OptimizeParams op;
  op.sweeps = 40;  // the tmesh stage's defaults otherwise
  op.cycles = params.optimize_cycles;
  op.target = params.optimize_target;
  op.gauss_points = gauss_points;  // the figure measured below
  op.grid_points = params.optimize_grid_points;
  // Sliding from the first round: the worst hexes of the tet route lie at the surface (on the
  // assembly, fixed-surface rounds were all refused: 50 of 150 s for nothing).
  op.slide_from = tmesh::OptimizeParams::SlideFrom::start;
  // The sweeps slide too: on the assembly they raise the joint rounds' 0.169 to 0.197 in 5 s
  // (alone, without joint rounds: 0.072 in 55 s).
  op.sweep_slide = true;
  op.trilinear_sweeps = 0;         // corner hexes are a T-mesh figure; the tet route reports the Bézier one
  const tmesh::OptimizeResult o = tmesh::optimize(blocks, op, &slide);
  r.min_scaled_before_optimization = o.min_before;
  r.optimization_joint_rounds = o.joint_rounds, r.optimization_nodes_moved = o.nodes_moved;
  r.optimization_surface_nodes_slid = o.surface_nodes_slid;
  r.optimization_stop = o.stop_reason;
  // A hex whose points moved is certified again (beyond roundoff the optimizer only keeps moves
  // that keep certificates; this is the figure the report gives).
  for (std::size_t e = 0; e < r.hexes.size(); ++e) {
    bool moved = false;
    for (std::size_t i = 0; i < r.hexes[e].points.size(); ++i) {
      const auto& x = blocks[e].control_points[i];
      const Eigen::Vector3d y(x[0], x[1], x[2]);
      moved = moved || y != r.hexes[e].points[i];
      r.hexes[e].points[i] = y;
    }
    if (moved) r.validity[e] = static_cast<int>(bezier::certify(r.hexes[e], params.certify).status);
  }
}

}  // namespace

void convert_and_measure(Result& r, const Mesh& surface, const std::vector<std::array<int, 2>>& bfaces, const Params& params) {
  check_params(params);
  const int nt = static_cast<int>(r.tets.size());
  if (r.hexes.size() != 4 * r.tets.size()) {
    core::LogSection s("Bézier tets → 4 hexes (Theorem 3), certified");
    r.hexes.assign(4 * nt, {});
    r.validity.assign(4 * nt, 0);
    core::Progress progress("tets", nt);
    for (int t = 0; t < nt; ++t) {
      convert_certify(r.tets[t], params.certify, &r.hexes[4 * t], &r.validity[4 * t]);
      progress.step(t + 1);
    }
    progress.finish();
  }
  const int gp = params.gauss_points > 0 ? params.gauss_points : r.degree + 1;
  if (params.optimize_cycles > 0) {
    core::LogSection s("optimization of the worst Jacobian (tmesh's optimizer on the hexes)");
    optimize_hexes(r, surface, bfaces, params, gp);
  }
  const quality::ValidityCounts counts = quality::count_validity(r.validity);
  r.certified_valid = counts.valid, r.certified_invalid = counts.invalid, r.undecided = counts.undecided;
  {
    core::LogSection s("scaled Jacobian at corners and Gauss points");
    quality::ScaledJacobian sj = quality::scaled_jacobian(r.hexes, gp);
    r.min_scaled_jacobian = std::move(sj.min_per_element);
    r.max_scaled_jacobian = std::move(sj.max_per_element);
    r.min_scaled = sj.min, r.max_scaled = sj.max;
  }
  core::LogSection s("boundary deviation and volume");
  // Tet face opposite vertex bf[1] lies, in each of the three hexes of the other corners, on the
  // hex face "axis = 0" of the axis that runs towards bf[1].
  std::vector<quality::BoundaryFace> boundary;
  for (const auto& bf : bfaces)
    for (int c = 0; c < 4; ++c)
      if (c != bf[1]) boundary.push_back({4 * bf[0] + c, axis_towards(c, bf[1]), 0});
  quality::BoundaryDeviation dev = quality::boundary_deviation(r.hexes, boundary, surface, params.boundary_samples);
  r.boundary_distance = std::move(dev.per_element);
  r.hausdorff_rel = dev.rel;
  const quality::Volume v = quality::volume(r.hexes, surface, r.degree + 2);
  r.spline_volume = v.elements, r.surface_volume = v.surface, r.volume_rel_error = v.rel_error;
}

Result run(const Mesh& input, const Params& params) {
  check_params(params);
  Result r;
  Mesh surf = input;
  if (params.remesh_edge_rel > 0) {
    core::LogSection s("remesh the surface (CGAL isotropic remeshing)");
    surf = remesh(input, params.remesh_edge_rel);
    core::log(std::to_string(surf.number_of_faces()) + " triangles after remeshing");
  }
  r.surface_triangles = static_cast<int>(surf.number_of_faces());
  tetmesh::TetMesh mesh;
  {
    core::LogSection s("tetrahedralize (TetGen)");
    mesh = tetmesh::tetrahedralize(surf, params.tetgen);
    core::log(std::to_string(mesh.tets.size()) + " tets, " + std::to_string(mesh.points.size()) + " vertices");
  }
  bezier_tets(mesh, input, params, r);
  convert_and_measure(r, input, tetmesh::boundary_faces(mesh), params);
  return r;
}

Result run(const std::vector<bezier::BezierTet>& tets, const Params& params) {
  check_params(params);
  if (tets.empty()) throw core::InvalidInputError("no tetrahedra");
  Result r;
  r.degree = std::max(tets[0].degree, params.degree);
  for (const auto& t : tets) r.tets.push_back(t.degree < r.degree ? bezier::elevate_degree(t, r.degree) : t);
  const tetmesh::TetMesh corners = corner_mesh(tets);
  const auto bfaces = tetmesh::boundary_faces(corners);
  r.boundary_faces = static_cast<int>(bfaces.size());
  const Mesh surf = boundary_surface(corners, bfaces);
  r.surface_triangles = static_cast<int>(surf.number_of_faces());
  convert_and_measure(r, surf, bfaces, params);
  return r;
}

core::Json report_figures(const Result& r) {
  return core::Json{{"bezier_elements", r.hexes.size()},
                    {"degree", r.degree},
                    {"min_scaled_jacobian", r.min_scaled},
                    {"max_scaled_jacobian", r.max_scaled},
                    {"hausdorff_rel", r.hausdorff_rel},
                    {"volume_rel_error", r.volume_rel_error},
                    {"spline_volume", r.spline_volume},
                    {"surface_volume", r.surface_volume},
                    {"tets", r.tets.size()},
                    {"surface_triangles", r.surface_triangles},
                    {"certified_valid", r.certified_valid},
                    {"certified_invalid", r.certified_invalid},
                    {"undecided", r.undecided},
                    {"boundary_faces", r.boundary_faces},
                    {"boundary_faces_curved", r.boundary_faces_curved},
                    {"boundary_faces_reverted", r.boundary_faces_reverted},
                    {"optimization", {{"stop", r.optimization_stop},
                                      {"min_scaled_jacobian_before",
                                       r.optimization_stop == "disabled" || r.optimization_stop == "rational_hexes" ? r.min_scaled : r.min_scaled_before_optimization},
                                      {"joint_rounds", r.optimization_joint_rounds},
                                      {"nodes_moved", r.optimization_nodes_moved},
                                      {"surface_nodes_slid", r.optimization_surface_nodes_slid}}}};
}

void write_bezier_vtu(const std::string& path, const Result& r) {
  std::vector<double> validity(r.validity.begin(), r.validity.end()), tet(r.hexes.size());
  for (std::size_t e = 0; e < tet.size(); ++e) tet[e] = static_cast<double>(e / 4);
  bezier::write_bezier_vtu(path, r.hexes,
                           {{"min_scaled_jacobian", 1, r.min_scaled_jacobian},
                            {"max_scaled_jacobian", 1, r.max_scaled_jacobian},
                            {"boundary_distance", 1, r.boundary_distance},
                            {"status", 1, validity},
                            {"tet", 1, tet}},
                           extract::shared_points(r.hexes));
}

}  // namespace volts::tet2hex
