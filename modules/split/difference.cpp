// Difference components (Liu et al. 2013, §4.3 and Fig. 7): each through hole whose rims are
// difference curves becomes a virtual component subtracted from a cube (the assembly's base: four
// virtual cylinders in one cube, Fig. 1(d)). Both rims of every hole are filled with
// new triangles (CGAL's hole filling with refinement); the outer faces plus the fills are the cube,
// the hole's walls plus the fills the virtual component. A hole with sharp vertical edges (a
// prism) keeps them as its cube edges; a smooth wall (a cylinder) is cut by four lines at constant
// angle around the hole's axis, at the angles of the holed face's corners, so the virtual cube's
// faces face the outer cube's.
#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <stdexcept>

#include "classify/classify.h"
#include "core/errors.h"
#include "split/isoline.h"
#include "split/split_internal.h"

namespace volts::split::detail {

using surface::Mesh;
using VI = Mesh::Vertex_index;

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

std::vector<std::vector<int>> difference_rims(const classify::Classification& c, std::set<Edge>* edges) {
  std::set<Edge> rim_edges;
  for (const auto& k : c.curves) {
    if (k.kind != classify::CurveKind::difference) continue;
    const std::size_t n = k.vertices.size();
    for (std::size_t i = 0; i + (k.closed ? 0 : 1) < n; ++i) rim_edges.insert(edge(k.vertices[i], k.vertices[(i + 1) % n]));
  }
  auto loops = chain_loops(rim_edges);
  if (edges) *edges = std::move(rim_edges);
  return loops;
}

namespace {

std::array<double, 3> centroid(const Mesh& mesh, const std::vector<int>& loop) {
  std::array<double, 3> s{0, 0, 0};
  for (int v : loop)
    for (int k = 0; k < 3; ++k) s[static_cast<std::size_t>(k)] += mesh.point(VI(static_cast<Mesh::size_type>(v)))[k] / static_cast<double>(loop.size());
  return s;
}

std::array<double, 3> cross(const std::array<double, 3>& p, const std::array<double, 3>& q) {
  return {p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
}

double dot(const std::array<double, 3>& p, const std::array<double, 3>& q) { return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]; }

std::array<double, 3> unit(std::array<double, 3> p) {
  const double l = std::sqrt(dot(p, p));
  for (double& x : p) x /= l;
  return p;
}

// The faces on either side of the mesh edge a–b.
std::array<std::size_t, 2> faces_of_edge(const Mesh& mesh, int a, int b) {
  const auto h = mesh.halfedge(VI(static_cast<Mesh::size_type>(a)), VI(static_cast<Mesh::size_type>(b)));
  if (h == Mesh::null_halfedge()) throw core::TopologyError("split: a rim edge is not an edge of the surface");
  return {static_cast<std::size_t>(mesh.face(h)), static_cast<std::size_t>(mesh.face(mesh.opposite(h)))};
}

// Per face: the hole whose wall it belongs to, or -1 (outside), from the rims as they are now
// (isoline insertion splits faces and rim edges). `hole_rims[h]` are hole h's two rim loops' edges.
std::vector<int> wall_of_faces(const Mesh& mesh, const std::set<Edge>& rim_edges, const std::vector<std::set<Edge>>& hole_rims, int outside_face) {
  const auto loops = chain_loops(rim_edges);
  const std::vector<int> side = regions_cut_by(mesh, loops);
  const int outside = side[static_cast<std::size_t>(outside_face)];
  std::vector<int> label_hole(static_cast<std::size_t>(*std::max_element(side.begin(), side.end()) + 1), -1);
  for (std::size_t h = 0; h < hole_rims.size(); ++h) {
    const auto& [a, b] = *hole_rims[h].begin();
    for (const std::size_t f : faces_of_edge(mesh, a, b))
      if (side[f] != outside) label_hole[static_cast<std::size_t>(side[f])] = static_cast<int>(h);
  }
  std::vector<int> out(side.size());
  for (std::size_t f = 0; f < side.size(); ++f) out[f] = side[f] == outside ? -1 : label_hole[static_cast<std::size_t>(side[f])];
  return out;
}

}  // namespace

Decomposition split_difference(const Mesh& input, const classify::Classification& c, const Params&) {
  Mesh mesh = input;
  // Rims: the difference curves, chained into loops; a through hole has two, each hole its own wall.
  std::set<Edge> rim_edges;
  const auto rims = difference_rims(c, &rim_edges);
  const int holes = static_cast<int>(rims.size()) / 2;
  if (rims.size() % 2 != 0 || holes < 1 || (c.genus >= 1 && holes != c.genus))
    throw core::TopologyError("split: the difference curves form " + std::to_string(rims.size()) + " rim loop(s) on a genus-" +
                              std::to_string(c.genus) + " surface; through holes have two each, one hole per genus (blind holes are not "
                              "supported yet) — set split.hole: torus or route: tet");
  const auto side = regions_cut_by(mesh, rims);
  if (*std::max_element(side.begin(), side.end()) != holes)
    throw core::TopologyError("split: the rims of the holes do not cut the surface into " + std::to_string(holes) + " wall(s) and the outside");
  // The outside holds the patches with the holes (a patch with more than one boundary loop).
  std::vector<int> patch_region;
  const auto patches = regions(mesh, sharp_edges(c), &patch_region);
  int outside = -1, outside_face = -1;
  for (std::size_t f = 0; f < side.size() && outside < 0; ++f)
    if (patches[static_cast<std::size_t>(patch_region[f])].loops.size() > 1) outside = side[f], outside_face = static_cast<int>(f);
  if (outside < 0) throw core::TopologyError("split: no patch has a hole's rim as an inner boundary");
  // The holes: the wall each rim bounds, two rims per wall.
  std::vector<std::vector<int>> hole_rim_ids;
  {
    std::map<int, int> hole_of_label;
    for (std::size_t r = 0; r < rims.size(); ++r) {
      int label = -1;
      for (const std::size_t f : faces_of_edge(mesh, rims[r][0], rims[r][1]))
        if (side[f] != outside) label = side[f];
      if (label < 0) throw core::TopologyError("split: a rim has the outside on both sides");
      const auto [it, fresh] = hole_of_label.try_emplace(label, static_cast<int>(hole_rim_ids.size()));
      if (fresh) hole_rim_ids.emplace_back();
      hole_rim_ids[static_cast<std::size_t>(it->second)].push_back(static_cast<int>(r));
    }
    for (const auto& ids : hole_rim_ids)
      if (ids.size() != 2) throw core::TopologyError("split: a hole's wall has " + std::to_string(ids.size()) + " rim(s) instead of two (a blind hole?)");
  }
  std::vector<std::set<Edge>> hole_rims(static_cast<std::size_t>(holes));
  for (int h = 0; h < holes; ++h)
    for (const int r : hole_rim_ids[static_cast<std::size_t>(h)]) {
      const auto& loop = rims[static_cast<std::size_t>(r)];
      for (std::size_t i = 0; i < loop.size(); ++i) hole_rims[static_cast<std::size_t>(h)].insert(edge(loop[i], loop[(i + 1) % loop.size()]));
    }
  std::vector<int> wall = wall_of_faces(mesh, rim_edges, hole_rims, outside_face);

  // Cuts of each wall: its sharp curves (a prism), else four lines of constant angle (a cylinder).
  const std::set<Edge> sharp = sharp_edges(c);
  std::vector<std::set<Edge>> wall_cuts(static_cast<std::size_t>(holes));
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge(e);
    const Edge k = edge(static_cast<int>(mesh.source(h)), static_cast<int>(mesh.target(h)));
    const int w = wall[static_cast<std::size_t>(mesh.face(h))];
    if (sharp.count(k) && !rim_edges.count(k) && w >= 0 && w == wall[static_cast<std::size_t>(mesh.face(mesh.opposite(h)))])
      wall_cuts[static_cast<std::size_t>(w)].insert(k);
  }
  for (int hole = 0; hole < holes; ++hole) {
    if (!wall_cuts[static_cast<std::size_t>(hole)].empty()) continue;
    const auto& two = hole_rim_ids[static_cast<std::size_t>(hole)];
    const auto c1 = centroid(mesh, rims[static_cast<std::size_t>(two[0])]), c2 = centroid(mesh, rims[static_cast<std::size_t>(two[1])]);
    const std::array<double, 3> axis{c2[0] - c1[0], c2[1] - c1[1], c2[2] - c1[2]};
    if (!(dot(axis, axis) > 0)) throw core::TopologyError("split: the two rims of a hole have the same centre");
    const auto a = unit(axis);
    const std::array<double, 3> helper = std::abs(a[0]) < 0.9 ? std::array<double, 3>{1, 0, 0} : std::array<double, 3>{0, 1, 0};
    const auto e2 = unit(cross(a, helper));
    const auto e1 = cross(e2, a);
    auto direction_angle = [&](const std::array<double, 3>& d) {
      const double t = std::atan2(dot(d, e2), dot(d, e1)) / (2 * kPi);
      return t - std::floor(t);
    };
    auto angle = [&](const surface::Point& p) { return direction_angle({p.x() - c1[0], p.y() - c1[1], p.z() - c1[2]}); };
    std::vector<double> theta;
    for (auto v : mesh.vertices()) theta.push_back(angle(mesh.point(v)));
    // The corners of the holed patch around the hole's first rim, in the order of its outer loop.
    std::vector<int> holed_corners;
    const int rim0 = rims[static_cast<std::size_t>(two[0])][0];
    for (std::size_t f = 0; f < side.size() && holed_corners.empty(); ++f) {
      const auto& patch = patches[static_cast<std::size_t>(patch_region[f])];
      if (wall[f] >= 0 || patch.loops.size() < 2) continue;
      bool on_rim0 = false;
      for (const auto& loop : patch.loops) on_rim0 |= std::find(loop.begin(), loop.end(), rim0) != loop.end();
      if (!on_rim0) continue;
      for (const auto& loop : patch.loops)
        for (int v : loop)
          if (std::binary_search(c.corners.begin(), c.corners.end(), v)) holed_corners.push_back(v);
    }
    std::vector<double> levels;
    if (holed_corners.size() == 4 && holes == 1) {
      // One hole: the angles of the face's corners seen from it (a centred hole: the diagonals).
      for (int v : holed_corners) levels.push_back(angle(mesh.point(VI(static_cast<Mesh::size_type>(v)))));
    } else if (holed_corners.size() == 4) {
      // Several holes share the face: the directions of its diagonals' frame, u ± v from its
      // corner edges, so every hole's box has its sides along the face's sides.
      auto at = [&](int i) { const auto& p = mesh.point(VI(static_cast<Mesh::size_type>(holed_corners[static_cast<std::size_t>(i)]))); return std::array<double, 3>{p.x(), p.y(), p.z()}; };
      const auto p0 = at(0), p1 = at(1), p3 = at(3);
      const auto u = unit({p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]}), v = unit({p3[0] - p0[0], p3[1] - p0[1], p3[2] - p0[2]});
      for (const double su : {1.0, -1.0})
        for (const double sv : {1.0, -1.0}) levels.push_back(direction_angle({su * u[0] + sv * v[0], su * u[1] + sv * v[1], su * u[2] + sv * v[2]}));
    } else {
      for (int k = 0; k < 4; ++k) levels.push_back(0.125 + 0.25 * k);
    }
    std::sort(levels.begin(), levels.end());
    for (double level : levels) {
      std::vector<char> mask(wall.size());
      for (std::size_t f = 0; f < wall.size(); ++f) mask[f] = wall[f] == hole;
      IsolineOptions o;
      o.period = 1.0;
      o.face_mask = &mask;
      std::vector<std::array<int, 3>> splits;
      o.splits = &splits;
      const auto chains = insert_isoline(mesh, theta, level, o);
      apply_splits(rim_edges, splits);
      for (auto& r : hole_rims) apply_splits(r, splits);
      for (auto& w : wall_cuts) apply_splits(w, splits);
      if (chains.size() != 1)
        throw core::TopologyError("split: a line of constant angle on hole " + std::to_string(hole) + "'s wall has " + std::to_string(chains.size()) +
                                  " pieces instead of one from rim to rim; the hole is not a straight through hole");
      for (std::size_t i = 0; i + 1 < chains[0].size(); ++i) wall_cuts[static_cast<std::size_t>(hole)].insert(edge(chains[0][i], chains[0][i + 1]));
      wall = wall_of_faces(mesh, rim_edges, hole_rims, outside_face);  // the split faces, labelled again
    }
  }

  // Layout: the mesh with the lines, then the fills.
  Decomposition d;
  d.genus = c.genus;
  copy_mesh(mesh, d.layout);
  std::vector<int> outer_tris;
  std::vector<std::vector<int>> wall_tris(static_cast<std::size_t>(holes));
  for (std::size_t f = 0; f < wall.size(); ++f) (wall[f] >= 0 ? wall_tris[static_cast<std::size_t>(wall[f])] : outer_tris).push_back(static_cast<int>(f));
  Submesh outer = submesh(d.layout, outer_tris, std::vector<char>(outer_tris.size(), 0));
  const std::vector<int> fill_tris = fill_openings(outer, d.layout, false, FillMethod::hole_filling, &d.planar_fills);
  if (fill_tris.empty()) throw core::TopologyError("split: removing the holes' walls leaves no opening");

  // The cube: the filled outer surface, its patches from its own sharp curves.
  const classify::Classification co = classify::classify(outer.mesh, {});
  if (co.genus != 0) throw core::TopologyError("split: the surface with its holes filled has genus " + std::to_string(co.genus));
  Decomposition cube = split_box(outer.mesh, co, ComponentType::cube);
  map_ids(cube, outer);
  d.layout.patches = cube.layout.patches;
  d.components.push_back(cube.components[0]);

  // Each fill belongs to the hole whose rim it closes: fill triangles joined across shared edges.
  std::map<int, int> hole_of_rim_vertex;
  for (int h = 0; h < holes; ++h)
    for (const auto& [a, b] : hole_rims[static_cast<std::size_t>(h)]) hole_of_rim_vertex[a] = h, hole_of_rim_vertex[b] = h;
  std::vector<std::vector<int>> fills_of(static_cast<std::size_t>(holes));
  {
    std::map<Edge, std::vector<std::size_t>> by_edge;
    for (std::size_t i = 0; i < fill_tris.size(); ++i) {
      const auto& t = d.layout.triangles[static_cast<std::size_t>(fill_tris[i])];
      for (int k = 0; k < 3; ++k) by_edge[edge(t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>((k + 1) % 3)])].push_back(i);
    }
    std::vector<int> group(fill_tris.size(), -1);
    for (std::size_t seed = 0; seed < fill_tris.size(); ++seed) {
      if (group[seed] >= 0) continue;
      // Flood one fill; its hole is the one whose rim vertices it touches.
      std::vector<std::size_t> stack{seed}, members;
      group[seed] = 1;
      int hole = -1;
      while (!stack.empty()) {
        const std::size_t i = stack.back();
        stack.pop_back();
        members.push_back(i);
        const auto& t = d.layout.triangles[static_cast<std::size_t>(fill_tris[i])];
        for (int k = 0; k < 3; ++k) {
          const auto it = hole_of_rim_vertex.find(t[static_cast<std::size_t>(k)]);
          if (it != hole_of_rim_vertex.end()) hole = it->second;
          for (const std::size_t j : by_edge[edge(t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>((k + 1) % 3)])])
            if (group[j] < 0) group[j] = 1, stack.push_back(j);
        }
      }
      if (hole < 0) throw core::TopologyError("split: a fill touches no hole's rim");
      for (const std::size_t i : members) fills_of[static_cast<std::size_t>(hole)].push_back(fill_tris[i]);
    }
  }

  for (int hole = 0; hole < holes; ++hole) {
    // The virtual component: walls (reversed: its outside is the solid) and its two fills.
    std::vector<int> vtris = wall_tris[static_cast<std::size_t>(hole)];
    std::vector<char> rev(vtris.size(), 1);
    const auto& own_fills = fills_of[static_cast<std::size_t>(hole)];
    vtris.insert(vtris.end(), own_fills.begin(), own_fills.end());
    rev.resize(vtris.size(), 0);
    Submesh virt = submesh(d.layout, vtris, rev);
    std::map<int, int> sub_of;
    for (std::size_t i = 0; i < virt.layout_vertex.size(); ++i) sub_of[virt.layout_vertex[i]] = static_cast<int>(i);
    std::set<Edge> vcuts;
    std::vector<char> vcorner(virt.layout_vertex.size(), 0);
    std::map<int, int> rim_degree;
    for (const auto& [a, b] : hole_rims[static_cast<std::size_t>(hole)]) vcuts.insert(edge(sub_of.at(a), sub_of.at(b)));
    for (const auto& [a, b] : wall_cuts[static_cast<std::size_t>(hole)]) {
      vcuts.insert(edge(sub_of.at(a), sub_of.at(b)));
      ++rim_degree[a], ++rim_degree[b];
    }
    std::set<int> rim_vertices;
    for (const auto& [a, b] : hole_rims[static_cast<std::size_t>(hole)]) rim_vertices.insert(a), rim_vertices.insert(b);
    for (const auto& [v, n] : rim_degree)
      if (rim_vertices.count(v)) vcorner[static_cast<std::size_t>(sub_of.at(v))] = 1;
    const auto vregs = regions(virt.mesh, vcuts, nullptr);
    if (vregs.size() != 6)
      throw core::TopologyError("split: hole " + std::to_string(hole) + "'s walls and fills make " + std::to_string(vregs.size()) +
                                " patches instead of the 6 faces of a cube");
    Decomposition one;
    Component vc;
    vc.type = ComponentType::virtual_component;
    for (std::size_t r = 0; r < vregs.size(); ++r) {
      one.layout.patches.push_back(quad_patch(vregs[r], vcorner, "virtual patch", static_cast<int>(r)));
      CubeFace f;
      f.patches = {static_cast<int>(r)};
      f.corners = one.layout.patches.back().corners;
      vc.faces.push_back(f);
      vc.patches.push_back(static_cast<int>(r));
    }
    one.components.push_back(vc);
    map_ids(one, virt);

    // The cube's patches first, then the holes' in order.
    const int offset = static_cast<int>(d.layout.patches.size());
    d.layout.patches.insert(d.layout.patches.end(), one.layout.patches.begin(), one.layout.patches.end());
    Component h = one.components[0];
    for (int& p : h.patches) p += offset;
    for (auto& f : h.faces)
      for (int& p : f.patches) p += offset;
    d.components.push_back(h);
    // Contacts: the fills are where the virtual component meets the cube's faces.
    const std::set<int> fills(own_fills.begin(), own_fills.end());
    for (int p : h.patches)
      if (fills.count(d.layout.patches[static_cast<std::size_t>(p)].triangles.front())) d.contacts.push_back({0, 1 + hole, "filled_patch", p});
  }
  d.quad_patches = static_cast<int>(d.layout.patches.size());
  return d;
}

}  // namespace volts::split::detail
