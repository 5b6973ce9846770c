#include "split/split.h"

#include <algorithm>
#include <set>
#include <sstream>

#include "core/errors.h"
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

Decomposition split(const surface::Mesh& mesh, const classify::Classification& c, const Params&) {
  (void)mesh;
  std::vector<int> curves_of_patch(c.patches, 0);
  bool closed_curve = false;
  for (const auto& k : c.curves) {
    closed_curve |= k.closed;
    if (k.patch_left == k.patch_right) throw core::TopologyError("split: curve inside a single patch (a dangling sharp curve); raise classify.sharp_angle_deg or fix the model");
    ++curves_of_patch[k.patch_left];
    ++curves_of_patch[k.patch_right];
  }
  const auto corners_of_patch = patch_corner_counts(c);
  int quads = 0;
  for (int p = 0; p < c.patches; ++p) quads += (curves_of_patch[p] == 4 && corners_of_patch[p] == 4);

  const bool box_like = c.genus == 0 && c.patches == 6 && c.curves.size() == 12 && c.corners.size() == 8 &&
                        !closed_curve && quads == 6;
  if (!box_like) {
    std::ostringstream s;
    s << "split: the surface is not box-like (genus " << c.genus << ", " << c.patches << " patches, "
      << c.curves.size() << " curves, " << c.corners.size() << " corners, " << quads
      << " quad patches); only a genus-0 surface whose sharp curves bound six quad patches like a cube is "
         "supported yet — the harmonic-field split of tori and holes (Liu et al. §4.1) is not implemented "
         "(issue 5); to mesh it now, set `route: tet` in the config";
    throw core::TopologyError(s.str());
  }
  Decomposition d;
  Component cube;
  cube.type = ComponentType::cube;
  for (int p = 0; p < c.patches; ++p) cube.patches.push_back(p);
  d.components.push_back(cube);
  d.quad_patches = quads;
  return d;
}

core::Json to_json(const Decomposition& d) {
  core::Json comps = core::Json::array();
  for (const auto& k : d.components) comps.push_back({{"type", to_string(k.type)}, {"patches", k.patches}});
  return core::Json{{"components", comps}, {"quad_patches", d.quad_patches}};
}

Decomposition from_json(const core::Json& j, const std::string& file) {
  Decomposition d;
  try {
    d.quad_patches = core::require(j, "quad_patches", file).get<int>();
    for (const auto& k : core::require(j, "components", file)) {
      Component c;
      const std::string t = core::require(k, "type", file).get<std::string>();
      if (t == "cube") c.type = ComponentType::cube;
      else if (t == "torus_cube") c.type = ComponentType::torus_cube;
      else if (t == "virtual") c.type = ComponentType::virtual_component;
      else throw core::InvalidInputError(file + ": unknown component type '" + t + "'");
      c.patches = core::require(k, "patches", file).get<std::vector<int>>();
      d.components.push_back(std::move(c));
    }
  } catch (const core::Json::exception& e) {
    throw core::InvalidInputError(file + ": malformed decomposition: " + e.what());
  }
  return d;
}

core::Json report_figures(const Decomposition& d, const classify::Classification& c) {
  core::Json comps = core::Json::array();
  for (const auto& k : d.components) comps.push_back({{"type", to_string(k.type)}, {"patches", k.patches.size()}});
  return core::Json{{"genus", c.genus}, {"components", comps}, {"quad_patches", d.quad_patches}};
}

void write_vtp(const std::string& path, const surface::Mesh& mesh, const classify::Classification& c, const Decomposition& d) {
  std::vector<int> patch_component(c.patches, -1);
  for (std::size_t i = 0; i < d.components.size(); ++i)
    for (int p : d.components[i].patches) patch_component[p] = static_cast<int>(i);
  viz::PolyData v;
  v.points = surface::vertex_array(mesh);
  viz::Field patch{"patch_id", 1, {}}, comp{"component_id", 1, {}};
  for (const auto& k : c.curves) {
    auto line = k.vertices;
    if (k.closed) line.push_back(line.front());
    v.lines.push_back(line);
    patch.values.push_back(-1);
    comp.values.push_back(-1);
  }
  v.polys = surface::triangle_array(mesh);
  for (auto f : mesh.faces()) {
    patch.values.push_back(c.face_patch[f]);
    comp.values.push_back(patch_component[c.face_patch[f]]);
  }
  v.cell_fields = {patch, comp};
  viz::write_vtp(path, v);
}

}  // namespace volts::split
