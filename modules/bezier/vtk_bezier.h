// volts::bezier — export of Bézier hexahedra for ParaView: VTK XML unstructured grid (.vtu) of
// VTK_BEZIER_HEXAHEDRON (79) cells with the HigherOrderDegrees and RationalWeights arrays; and
// import of Bézier/Lagrange hexahedra and tetrahedra from any .vtu (for volts-check).
//
// Written with VTK's own vtkXMLUnstructuredGridWriter (VTK >= 9.1), appended raw binary, LZ4
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
#include "bezier/bezier_tet.h"

namespace volts::bezier {

/// Position of control point (i,j,k) of a hexahedron of degrees `degree` in VTK's point order
/// (= vtkHigherOrderHexahedron::PointIndexFromIJK, VTK 9 numbering): 8 corners, 12 edges,
/// 6 faces, interior. Throws core::InvalidInputError if (i,j,k) is out of range or a degree < 1.
int vtk_hex_point_index(int i, int j, int k, const std::array<int, 3>& degree);

/// Position of control point (a1,a2,a3) (exponents of u,v,w) of a degree-n tetrahedron in VTK's
/// point order (vtkHigherOrderTetra::Index): corners, edges, faces, interior.
int vtk_tet_point_index(int a1, int a2, int a3, int degree);

/// A per-cell field: `components` values per hex, hex after hex.
struct CellArray {
  std::string name;
  int components = 1;
  std::vector<double> values;
};

/// Writes the hexes to `path` (atomically, core::write_atomically). RationalWeights is written
/// for every point (1 for polynomial hexes), HigherOrderDegrees for every cell; mixed degrees are
/// allowed. Points: with `shared` empty every cell gets its own copy of its control points (not a
/// connected mesh: ParaView's surface of it has every element face). Else shared[o_h + n] is the
/// file's point for control point n of hex h (o_h: the points of the hexes before h), numbered
/// 0, 1, ... in order of first use; a point takes the position and weight of its first use — a
/// connected mesh (extract::shared_points makes one).
/// Throws core::InvalidInputError for a malformed hex, cell array (wrong size, empty or reserved
/// name) or `shared` (wrong size, an id out of order), core::IoError if the file cannot be written
/// (no temporary file is left behind).
void write_bezier_vtu(const std::string& path, const std::vector<BezierHex>& hexes,
                      const std::vector<CellArray>& cell_arrays = {}, const std::vector<int>& shared = {});

/// The elements of a .vtu, in cell order.
struct VtuElements {
  std::vector<BezierHex> hexes;
  std::vector<BezierTet> tets;
  std::vector<int> vtk_type;  ///< per cell: the VTK cell type as read
  std::vector<int> element;   ///< per cell: index into hexes (hexahedra) or tets (tetrahedra)
  bool is_tet(int cell) const { return vtk_type[cell] == 78 || vtk_type[cell] == 71 || vtk_type[cell] == 10; }
};

/// Reads every cell of a VTK XML unstructured grid as a Bézier element (with VTK's own reader, so
/// files older than version 2.1 get VTK's renumbering of higher-order hexahedra):
///  * 79 Bézier hexahedron, 78 Bézier tetrahedron: degrees from the active HigherOrderDegrees cell
///    array when present (else from the point count), weights from the active RationalWeights point
///    array when present (all 1 → polynomial);
///  * 72 Lagrange hexahedron, 71 Lagrange tetrahedron (equispaced nodes, VTK order), 12 hexahedron,
///    10 tetrahedron: converted exactly to Bézier form (inverse Bernstein collocation).
/// Throws core::InvalidInputError naming the file for a missing, unreadable or malformed file, and
/// naming the cell for a cell of another type or an inconsistent point count/degree.
VtuElements read_bezier_vtu(const std::string& path);

/// Copies the .vtu at `in` to `out` (atomically) with these cell arrays added (replacing arrays of
/// the same name). Throws as read_bezier_vtu for `in`, InvalidInputError for an array of the wrong
/// size, core::IoError if `out` cannot be written.
void write_vtu_with_cell_arrays(const std::string& in, const std::string& out, const std::vector<CellArray>& arrays);

}  // namespace volts::bezier
