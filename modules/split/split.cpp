#include "split/split.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include "core/errors.h"
#include "core/log.h"
#include "split/split_internal.h"
#include "surface/mesh_json.h"
#include "viz/viz.h"

namespace volts::split {

const char* to_string(ComponentType type) {
  switch (type) {
    case ComponentType::cube: return "cube";
    case ComponentType::torus_cube: return "torus_cube";
    case ComponentType::virtual_component: return "virtual";
  }
  return "?";
}

std::vector<int> patch_corner_counts(const classify::Classification& c) {
  // Curve ends are corners; a patch's corners are the ends of the curves on its boundary.
  std::vector<std::set<int>> corners(c.patches);
  for (const auto& k : c.curves) {
    if (k.closed) continue;
    for (int p : {k.patch_left, k.patch_right}) {
      corners[p].insert(k.vertices.front());
      corners[p].insert(k.vertices.back());
    }
  }
  std::vector<int> n(c.patches);
  for (int p = 0; p < c.patches; ++p) n[p] = static_cast<int>(corners[p].size());
  return n;
}

namespace detail {

std::set<Edge> sharp_edges(const classify::Classification& c) {
  std::set<Edge> s;
  for (const auto& k : c.curves) {
    const std::size_t n = k.vertices.size();
    for (std::size_t i = 0; i + (k.closed ? 0 : 1) < n; ++i) s.insert(edge(k.vertices[i], k.vertices[(i + 1) % n]));
  }
  return s;
}

int nearest_vertex(const surface::Mesh& mesh, const std::array<double, 3>& p) {
  int best = -1;
  double bd = std::numeric_limits<double>::infinity();
  for (auto v : mesh.vertices()) {
    const auto& q = mesh.point(v);
    const double d = (q.x() - p[0]) * (q.x() - p[0]) + (q.y() - p[1]) * (q.y() - p[1]) + (q.z() - p[2]) * (q.z() - p[2]);
    if (d < bd) bd = d, best = static_cast<int>(v);
  }
  if (best < 0 || !std::isfinite(bd)) throw core::ConfigError("split: a point given in the config is not finite");
  return best;
}

Decomposition split_box(const surface::Mesh& mesh, const classify::Classification& c, ComponentType type) {
  std::vector<int> curves_of_patch(c.patches, 0);
  bool closed_curve = false;
  for (const auto& k : c.curves) {
    closed_curve |= k.closed;
    if (k.patch_left == k.patch_right)
      throw core::TopologyError("split: curve inside a single patch (a dangling sharp curve); raise classify.sharp_angle_deg or fix the model");
    ++curves_of_patch[k.patch_left];
    ++curves_of_patch[k.patch_right];
  }
  const auto corners_of_patch = patch_corner_counts(c);
  int quads = 0;
  for (int p = 0; p < c.patches; ++p) quads += (curves_of_patch[p] == 4 && corners_of_patch[p] == 4);
  const bool box_like = c.genus == 0 && c.patches == 6 && c.curves.size() == 12 && c.corners.size() == 8 && !closed_curve && quads == 6;
  if (!box_like) {
    std::ostringstream s;
    s << "split: the genus-" << c.genus << " surface is not box-like (" << c.patches << " patches, " << c.curves.size()
      << " curves, " << c.corners.size() << " corners, " << quads
      << " quad patches); a genus-0 surface must have sharp curves that bound six quad patches like a cube — the "
         "automatic six-patch segmentation of smooth genus-0 surfaces is not implemented; set `route: tet` to mesh it";
    throw core::TopologyError(s.str());
  }
  Decomposition d;
  d.genus = 0;
  detail::copy_mesh(mesh, d.layout);
  std::vector<int> face_region;
  const auto regs = detail::regions(mesh, detail::sharp_edges(c), &face_region);
  std::vector<char> is_corner(mesh.number_of_vertices(), 0);
  for (int v : c.corners) is_corner[v] = 1;
  std::vector<int> region_of_patch(c.patches, -1);
  for (std::size_t f = 0; f < c.face_patch.size(); ++f) region_of_patch[c.face_patch[f]] = face_region[f];
  Component cube;
  cube.type = type;
  for (int p = 0; p < c.patches; ++p) {
    d.layout.patches.push_back(detail::quad_patch(regs.at(region_of_patch[p]), is_corner, "patch", p));
    cube.patches.push_back(p);
    CubeFace face;
    face.patches = {p};
    face.corners = d.layout.patches.back().corners;
    cube.faces.push_back(face);
  }
  d.components.push_back(cube);
  d.quad_patches = quads;
  return d;
}

}  // namespace detail

Decomposition split(const surface::Mesh& mesh, const classify::Classification& c, const Params& params) {
  if (params.hole != "auto" && params.hole != "torus" && params.hole != "difference")
    throw core::ConfigError("split.hole must be 'auto', 'torus' or 'difference', not '" + params.hole + "'");
  if (c.genus == 0) return detail::split_box(mesh, c, ComponentType::cube);
  if (c.genus == 1) {
    const bool corners = !c.corners.empty();
    const bool difference = params.hole == "difference" || (params.hole == "auto" && corners);
    if (difference) {
      if (c.difference_curves() == 0)
        throw core::TopologyError("split: split.hole asks for a difference but the genus-1 surface has no difference curves (rims of a hole in a patch)");
      return detail::split_difference(mesh, c, params);
    }
    if (corners)
      throw core::TopologyError("split: split.hole is 'torus' but the surface has " + std::to_string(c.corners.size()) +
                                " sharp corners; a torus ring cannot keep them — use split.hole: auto (difference)");
    Decomposition d = detail::split_torus(mesh, detail::sharp_edges(c), params);
    return d;
  }
  // Several through holes, each bounded by two difference curves (a plate with bolt holes, the
  // assembly's base): one cube minus a virtual component per hole, as for one.
  // With one rim more than the holes' (an odd count): a torus standing on such a cube, the rim
  // its foot (the assembly: the union of a difference and a torus).
  if (c.genus >= 2 && !c.corners.empty() && params.hole != "torus" && c.difference_curves() > 0) {
    const int rims = static_cast<int>(detail::difference_rims(c).size());
    if (rims == 2 * c.genus) return detail::split_difference(mesh, c, params);
    if (rims == 2 * c.genus - 1) return detail::split_torus_on_cube(mesh, c, params);
  }
  if (c.genus == 2) {
    if (params.genus2 != "auto") return detail::split_two_tori(mesh, params, &c);
    Params p = params;
    p.genus2 = "connector";
    // The connector at split.connector_cut, then with its ends near the holes (a shank that runs
    // almost to its eyes, the rod: at 0.5 its rings' cross sections cross its sharp curves twice).
    std::vector<double> cuts{params.connector_cut};
    if (params.connector_cut < auto_connector_cut) cuts.push_back(auto_connector_cut);
    std::string why;
    for (const double cut : cuts) {
      p.connector_cut = cut;
      try {
        if (cut != params.connector_cut) core::log("split: a connector with its ends " + std::to_string(cut) + " of the way to the holes");
        return detail::split_two_tori(mesh, p, &c);
      } catch (const core::TopologyError& e) {
        why += (why.empty() ? "" : "; ") + ("at connector_cut " + std::to_string(cut) + ": " + e.what());
      }
    }
    core::log_warning("split: no connector cube between the two tori (" + why +
                      "); they meet on the waist's disk instead, which is not a conforming interface (split.genus2: disk). "
                      "Other cuts may let the neck be cut: split.connector_cut");
    p.connector_cut = params.connector_cut;
    p.genus2 = "disk";
    return detail::split_two_tori(mesh, p, &c);
  }
  std::ostringstream s;
  s << "split: genus " << c.genus << " (" << c.patches << " patches, " << c.curves.size() << " curves, " << c.corners.size()
    << " corners) is not implemented yet: only genus 0 (a cube), genus 1 (a torus, or a cube minus a through hole), genus 2 "
       "(two tori), a cube minus through holes bounded by difference curves and a torus standing on such a cube are; "
       "set `route: tet` to mesh it";
  throw core::TopologyError(s.str());
}

surface::Mesh layout_mesh(const Layout& layout, bool with_filled) {
  surface::Mesh m;
  for (const auto& p : layout.points) m.add_vertex(surface::Point(p[0], p[1], p[2]));
  for (std::size_t t = 0; t < layout.triangles.size(); ++t) {
    if (layout.filled[t] && !with_filled) continue;
    const auto& tr = layout.triangles[t];
    using VI = surface::Mesh::Vertex_index;
    if (m.add_face(VI(tr[0]), VI(tr[1]), VI(tr[2])) == surface::Mesh::null_face())
      throw core::InvalidInputError("split layout: triangle " + std::to_string(t) + " is not manifold");
  }
  return m;
}

namespace {

core::Json sides_json(const std::array<std::vector<int>, 4>& s) { return core::Json::array({s[0], s[1], s[2], s[3]}); }

template <class T>
void read_sides(const core::Json& j, T& x, const std::string& file) {
  x.corners = core::require(j, "corners", file).get<std::array<int, 4>>();
  const auto& s = core::require(j, "sides", file);
  if (!s.is_array() || s.size() != 4) throw core::InvalidInputError(file + ": a patch or internal face needs 4 sides");
  for (int k = 0; k < 4; ++k) x.sides[k] = s[k].get<std::vector<int>>();
}

ComponentType parse_type(const std::string& t, const std::string& file) {
  if (t == "cube") return ComponentType::cube;
  if (t == "torus_cube") return ComponentType::torus_cube;
  if (t == "virtual") return ComponentType::virtual_component;
  throw core::InvalidInputError(file + ": unknown component type '" + t + "'");
}

}  // namespace

core::Json to_json(const Decomposition& d) {
  const Layout& L = d.layout;
  std::vector<double> pts;
  for (const auto& p : L.points) pts.insert(pts.end(), p.begin(), p.end());
  std::vector<int> tris;
  for (const auto& t : L.triangles) tris.insert(tris.end(), t.begin(), t.end());
  std::vector<int> filled(L.filled.begin(), L.filled.end());
  core::Json patches = core::Json::array(), internal = core::Json::array(), comps = core::Json::array(), tori = core::Json::array(),
             contacts = core::Json::array();
  for (const auto& p : L.patches) patches.push_back({{"triangles", p.triangles}, {"corners", p.corners}, {"sides", sides_json(p.sides)}});
  for (const auto& f : L.internal_faces) internal.push_back({{"corners", f.corners}, {"sides", sides_json(f.sides)}, {"loop", f.loop}});
  for (const auto& k : d.components) {
    core::Json faces = core::Json::array();
    for (const auto& f : k.faces) faces.push_back({{"patches", f.patches}, {"internal_face", f.internal_face}, {"corners", f.corners}});
    comps.push_back({{"type", to_string(k.type)}, {"patches", k.patches}, {"faces", faces}, {"torus", k.torus}});
  }
  for (const auto& t : d.tori) tori.push_back({{"components", t.components}, {"cross_sections", t.cross_sections}});
  for (const auto& c : d.contacts) contacts.push_back({{"a", c.a}, {"b", c.b}, {"via", c.via}, {"index", c.index}});
  return core::Json{{"layout", {{"points", pts}, {"triangles", tris}, {"filled", filled}, {"patches", patches}, {"internal_faces", internal}}},
                    {"components", comps},
                    {"tori", tori},
                    {"contacts", contacts},
                    {"quad_patches", d.quad_patches},
                    {"genus", d.genus},
                    {"critical_points", {{"min", d.critical_min}, {"max", d.critical_max}, {"saddle", d.critical_saddle}}},
                    {"cross_section_lines", d.cross_section_lines},
                    {"longitude_lines", d.longitude_lines}};
}

Decomposition from_json(const core::Json& j, const std::string& file) {
  Decomposition d;
  try {
    const auto& lj = core::require(j, "layout", file);
    const auto pts = core::require(lj, "points", file).get<std::vector<double>>();
    const auto tris = core::require(lj, "triangles", file).get<std::vector<int>>();
    const auto filled = core::require(lj, "filled", file).get<std::vector<int>>();
    if (pts.size() % 3 || tris.size() % 3 || filled.size() * 3 != tris.size())
      throw core::InvalidInputError(file + ": decomposition layout arrays have inconsistent sizes");
    for (std::size_t i = 0; i < pts.size(); i += 3) d.layout.points.push_back({pts[i], pts[i + 1], pts[i + 2]});
    const int np = static_cast<int>(d.layout.points.size());
    auto check_vertex = [&](int v) {
      if (v < 0 || v >= np) throw core::InvalidInputError(file + ": decomposition refers to vertex " + std::to_string(v) + " of " + std::to_string(np));
    };
    for (std::size_t i = 0; i < tris.size(); i += 3) {
      for (int k = 0; k < 3; ++k) check_vertex(tris[i + k]);
      d.layout.triangles.push_back({tris[i], tris[i + 1], tris[i + 2]});
    }
    for (int f : filled) d.layout.filled.push_back(f ? 1 : 0);
    const int nt = static_cast<int>(d.layout.triangles.size());
    for (const auto& pj : core::require(lj, "patches", file)) {
      Patch p;
      p.triangles = core::require(pj, "triangles", file).get<std::vector<int>>();
      if (p.triangles.empty()) throw core::InvalidInputError(file + ": a patch has no triangles");
      for (int t : p.triangles)
        if (t < 0 || t >= nt) throw core::InvalidInputError(file + ": a patch refers to triangle " + std::to_string(t) + " of " + std::to_string(nt));
      read_sides(pj, p, file);
      for (int v : p.corners) check_vertex(v);
      for (const auto& s : p.sides)
        for (int v : s) check_vertex(v);
      d.layout.patches.push_back(std::move(p));
    }
    for (const auto& fj : core::require(lj, "internal_faces", file)) {
      InternalFace f;
      read_sides(fj, f, file);
      f.loop = core::require(fj, "loop", file).get<std::vector<int>>();
      for (int v : f.loop) check_vertex(v);
      for (int v : f.corners) check_vertex(v);
      for (const auto& s : f.sides)
        for (int v : s) check_vertex(v);
      d.layout.internal_faces.push_back(std::move(f));
    }
    const int npatch = static_cast<int>(d.layout.patches.size()), nint = static_cast<int>(d.layout.internal_faces.size());
    for (const auto& k : core::require(j, "components", file)) {
      Component c;
      c.type = parse_type(core::require(k, "type", file).get<std::string>(), file);
      c.patches = core::require(k, "patches", file).get<std::vector<int>>();
      for (int p : c.patches)
        if (p < 0 || p >= npatch) throw core::InvalidInputError(file + ": a component refers to patch " + std::to_string(p) + " of " + std::to_string(npatch));
      c.torus = core::require(k, "torus", file).get<int>();
      for (const auto& fj : core::require(k, "faces", file)) {
        CubeFace f;
        f.patches = core::require(fj, "patches", file).get<std::vector<int>>();
        f.internal_face = core::require(fj, "internal_face", file).get<int>();
        f.corners = core::require(fj, "corners", file).get<std::array<int, 4>>();
        if (f.internal_face >= nint) throw core::InvalidInputError(file + ": a component face refers to internal face " + std::to_string(f.internal_face));
        for (int p : f.patches)
          if (p < 0 || p >= npatch) throw core::InvalidInputError(file + ": a component face refers to patch " + std::to_string(p) + " of " + std::to_string(npatch));
        for (int v : f.corners) check_vertex(v);
        c.faces.push_back(std::move(f));
      }
      d.components.push_back(std::move(c));
    }
    for (const auto& t : core::require(j, "tori", file))
      d.tori.push_back({core::require(t, "components", file).get<std::vector<int>>(), core::require(t, "cross_sections", file).get<std::vector<int>>()});
    for (const auto& c : core::require(j, "contacts", file))
      d.contacts.push_back({core::require(c, "a", file).get<int>(), core::require(c, "b", file).get<int>(),
                            core::require(c, "via", file).get<std::string>(), core::require(c, "index", file).get<int>()});
    d.quad_patches = core::require(j, "quad_patches", file).get<int>();
    d.genus = core::require(j, "genus", file).get<int>();
    const auto& cp = core::require(j, "critical_points", file);
    d.critical_min = core::require(cp, "min", file).get<int>();
    d.critical_max = core::require(cp, "max", file).get<int>();
    d.critical_saddle = core::require(cp, "saddle", file).get<int>();
    d.cross_section_lines = core::require(j, "cross_section_lines", file).get<std::vector<std::vector<int>>>();
    d.longitude_lines = core::require(j, "longitude_lines", file).get<std::vector<std::vector<int>>>();
  } catch (const core::Json::exception& e) {
    throw core::InvalidInputError(file + ": malformed decomposition: " + e.what());
  }
  return d;
}

core::Json report_figures(const Decomposition& d) {
  core::Json comps = core::Json::array();
  for (const auto& k : d.components)
    comps.push_back({{"type", to_string(k.type)}, {"faces", k.faces.size()}, {"patches", k.patches.size()}});
  core::Json j{{"genus", d.genus},
                    {"critical_points", {{"min", d.critical_min}, {"max", d.critical_max}, {"saddle", d.critical_saddle}}},
                    {"components", comps},
                    {"tori", d.tori.size()},
                    {"quad_patches", d.quad_patches},
                    {"filled_triangles", std::count(d.layout.filled.begin(), d.layout.filled.end(), 1)}};
  if (!d.genus2.empty()) j["genus2"] = d.genus2;
  j["planar_fills"] = d.planar_fills;
  return j;
}

void write_vtp(const std::string& path, const Decomposition& d) {
  const Layout& L = d.layout;
  std::vector<int> tri_patch(L.triangles.size(), -1), tri_comp(L.triangles.size(), -1);
  for (std::size_t c = 0; c < d.components.size(); ++c)
    for (int p : d.components[c].patches)
      for (int t : L.patches[p].triangles)
        if (tri_patch[t] < 0 || d.components[c].type != ComponentType::virtual_component)
          tri_patch[t] = p, tri_comp[t] = static_cast<int>(c);
  viz::PolyData v;
  v.points = L.points;
  viz::Field patch{"patch_id", 1, {}}, comp{"component_id", 1, {}}, filled{"filled", 1, {}}, kind{"line_kind", 1, {}};
  auto add_line = [&](std::vector<int> line, bool closed, int k) {
    if (closed && !line.empty()) line.push_back(line.front());
    v.lines.push_back(std::move(line));
    patch.values.push_back(-1), comp.values.push_back(-1), filled.values.push_back(0), kind.values.push_back(k);
  };
  // line_kind: 1 cross section, 2 longitudinal line, 3 patch side.
  for (const auto& l : d.cross_section_lines) add_line(l, true, 1);
  for (const auto& l : d.longitude_lines) add_line(l, true, 2);
  for (const auto& p : L.patches)
    for (const auto& s : p.sides) add_line(s, false, 3);
  for (std::size_t t = 0; t < L.triangles.size(); ++t) {
    v.polys.push_back({L.triangles[t][0], L.triangles[t][1], L.triangles[t][2]});
    patch.values.push_back(tri_patch[t]), comp.values.push_back(tri_comp[t]), filled.values.push_back(L.filled[t]), kind.values.push_back(0);
  }
  v.cell_fields = {patch, comp, filled, kind};
  for (const auto& [name, f] : {std::pair{"harmonic_field", &d.field}, {"ring_field", &d.ring_field}, {"tube_field", &d.tube_field}})
    if (f->size() == L.points.size()) v.point_fields.push_back({name, 1, *f});
  viz::write_vtp(path, v);
}

}  // namespace volts::split
