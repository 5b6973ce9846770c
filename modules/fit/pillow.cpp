#include "fit/pillow.h"

#include <string>

#include "core/errors.h"
#include "tmesh/pillow.h"

namespace volts::fit {

std::vector<tmesh::TMesh> initial_solids(const std::function<tmesh::Vec3(const tmesh::Vec3&)>& map, const PillowParams& params) {
  if (params.elements < 1 || params.elements > 32)
    throw core::ConfigError("fit.elements must be in [1, 32], got " + std::to_string(params.elements));
  if (params.degree < 2 || params.degree > 5) throw core::ConfigError("fit.degree must be in [2, 5], got " + std::to_string(params.degree));
  const int n = params.elements;
  tmesh::PolycubeMaps maps;
  maps.blocks = {tmesh::cube_blocks({1, 1, 1, 1, 1, 1}, {n, n, n}, n)};  // pillow as thick as the core: Ω_c = [1/3,2/3]^3
  maps.physical = [&](int, const tmesh::Vec3& uvw) { return map(uvw); };
  maps.polycube = [](int, const tmesh::Vec3& uvw) { return uvw; };
  tmesh::Params tp;
  tp.degree = params.degree;
  tp.level = 1;          // unused with explicit blocks
  tp.pillow_layers = 1;  // names the blocks "core" and "pillow"
  std::vector<tmesh::TMesh> solids = tmesh::build(maps, tp);
  // tmesh interpolates the map at the Greville points; the paper's initial nets sample it there
  // (a sampled net follows the map's own injectivity, an interpolating one can overshoot).
  std::vector<char> done;
  std::vector<tmesh::Vec3> position;
  for (auto& s : solids)
    for (std::size_t i = 0; i < s.control_points.size(); ++i) {
      const auto id = static_cast<std::size_t>(s.function_ids[i]);
      if (id >= done.size()) done.resize(id + 1, 0), position.resize(id + 1);
      if (!done[id]) position[id] = map(tmesh::block_point(s.corners, s.parameters[i])), done[id] = 1;
      s.control_points[i] = position[id];
    }
  return solids;
}

}  // namespace volts::fit
