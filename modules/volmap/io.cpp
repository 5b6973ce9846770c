// Files of the volume map: ParaView .vtu views and the stage-file JSON.
#include <cmath>
#include <string>

#include "core/errors.h"
#include "viz/viz.h"
#include "volmap/volmap.h"

namespace volts::volmap {
namespace {

viz::UnstructuredGrid grid(const VolumeMap& map, bool in_parameter_space, const std::vector<int>& component) {
  if (!component.empty() && component.size() != map.tets.size())
    throw core::InvalidInputError("volmap: component has " + std::to_string(component.size()) + " values for " +
                                  std::to_string(map.tets.size()) + " tets");
  viz::UnstructuredGrid g;
  const auto& at = in_parameter_space ? map.parameter : map.physical;
  const auto& other = in_parameter_space ? map.physical : map.parameter;
  viz::Field f{in_parameter_space ? "xyz" : "uvw", 3, {}};
  for (std::size_t i = 0; i < at.size(); ++i) {
    g.points.push_back({at[i][0], at[i][1], at[i][2]});
    f.values.insert(f.values.end(), {other[i][0], other[i][1], other[i][2]});
  }
  g.point_fields.push_back(std::move(f));
  double phys = 0;
  std::vector<double> pv(map.tets.size()), xv(map.tets.size());
  for (std::size_t t = 0; t < map.tets.size(); ++t) {
    const auto& c = map.tets[t];
    g.cells.push_back({c[0], c[1], c[2], c[3]});
    g.cell_types.push_back(10);  // VTK_TETRA
    pv[t] = parameter_volume(map, static_cast<int>(t));
    xv[t] = tetmesh::signed_volume6(map.physical[c[0]], map.physical[c[1]], map.physical[c[2]], map.physical[c[3]]) / 6;
    phys += xv[t];
  }
  viz::Field ratio{"volume_ratio", 1, {}}, flipped{"flipped", 1, {}};
  for (std::size_t t = 0; t < map.tets.size(); ++t) {
    ratio.values.push_back(pv[t] / xv[t] * phys / map.parameter_volume);
    flipped.values.push_back(pv[t] > 0 ? 0 : 1);
  }
  g.cell_fields.push_back(std::move(ratio));
  g.cell_fields.push_back(std::move(flipped));
  if (!component.empty()) g.cell_fields.push_back({"component", 1, std::vector<double>(component.begin(), component.end())});
  return g;
}

std::vector<double> flat(const std::vector<Eigen::Vector3d>& p) {
  std::vector<double> r;
  r.reserve(3 * p.size());
  for (const auto& x : p) r.insert(r.end(), {x[0], x[1], x[2]});
  return r;
}

std::vector<Eigen::Vector3d> points(const core::Json& j, const std::string& key, const std::string& file) {
  std::vector<double> v;
  try {
    v = core::require(j, key, file).get<std::vector<double>>();
  } catch (const nlohmann::json::exception&) {
    throw core::InvalidInputError(file + ": " + key + " must be an array of numbers");
  }
  if (v.size() % 3) throw core::InvalidInputError(file + ": " + key + " needs 3 values per point");
  std::vector<Eigen::Vector3d> r;
  for (std::size_t i = 0; i < v.size(); i += 3) {
    r.emplace_back(v[i], v[i + 1], v[i + 2]);
    if (!r.back().allFinite()) throw core::InvalidInputError(file + ": " + key + ": point " + std::to_string(i / 3) + " is not finite");
  }
  return r;
}

viz::UnstructuredGrid several(const std::vector<const VolumeMap*>& maps, const std::vector<std::array<double, 3>>& offsets,
                              bool in_parameter_space, const std::string& index_field) {
  if (offsets.size() != maps.size())
    throw core::InvalidInputError("volmap: " + std::to_string(offsets.size()) + " offsets for " + std::to_string(maps.size()) + " maps");
  viz::UnstructuredGrid all;
  viz::Field index{index_field, 1, {}};
  for (std::size_t i = 0; i < maps.size(); ++i) {
    viz::UnstructuredGrid g = grid(*maps[i], in_parameter_space, {});
    const auto& o = offsets[i];
    if (in_parameter_space) {
      for (auto& p : g.points)
        for (int k = 0; k < 3; ++k) p[k] += o[k];
    } else {
      auto& uvw = g.point_fields[0].values;
      for (std::size_t v = 0; v < uvw.size(); ++v) uvw[v] += o[v % 3];
    }
    const int offset = static_cast<int>(all.points.size());
    for (auto& c : g.cells)
      for (int& x : c) x += offset;
    all.points.insert(all.points.end(), g.points.begin(), g.points.end());
    all.cells.insert(all.cells.end(), g.cells.begin(), g.cells.end());
    all.cell_types.insert(all.cell_types.end(), g.cell_types.begin(), g.cell_types.end());
    if (i == 0) {
      all.point_fields = g.point_fields;
      all.cell_fields = g.cell_fields;
    } else {
      for (std::size_t f = 0; f < g.point_fields.size(); ++f)
        all.point_fields[f].values.insert(all.point_fields[f].values.end(), g.point_fields[f].values.begin(), g.point_fields[f].values.end());
      for (std::size_t f = 0; f < g.cell_fields.size(); ++f)
        all.cell_fields[f].values.insert(all.cell_fields[f].values.end(), g.cell_fields[f].values.begin(), g.cell_fields[f].values.end());
    }
    index.values.insert(index.values.end(), g.cells.size(), static_cast<double>(i));
  }
  all.cell_fields.push_back(std::move(index));
  return all;
}

}  // namespace

void write_vtu(const std::string& path, const std::vector<const VolumeMap*>& maps, const std::vector<std::array<double, 3>>& offsets,
               const std::string& index_field) {
  viz::write_vtu(path, several(maps, offsets, false, index_field));
}

void write_parameter_vtu(const std::string& path, const std::vector<const VolumeMap*>& maps,
                         const std::vector<std::array<double, 3>>& offsets, const std::string& index_field) {
  viz::write_vtu(path, several(maps, offsets, true, index_field));
}

void write_vtu(const std::string& path, const VolumeMap& map, const std::vector<int>& component) {
  viz::write_vtu(path, grid(map, false, component));
}

void write_parameter_vtu(const std::string& path, const VolumeMap& map, const std::vector<int>& component) {
  viz::write_vtu(path, grid(map, true, component));
}

core::Json report_figures(const VolumeMap& m) {
  return core::Json{{"points", m.physical.size()},
                    {"tets", m.tets.size()},
                    {"surface_vertices", m.surface_vertices},
                    {"split_edges", m.split_edges},
                    {"split_faces", m.split_faces},
                    {"collapsed_edges", m.collapsed_edges},
                    {"flips", m.flips},
                    {"flipped_tets_before_untangling", m.flipped_tets_before_untangling},
                    {"flipped_tets", m.flipped_tets},
                    {"untangle_sweeps", m.untangle_sweeps},
                    {"untangle_moves", m.untangle_moves},
                    {"untangle_joint", m.untangle_joint},
                    {"untangle_stop", m.untangle_stop},
                    {"min_volume_ratio", m.min_volume_ratio},
                    {"min_volume_ratio_before_smoothing", m.min_volume_ratio_before_smoothing},
                    {"smooth_sweeps", m.smooth_sweeps},
                    {"parameter_volume", m.parameter_volume}};
}

core::Json to_json(const VolumeMap& m) {
  std::vector<int> tets;
  tets.reserve(4 * m.tets.size());
  for (const auto& t : m.tets) tets.insert(tets.end(), t.begin(), t.end());
  core::Json j = report_figures(m);
  j.erase("points");
  j.erase("tets");
  j["physical"] = flat(m.physical);
  j["parameter"] = flat(m.parameter);
  j["tets"] = tets;
  return j;
}

VolumeMap from_json(const core::Json& j, const std::string& file) {
  VolumeMap m;
  const auto get_int = [&](const char* key) {
    const core::Json& v = core::require(j, key, file);
    if (!v.is_number_integer()) throw core::InvalidInputError(file + ": " + key + " must be an integer");
    try {
      return v.get<int>();
    } catch (const core::Json::exception&) {  // beyond int
      throw core::InvalidInputError(file + ": " + key + " is out of range");
    }
  };
  const auto get_double = [&](const char* key) {
    const core::Json& v = core::require(j, key, file);
    if (!v.is_number()) throw core::InvalidInputError(file + ": " + key + " must be a number");
    return v.get<double>();
  };
  m.physical = points(j, "physical", file);
  m.parameter = points(j, "parameter", file);
  if (m.parameter.size() != m.physical.size())
    throw core::InvalidInputError(file + ": parameter has " + std::to_string(m.parameter.size()) + " points, physical " +
                                  std::to_string(m.physical.size()));
  m.surface_vertices = get_int("surface_vertices");
  if (m.surface_vertices < 0 || m.surface_vertices > static_cast<int>(m.physical.size()))
    throw core::InvalidInputError(file + ": surface_vertices out of range");
  std::vector<int> t;
  try {
    t = core::require(j, "tets", file).get<std::vector<int>>();
  } catch (const nlohmann::json::exception&) {
    throw core::InvalidInputError(file + ": tets must be an array of integers");
  }
  if (t.size() % 4) throw core::InvalidInputError(file + ": tets needs 4 ids per tet");
  for (std::size_t i = 0; i < t.size(); i += 4) {
    std::array<int, 4> c{t[i], t[i + 1], t[i + 2], t[i + 3]};
    for (int v : c)
      if (v < 0 || v >= static_cast<int>(m.physical.size()))
        throw core::InvalidInputError(file + ": tets: tet " + std::to_string(i / 4) + " has vertex id " + std::to_string(v) + " out of range");
    m.tets.push_back(c);
  }
  m.split_edges = get_int("split_edges");
  m.split_faces = get_int("split_faces");
  if (j.contains("collapsed_edges")) m.collapsed_edges = get_int("collapsed_edges");
  if (j.contains("flips")) m.flips = get_int("flips");
  m.flipped_tets_before_untangling = get_int("flipped_tets_before_untangling");
  m.flipped_tets = get_int("flipped_tets");
  m.untangle_sweeps = get_int("untangle_sweeps");
  m.untangle_moves = get_int("untangle_moves");
  const core::Json& joint = core::require(j, "untangle_joint", file);
  if (!joint.is_boolean()) throw core::InvalidInputError(file + ": untangle_joint must be true or false");
  m.untangle_joint = joint.get<bool>();
  if (j.contains("untangle_stop")) {
    if (!j["untangle_stop"].is_string()) throw core::InvalidInputError(file + ": untangle_stop must be a string");
    m.untangle_stop = j["untangle_stop"].get<std::string>();
  }
  m.min_volume_ratio = get_double("min_volume_ratio");
  m.min_volume_ratio_before_smoothing =
      j.contains("min_volume_ratio_before_smoothing") ? get_double("min_volume_ratio_before_smoothing") : m.min_volume_ratio;
  if (j.contains("smooth_sweeps")) m.smooth_sweeps = get_int("smooth_sweeps");
  m.parameter_volume = get_double("parameter_volume");
  return m;
}

}  // namespace volts::volmap
