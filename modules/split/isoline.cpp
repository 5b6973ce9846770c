#include "split/isoline.h"

#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "core/errors.h"

namespace volts::split {

using surface::Mesh;
using VI = Mesh::Vertex_index;
using HI = Mesh::Halfedge_index;

std::vector<std::vector<int>> insert_isoline(Mesh& mesh, std::vector<double>& f, double c, double snap) {
  if (f.size() != mesh.number_of_vertices()) throw core::InvalidInputError("isoline: field size does not match the mesh");
  const auto [lo, hi] = std::minmax_element(f.begin(), f.end());
  const double tol = snap * (*hi - *lo);
  for (double& x : f)
    if (std::abs(x - c) <= tol) x = c;  // avoid slivers: the level passes through this vertex

  // 1. Split every edge the level crosses strictly.
  std::vector<std::pair<int, int>> crossed;
  for (auto e : mesh.edges()) {
    const HI h = mesh.halfedge(e);
    const int a = static_cast<int>(mesh.source(h)), b = static_cast<int>(mesh.target(h));
    if ((f[a] - c) * (f[b] - c) < 0) crossed.emplace_back(a, b);
  }
  for (const auto& [a, b] : crossed) {
    const HI h = mesh.halfedge(VI(a), VI(b));
    const double t = (c - f[a]) / (f[b] - f[a]);
    const auto& pa = mesh.point(VI(a));
    const auto& pb = mesh.point(VI(b));
    const HI hn = CGAL::Euler::split_edge(h, mesh);  // new vertex is target(hn)
    const VI v = mesh.target(hn);
    mesh.point(v) = surface::Point(pa.x() + t * (pb.x() - pa.x()), pa.y() + t * (pb.y() - pa.y()), pa.z() + t * (pb.z() - pa.z()));
    if (static_cast<std::size_t>(v) != f.size()) throw core::InvalidInputError("isoline: mesh has removed elements");
    f.push_back(c);
  }

  // 2. Split every face between two non-adjacent vertices on the level; then triangulate quads.
  auto on = [&](VI v) { return f[v] == c; };
  std::vector<Mesh::Face_index> faces(mesh.faces().begin(), mesh.faces().end());
  for (auto fc : faces) {
    std::vector<HI> level;  // halfedges of the face pointing to level vertices
    for (HI h : CGAL::halfedges_around_face(mesh.halfedge(fc), mesh))
      if (on(mesh.target(h))) level.push_back(h);
    if (level.size() < 2) continue;
    if (level.size() > 2) throw core::TopologyError("isoline: a triangle has all its vertices on the level; choose another value");
    if (mesh.next(level[0]) == level[1] || mesh.next(level[1]) == level[0]) continue;  // already an edge
    CGAL::Euler::split_face(level[0], level[1], mesh);
  }
  faces.assign(mesh.faces().begin(), mesh.faces().end());
  for (auto fc : faces) {
    if (mesh.degree(fc) == 3) continue;
    if (mesh.degree(fc) != 4) throw core::TopologyError("isoline: unexpected polygon after splitting");
    const HI h0 = mesh.halfedge(fc), h1 = mesh.next(h0), h2 = mesh.next(h1), h3 = mesh.next(h2);
    // Shorter diagonal: better-shaped triangles.
    const double d02 = CGAL::squared_distance(mesh.point(mesh.target(h0)), mesh.point(mesh.target(h2)));
    const double d13 = CGAL::squared_distance(mesh.point(mesh.target(h1)), mesh.point(mesh.target(h3)));
    if (d02 <= d13) CGAL::Euler::split_face(h0, h2, mesh);
    else CGAL::Euler::split_face(h1, h3, mesh);
  }

  // 3. Level edges and their loops.
  std::map<int, std::vector<int>> adj;
  for (auto e : mesh.edges()) {
    const HI h = mesh.halfedge(e);
    const VI a = mesh.source(h), b = mesh.target(h);
    if (!on(a) || !on(b)) continue;
    // An edge with both ends on the level lies on it unless both its faces are on the same side
    // with the opposite vertices strictly on that side (the level only touches the edge): keep it
    // only if the two opposite vertices are on different sides or one is on the level.
    const double s1 = f[mesh.target(mesh.next(h))] - c, s2 = f[mesh.target(mesh.next(mesh.opposite(h)))] - c;
    if (s1 * s2 > 0) continue;
    adj[static_cast<int>(a)].push_back(static_cast<int>(b));
    adj[static_cast<int>(b)].push_back(static_cast<int>(a));
  }
  std::vector<std::vector<int>> loops;
  std::set<int> used;
  for (auto& [v, n] : adj) {
    if (n.size() != 2)
      throw core::TopologyError("isoline: the level set is not a set of simple loops at vertex " + std::to_string(v) +
                                " (" + std::to_string(n.size()) + " level edges meet; is the value critical?)");
    std::sort(n.begin(), n.end());
  }
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

std::vector<int> regions_cut_by(const Mesh& mesh, const std::vector<std::vector<int>>& loops) {
  std::set<std::pair<int, int>> cut;
  for (const auto& l : loops)
    for (std::size_t i = 0; i < l.size(); ++i) {
      const int a = l[i], b = l[(i + 1) % l.size()];
      cut.insert({std::min(a, b), std::max(a, b)});
    }
  std::vector<int> label(mesh.number_of_faces(), -1);
  int next = 0;
  std::vector<Mesh::Face_index> stack;
  for (auto f0 : mesh.faces()) {
    if (label[f0] >= 0) continue;
    label[f0] = next;
    stack.push_back(f0);
    while (!stack.empty()) {
      const auto fc = stack.back();
      stack.pop_back();
      for (HI h : CGAL::halfedges_around_face(mesh.halfedge(fc), mesh)) {
        const int a = static_cast<int>(mesh.source(h)), b = static_cast<int>(mesh.target(h));
        if (cut.count({std::min(a, b), std::max(a, b)})) continue;
        const auto g = mesh.face(mesh.opposite(h));
        if (label[g] < 0) label[g] = next, stack.push_back(g);
      }
    }
    ++next;
  }
  return label;
}

}  // namespace volts::split
