// Tests of the .vtu import of bezier/vtk_bezier.h (read_bezier_vtu, write_vtu_with_cell_arrays):
// round trips through our writer and through files made with VTK directly, VTK's own evaluation of
// Bézier tetrahedra as the reference for the point order, exact Lagrange-to-Bézier conversion, and
// clear errors for missing, malformed and unsupported input.
#include <gtest/gtest.h>
#include <vtkBezierTetra.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkGenericCell.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "bezier/vtk_bezier.h"
#include "core/errors.h"
#include "element_factory.h"

namespace fs = std::filesystem;
using namespace volts;
using namespace volts::bezier;
using namespace volts::bezier::testing;
using Eigen::Vector3d;

namespace {

fs::path output_dir(const std::string& test) {
  const fs::path dir = fs::path(VOLTS_BINARY_DIR) / "test_output" / "bezier_read" / test;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// One cell per entry: its VTK type and its points (in VTK order), optional weights.
struct Cell {
  int type;
  std::vector<Vector3d> points;
  std::vector<double> weights;
};

void write_cells(const std::string& path, const std::vector<Cell>& cells) {
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> w;
  w->SetName("RationalWeights");
  vtkNew<vtkUnstructuredGrid> g;
  bool any_weights = false;
  for (const Cell& c : cells) {
    std::vector<vtkIdType> ids;
    for (std::size_t i = 0; i < c.points.size(); ++i) {
      ids.push_back(pts->InsertNextPoint(c.points[i].data()));
      w->InsertNextValue(c.weights.empty() ? 1.0 : c.weights[i]);
      any_weights = any_weights || !c.weights.empty();
    }
    g->InsertNextCell(c.type, static_cast<vtkIdType>(ids.size()), ids.data());
  }
  g->SetPoints(pts);
  if (any_weights) g->GetPointData()->SetRationalWeights(w);
  vtkNew<vtkXMLUnstructuredGridWriter> wr;
  wr->SetFileName(path.c_str());
  wr->SetInputData(g);
  ASSERT_EQ(wr->Write(), 1);
}

Cell vtk_tet(const BezierTet& t, int type) {
  Cell c{type, std::vector<Vector3d>(t.points.size()), {}};
  if (t.is_rational()) c.weights.resize(t.points.size());
  int n = 0;
  for (const auto& a : simplex_multi_indices(3, t.degree)) {
    const int v = vtk_tet_point_index(a[1], a[2], a[3], t.degree);
    c.points[v] = t.points[n];
    if (t.is_rational()) c.weights[v] = t.weights[n];
    ++n;
  }
  return c;
}

}  // namespace

TEST(VtkBezierRead, HexesRoundTripThroughOurWriter) {
  const fs::path dir = output_dir("hexes");
  std::mt19937 rng(51);
  std::vector<BezierHex> hexes = {perturbed_hex(rng, {3, 3, 3}, 0.05, true), perturbed_hex(rng, {2, 3, 4}, 0.05, false),
                                  perturbed_hex(rng, {1, 1, 1}, 0.05, false)};
  write_bezier_vtu((dir / "h.vtu").string(), hexes);
  const VtuElements el = read_bezier_vtu((dir / "h.vtu").string());
  ASSERT_EQ(el.hexes.size(), 3u);
  EXPECT_TRUE(el.tets.empty());
  for (int c = 0; c < 3; ++c) {
    EXPECT_FALSE(el.is_tet(c));
    const BezierHex& h = el.hexes[el.element[c]];
    EXPECT_EQ(h.degree, hexes[c].degree);
    EXPECT_EQ(h.is_rational(), hexes[c].is_rational());
    for (int n = 0; n < h.num_points(); ++n) EXPECT_EQ(h.points[n], hexes[c].points[n]);
  }
}

TEST(VtkBezierRead, BezierTetsFollowVtkPointOrder) {
  const fs::path dir = output_dir("tets");
  std::mt19937 rng(52);
  std::vector<BezierTet> tets;
  std::vector<Cell> cells;
  for (int n = 1; n <= 4; ++n) {
    tets.push_back(perturbed_tet(rng, n, 0.05, false));
    cells.push_back(vtk_tet(tets.back(), VTK_BEZIER_TETRAHEDRON));
  }
  const std::string path = (dir / "t.vtu").string();
  write_cells(path, cells);
  const VtuElements el = read_bezier_vtu(path);
  ASSERT_EQ(el.tets.size(), 4u);
  // VTK's own Bézier tetra evaluates the file's cells like our reading of them.
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkNew<vtkGenericCell> cell;
  for (int c = 0; c < 4; ++c) {
    reader->GetOutput()->GetCell(c, cell);
    for (int s = 0; s < 5; ++s) {
      const Vector3d x = random_in_tet(rng);
      double pc[3] = {x[0], x[1], x[2]}, y[3], w[64];
      int sub = 0;
      cell->EvaluateLocation(sub, pc, y, w);
      EXPECT_LT((evaluate(el.tets[c], x) - Vector3d(y[0], y[1], y[2])).norm(), 1e-12) << "degree " << c + 1;
      EXPECT_LT((evaluate(el.tets[c], x) - evaluate(tets[c], x)).norm(), 1e-13);
    }
  }
}

TEST(VtkBezierRead, RationalTetsAndLagrangeCellsConvertExactly) {
  const fs::path dir = output_dir("lagrange");
  std::mt19937 rng(53);
  const BezierTet rt = perturbed_tet(rng, 2, 0.05, true);
  // Lagrange cells: nodes are the map at equispaced parameters, in VTK order.
  const BezierTet lt = perturbed_tet(rng, 3, 0.05, false);
  Cell lag_tet{VTK_LAGRANGE_TETRAHEDRON, std::vector<Vector3d>(lt.points.size()), {}};
  for (const auto& a : simplex_multi_indices(3, 3))
    lag_tet.points[vtk_tet_point_index(a[1], a[2], a[3], 3)] = evaluate(lt, Vector3d(a[1], a[2], a[3]) / 3.0);
  const BezierHex lh = perturbed_hex(rng, {3, 3, 3}, 0.05, false);
  Cell lag_hex{VTK_LAGRANGE_HEXAHEDRON, std::vector<Vector3d>(64), {}};
  for (int n = 0; n < 64; ++n) {
    const auto [i, j, k] = lh.ijk(n);
    lag_hex.points[vtk_hex_point_index(i, j, k, lh.degree)] = evaluate(lh, Vector3d(i, j, k) / 3.0);
  }
  const std::string path = (dir / "l.vtu").string();
  write_cells(path, {vtk_tet(rt, VTK_BEZIER_TETRAHEDRON), lag_tet, lag_hex});
  const VtuElements el = read_bezier_vtu(path);
  ASSERT_EQ(el.tets.size(), 2u);
  ASSERT_EQ(el.hexes.size(), 1u);
  EXPECT_TRUE(el.tets[0].is_rational());
  for (int s = 0; s < 10; ++s) {
    const Vector3d x = random_in_tet(rng);
    EXPECT_LT((evaluate(el.tets[0], x) - evaluate(rt, x)).norm(), 1e-13);
    EXPECT_LT((evaluate(el.tets[1], x) - evaluate(lt, x)).norm(), 1e-12);
    EXPECT_LT((evaluate(el.hexes[0], x) - evaluate(lh, x)).norm(), 1e-12);
  }
}

TEST(VtkBezierRead, ClearErrors) {
  const fs::path dir = output_dir("errors");
  const auto message = [](const std::string& p) -> std::string {
    try {
      read_bezier_vtu(p);
    } catch (const core::InvalidInputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(message((dir / "missing.vtu").string()).find("missing.vtu: no such file"), std::string::npos);
  std::ofstream((dir / "garbage.vtu").string()) << "<VTKFile type=\"UnstructuredGrid\" version=\"2.2\"><Unstr";
  EXPECT_NE(message((dir / "garbage.vtu").string()).find("garbage.vtu"), std::string::npos);
  std::vector<Vector3d> wedge = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  write_cells((dir / "wedge.vtu").string(), {{VTK_WEDGE, wedge, {}}});
  const std::string m = message((dir / "wedge.vtu").string());
  EXPECT_NE(m.find("wedge.vtu: cell 0 (VTK type 13"), std::string::npos) << m;
  EXPECT_NE(m.find("unsupported cell type"), std::string::npos) << m;
  std::vector<Vector3d> bad(11, Vector3d::Zero());  // no tet has 11 points
  write_cells((dir / "bad.vtu").string(), {{VTK_BEZIER_TETRAHEDRON, bad, {}}});
  EXPECT_NE(message((dir / "bad.vtu").string()).find("cell 0"), std::string::npos);
}

TEST(VtkBezierRead, CellArraysAreAddedToACopy) {
  const fs::path dir = output_dir("arrays");
  std::mt19937 rng(54);
  write_bezier_vtu((dir / "in.vtu").string(), {perturbed_hex(rng, {2, 2, 2}, 0.05, false), perturbed_hex(rng, {2, 2, 2}, 0.05, false)});
  write_vtu_with_cell_arrays((dir / "in.vtu").string(), (dir / "out.vtu").string(), {{"status", 1, {1, -1}}});
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName((dir / "out.vtu").string().c_str());
  reader->Update();
  vtkDataArray* a = reader->GetOutput()->GetCellData()->GetArray("status");
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a->GetComponent(1, 0), -1.0);
  EXPECT_NE(reader->GetOutput()->GetCellData()->GetArray("HigherOrderDegrees"), nullptr);
  EXPECT_EQ(read_bezier_vtu((dir / "out.vtu").string()).hexes.size(), 2u);
  EXPECT_THROW(write_vtu_with_cell_arrays((dir / "in.vtu").string(), (dir / "x.vtu").string(), {{"s", 1, {1}}}),
               core::InvalidInputError);
}
