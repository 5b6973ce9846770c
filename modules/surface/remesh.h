// volts::surface — isotropic remeshing with the sharp edges kept: CGAL's
// Polygon_mesh_processing::isotropic_remeshing (Botsch & Kobbelt 2004), edges whose dihedral angle
// exceeds `sharp_angle_deg` constrained and protected, so creases and corners stay where they are.
// Used where triangle shape matters more than the input's vertices: the tet route's curved
// boundary and the fit route's six-patch segmentation (long skinny CAD triangles make patch
// boundaries staircase and the disk maps onto the cube's faces fold).
#pragma once

#include <vector>

#include "surface/surface.h"

namespace volts::surface {

struct RemeshParams {
  double edge_length = 0;       ///< target edge length (model units, > 0)
  double sharp_angle_deg = 30;  ///< an edge is sharp (kept) if its face normals differ by more [degrees]
  int iterations = 3;           ///< remeshing iterations [1, 20]
};

struct Remeshed {
  Mesh mesh;                              ///< closed, outward, garbage collected
  std::vector<int> sharp_edge_vertices;   ///< pairs (a, b), a < b, of the kept sharp edges of `mesh`
};

/// Throws core::InvalidInputError if edge_length is not positive and finite or iterations is out of range.
Remeshed remesh_isotropic(const Mesh& mesh, const RemeshParams& params);

}  // namespace volts::surface
