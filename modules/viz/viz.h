// volts::viz — ParaView files for every stage's intermediate results (.vtp polydata, .vtu
// unstructured grids), written through VTK's XML writers, atomically.
//
// Stages fill these plain structs instead of touching VTK, so VTK stays an implementation detail
// of this module (and of bezier/vtk_bezier.h for higher-order cells).
#pragma once

#include <array>
#include <string>
#include <vector>

namespace volts::viz {

/// A named data array: `components` values per point or per cell, flattened.
struct Field {
  std::string name;
  int components = 1;
  std::vector<double> values;
};

/// Points with vertex, line and polygon cells (a .vtp). Cell fields cover verts, then lines, then
/// polys, in that order (VTK's order for polydata cells).
struct PolyData {
  std::vector<std::array<double, 3>> points;
  std::vector<std::vector<int>> verts;
  std::vector<std::vector<int>> lines;
  std::vector<std::vector<int>> polys;
  std::vector<Field> point_fields;
  std::vector<Field> cell_fields;
};

/// Linear cells of any VTK type (a .vtu), e.g. 12 = hexahedron, 10 = tetrahedron.
struct UnstructuredGrid {
  std::vector<std::array<double, 3>> points;
  std::vector<std::vector<int>> cells;
  std::vector<int> cell_types;
  std::vector<Field> point_fields;
  std::vector<Field> cell_fields;
};

/// Write .vtp / .vtu (binary appended, compressed). Throws core::IoError; never leaves a partial file.
/// Throws core::InvalidInputError if a field's size does not match its point or cell count (a bug).
void write_vtp(const std::string& path, const PolyData& data);
void write_vtu(const std::string& path, const UnstructuredGrid& data);

}  // namespace volts::viz
