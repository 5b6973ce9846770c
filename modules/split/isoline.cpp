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

double circle_difference(double a, double b, double period) {
  double d = b - a;
  if (period > 0) {
    d -= period * std::floor(d / period);       // [0, period)
    if (d > 0.5 * period) d -= period;           // (-period/2, period/2]
  }
  return d;
}

std::vector<std::vector<int>> insert_isoline(Mesh& mesh, std::vector<double>& f, double c, double snap) {
  IsolineOptions o;
  o.snap = snap;
  return insert_isoline(mesh, f, c, o);
}

std::vector<std::vector<int>> insert_isoline(Mesh& mesh, std::vector<double>& f, double c, const IsolineOptions& o) {
  if (f.size() != mesh.number_of_vertices()) throw core::InvalidInputError("isoline: field size does not match the mesh");
  for (const auto& k : o.carried)
    if (!k.values || k.values->size() != f.size()) throw core::InvalidInputError("isoline: a carried field's size does not match the mesh");
  const double P = o.period;
  std::vector<char> mask;
  if (o.face_mask) {
    if (o.face_mask->size() != mesh.number_of_faces()) throw core::InvalidInputError("isoline: face mask size does not match the mesh");
    mask = *o.face_mask;
  } else {
    mask.assign(mesh.number_of_faces(), 1);
  }
  // Offset of a value from the level: signed, modulo the period for circle-valued fields.
  auto off = [&](double x) { return circle_difference(c, x, P); };
  std::vector<char> in_mask(mesh.number_of_vertices(), 0);
  for (auto fc : mesh.faces())
    if (mask[fc])
      for (auto v : CGAL::vertices_around_face(mesh.halfedge(fc), mesh)) in_mask[v] = 1;
  double range = P;
  if (P <= 0) {
    const auto [lo, hi] = std::minmax_element(f.begin(), f.end());
    range = *hi - *lo;
  }
  const double tol = o.snap * range;
  for (std::size_t v = 0; v < f.size(); ++v)
    if (in_mask[v] && std::abs(off(f[v])) <= tol) f[v] = c;  // avoid slivers: the level passes through this vertex
  auto on = [&](VI v) { return f[v] == c; };
  auto masked_edge = [&](HI h) {
    const auto f1 = mesh.face(h), f2 = mesh.face(mesh.opposite(h));
    return (f1 != Mesh::null_face() && mask[f1]) || (f2 != Mesh::null_face() && mask[f2]);
  };

  // 1. Split every masked edge the level crosses strictly.
  std::vector<std::pair<int, int>> crossed;
  for (auto e : mesh.edges()) {
    const HI h = mesh.halfedge(e);
    if (!masked_edge(h)) continue;
    const int a = static_cast<int>(mesh.source(h)), b = static_cast<int>(mesh.target(h));
    // Offsets of both ends (not oa + d: rounding would find a crossing at an end on the level);
    // a circle-valued field crosses c only if the short arc from a to b passes through c.
    const double oa = off(f[a]), ob = off(f[b]);
    if (oa != 0 && ob != 0 && (oa < 0) != (ob < 0) && (P <= 0 || (ob - oa < 0.5 * P && oa - ob < 0.5 * P))) crossed.emplace_back(a, b);
  }
  for (const auto& [a, b] : crossed) {
    const HI h = mesh.halfedge(VI(a), VI(b));
    const double oa = off(f[a]), t = oa / (oa - off(f[b]));
    // Copies: split_edge adds a vertex, which can reallocate the point property (ASan: use after free).
    const surface::Point pa = mesh.point(VI(a));
    const surface::Point pb = mesh.point(VI(b));
    const HI hn = CGAL::Euler::split_edge(h, mesh);  // new vertex is target(hn)
    const VI v = mesh.target(hn);
    mesh.point(v) = surface::Point(pa.x() + t * (pb.x() - pa.x()), pa.y() + t * (pb.y() - pa.y()), pa.z() + t * (pb.z() - pa.z()));
    if (static_cast<std::size_t>(v) != f.size()) throw core::InvalidInputError("isoline: mesh has removed elements");
    f.push_back(c);
    for (const auto& k : o.carried) {
      auto& g = *k.values;
      double x = g[a] + t * circle_difference(g[a], g[b], k.period);
      if (k.period > 0) x -= k.period * std::floor(x / k.period);
      g.push_back(x);
    }
    in_mask.push_back(1);
    if (o.splits) o.splits->push_back({a, b, static_cast<int>(v)});
  }

  // 2. Split every masked face between two non-adjacent vertices on the level; then triangulate quads.
  std::vector<Mesh::Face_index> faces(mesh.faces().begin(), mesh.faces().end());
  auto set_mask = [&](Mesh::Face_index fc, char m) {
    if (static_cast<std::size_t>(fc) >= mask.size()) mask.resize(static_cast<std::size_t>(fc) + 1, 0);
    mask[fc] = m;
  };
  for (auto fc : faces) {
    if (!mask[fc]) continue;
    std::vector<HI> level;  // halfedges of the face pointing to level vertices
    for (HI h : CGAL::halfedges_around_face(mesh.halfedge(fc), mesh))
      if (on(mesh.target(h))) level.push_back(h);
    if (level.size() < 2) continue;
    if (level.size() > 2)
      throw core::TopologyError("isoline: a face has " + std::to_string(level.size()) + " of its " + std::to_string(mesh.degree(fc)) +
                                " vertices on the level; choose another value");
    if (mesh.next(level[0]) == level[1] || mesh.next(level[1]) == level[0]) continue;  // already an edge
    const HI hn = CGAL::Euler::split_face(level[0], level[1], mesh);
    set_mask(mesh.face(mesh.opposite(hn)), 1);
    set_mask(mesh.face(hn), 1);
  }
  faces.assign(mesh.faces().begin(), mesh.faces().end());
  for (auto fc : faces) {
    if (mesh.degree(fc) == 3) continue;
    if (mesh.degree(fc) != 4) throw core::TopologyError("isoline: unexpected polygon after splitting");
    const char m = mask[fc];
    const HI h0 = mesh.halfedge(fc), h1 = mesh.next(h0), h2 = mesh.next(h1), h3 = mesh.next(h2);
    // Shorter diagonal: better-shaped triangles.
    const double d02 = CGAL::squared_distance(mesh.point(mesh.target(h0)), mesh.point(mesh.target(h2)));
    const double d13 = CGAL::squared_distance(mesh.point(mesh.target(h1)), mesh.point(mesh.target(h3)));
    const HI hn = d02 <= d13 ? CGAL::Euler::split_face(h0, h2, mesh) : CGAL::Euler::split_face(h1, h3, mesh);
    set_mask(mesh.face(hn), m);
    set_mask(mesh.face(mesh.opposite(hn)), m);
  }
  mask.resize(mesh.number_of_faces(), 0);
  if (o.face_mask) *o.face_mask = mask;

  // 3. Level edges (inside the mask) and their loops or chains.
  std::map<int, std::vector<int>> adj;
  for (auto e : mesh.edges()) {
    const HI h = mesh.halfedge(e);
    const VI a = mesh.source(h), b = mesh.target(h);
    if (!on(a) || !on(b)) continue;
    const HI g = mesh.opposite(h);
    const bool m1 = mask[mesh.face(h)], m2 = mask[mesh.face(g)];
    if (!m1 && !m2) continue;
    // An edge with both ends on the level lies on it unless both its faces are on the same side
    // with the opposite vertices strictly on that side (the level only touches the edge): keep it
    // only if the two opposite vertices are on different sides or one is on the level. An edge on
    // the mask's border is never a level edge: chains inside the mask end on the border.
    const double s1 = off(f[mesh.target(mesh.next(h))]), s2 = off(f[mesh.target(mesh.next(g))]);
    if (m1 && m2 ? s1 * s2 > 0 : true) continue;
    adj[static_cast<int>(a)].push_back(static_cast<int>(b));
    adj[static_cast<int>(b)].push_back(static_cast<int>(a));
  }
  for (auto& [v, n] : adj) {
    if (n.size() > 2 || (n.size() == 1 && !o.face_mask))
      throw core::TopologyError("isoline: the level set is not a set of simple loops at vertex " + std::to_string(v) +
                                " (" + std::to_string(n.size()) + " level edges meet; is the value critical?)");
    std::sort(n.begin(), n.end());
  }
  std::vector<std::vector<int>> loops;
  std::set<int> used;
  auto walk = [&](int start) {
    std::vector<int> loop = {start};
    used.insert(start);
    int prev = start, cur = adj.at(start)[0];
    while (cur != start) {
      loop.push_back(cur);
      used.insert(cur);
      const auto& n = adj.at(cur);
      if (n.size() == 1) break;  // end of a chain
      const int next = n[0] == prev ? n[1] : n[0];
      prev = cur;
      cur = next;
    }
    loops.push_back(std::move(loop));
  };
  for (const auto& [start, n0] : adj)  // chains first, from their lower end
    if (n0.size() == 1 && !used.count(start)) walk(start);
  for (const auto& [start, n0] : adj)
    if (!used.count(start)) walk(start);
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
