// Test helper: the control mesh of one cube, every face on the surface, under a map of the unit
// cube (level 2, `pillow` layers) — the shape the optimization tests deform.
#pragma once

#include <functional>
#include <vector>

#include "tmesh/tmesh.h"

namespace volts::tmesh::testing {

inline std::vector<TMesh> unit_cube_blocks(const std::function<Vec3(const Vec3&)>& map, int pillow) {
  PolycubeMaps m;
  m.boundary = {{1, 1, 1, 1, 1, 1}};
  m.physical = [map](int, const Vec3& abc) { return map(abc); };
  m.polycube = [](int, const Vec3& abc) { return abc; };
  Params p;
  p.level = 2;
  p.pillow_layers = pillow;
  return build(m, p);
}

}  // namespace volts::tmesh::testing
