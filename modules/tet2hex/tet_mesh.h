// volts::tet2hex — tetrahedral meshes for the tet route: .vtu input of linear or Bézier tetrahedra
// and linear tets as Bézier tets. The TetGen tetrahedralization itself is volts::tetmesh.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "bezier/bezier_tet.h"
#include "surface/surface.h"
#include "tetmesh/tetmesh.h"

namespace volts::tet2hex {

/// Reads a .vtu (VTK XML unstructured grid) of VTK_TETRA (10) or VTK_BEZIER_TETRAHEDRON (78;
/// degree from the point count, RationalWeights honoured) cells with bezier::read_bezier_vtu;
/// other cells are refused, naming the file and the cell. Tets are returned as Bézier tets (linear ones of degree 1), reoriented to
/// positive volume. Throws core::InvalidInputError naming the file for a missing or unreadable
/// file, no cells, another cell type, or mixed degrees.
std::vector<bezier::BezierTet> read_tet_vtu(const std::string& path);

/// The linear tets of `mesh` as Bézier tets of degree 1.
std::vector<bezier::BezierTet> linear_tets(const tetmesh::TetMesh& mesh);

}  // namespace volts::tet2hex
