#include "bezier/vtk_bezier.h"

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace volts::bezier {

int vtk_hex_point_index(int i, int j, int k, const std::array<int, 3>& degree) {
  const int p = degree[0], q = degree[1], r = degree[2];
  if (p < 1 || q < 1 || r < 1)
    throw core::InvalidInputError("vtk_hex_point_index: degrees must be >= 1");
  if (i < 0 || i > p || j < 0 || j > q || k < 0 || k > r)
    throw core::InvalidInputError("vtk_hex_point_index: (" + std::to_string(i) + "," + std::to_string(j) + "," +
                                  std::to_string(k) + ") outside the control grid");
  const bool ib = i == 0 || i == p, jb = j == 0 || j == q, kb = k == 0 || k == r;
  const int on = int(ib) + int(jb) + int(kb);
  // Corners counter-clockwise in the bottom face (k = 0), then the top face.
  const int corner_in_face = i ? (j ? 2 : 1) : (j ? 3 : 0);
  if (on == 3) return corner_in_face + (k ? 4 : 0);
  int offset = 8;
  if (on == 2) {
    // Bottom edges: (j=0), (i=p), (j=q), (i=0), all running in increasing i or j; top edges the
    // same; then the vertical edges at corners 0..3, increasing k.
    const int ring = 2 * (p - 1) + 2 * (q - 1);
    if (!ib) return offset + (k ? ring : 0) + (j ? (p - 1) + (q - 1) : 0) + (i - 1);
    if (!jb) return offset + (k ? ring : 0) + (i ? (p - 1) : 2 * (p - 1) + (q - 1)) + (j - 1);
    return offset + 2 * ring + corner_in_face * (r - 1) + (k - 1);
  }
  offset += 4 * ((p - 1) + (q - 1) + (r - 1));
  if (on == 1) {
    // Faces i=0, i=p (j fastest), j=0, j=q (i fastest), k=0, k=r (i fastest).
    if (ib) return offset + (i ? (q - 1) * (r - 1) : 0) + (j - 1) + (q - 1) * (k - 1);
    offset += 2 * (q - 1) * (r - 1);
    if (jb) return offset + (j ? (p - 1) * (r - 1) : 0) + (i - 1) + (p - 1) * (k - 1);
    offset += 2 * (p - 1) * (r - 1);
    return offset + (k ? (p - 1) * (q - 1) : 0) + (i - 1) + (p - 1) * (j - 1);
  }
  offset += 2 * ((q - 1) * (r - 1) + (p - 1) * (r - 1) + (p - 1) * (q - 1));
  return offset + (i - 1) + (p - 1) * ((j - 1) + (q - 1) * (k - 1));
}

namespace {

// vtkErrorCode::GetStringFromErrorCode lives in VTK::CommonMisc; the few codes a writer sets are
// named here instead of linking one more VTK library.
std::string describe(unsigned long code) {
  switch (code) {
    case vtkErrorCode::CannotOpenFileError: return "cannot open file";
    case vtkErrorCode::OutOfDiskSpaceError: return "out of disk space";
    case vtkErrorCode::NoFileNameError: return "no file name";
    default: return "vtkErrorCode " + std::to_string(code);
  }
}

}  // namespace

void write_bezier_vtu(const std::string& path, const std::vector<BezierHex>& hexes,
                      const std::vector<CellArray>& cell_arrays) {
  for (std::size_t h = 0; h < hexes.size(); ++h) {
    try {
      check(hexes[h]);
    } catch (const core::InvalidInputError& e) {
      throw core::InvalidInputError(path + ": hex " + std::to_string(h) + ": " + e.what());
    }
  }
  for (const CellArray& a : cell_arrays) {
    if (a.name.empty() || a.name == "HigherOrderDegrees" || a.name == "RationalWeights")
      throw core::InvalidInputError(path + ": cell array name '" + a.name + "' is empty or reserved");
    if (a.components < 1 || a.values.size() != hexes.size() * static_cast<std::size_t>(a.components))
      throw core::InvalidInputError(path + ": cell array '" + a.name + "' has " + std::to_string(a.values.size()) +
                                    " values, expected " + std::to_string(a.components) + " per hex for " +
                                    std::to_string(hexes.size()) + " hexes");
  }

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();  // control points at full precision
  vtkNew<vtkDoubleArray> weights;
  weights->SetName("RationalWeights");
  vtkNew<vtkIntArray> degrees;
  degrees->SetName("HigherOrderDegrees");
  degrees->SetNumberOfComponents(3);
  degrees->SetNumberOfTuples(static_cast<vtkIdType>(hexes.size()));
  vtkNew<vtkUnstructuredGrid> grid;
  grid->Allocate(static_cast<vtkIdType>(hexes.size()));
  std::vector<vtkIdType> ids;
  for (std::size_t h = 0; h < hexes.size(); ++h) {
    const BezierHex& hex = hexes[h];
    const vtkIdType base = points->GetNumberOfPoints();
    ids.assign(hex.num_points(), 0);
    for (int n = 0; n < hex.num_points(); ++n) {
      points->InsertNextPoint(hex.points[n].data());
      weights->InsertNextValue(hex.weight(n));
      const auto [i, j, k] = hex.ijk(n);
      ids[vtk_hex_point_index(i, j, k, hex.degree)] = base + n;
    }
    grid->InsertNextCell(VTK_BEZIER_HEXAHEDRON, static_cast<vtkIdType>(ids.size()), ids.data());
    degrees->SetTuple3(static_cast<vtkIdType>(h), hex.degree[0], hex.degree[1], hex.degree[2]);
  }
  grid->SetPoints(points);
  // Declared active so that readers (ParaView) use them; written as attributes of <PointData>/<CellData>.
  grid->GetPointData()->SetRationalWeights(weights);
  grid->GetCellData()->SetHigherOrderDegrees(degrees);
  for (const CellArray& a : cell_arrays) {
    vtkNew<vtkDoubleArray> arr;
    arr->SetName(a.name.c_str());
    arr->SetNumberOfComponents(a.components);
    arr->SetNumberOfTuples(static_cast<vtkIdType>(hexes.size()));
    for (std::size_t v = 0; v < a.values.size(); ++v) arr->SetValue(static_cast<vtkIdType>(v), a.values[v]);
    grid->GetCellData()->AddArray(arr);
  }

  core::write_atomically(path, [&](const std::string& tmp) {
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetFileName(tmp.c_str());
    writer->SetInputData(grid);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();  // raw binary
    writer->SetHeaderTypeToUInt64();  // arrays over 4 GiB
    if (writer->Write() != 1 || writer->GetErrorCode() != vtkErrorCode::NoError)
      throw core::IoError(path + ": VTK writer failed: " + describe(writer->GetErrorCode()));
  });
}

}  // namespace volts::bezier
