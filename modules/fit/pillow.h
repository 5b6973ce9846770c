// volts::fit — the pillow partition and the initial solids of Lin, Huang & Hu 2018 ("Partition of
// the tet mesh model by pillow operation", "Construction of the initial TBSs"): the unit cube
// shrunk to Ω_c = [1/3,2/3]^3, six frusta joining its faces to the cube's (v_i joined to v_i^c),
// and per sub-domain a TBS of degree p with uniform knots and Bézier end conditions whose control
// points are the volume map at the sub-domain's grid points.
//
// The seven sub-domains are tmesh::cube_blocks of a cube with all six faces on the surface and a
// pillow as thick as the core (layers = elements), so they are conforming face to face and the
// grids on common curves and faces are the same points (one function id, one position).
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "tmesh/tmesh.h"

namespace volts::fit {

struct PillowParams {
  int elements = 4;  ///< knot spans per direction of each of the seven solids [1, 32]
  int degree = 3;    ///< degree per direction [2, 5]
};

/// The seven initial solids (core first, then the frusta in tmesh::cube_blocks order), each a
/// tmesh::TMesh (kind "core" or "pillow", boundary flags on the cube faces, `parameters` = the
/// Greville points its control points sample) whose control point at Greville point g is
/// `map(block_point(corners, g))`, `map` taking [0,1]^3 to physical space. Throws
/// core::ConfigError for parameters out of range, what `map` throws.
std::vector<tmesh::TMesh> initial_solids(const std::function<tmesh::Vec3(const tmesh::Vec3&)>& map, const PillowParams& params);

}  // namespace volts::fit
