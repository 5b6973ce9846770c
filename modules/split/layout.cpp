#include "split/layout.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include "core/errors.h"
#include "core/log.h"
#include "split/isoline.h"

namespace volts::split::detail {

using surface::Mesh;
using HI = Mesh::Halfedge_index;

void apply_splits(LabelledEdges& edges, const std::vector<std::array<int, 3>>& splits) {
  for (const auto& [a, b, v] : splits) {
    const auto it = edges.find(edge(a, b));
    if (it == edges.end()) continue;
    const int label = it->second;
    edges.erase(it);
    edges[edge(a, v)] = label;
    edges[edge(v, b)] = label;
  }
}

void apply_splits(std::set<Edge>& edges, const std::vector<std::array<int, 3>>& splits) {
  for (const auto& [a, b, v] : splits)
    if (edges.erase(edge(a, b))) edges.insert(edge(a, v)), edges.insert(edge(v, b));
}

void add_loop(LabelledEdges& edges, const std::vector<int>& loop, int label, bool closed) {
  const std::size_t n = loop.size();
  for (std::size_t i = 0; i + (closed ? 0 : 1) < n; ++i) edges[edge(loop[i], loop[(i + 1) % n])] = label;
}

std::vector<std::vector<int>> chain_loops(const std::set<Edge>& edges) {
  std::map<int, std::vector<int>> adj;
  for (const auto& [a, b] : edges) adj[a].push_back(b), adj[b].push_back(a);
  for (auto& [v, n] : adj) {
    if (n.size() != 2)
      throw core::TopologyError("split: " + std::to_string(n.size()) + " curve edges meet at vertex " + std::to_string(v) +
                                " where a closed curve was expected");
    std::sort(n.begin(), n.end());
  }
  std::vector<std::vector<int>> loops;
  std::set<int> used;
  for (const auto& [start, n0] : adj) {
    if (used.count(start)) continue;
    std::vector<int> loop = {start};
    used.insert(start);
    int prev = start, cur = n0[0];
    while (cur != start) {
      loop.push_back(cur);
      used.insert(cur);
      const auto& n = adj.at(cur);
      const int next = n[0] == prev ? n[1] : n[0];
      prev = cur;
      cur = next;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

int loop_period(const std::vector<int>& loop, const std::vector<double>& field) {
  double s = 0;
  for (std::size_t i = 0; i < loop.size(); ++i) s += circle_difference(field[loop[i]], field[loop[(i + 1) % loop.size()]], 1.0);
  return static_cast<int>(std::lround(s));
}

std::vector<Region> regions(const Mesh& mesh, const std::set<Edge>& cuts, std::vector<int>* face_region) {
  auto is_cut = [&](HI h) { return cuts.count(edge(static_cast<int>(mesh.source(h)), static_cast<int>(mesh.target(h)))) > 0; };
  std::vector<int> label(mesh.number_of_faces(), -1);
  std::vector<Region> out;
  for (auto f0 : mesh.faces()) {
    if (label[f0] >= 0) continue;
    const int id = static_cast<int>(out.size());
    out.emplace_back();
    Region& r = out.back();
    std::vector<Mesh::Face_index> stack = {f0};
    label[f0] = id;
    while (!stack.empty()) {
      const auto fc = stack.back();
      stack.pop_back();
      r.faces.push_back(static_cast<int>(fc));
      for (HI h : CGAL::halfedges_around_face(mesh.halfedge(fc), mesh)) {
        if (is_cut(h)) continue;
        const auto g = mesh.face(mesh.opposite(h));
        if (label[g] < 0) label[g] = id, stack.push_back(g);
      }
    }
    std::sort(r.faces.begin(), r.faces.end());
    // Boundary loops: halfedges of the region's faces on cut edges, or bordering another region.
    std::set<int> vertices;
    std::set<Edge> edges_seen;
    std::set<std::size_t> done;
    std::vector<HI> boundary;
    for (int f : r.faces)
      for (HI h : CGAL::halfedges_around_face(mesh.halfedge(Mesh::Face_index(f)), mesh)) {
        vertices.insert(static_cast<int>(mesh.target(h)));
        edges_seen.insert(edge(static_cast<int>(mesh.source(h)), static_cast<int>(mesh.target(h))));
        if (is_cut(h) || label[mesh.face(mesh.opposite(h))] != id) boundary.push_back(h);
      }
    r.euler = static_cast<int>(vertices.size()) - static_cast<int>(edges_seen.size()) + static_cast<int>(r.faces.size());
    for (HI h0 : boundary) {
      if (done.count(static_cast<std::size_t>(h0))) continue;
      std::vector<int> loop;
      HI h = h0;
      do {
        done.insert(static_cast<std::size_t>(h));
        loop.push_back(static_cast<int>(mesh.source(h)));
        // Next boundary halfedge: turn around target(h) inside the region.
        HI g = mesh.next(h);
        while (!(is_cut(g) || label[mesh.face(mesh.opposite(g))] != id)) g = mesh.next(mesh.opposite(g));
        h = g;
      } while (h != h0 && loop.size() <= mesh.number_of_halfedges());
      r.loops.push_back(std::move(loop));
    }
  }
  if (face_region) *face_region = std::move(label);
  return out;
}

namespace {

// Rotates a closed loop to start at its corner of smallest id and splits it at its corners.
std::vector<std::vector<int>> split_at_corners(const std::vector<int>& loop, const std::vector<char>& is_corner,
                                               std::vector<int>* corners) {
  std::vector<std::size_t> at;
  for (std::size_t i = 0; i < loop.size(); ++i)
    if (is_corner[loop[i]]) at.push_back(i);
  corners->clear();
  if (at.empty()) return {};
  std::size_t first = at[0];
  for (std::size_t i : at)
    if (loop[i] < loop[first]) first = i;
  std::vector<std::vector<int>> sides;
  const std::size_t n = loop.size();
  for (std::size_t k = 0; k < n; ++k) {
    const int v = loop[(first + k) % n];
    if (is_corner[v]) {
      if (!sides.empty()) sides.back().push_back(v);
      corners->push_back(v);
      sides.push_back({v});
    } else {
      sides.back().push_back(v);
    }
  }
  sides.back().push_back(loop[first]);
  return sides;
}

}  // namespace

Patch quad_patch(const Region& r, const std::vector<char>& is_corner, const std::string& what, int id) {
  std::vector<int> corners;
  const auto sides = r.loops.size() == 1 ? split_at_corners(r.loops[0], is_corner, &corners) : std::vector<std::vector<int>>{};
  if (r.loops.size() != 1 || r.euler != 1 || corners.size() != 4)
    throw core::TopologyError("split: " + what + " " + std::to_string(id) + " is not a quad patch (" +
                              std::to_string(r.loops.size()) + " boundary loop(s), Euler characteristic " +
                              std::to_string(r.euler) + ", " + std::to_string(corners.size()) + " corners; a quad has 1, 1, 4)");
  Patch p;
  p.triangles = r.faces;
  for (int k = 0; k < 4; ++k) p.corners[k] = corners[k], p.sides[k] = sides[k];
  return p;
}

InternalFace internal_face(const std::vector<int>& loop, const std::vector<char>& is_corner, int id) {
  std::vector<int> corners;
  const auto sides = split_at_corners(loop, is_corner, &corners);
  if (corners.size() != 4)
    throw core::TopologyError("split: cross section " + std::to_string(id) + " meets " + std::to_string(corners.size()) +
                              " longitudinal corner lines instead of 4");
  InternalFace f;
  f.loop = loop;
  for (int k = 0; k < 4; ++k) f.corners[k] = corners[k], f.sides[k] = sides[k];
  return f;
}

void copy_mesh(const Mesh& mesh, Layout& layout) {
  if (mesh.has_garbage()) throw std::logic_error("split: layout mesh has removed elements");
  layout.points.clear();
  layout.triangles.clear();
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    layout.points.push_back({p.x(), p.y(), p.z()});
  }
  for (auto f : mesh.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) t[k++] = static_cast<int>(v);
    layout.triangles.push_back(t);
  }
  layout.filled.assign(layout.triangles.size(), 0);
}

Submesh submesh(const Layout& L, const std::vector<int>& triangles, const std::vector<char>& reversed) {
  Submesh s;
  std::map<int, Mesh::Vertex_index> vmap;
  auto vertex = [&](int v) {
    auto it = vmap.find(v);
    if (it != vmap.end()) return it->second;
    const auto& p = L.points[v];
    const auto x = s.mesh.add_vertex(surface::Point(p[0], p[1], p[2]));
    s.layout_vertex.push_back(v);
    return vmap[v] = x;
  };
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    auto t = L.triangles[triangles[i]];
    if (reversed[i]) std::swap(t[1], t[2]);
    if (s.mesh.add_face(vertex(t[0]), vertex(t[1]), vertex(t[2])) == Mesh::null_face())
      throw core::TopologyError("split: the filled surface is not manifold at triangle " + std::to_string(triangles[i]));
    s.layout_triangle.push_back(triangles[i]);
  }
  return s;
}

std::vector<int> merge_vertices(const Layout& part, const std::vector<int>& layout_vertex, Layout& into) {
  std::vector<int> vmap(part.points.size());
  for (std::size_t v = 0; v < vmap.size(); ++v) {
    if (v < layout_vertex.size()) {
      vmap[v] = layout_vertex[v];
    } else {
      vmap[v] = static_cast<int>(into.points.size());
      into.points.push_back(part.points[v]);
    }
  }
  return vmap;
}

void map_ids(Decomposition& sub, const Submesh& s) {
  for (auto& p : sub.layout.patches) {
    for (int& t : p.triangles) t = s.layout_triangle[t];
    std::sort(p.triangles.begin(), p.triangles.end());
    for (int& v : p.corners) v = s.layout_vertex[v];
    for (auto& side : p.sides)
      for (int& v : side) v = s.layout_vertex[v];
  }
  for (auto& c : sub.components)
    for (auto& f : c.faces)
      for (int& v : f.corners) v = s.layout_vertex[v];
}

namespace {

using K2 = surface::Kernel;

// A rim at most this far off its least-squares plane, relative to its diameter, counts as planar.
constexpr double kMaxOffPlane = 0.1;

}  // namespace

// Hand-written around CGAL's CDT: CGAL fills holes in 3D (triangulate_hole) but not in a loop's
// plane with a given interior spacing and no points on the rim.
bool fill_opening_in_plane(Mesh& m, HI border, double max_off_plane) {
  std::vector<Mesh::Vertex_index> rim;
  for (auto h : CGAL::halfedges_around_face(border, m)) rim.push_back(m.source(h));
  const std::size_t n = rim.size();
  if (n < 3) return false;
  std::vector<Eigen::Vector3d> x(n);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const auto& q = m.point(rim[i]);
    x[i] = {q.x(), q.y(), q.z()}, centre += x[i] / static_cast<double>(n);
  }
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& y : x) cov += (y - centre) * (y - centre).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d u = eig.eigenvectors().col(2), v = eig.eigenvectors().col(1), normal = eig.eigenvectors().col(0);
  CGAL::Polygon_2<K2> poly;
  std::vector<double> offset(n);
  double diameter = 0, perimeter = 0;
  for (std::size_t i = 0; i < n; ++i) {
    poly.push_back(K2::Point_2((x[i] - centre).dot(u), (x[i] - centre).dot(v)));
    offset[i] = (x[i] - centre).dot(normal);
    perimeter += (x[(i + 1) % n] - x[i]).norm();
    for (std::size_t j = 0; j < i; ++j) diameter = std::max(diameter, (x[i] - x[j]).norm());
  }
  double off = 0;
  for (const double o : offset) off = std::max(off, std::abs(o));
  if (!(diameter > 0) || off > max_off_plane * diameter || !poly.is_simple()) return false;
  const bool ccw = poly.orientation() == CGAL::COUNTERCLOCKWISE;

  using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, K2>;
  using Fb = CGAL::Constrained_triangulation_face_base_2<K2>;
  using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K2, CGAL::Triangulation_data_structure_2<Vb, Fb>, CGAL::Exact_predicates_tag>;
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> vh(n);
  for (std::size_t i = 0; i < n; ++i) vh[i] = cdt.insert(poly[static_cast<int>(i)]), vh[i]->info() = static_cast<int>(i);
  for (std::size_t i = 0; i < n; ++i) cdt.insert_constraint(vh[i], vh[(i + 1) % n]);
  if (cdt.number_of_vertices() != n) return false;  // rim points merged or constraints split
  const double h = perimeter / static_cast<double>(n);
  const auto box = poly.bbox();
  std::vector<Cdt::Vertex_handle> inner;
  for (int row = 0; box.ymin() + row * h * std::sqrt(0.75) < box.ymax(); ++row)
    for (double px = box.xmin() + (row % 2 ? 0.5 * h : 0.0); px < box.xmax(); px += h) {
      const K2::Point_2 p(px, box.ymin() + row * h * std::sqrt(0.75));
      if (poly.bounded_side(p) != CGAL::ON_BOUNDED_SIDE) continue;
      double d = std::numeric_limits<double>::infinity();
      for (auto e = poly.edges_begin(); e != poly.edges_end(); ++e) d = std::min(d, std::sqrt(CGAL::to_double(CGAL::squared_distance(p, *e))));
      if (d < 0.5 * h) continue;
      const auto w = cdt.insert(p);
      w->info() = static_cast<int>(n + inner.size());
      inner.push_back(w);
    }
  if (cdt.number_of_vertices() != n + inner.size()) return false;
  // Faces inside the polygon: reached from the infinite face across the rim once (a topological
  // test: nearly collinear rim points leave slivers outside whose centroids a point test misjudges).
  std::vector<std::array<int, 3>> tris;
  std::map<Cdt::Face_handle, int> depth;
  std::vector<Cdt::Face_handle> stack{cdt.infinite_face()};
  depth[cdt.infinite_face()] = 0;
  std::vector<Cdt::Face_handle> next_level;
  for (int level = 0; level < 2 && !stack.empty(); ++level) {
    while (!stack.empty()) {
      const Cdt::Face_handle f = stack.back();
      stack.pop_back();
      for (int e = 0; e < 3; ++e) {
        const Cdt::Face_handle g = f->neighbor(e);
        if (depth.count(g)) continue;
        if (cdt.is_constrained(Cdt::Edge(f, e))) {
          next_level.push_back(g);
        } else {
          depth[g] = level;
          stack.push_back(g);
        }
      }
    }
    for (const auto& g : next_level)
      if (!depth.count(g)) depth[g] = level + 1, stack.push_back(g);
    next_level.clear();
  }
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    const auto it = depth.find(f);
    if (it == depth.end() || it->second != 1) continue;
    std::array<int, 3> t{f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()};
    if (!ccw) std::swap(t[1], t[2]);
    tris.push_back(t);
  }
  // Heights of the interior points: harmonic in the rim's offsets.
  const std::size_t total = n + inner.size();
  std::vector<std::set<int>> nb(total);
  for (const auto& t : tris)
    for (int a = 0; a < 3; ++a) nb[static_cast<std::size_t>(t[a])].insert(t[(a + 1) % 3]), nb[static_cast<std::size_t>(t[(a + 1) % 3])].insert(t[a]);
  std::vector<double> w(total, 0.0);
  for (std::size_t i = 0; i < n; ++i) w[i] = offset[i];
  for (int sweep = 0; sweep < 2000; ++sweep) {
    double change = 0;
    for (std::size_t i = n; i < total; ++i) {
      if (nb[i].empty()) return false;
      double sum = 0;
      for (const int j : nb[i]) sum += w[static_cast<std::size_t>(j)];
      const double next = sum / static_cast<double>(nb[i].size());
      change = std::max(change, std::abs(next - w[i])), w[i] = next;
    }
    if (change < 1e-12 * diameter) break;
  }
  std::vector<Mesh::Vertex_index> vertex(rim);
  for (std::size_t k = 0; k < inner.size(); ++k) {
    const auto& p = inner[k]->point();
    const Eigen::Vector3d y = centre + p.x() * u + p.y() * v + w[n + k] * normal;
    vertex.push_back(m.add_vertex(surface::Point(y[0], y[1], y[2])));
  }
  // Faces added inward from the rim, each along the current front: one that touches the filled
  // part elsewhere than its front edges would pinch the front (Surface_mesh refuses such faces).
  // A triangulated disk can always be built this way (it is shellable).
  std::map<std::pair<int, int>, int> on_front;  // edge -> faces on it so far (the rim's walls count)
  for (std::size_t i = 0; i < n; ++i) on_front[std::minmax(static_cast<int>(i), static_cast<int>((i + 1) % n))] = 1;
  std::vector<char> touched(total, 0), added(tris.size(), 0);
  std::fill(touched.begin(), touched.begin() + static_cast<std::ptrdiff_t>(n), 1);
  std::size_t count = 0;
  for (bool progress = true; progress && count < tris.size();) {
    progress = false;
    for (std::size_t t = 0; t < tris.size(); ++t) {
      if (added[t]) continue;
      std::array<char, 3> front{};  // per vertex: an endpoint of one of t's front edges
      bool any = false;
      for (int a = 0; a < 3; ++a) {
        const auto it = on_front.find(std::minmax(tris[t][a], tris[t][(a + 1) % 3]));
        if (it != on_front.end() && it->second == 1) front[a] = front[(a + 1) % 3] = 1, any = true;
      }
      bool pinch = false;
      for (int a = 0; a < 3; ++a) pinch = pinch || (touched[static_cast<std::size_t>(tris[t][a])] && !front[a]);
      if (!any || pinch) continue;
      const auto f = m.add_face(vertex[static_cast<std::size_t>(tris[t][0])], vertex[static_cast<std::size_t>(tris[t][1])], vertex[static_cast<std::size_t>(tris[t][2])]);
      if (f == Mesh::null_face()) throw core::TopologyError("split: the planar fill of an opening is not a manifold disk");
      added[t] = 1, ++count, progress = true;
      for (int a = 0; a < 3; ++a) touched[static_cast<std::size_t>(tris[t][a])] = 1, ++on_front[std::minmax(tris[t][a], tris[t][(a + 1) % 3])];
    }
  }
  if (count != tris.size()) throw core::TopologyError("split: the planar fill of an opening is not connected");
  return true;
}

std::vector<int> fill_openings(Submesh& s, Layout& L, bool no_chords, FillMethod method, int* planar_count) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  std::vector<HI> borders;
  std::set<std::size_t> seen;
  for (auto h : s.mesh.halfedges()) {
    if (!s.mesh.is_border(h) || seen.count(static_cast<std::size_t>(h))) continue;
    borders.push_back(h);
    for (auto g : CGAL::halfedges_around_face(h, s.mesh)) seen.insert(static_cast<std::size_t>(g));
  }
  const std::size_t old_vertices = s.mesh.number_of_vertices(), old_faces = s.mesh.number_of_faces();
  std::set<Mesh::Vertex_index> rim;
  for (auto h : borders)
    for (auto g : CGAL::halfedges_around_face(h, s.mesh)) rim.insert(s.mesh.target(g));
  // CGAL's hole filling first; where that fill crosses the surface (a cut near a flat face or a
  // flare: the rod's shank at its eyes), every opening is filled again by its planar fill.
  const Mesh before = s.mesh;
  auto fill_with = [&](bool planar) {
    for (auto h : borders) {
      if (planar) {
        if (!fill_opening_in_plane(s.mesh, h, kMaxOffPlane))
          throw core::TopologyError("split: the fill of an opening crosses the surface, and the opening is not a planar simple loop (" +
                                    std::to_string(rim.size()) + " rim vertices)");
        continue;
      }
      std::vector<Mesh::Face_index> faces;
      std::vector<Mesh::Vertex_index> verts;
      PMP::triangulate_and_refine_hole(s.mesh, h, std::back_inserter(faces), std::back_inserter(verts));
    }
    // Chords: edges between fill faces on both sides with both ends on a rim. Split each at its
    // midpoint and join the new vertex to the two opposite corners.
    for (bool changed = no_chords; changed;) {
      changed = false;
      for (auto h : s.mesh.halfedges()) {
        const auto g = s.mesh.opposite(h);
        const auto f = s.mesh.face(h), fo = s.mesh.face(g);
        if (f == Mesh::null_face() || fo == Mesh::null_face() || static_cast<std::size_t>(f) < old_faces || static_cast<std::size_t>(fo) < old_faces) continue;
        const auto a = s.mesh.source(h), b = s.mesh.target(h);
        if (!rim.count(a) || !rim.count(b)) continue;
        const auto pa = s.mesh.point(a), pb = s.mesh.point(b);
        const HI hnew = CGAL::Euler::split_edge(h, s.mesh);  // a -> v (hnew), v -> b (h)
        s.mesh.point(s.mesh.target(hnew)) = CGAL::midpoint(pa, pb);
        CGAL::Euler::split_face(hnew, s.mesh.next(s.mesh.next(hnew)), s.mesh);
        CGAL::Euler::split_face(s.mesh.opposite(h), s.mesh.next(s.mesh.next(s.mesh.opposite(h))), s.mesh);
        changed = true;
        break;
      }
    }
  };
  bool planar = method == FillMethod::planar;
  fill_with(planar);
  if (!planar && !borders.empty() && PMP::does_self_intersect(s.mesh)) {
    s.mesh = before;
    fill_with(planar = true);
    core::log_verbose("split: CGAL's fill of an opening crossed the surface; filled in the opening's plane instead");
  }
  if (planar && PMP::does_self_intersect(s.mesh))
    throw core::TopologyError("split: the planar fill of an opening crosses the surface (a cut along a flat face?)");
  if (planar_count) *planar_count = planar ? static_cast<int>(borders.size()) : 0;
  if (s.mesh.has_garbage()) throw std::logic_error("split: hole filling removed elements");
  // New vertices and faces come after the old ones.
  for (std::size_t v = old_vertices; v < s.mesh.number_of_vertices(); ++v) {
    const auto& p = s.mesh.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(v)));
    s.layout_vertex.push_back(static_cast<int>(L.points.size()));
    L.points.push_back({p.x(), p.y(), p.z()});
  }
  std::vector<int> fill;
  for (std::size_t f = old_faces; f < s.mesh.number_of_faces(); ++f) {
    std::array<int, 3> t{};
    int k = 0;
    const Mesh::Face_index fi(static_cast<Mesh::size_type>(f));
    for (auto v : CGAL::vertices_around_face(s.mesh.halfedge(fi), s.mesh)) t[k++] = s.layout_vertex[v];
    s.layout_triangle.push_back(static_cast<int>(L.triangles.size()));
    fill.push_back(static_cast<int>(L.triangles.size()));
    L.triangles.push_back(t);
    L.filled.push_back(1);
  }
  return fill;
}

}  // namespace volts::split::detail
