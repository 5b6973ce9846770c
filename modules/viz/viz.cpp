#include "viz/viz.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace volts::viz {
namespace {

vtkNew<vtkPoints> make_points(const std::vector<std::array<double, 3>>& pts) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(pts.size()));
  for (std::size_t i = 0; i < pts.size(); ++i) points->SetPoint(static_cast<vtkIdType>(i), pts[i].data());
  return points;
}

void add_fields(vtkDataSetAttributes* attrs, const std::vector<Field>& fields, std::size_t count,
                const std::string& where, const std::string& path) {
  for (const Field& f : fields) {
    if (f.components < 1 || f.values.size() != count * static_cast<std::size_t>(f.components))
      throw core::InvalidInputError(path + ": " + where + " field '" + f.name + "' has " +
                                    std::to_string(f.values.size()) + " values for " + std::to_string(count) +
                                    " " + where + "s");
    vtkNew<vtkDoubleArray> a;
    a->SetName(f.name.c_str());
    a->SetNumberOfComponents(f.components);
    a->SetNumberOfTuples(static_cast<vtkIdType>(count));
    for (std::size_t i = 0; i < f.values.size(); ++i) a->SetValue(static_cast<vtkIdType>(i), f.values[i]);
    attrs->AddArray(a);
  }
}

vtkNew<vtkCellArray> make_cells(const std::vector<std::vector<int>>& cells) {
  vtkNew<vtkCellArray> ca;
  for (const auto& c : cells) {
    ca->InsertNextCell(static_cast<vtkIdType>(c.size()));
    for (int v : c) ca->InsertCellPoint(v);
  }
  return ca;
}

template <class Writer>
void write_with(const std::string& path, vtkDataObject* data) {
  core::write_atomically(path, [&](const std::string& tmp) {
    vtkNew<Writer> w;
    w->SetFileName(tmp.c_str());
    w->SetInputData(data);
    w->SetDataModeToAppended();
    w->SetCompressorTypeToLZ4();  // zlib took half of polycube's write (its two tet meshes)
    if (w->Write() != 1) throw core::IoError(path + ": VTK writer failed");
  });
}

}  // namespace

void write_vtp(const std::string& path, const PolyData& d) {
  vtkNew<vtkPolyData> pd;
  pd->SetPoints(make_points(d.points));
  pd->SetVerts(make_cells(d.verts));
  pd->SetLines(make_cells(d.lines));
  pd->SetPolys(make_cells(d.polys));
  add_fields(pd->GetPointData(), d.point_fields, d.points.size(), "point", path);
  add_fields(pd->GetCellData(), d.cell_fields, d.verts.size() + d.lines.size() + d.polys.size(), "cell", path);
  write_with<vtkXMLPolyDataWriter>(path, pd);
}

void write_vtu(const std::string& path, const UnstructuredGrid& d) {
  if (d.cells.size() != d.cell_types.size())
    throw core::InvalidInputError(path + ": cell and cell type counts differ");
  vtkNew<vtkUnstructuredGrid> ug;
  ug->SetPoints(make_points(d.points));
  ug->Allocate(static_cast<vtkIdType>(d.cells.size()));
  vtkNew<vtkIdList> ids;
  for (std::size_t c = 0; c < d.cells.size(); ++c) {
    ids->Reset();
    for (int v : d.cells[c]) ids->InsertNextId(v);
    ug->InsertNextCell(d.cell_types[c], ids);
  }
  add_fields(ug->GetPointData(), d.point_fields, d.points.size(), "point", path);
  add_fields(ug->GetCellData(), d.cell_fields, d.cells.size(), "cell", path);
  write_with<vtkXMLUnstructuredGridWriter>(path, ug);
}

}  // namespace volts::viz
