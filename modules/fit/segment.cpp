#include "fit/segment.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "core/errors.h"

namespace volts::fit {
namespace {

using Mesh = surface::Mesh;
using Eigen::Vector3d;

const char* kName[6] = {"+x", "-x", "+y", "-y", "+z", "-z"};

Vector3d direction(int l) {
  Vector3d d = Vector3d::Zero();
  d[l / 2] = l % 2 == 0 ? 1 : -1;
  return d;
}
bool opposite(int a, int b) { return a != b && a / 2 == b / 2; }

Vector3d to_eigen(const surface::Point& p) { return {p.x(), p.y(), p.z()}; }

// Connected components of equal labels over edge-adjacent faces; comp[f] = component id.
int components(const Mesh& mesh, const std::vector<int>& label, std::vector<int>& comp) {
  comp.assign(mesh.number_of_faces(), -1);
  int count = 0;
  std::vector<Mesh::Face_index> stack;
  for (auto f0 : mesh.faces()) {
    if (comp[f0.idx()] >= 0) continue;
    comp[f0.idx()] = count;
    stack.push_back(f0);
    while (!stack.empty()) {
      const auto f = stack.back();
      stack.pop_back();
      for (auto h : mesh.halfedges_around_face(mesh.halfedge(f))) {
        const auto g = mesh.face(mesh.opposite(h));
        if (g == Mesh::null_face() || comp[g.idx()] >= 0 || label[g.idx()] != label[f.idx()]) continue;
        comp[g.idx()] = count;
        stack.push_back(g);
      }
    }
    ++count;
  }
  return count;
}

}  // namespace

std::string CubeLayout::summary() const {
  std::ostringstream s;
  auto list = [&](const char* what, const auto& v) {
    s << what << " [";
    for (int l = 0; l < 6; ++l) s << (l ? " " : "") << v[l];
    s << "] ";
  };
  list("components", components);
  list("loops", loops);
  list("sides", sides);
  list("euler", euler);
  s << "corners " << corners << ", opposite-patch vertices " << opposite_vertices << ", crowded vertices "
    << crowded_vertices;
  return s.str();
}

CubeLayout cube_layout(const Mesh& mesh, const std::vector<int>& label) {
  CubeLayout r;
  auto problem = [&](const std::string& p) {
    if (r.problem.empty()) r.problem = p;
  };
  if (label.size() != mesh.number_of_faces())
    throw core::InvalidInputError("cube_layout: " + std::to_string(label.size()) + " labels for " +
                                  std::to_string(mesh.number_of_faces()) + " faces");
  for (int l : label)
    if (l < 0 || l > 5) throw core::InvalidInputError("cube_layout: label " + std::to_string(l) + " outside 0..5");
  std::vector<int> comp;
  const int ncomp = components(mesh, label, comp);
  {
    std::vector<int> comp_label(ncomp, -1);
    for (auto f : mesh.faces()) comp_label[comp[f.idx()]] = label[f.idx()];
    for (int c : comp_label) ++r.components[c];
  }
  for (int l = 0; l < 6; ++l)
    if (r.components[l] != 1)
      problem("patch " + std::string(kName[l]) + " has " + std::to_string(r.components[l]) + " connected components");
  // Vertices: the labels around each, in cyclic order, must form at most three runs of distinct,
  // mutually non-opposite labels.
  std::array<int, 8> found{};
  for (auto v : mesh.vertices()) {
    std::vector<int> ring;
    for (auto f : mesh.faces_around_target(mesh.halfedge(v)))
      if (f != Mesh::null_face()) ring.push_back(label[f.idx()]);
    int runs = 0;
    for (size_t a = 0; a < ring.size(); ++a) runs += ring[a] != ring[(a + 1) % ring.size()];
    const std::set<int> distinct(ring.begin(), ring.end());
    bool opp = false;
    for (int a : distinct)
      for (int b : distinct) opp = opp || opposite(a, b);
    if (opp) {
      ++r.opposite_vertices;
      problem("opposite patches meet at vertex " + std::to_string(v.idx()));
    }
    if (distinct.size() > 3 || (runs > 0 && runs != static_cast<int>(distinct.size()))) {
      ++r.crowded_vertices;
      problem("vertex " + std::to_string(v.idx()) + " has " + std::to_string(distinct.size()) + " patches in " +
              std::to_string(runs) + " runs around it");
    }
    if (distinct.size() == 3 && !opp) {
      int c = 0;
      for (int l : distinct) c |= (l % 2 == 0 ? 1 : 0) << (l / 2);
      ++r.corners;
      ++found[c];
      r.corner_vertex[c] = static_cast<int>(v.idx());
    }
  }
  for (int c = 0; c < 8; ++c)
    if (found[c] != 1) r.corner_vertex[c] = -1;
  if (r.corners != 8) problem(std::to_string(r.corners) + " corners where three patches meet (a cube has 8)");
  for (int c = 0; c < 8; ++c)
    if (found[c] != 1) problem("cube corner " + std::to_string(c) + " found " + std::to_string(found[c]) + " times");
  // Each patch: one boundary loop, its neighbours in four runs (one per non-opposite label), and
  // V − E + F = 1 (a disk).
  for (int l = 0; l < 6; ++l) {
    std::set<Mesh::Halfedge_index> seen;
    std::vector<int> neighbours;
    for (auto h0 : mesh.halfedges()) {
      if (label[mesh.face(h0).idx()] != l || label[mesh.face(mesh.opposite(h0)).idx()] == l || seen.count(h0)) continue;
      ++r.loops[l];
      const size_t first = neighbours.size();
      auto h = h0;
      do {
        seen.insert(h);
        neighbours.push_back(label[mesh.face(mesh.opposite(h)).idx()]);
        auto n = mesh.next(h);
        while (label[mesh.face(mesh.opposite(n)).idx()] == l) n = mesh.next(mesh.opposite(n));
        h = n;
      } while (h != h0 && !seen.count(h));
      const size_t len = neighbours.size() - first;
      for (size_t a = 0; a < len; ++a)
        r.sides[l] += neighbours[first + a] != neighbours[first + (a + 1) % len];
    }
    std::set<Mesh::Vertex_index> verts;
    std::set<Mesh::Edge_index> edges;
    long faces = 0;
    for (auto f : mesh.faces()) {
      if (label[f.idx()] != l) continue;
      ++faces;
      for (auto h : mesh.halfedges_around_face(mesh.halfedge(f))) {
        verts.insert(mesh.target(h));
        edges.insert(mesh.edge(h));
      }
    }
    r.euler[l] = static_cast<long>(verts.size()) - static_cast<long>(edges.size()) + faces;
    const std::set<int> distinct(neighbours.begin(), neighbours.end());
    if (r.loops[l] != 1) problem("patch " + std::string(kName[l]) + " has " + std::to_string(r.loops[l]) + " boundary loops");
    if (r.sides[l] != 4 || distinct.size() != 4)
      problem("patch " + std::string(kName[l]) + " has " + std::to_string(r.sides[l]) + " sides along " +
              std::to_string(distinct.size()) + " neighbours (a cube face has 4)");
    if (r.euler[l] != 1)
      problem("patch " + std::string(kName[l]) + " has Euler characteristic " + std::to_string(r.euler[l]));
  }
  return r;
}

SixPatches six_patches(const Mesh& mesh, const SixPatchParams& params) {
  if (surface::genus(mesh) != 0)
    throw core::TopologyError("six_patches: the surface has genus " + std::to_string(surface::genus(mesh)) +
                              " (six patches meeting like cube faces need genus 0)");
  const size_t nf = mesh.number_of_faces();
  std::vector<Vector3d> normal(nf);
  std::vector<double> area(nf);
  for (auto f : mesh.faces()) {
    std::array<Vector3d, 3> p;
    int a = 0;
    for (auto v : mesh.vertices_around_face(mesh.halfedge(f))) p[a++] = to_eigen(mesh.point(v));
    const Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    area[f.idx()] = 0.5 * n.norm();
    normal[f.idx()] = n.normalized();
  }
  SixPatches out;
  out.label.assign(nf, 0);
  std::vector<int> nearest(nf);
  for (size_t f = 0; f < nf; ++f) {
    int best = 0;
    for (int l = 1; l < 6; ++l)
      if (normal[f].dot(direction(l)) > normal[f].dot(direction(best))) best = l;
    nearest[f] = out.label[f] = best;
  }
  // Iterated conditional modes: each face takes the label of its own or its neighbours' that
  // minimises deviation + smoothness · (neighbours with another label).
  for (int sweep = 0; sweep < params.sweeps; ++sweep) {
    int changed = 0;
    for (auto f : mesh.faces()) {
      std::array<int, 3> nb;
      int a = 0;
      for (auto h : mesh.halfedges_around_face(mesh.halfedge(f))) nb[a++] = out.label[mesh.face(mesh.opposite(h)).idx()];
      int best = out.label[f.idx()];
      double best_cost = 1e300;
      for (int l : {out.label[f.idx()], nb[0], nb[1], nb[2]}) {
        const double cost = 1 - normal[f.idx()].dot(direction(l)) +
                            params.smoothness * ((nb[0] != l) + (nb[1] != l) + (nb[2] != l));
        if (cost < best_cost - 1e-12) best_cost = cost, best = l;
      }
      if (best != out.label[f.idx()]) out.label[f.idx()] = best, ++changed;
    }
    if (changed == 0) break;
  }
  // Each label keeps its largest component; the others join the neighbour sharing most boundary.
  for (size_t round = 0;; ++round) {
    if (round > nf) throw core::TopologyError("six_patches: components did not settle");
    std::vector<int> comp;
    const int ncomp = components(mesh, out.label, comp);
    std::vector<double> comp_area(ncomp, 0);
    std::vector<int> comp_label(ncomp, -1);
    for (size_t f = 0; f < nf; ++f) comp_area[comp[f]] += area[f], comp_label[comp[f]] = out.label[f];
    std::array<int, 6> keep;
    keep.fill(-1);
    for (int c = 0; c < ncomp; ++c)
      if (keep[comp_label[c]] < 0 || comp_area[c] > comp_area[keep[comp_label[c]]]) keep[comp_label[c]] = c;
    for (int l = 0; l < 6; ++l)
      if (keep[l] < 0)
        throw core::TopologyError(std::string("six_patches: no face is nearest to direction ") + kName[l]);
    if (ncomp == 6) break;
    // Boundary length of each small component with each other label.
    std::vector<std::map<int, double>> shared(ncomp);
    for (auto e : mesh.edges()) {
      const auto h = mesh.halfedge(e);
      const int f = mesh.face(h).idx(), g = mesh.face(mesh.opposite(h)).idx();
      if (comp[f] == comp[g]) continue;
      const double len = (to_eigen(mesh.point(mesh.source(h))) - to_eigen(mesh.point(mesh.target(h)))).norm();
      shared[comp[f]][out.label[g]] += len;
      shared[comp[g]][out.label[f]] += len;
    }
    // Smallest first: one merge per round keeps the boundary data valid; small components of
    // different labels that touch are resolved in later rounds.
    int smallest = -1;
    for (int c = 0; c < ncomp; ++c)
      if (keep[comp_label[c]] != c && (smallest < 0 || comp_area[c] < comp_area[smallest])) smallest = c;
    // Into the neighbour whose direction best fits the component's mean normal; never into the
    // opposite direction unless it is the only neighbour (an island).
    Vector3d mean = Vector3d::Zero();
    for (size_t f = 0; f < nf; ++f)
      if (comp[f] == smallest) mean += area[f] * normal[f];
    int to = -1;
    for (int pass = 0; pass < 2 && to < 0; ++pass)
      for (const auto& [l, len] : shared[smallest])
        if (l != comp_label[smallest] && (pass == 1 || !opposite(l, comp_label[smallest])) &&
            (to < 0 || mean.dot(direction(l)) > mean.dot(direction(to))))
          to = l;
    for (size_t f = 0; f < nf; ++f)
      if (comp[f] == smallest) out.label[f] = to;
  }
  for (size_t f = 0; f < nf; ++f) {
    out.relabeled += out.label[f] != nearest[f];
    const double c = std::clamp(normal[f].dot(direction(out.label[f])), -1.0, 1.0);
    out.max_deviation_deg = std::max(out.max_deviation_deg, std::acos(c) * 180 / M_PI);
  }
  out.layout = cube_layout(mesh, out.label);
  out.corners = out.layout.corner_vertex;
  if (params.require_cube_layout && !out.layout.ok())
    throw core::TopologyError("six_patches: " + out.layout.problem + " (" + out.layout.summary() + ")");
  return out;
}

}  // namespace volts::fit
