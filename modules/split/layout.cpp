#include "split/layout.h"

#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <algorithm>
#include <set>
#include <iterator>
#include <cmath>
#include <stdexcept>

#include "core/errors.h"
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

std::vector<int> fill_openings(Submesh& s, Layout& L, bool no_chords) {
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
  for (auto h : borders) {
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
