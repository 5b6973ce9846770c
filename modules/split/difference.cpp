// Difference components (Liu et al. 2013, §4.3 and Fig. 7): a through hole whose rims are
// difference curves becomes a virtual component subtracted from a cube. Both rims are filled with
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

Decomposition split_difference(const Mesh& input, const classify::Classification& c, const Params&) {
  Mesh mesh = input;
  // Rims: the difference curves, chained into loops; a through hole has two.
  std::set<Edge> rim_edges;
  for (const auto& k : c.curves) {
    if (k.kind != classify::CurveKind::difference) continue;
    const std::size_t n = k.vertices.size();
    for (std::size_t i = 0; i + (k.closed ? 0 : 1) < n; ++i) rim_edges.insert(edge(k.vertices[i], k.vertices[(i + 1) % n]));
  }
  const auto rims = chain_loops(rim_edges);
  if (rims.size() != 2)
    throw core::TopologyError("split: the difference curves form " + std::to_string(rims.size()) +
                              " rim loop(s); a through hole has two (blind holes and several holes are not supported yet) — "
                              "set split.hole: torus or route: tet");
  const auto side = regions_cut_by(mesh, rims);
  if (*std::max_element(side.begin(), side.end()) != 1)
    throw core::TopologyError("split: the two rims of the hole do not cut the surface into walls and outside");
  // The outside holds the patch with the hole (a patch with more than one boundary loop).
  std::vector<int> patch_region;
  const auto patches = regions(mesh, sharp_edges(c), &patch_region);
  int outside = -1;
  for (std::size_t f = 0; f < side.size() && outside < 0; ++f)
    if (patches[patch_region[f]].loops.size() > 1) outside = side[f];
  if (outside < 0) throw core::TopologyError("split: no patch has the hole's rim as an inner boundary");
  std::vector<char> wall(mesh.number_of_faces(), 0);
  for (std::size_t f = 0; f < side.size(); ++f) wall[f] = side[f] != outside;

  // Cuts of the wall: its sharp curves (a prism), else four lines of constant angle (a cylinder).
  const std::set<Edge> sharp = sharp_edges(c);
  std::set<Edge> wall_cuts;
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge(e);
    const Edge k = edge(static_cast<int>(mesh.source(h)), static_cast<int>(mesh.target(h)));
    if (sharp.count(k) && !rim_edges.count(k) && wall[mesh.face(h)] && wall[mesh.face(mesh.opposite(h))]) wall_cuts.insert(k);
  }
  if (wall_cuts.empty()) {
    auto centroid = [&](const std::vector<int>& loop) {
      std::array<double, 3> s{0, 0, 0};
      for (int v : loop)
        for (int k = 0; k < 3; ++k) s[k] += mesh.point(VI(v))[k] / static_cast<double>(loop.size());
      return s;
    };
    const auto c1 = centroid(rims[0]), c2 = centroid(rims[1]);
    std::array<double, 3> a{c2[0] - c1[0], c2[1] - c1[1], c2[2] - c1[2]};
    const double al = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    if (!(al > 0)) throw core::TopologyError("split: the two rims of the hole have the same centre");
    for (double& x : a) x /= al;
    auto cross = [](const std::array<double, 3>& p, const std::array<double, 3>& q) {
      return std::array<double, 3>{p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
    };
    const std::array<double, 3> helper = std::abs(a[0]) < 0.9 ? std::array<double, 3>{1, 0, 0} : std::array<double, 3>{0, 1, 0};
    auto e2 = cross(a, helper);
    const double l2 = std::sqrt(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]);
    for (double& x : e2) x /= l2;
    const auto e1 = cross(e2, a);
    auto angle = [&](const surface::Point& p) {
      const double d[3] = {p.x() - c1[0], p.y() - c1[1], p.z() - c1[2]};
      double t = std::atan2(d[0] * e2[0] + d[1] * e2[1] + d[2] * e2[2], d[0] * e1[0] + d[1] * e1[1] + d[2] * e1[2]) / (2 * kPi);
      return t - std::floor(t);
    };
    std::vector<double> theta;
    for (auto v : mesh.vertices()) theta.push_back(angle(mesh.point(v)));
    // The angles of the corners of the patch around the first rim, if it has four.
    std::vector<double> levels;
    std::set<int> holed_corners;
    for (std::size_t f = 0; f < side.size(); ++f) {
      if (wall[f] || patches[patch_region[f]].loops.size() < 2) continue;
      bool on_rim0 = false;
      for (const auto& loop : patches[patch_region[f]].loops)
        on_rim0 |= std::find(loop.begin(), loop.end(), rims[0][0]) != loop.end();
      if (!on_rim0) continue;
      for (const auto& loop : patches[patch_region[f]].loops)
        for (int v : loop)
          if (std::binary_search(c.corners.begin(), c.corners.end(), v)) holed_corners.insert(v);
      break;
    }
    if (holed_corners.size() == 4)
      for (int v : holed_corners) levels.push_back(angle(mesh.point(VI(v))));
    else
      for (int k = 0; k < 4; ++k) levels.push_back(0.125 + 0.25 * k);
    std::sort(levels.begin(), levels.end());
    IsolineOptions o;
    o.period = 1.0;
    o.face_mask = &wall;
    std::vector<std::array<int, 3>> splits;
    o.splits = &splits;
    for (double level : levels) {
      splits.clear();
      const auto chains = insert_isoline(mesh, theta, level, o);
      apply_splits(rim_edges, splits);
      apply_splits(wall_cuts, splits);
      if (chains.size() != 1)
        throw core::TopologyError("split: a line of constant angle on the hole's wall has " + std::to_string(chains.size()) +
                                  " pieces instead of one from rim to rim; the hole is not a straight through hole");
      for (std::size_t i = 0; i + 1 < chains[0].size(); ++i) wall_cuts.insert(edge(chains[0][i], chains[0][i + 1]));
    }
  }

  // Layout: the mesh with the lines, then the fills.
  Decomposition d;
  d.genus = 1;
  copy_mesh(mesh, d.layout);
  std::vector<int> outer_tris, wall_tris;
  for (std::size_t f = 0; f < wall.size(); ++f) (wall[f] ? wall_tris : outer_tris).push_back(static_cast<int>(f));
  Submesh outer = submesh(d.layout, outer_tris, std::vector<char>(outer_tris.size(), 0));
  const std::vector<int> fill_tris = fill_openings(outer, d.layout, false, FillMethod::hole_filling, &d.planar_fills);
  if (fill_tris.empty()) throw core::TopologyError("split: removing the hole's walls leaves no opening");

  // The cube: the filled outer surface, its patches from its own sharp curves.
  const classify::Classification co = classify::classify(outer.mesh, {});
  if (co.genus != 0) throw core::TopologyError("split: the surface with its hole filled has genus " + std::to_string(co.genus));
  Decomposition cube = split_box(outer.mesh, co, ComponentType::cube);
  map_ids(cube, outer);

  // The virtual component: walls (reversed: its outside is the solid) and fills.
  std::vector<int> vtris = wall_tris;
  std::vector<char> rev(wall_tris.size(), 1);
  vtris.insert(vtris.end(), fill_tris.begin(), fill_tris.end());
  rev.resize(vtris.size(), 0);
  Submesh virt = submesh(d.layout, vtris, rev);
  std::map<int, int> sub_of;
  for (std::size_t i = 0; i < virt.layout_vertex.size(); ++i) sub_of[virt.layout_vertex[i]] = static_cast<int>(i);
  std::set<Edge> vcuts;
  std::vector<char> vcorner(virt.layout_vertex.size(), 0);
  std::map<int, int> rim_degree;
  for (const auto& [a, b] : rim_edges) vcuts.insert(edge(sub_of.at(a), sub_of.at(b)));
  for (const auto& [a, b] : wall_cuts) {
    vcuts.insert(edge(sub_of.at(a), sub_of.at(b)));
    ++rim_degree[a], ++rim_degree[b];
  }
  std::set<int> rim_vertices;
  for (const auto& [a, b] : rim_edges) rim_vertices.insert(a), rim_vertices.insert(b);
  for (const auto& [v, n] : rim_degree)
    if (rim_vertices.count(v)) vcorner[sub_of.at(v)] = 1;
  const auto vregs = regions(virt.mesh, vcuts, nullptr);
  if (vregs.size() != 6)
    throw core::TopologyError("split: the virtual component's walls and fills make " + std::to_string(vregs.size()) +
                              " patches instead of the 6 faces of a cube");
  Decomposition hole;
  Component vc;
  vc.type = ComponentType::virtual_component;
  for (std::size_t r = 0; r < vregs.size(); ++r) {
    hole.layout.patches.push_back(quad_patch(vregs[r], vcorner, "virtual patch", static_cast<int>(r)));
    CubeFace f;
    f.patches = {static_cast<int>(r)};
    f.corners = hole.layout.patches.back().corners;
    vc.faces.push_back(f);
    vc.patches.push_back(static_cast<int>(r));
  }
  hole.components.push_back(vc);
  map_ids(hole, virt);

  // Together: the cube's patches first, then the hole's.
  const int offset = static_cast<int>(cube.layout.patches.size());
  d.layout.patches = cube.layout.patches;
  d.layout.patches.insert(d.layout.patches.end(), hole.layout.patches.begin(), hole.layout.patches.end());
  d.components.push_back(cube.components[0]);
  Component h = hole.components[0];
  for (int& p : h.patches) p += offset;
  for (auto& f : h.faces)
    for (int& p : f.patches) p += offset;
  d.components.push_back(h);
  // Contacts: the fills are where the virtual component meets the cube's faces.
  std::set<int> fills(fill_tris.begin(), fill_tris.end());
  for (int p : h.patches)
    if (fills.count(d.layout.patches[p].triangles.front())) d.contacts.push_back({0, 1, "filled_patch", p});
  d.quad_patches = static_cast<int>(d.layout.patches.size());
  return d;
}

}  // namespace volts::split::detail
