// .vtu input of tets (the TetGen tetrahedralization is tested in tests/tetmesh).
#include <gtest/gtest.h>

#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkHigherOrderTetra.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "core/errors.h"
#include "tet2hex/tet_mesh.h"
#include "test_util.h"

using namespace volts;
using namespace volts::tet2hex;
namespace fs = std::filesystem;

// Bézier tets written in VTK's point order (with a negatively oriented one) read back as the same maps.
TEST(ReadTetVtu, BezierTetsRoundTrip) {
  std::mt19937 rng(9);
  const int n = 3;
  std::vector<bezier::BezierTet> tets = {test::random_tet(rng, n, 0.05, true), test::random_tet(rng, n, 0.05, true)};
  const bool flip[2] = {false, true};
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> w;
  w->SetName("RationalWeights");
  vtkNew<vtkIntArray> deg;
  deg->SetName("HigherOrderDegrees");
  deg->SetNumberOfComponents(3);
  vtkNew<vtkUnstructuredGrid> g;
  g->SetPoints(pts);
  const int N = bezier::simplex_size(3, n);
  for (int t = 0; t < 2; ++t) {
    std::vector<vtkIdType> ids(N);
    for (int q = 0; q < N; ++q) {
      vtkIdType b[4];
      vtkHigherOrderTetra::BarycentricIndex(q, b, n);
      // Flipped cell: exchange the roles of corners 2 and 3 (VTK's b[1], b[2]).
      const int idx = flip[t] ? bezier::simplex_index(3, n, b[0], b[2], b[1]) : bezier::simplex_index(3, n, b[0], b[1], b[2]);
      const auto& p = tets[t].points[idx];
      ids[q] = pts->InsertNextPoint(p[0], p[1], p[2]);
      w->InsertNextValue(tets[t].weights[idx]);
    }
    g->InsertNextCell(78, N, ids.data());
    deg->InsertNextTuple3(n, n, n);
  }
  g->GetPointData()->AddArray(w);
  g->GetPointData()->SetActiveAttribute("RationalWeights", vtkDataSetAttributes::RATIONALWEIGHTS);
  g->GetCellData()->AddArray(deg);
  g->GetCellData()->SetActiveAttribute("HigherOrderDegrees", vtkDataSetAttributes::HIGHERORDERDEGREES);
  const fs::path file = fs::temp_directory_path() / ("volts_tet2hex_" + std::to_string(::getpid()) + ".vtu");
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(file.c_str());
  writer->SetInputData(g);
  ASSERT_EQ(writer->Write(), 1);
  const auto back = read_tet_vtu(file.string());
  ASSERT_EQ(back.size(), 2u);
  std::uniform_real_distribution<double> u(0, 1);
  for (int t = 0; t < 2; ++t) {
    EXPECT_EQ(back[t].degree, n);
    // The flipped cell comes back reoriented (v, w exchanged again): the same map as the original.
    for (int i = 0; i < 50; ++i) {
      const Eigen::Vector3d uvw = test::random_uvw(rng);
      EXPECT_LE((bezier::evaluate(back[t], uvw) - bezier::evaluate(tets[t], uvw)).norm(), 1e-13);
    }
  }
  fs::remove(file);
}

TEST(ReadTetVtu, BadFilesAreRefusedNamingTheFile) {
  const fs::path missing = fs::temp_directory_path() / "volts_no_such_file.vtu";
  try {
    read_tet_vtu(missing.string());
    FAIL();
  } catch (const core::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos);
  }
  const fs::path junk = fs::temp_directory_path() / ("volts_junk_" + std::to_string(::getpid()) + ".vtu");
  std::ofstream(junk) << "not xml at all";
  EXPECT_THROW(read_tet_vtu(junk.string()), core::InvalidInputError);
  fs::remove(junk);
  // A hexahedron is not a tet.
  vtkNew<vtkPoints> pts;
  for (int i = 0; i < 8; ++i) pts->InsertNextPoint(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  vtkNew<vtkUnstructuredGrid> g;
  g->SetPoints(pts);
  const vtkIdType ids[8] = {0, 1, 3, 2, 4, 5, 7, 6};
  g->InsertNextCell(12, 8, ids);
  const fs::path hex = fs::temp_directory_path() / ("volts_hex_" + std::to_string(::getpid()) + ".vtu");
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(hex.c_str());
  writer->SetInputData(g);
  writer->Write();
  try {
    read_tet_vtu(hex.string());
    FAIL();
  } catch (const core::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("VTK type 12"), std::string::npos) << e.what();
  }
  fs::remove(hex);
}
