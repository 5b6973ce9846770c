// volts::surface — the surface mesh inside stage files: flat "vertices" [x0,y0,z0,x1,...] and
// "faces" [a0,b0,c0,...] (0-based), so every stage file carries the input surface with it.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/stage_file.h"
#include "surface/surface.h"

namespace volts::surface {

/// Plain arrays of the mesh (for viz files and solvers): xyz per vertex, three indices per face.
std::vector<std::array<double, 3>> vertex_array(const Mesh& mesh);
std::vector<std::vector<int>> triangle_array(const Mesh& mesh);
/// The same faces as fixed triples (the mesh is triangular), e.g. for tmesh::SlideSurface.
std::vector<std::array<int, 3>> triangle_triples(const Mesh& mesh);

core::Json mesh_to_json(const Mesh& mesh);
/// Throws core::InvalidInputError naming `file` if the arrays are missing, malformed or out of range.
Mesh mesh_from_json(const core::Json& j, const std::string& file);

}  // namespace volts::surface
