// volts::bezier — export of Bézier hexahedra for ParaView: VTK XML unstructured grid (.vtu) of
// VTK_BEZIER_HEXAHEDRON (79) cells with the HigherOrderDegrees and RationalWeights arrays.
//
// Written with VTK's own vtkXMLUnstructuredGridWriter (VTK >= 9.1), appended raw binary, zlib
// compressed, Float64 points. That writer already stamps the file version="2.2" and declares both
// arrays active (<PointData RationalWeights=...>, <CellData HigherOrderDegrees=...>), so no
// post-processing: VTK >= 9 readers apply their VTK-8-to-9 renumbering of the vertical edges of
// higher-order hexahedra only to files older than 2.1, and files written here are in VTK 9 point
// order (vtk_hex_point_index). The tests check the header text and that VTK's own
// vtkBezierHexahedron evaluates the read-back cells like evaluate().
#pragma once

#include <array>
#include <string>
#include <vector>

#include "bezier/bezier_hex.h"

namespace volts::bezier {

/// Position of control point (i,j,k) of a hexahedron of degrees `degree` in VTK's point order
/// (= vtkHigherOrderHexahedron::PointIndexFromIJK, VTK 9 numbering): 8 corners, 12 edges,
/// 6 faces, interior. Throws core::InvalidInputError if (i,j,k) is out of range or a degree < 1.
int vtk_hex_point_index(int i, int j, int k, const std::array<int, 3>& degree);

/// A per-cell field: `components` values per hex, hex after hex.
struct CellArray {
  std::string name;
  int components = 1;
  std::vector<double> values;
};

/// Writes the hexes to `path` (atomically, core::write_atomically). Every cell gets its own copy
/// of its control points — shared points of neighbouring elements are duplicated (simplest; fine
/// for viewing, not a connected mesh). RationalWeights is written for every point (1 for
/// polynomial hexes), HigherOrderDegrees for every cell; mixed degrees are allowed.
/// Throws core::InvalidInputError for a malformed hex or cell array (wrong size, empty or reserved
/// name), core::IoError if the file cannot be written (no temporary file is left behind).
void write_bezier_vtu(const std::string& path, const std::vector<BezierHex>& hexes,
                      const std::vector<CellArray>& cell_arrays = {});

}  // namespace volts::bezier
