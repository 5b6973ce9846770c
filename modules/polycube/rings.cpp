#include "polycube/rings.h"

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

#include "core/errors.h"

namespace volts::polycube {

namespace {

std::string join(const std::vector<int>& v) {
  std::string s;
  for (int x : v) s += (s.empty() ? "" : ", ") + std::to_string(x);
  return s;
}

std::string describe_tori(const split::Decomposition& d) {
  std::string s;
  for (std::size_t t = 0; t < d.tori.size(); ++t) s += (t ? "; torus " : "torus ") + std::to_string(t) + ": components " + join(d.tori[t].components);
  return s.empty() ? "no torus" : s;
}

// Components of d (a torus in ring order, or one connector cube) with their own ids (see Ring):
// their patches, and the cross sections between them.
Ring make_piece(const split::Decomposition& d, const split::Torus& torus, const std::string& who) {
  const split::Layout& L = d.layout;
  Ring r;
  r.component = torus.components;
  std::set<int> patch_set, face_set(torus.cross_sections.begin(), torus.cross_sections.end());
  for (int c : torus.components) {
    for (int p : d.components[c].patches) patch_set.insert(p);
    for (const auto& f : d.components[c].faces) {
      for (int p : f.patches) patch_set.insert(p);
      if (f.internal_face >= 0) face_set.insert(f.internal_face);
    }
  }
  // Triangles: surface ones first (the first keeps its orientation), then fills.
  std::vector<int> surface_tris, fill_tris;
  std::map<int, int> times;  // layout triangle -> patches of this torus holding it
  for (int p : patch_set)
    for (int x : L.patches[p].triangles) ++times[x];
  for (const auto& [x, n] : times) {
    if (n != 1)
      throw core::TopologyError("polycube: triangle " + std::to_string(x) + " lies in " + std::to_string(n) + " patches of " + who);
    (L.filled[x] ? fill_tris : surface_tris).push_back(x);
  }
  if (surface_tris.empty()) throw core::TopologyError("polycube: " + who + " has no surface triangle");
  r.layout_triangle = surface_tris;
  r.layout_triangle.insert(r.layout_triangle.end(), fill_tris.begin(), fill_tris.end());
  const std::vector<char> rev = consistent_orientation(L, r.layout_triangle);
  std::vector<int> local_v(L.points.size(), -1), local_t(L.triangles.size(), -1);
  for (int x : r.layout_triangle)
    for (int v : L.triangles[x]) local_v[v] = 0;
  for (std::size_t v = 0; v < local_v.size(); ++v)
    if (local_v[v] == 0) local_v[v] = static_cast<int>(r.layout_vertex.size()), r.layout_vertex.push_back(static_cast<int>(v));
  auto vmap = [&](int v) {
    if (v < 0 || v >= static_cast<int>(local_v.size()) || local_v[v] < 0)
      throw core::TopologyError("polycube: vertex " + std::to_string(v) + " of " + who + " is on none of its triangles");
    return local_v[v];
  };
  split::Decomposition& s = r.decomposition;
  split::Layout& R = s.layout;
  for (int v : r.layout_vertex) R.points.push_back(L.points[v]);
  for (std::size_t i = 0; i < r.layout_triangle.size(); ++i) {
    const int x = r.layout_triangle[i];
    if (rev[i] && !L.filled[x])
      throw core::TopologyError("polycube: the surface of " + who + " is not one consistently oriented piece (triangle " + std::to_string(x) + ")");
    auto tr = L.triangles[x];
    if (rev[i]) std::swap(tr[1], tr[2]);
    R.triangles.push_back({local_v[tr[0]], local_v[tr[1]], local_v[tr[2]]});
    R.filled.push_back(L.filled[x]);
    local_t[x] = static_cast<int>(i);
  }
  auto map_sides = [&](auto& x) {
    for (int& v : x.corners) v = vmap(v);
    for (auto& side : x.sides)
      for (int& v : side) v = vmap(v);
  };
  std::map<int, int> local_p, local_f;
  for (int p : patch_set) {
    split::Patch P = L.patches[p];
    for (int& x : P.triangles) x = local_t[x];
    std::sort(P.triangles.begin(), P.triangles.end());
    map_sides(P);
    local_p[p] = static_cast<int>(R.patches.size());
    R.patches.push_back(std::move(P));
  }
  for (int f : face_set) {
    split::InternalFace F = L.internal_faces.at(f);
    map_sides(F);
    for (int& v : F.loop) v = vmap(v);
    local_f[f] = static_cast<int>(R.internal_faces.size());
    R.internal_faces.push_back(std::move(F));
  }
  std::map<int, int> local_c;
  for (int c : torus.components) {
    split::Component C = d.components[c];
    for (int& p : C.patches) p = local_p.at(p);
    for (auto& f : C.faces) {
      for (int& p : f.patches) p = local_p.at(p);
      if (f.internal_face >= 0) f.internal_face = local_f.at(f.internal_face);
      for (int& v : f.corners) v = vmap(v);
    }
    const bool is_torus = C.type == split::ComponentType::torus_cube;
    C.torus = is_torus ? 0 : -1;
    local_c[c] = static_cast<int>(s.components.size());
    s.components.push_back(std::move(C));
  }
  split::Torus T;
  for (int c : torus.components) T.components.push_back(local_c.at(c));
  for (int f : torus.cross_sections) T.cross_sections.push_back(local_f.at(f));
  if (!T.cross_sections.empty()) s.tori = {T};
  for (const auto& c : d.contacts)
    if (c.via == "internal_face" && local_c.count(c.a) && local_c.count(c.b))
      s.contacts.push_back({local_c.at(c.a), local_c.at(c.b), c.via, local_f.at(c.index)});
  s.quad_patches = static_cast<int>(R.patches.size());
  s.genus = s.tori.empty() ? 0 : 1;
  // Closed and manifold, else no volume map.
  surface::Mesh m;
  try {
    m = split::layout_mesh(R, true);
  } catch (const core::InvalidInputError& e) {
    throw core::TopologyError("polycube: the surface of " + who + " is not manifold (" + e.what() + ")");
  }
  for (auto h : m.halfedges())
    if (m.is_border(h))
      throw core::TopologyError("polycube: the surface of " + who + " is not closed (open at layout vertex " +
                                std::to_string(r.layout_vertex[static_cast<int>(m.target(h))]) + ")");
  return r;
}

// The checks rings() and connector() share: two tori whose components are torus cubes of theirs,
// and either one filled disk between them or one connector cube (a cube component) with a filled
// disk to each. Returns the connector's component, or -1.
int check_two_tori(const split::Decomposition& d) {
  const std::string unsupported = "; only one torus, two tori meeting on one filled disk, or two tori joined by a connector cube can be mapped";
  if (d.tori.size() != 2)
    throw core::TopologyError("polycube: " + std::to_string(d.tori.size()) + " tori (" + describe_tori(d) + ")" + unsupported);
  const int n = static_cast<int>(d.components.size());
  std::vector<int> torus_of(n, -1);
  for (int t = 0; t < 2; ++t)
    for (int c : d.tori[t].components) {
      if (c < 0 || c >= n) throw core::TopologyError("polycube: torus " + std::to_string(t) + " lists component " + std::to_string(c) + ", out of range");
      if (torus_of[c] >= 0) throw core::TopologyError("polycube: component " + std::to_string(c) + " is in tori " + std::to_string(torus_of[c]) + " and " + std::to_string(t));
      torus_of[c] = t;
    }
  int connector = -1;
  for (int c = 0; c < n; ++c) {
    if (torus_of[c] >= 0 && d.components[c].type == split::ComponentType::torus_cube) continue;
    if (torus_of[c] < 0 && d.components[c].type == split::ComponentType::cube && connector < 0) {
      connector = c;
      torus_of[c] = 2;
      continue;
    }
    throw core::TopologyError("polycube: component " + std::to_string(c) + " (" + split::to_string(d.components[c].type) +
                              ") is neither a cube of either torus nor the one connector cube (" + describe_tori(d) + ")" + unsupported);
  }
  std::array<int, 3> disks{0, 0, 0};  // per torus: its disks; [2]: between the tori
  for (const auto& c : d.contacts) {
    if (c.a < 0 || c.a >= n || c.b < 0 || c.b >= n)
      throw core::TopologyError("polycube: a contact names component " + std::to_string(std::max(c.a, c.b)) + ", out of range");
    auto label = [&](int x) { return std::to_string(x) + (torus_of[x] == 2 ? " (connector)" : " (torus " + std::to_string(torus_of[x]) + ")"); };
    const std::string pair = "components " + label(c.a) + " and " + label(c.b) + " meet via " + c.via + " " + std::to_string(c.index);
    if (torus_of[c.a] == torus_of[c.b]) {
      if (c.via != "internal_face" || torus_of[c.a] == 2) throw core::TopologyError("polycube: " + pair + ", not a cross section of their torus");
    } else {
      if (c.via != "filled_patch") throw core::TopologyError("polycube: " + pair + unsupported);
      const int ta = torus_of[c.a], tb = torus_of[c.b];
      if (ta == 2 || tb == 2) ++disks[ta == 2 ? tb : ta];
      else ++disks[2];
    }
  }
  if (connector >= 0 && disks != std::array<int, 3>{1, 1, 0})
    throw core::TopologyError("polycube: component " + std::to_string(connector) + " (cube) is not a cube of either torus, nor a connector "
                              "joined to each torus by one filled disk (it meets torus 0 on " + std::to_string(disks[0]) + ", torus 1 on " +
                              std::to_string(disks[1]) + "; the tori meet on " + std::to_string(disks[2]) + "; " + describe_tori(d) + ")" + unsupported);
  if (connector < 0 && disks[2] != 1)
    throw core::TopologyError("polycube: the tori meet on " + std::to_string(disks[2]) + " filled disks (" + describe_tori(d) + ")" + unsupported);
  return connector;
}

}  // namespace

std::vector<Ring> rings(const split::Decomposition& d) {
  const int connector = check_two_tori(d);
  std::vector<Ring> r;
  for (int t = 0; t < 2; ++t) {
    const split::Torus& torus = d.tori[static_cast<std::size_t>(t)];
    r.push_back(make_piece(d, torus, "torus " + std::to_string(t) + " (components " + join(torus.components) + ")"));
  }
  // Every fill triangle closes both tori (the disk lies in one patch of each), or (a connector)
  // exactly one of them.
  for (std::size_t x = 0; x < d.layout.triangles.size(); ++x) {
    if (!d.layout.filled[x]) continue;
    int in = 0;
    for (int t = 0; t < 2; ++t)
      in += std::find(r[t].layout_triangle.begin(), r[t].layout_triangle.end(), static_cast<int>(x)) != r[t].layout_triangle.end();
    if (in != (connector < 0 ? 2 : 1))
      throw core::TopologyError("polycube: fill triangle " + std::to_string(x) + " closes " + std::to_string(in) + " of the two tori (" +
                                describe_tori(d) + "): " + (connector < 0 ? "the tori do not meet on one filled disk" : "each disk must close one torus"));
  }
  return r;
}

std::optional<Ring> connector(const split::Decomposition& d) {
  const int c = check_two_tori(d);
  if (c < 0) return std::nullopt;
  split::Torus one;
  one.components = {c};
  Ring r = make_piece(d, one, "connector (component " + std::to_string(c) + ")");
  if (r.decomposition.components[0].faces.size() != 6)
    throw core::TopologyError("polycube: the connector (component " + std::to_string(c) + ") does not have six faces");
  return r;
}

TorusOnCube torus_on_cube(const split::Decomposition& d) {
  const split::Layout& L = d.layout;
  const int n = static_cast<int>(d.components.size());
  const std::string unsupported = "; a torus standing on a cube minus holes is one torus, one cube, its virtual components and one filled patch between the torus and the cube";
  if (d.tori.size() != 1) throw core::TopologyError("polycube: " + std::to_string(d.tori.size()) + " tori (" + describe_tori(d) + ")" + unsupported);
  std::vector<int> in_torus(static_cast<std::size_t>(n), 0), kept;
  for (int c : d.tori[0].components) {
    if (c < 0 || c >= n || d.components[c].type != split::ComponentType::torus_cube)
      throw core::TopologyError("polycube: torus 0 lists component " + std::to_string(c) + ", which is not a torus cube" + unsupported);
    in_torus[c] = 1;
  }
  int cubes = 0;
  for (int c = 0; c < n; ++c)
    if (!in_torus[c]) {
      if (d.components[c].type == split::ComponentType::torus_cube)
        throw core::TopologyError("polycube: component " + std::to_string(c) + " is a torus cube in no torus" + unsupported);
      cubes += d.components[c].type == split::ComponentType::cube;
      kept.push_back(c);
    }
  if (cubes != 1 || kept.size() < 2)
    throw core::TopologyError("polycube: components " + join(kept) + " besides the torus (" + describe_tori(d) + ")" + unsupported);
  TorusOnCube r;
  int foot = -1;
  for (const auto& x : d.contacts) {
    if (x.via != "filled_patch" || in_torus[x.a] == in_torus[x.b]) continue;
    if (foot >= 0) throw core::TopologyError("polycube: the torus meets the cube on filled patches " + std::to_string(foot) + " and " + std::to_string(x.index) + unsupported);
    foot = x.index, r.foot_component = in_torus[x.a] ? x.a : x.b;
    if (d.components[in_torus[x.a] ? x.b : x.a].type != split::ComponentType::cube)
      throw core::TopologyError("polycube: the torus meets virtual component " + std::to_string(in_torus[x.a] ? x.b : x.a) + unsupported);
  }
  if (foot < 0 || foot >= static_cast<int>(L.patches.size())) throw core::TopologyError("polycube: the torus does not meet the cube on a filled patch" + unsupported);
  const auto& ring_patches = d.components[r.foot_component].patches;
  if (std::find(ring_patches.begin(), ring_patches.end(), foot) == ring_patches.end())
    throw core::TopologyError("polycube: the foot (patch " + std::to_string(foot) + ") is not a whole patch of component " + std::to_string(r.foot_component));
  r.ring = make_piece(d, d.tori[0], "the torus (components " + join(d.tori[0].components) + ")");

  // The base: its components' patches, then the foot; the foot's triangles close its solid.
  Ring& b = r.base;
  b.component = kept;
  std::vector<int> patches;
  for (int c : kept) patches.insert(patches.end(), d.components[c].patches.begin(), d.components[c].patches.end());
  std::sort(patches.begin(), patches.end());
  patches.push_back(foot);
  std::vector<int> local_t(L.triangles.size(), -1), local_v(L.points.size(), -1);
  for (int p : patches)
    for (int x : L.patches[p].triangles) local_t[x] = 0;
  for (std::size_t x = 0; x < local_t.size(); ++x)
    if (local_t[x] == 0) local_t[x] = static_cast<int>(b.layout_triangle.size()), b.layout_triangle.push_back(static_cast<int>(x));
  for (int x : b.layout_triangle)
    for (int v : L.triangles[x]) local_v[v] = 0;
  for (std::size_t v = 0; v < local_v.size(); ++v)
    if (local_v[v] == 0) local_v[v] = static_cast<int>(b.layout_vertex.size()), b.layout_vertex.push_back(static_cast<int>(v));
  const std::set<int> foot_tris(L.patches[foot].triangles.begin(), L.patches[foot].triangles.end());
  split::Decomposition& s = b.decomposition;
  split::Layout& B = s.layout;
  for (int v : b.layout_vertex) B.points.push_back(L.points[v]);
  for (int x : b.layout_triangle) {
    const auto& t = L.triangles[x];
    B.triangles.push_back({local_v[t[0]], local_v[t[1]], local_v[t[2]]});
    B.filled.push_back(L.filled[x] && !foot_tris.count(x) ? 1 : 0);
  }
  std::map<int, int> local_p, local_c;
  for (int p : patches) {
    split::Patch P = L.patches[p];
    for (int& x : P.triangles) x = local_t[x];
    for (int& v : P.corners) v = local_v[v];
    for (auto& side : P.sides)
      for (int& v : side) v = local_v[v];
    local_p[p] = static_cast<int>(B.patches.size());
    B.patches.push_back(std::move(P));
  }
  r.foot_patch = local_p.at(foot);
  for (int c : kept) {
    split::Component C = d.components[c];
    for (int& p : C.patches) p = local_p.at(p);
    for (auto& f : C.faces) {
      for (int& p : f.patches) p = local_p.at(p);
      for (int& v : f.corners) v = local_v[v];
    }
    local_c[c] = static_cast<int>(s.components.size());
    s.components.push_back(std::move(C));
  }
  for (const auto& x : d.contacts)
    if (local_c.count(x.a) && local_c.count(x.b)) s.contacts.push_back({local_c.at(x.a), local_c.at(x.b), x.via, local_p.at(x.index)});
  s.genus = static_cast<int>(kept.size()) - 1;
  s.quad_patches = static_cast<int>(B.patches.size());
  surface::Mesh solid;
  try {
    solid = split::layout_mesh(B, false);  // the holes' fills left out
  } catch (const core::InvalidInputError& e) {
    throw core::TopologyError("polycube: the base (components " + join(kept) + ") closed by the foot is not manifold (" + e.what() + ")");
  }
  for (auto h : solid.halfedges())
    if (solid.is_border(h))
      throw core::TopologyError("polycube: the base (components " + join(kept) + ") closed by the foot is not closed (open at layout vertex " +
                                std::to_string(b.layout_vertex[static_cast<int>(solid.target(h))]) + ")");
  return r;
}

volmap::VolumeMap torus_volume_map(const split::Decomposition& d, const TorusSurfaceMap& m, const Params& params) {
  volmap::Params vp;
  vp.tetgen.max_volume_rel = params.tet_max_volume_rel;
  vp.smooth_sweeps = params.smooth_sweeps;
  vp.smooth_below_ratio = params.smooth_below_ratio;
  return volmap::harmonic_volume_map(split::layout_mesh(d.layout, true), m.embedding.points, vp);
}

core::Json to_json(const Ring& r, const TorusSurfaceMap& m, const volmap::VolumeMap& vm) {
  return core::Json{{"components", r.component},
                    {"layout_vertex", r.layout_vertex},
                    {"layout_triangle", r.layout_triangle},
                    {"polycube", to_json(m)},
                    {"volume_map", volmap::to_json(vm)}};
}

void write_rings_vtp(const std::string& path, const std::vector<Ring>& rings, const std::vector<TorusSurfaceMap>& maps, bool mapped) {
  if (rings.size() != maps.size()) throw std::logic_error("polycube: write_rings_vtp needs one map per ring");
  viz::PolyData all;
  all.point_fields = {{mapped ? "xyz" : "uvw", 3, {}}};
  all.cell_fields = {{"component_id", 1, {}}, {"filled", 1, {}}, {"ring", 1, {}}};
  for (std::size_t i = 0; i < rings.size(); ++i) {
    const viz::PolyData v = torus_polydata(rings[i].decomposition, maps[i], mapped, {kRingSpacing * static_cast<double>(i), 0, 0});
    const int offset = static_cast<int>(all.points.size());
    all.points.insert(all.points.end(), v.points.begin(), v.points.end());
    auto& pf = all.point_fields[0].values;
    pf.insert(pf.end(), v.point_fields[0].values.begin(), v.point_fields[0].values.end());
    for (std::size_t c = 0; c < v.polys.size(); ++c) {
      std::vector<int> poly = v.polys[c];
      for (int& x : poly) x += offset;
      all.polys.push_back(std::move(poly));
      const int local = static_cast<int>(v.cell_fields[0].values[c]);
      all.cell_fields[0].values.push_back(local < 0 ? -1 : rings[i].component[local]);
      all.cell_fields[1].values.push_back(v.cell_fields[1].values[c]);
      all.cell_fields[2].values.push_back(static_cast<double>(i));
    }
  }
  viz::write_vtp(path, all);
}

}  // namespace volts::polycube
