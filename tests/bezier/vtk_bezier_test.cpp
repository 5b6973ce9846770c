// Tests of bezier/vtk_bezier.h against VTK itself: point order, file header, and VTK's own
// evaluation of the read-back Bézier cells.
#include "bezier/vtk_bezier.h"

#include <gtest/gtest.h>
#include <vtkBezierHexahedron.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkGenericCell.h>
#include <vtkHigherOrderHexahedron.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <filesystem>
#include <random>
#include <set>

#include "bezier/bspline.h"
#include "bezier/bspline_volume.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "element_factory.h"

namespace fs = std::filesystem;
using namespace volts;
using namespace volts::bezier;
using Eigen::Vector3d;

namespace {

fs::path output_dir(const std::string& test) {
  const fs::path dir = fs::path(VOLTS_BINARY_DIR) / "test_output" / "bezier" / test;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Cubic (and one anisotropic) rational hexes of a curved B-spline volume: 2x2x1 elements.
std::vector<BezierHex> sample_hexes() {
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> jitter(-0.08, 0.08);
  const TensorBSplineVolume v = volts::bezier::testing::curved_rational_volume(rng);
  std::vector<BezierHex> hexes = extract_bezier_hexes(v);
  // An anisotropic, polynomial one to check HigherOrderDegrees.
  BezierHex a;
  a.degree = {2, 3, 4};
  for (int m = 0; m < a.num_points(); ++m) {
    const auto [i, j, k] = a.ijk(m);
    a.points.emplace_back(2.0 + double(i) / 2 + jitter(rng), double(j) / 3 + jitter(rng), double(k) / 4 + jitter(rng));
  }
  hexes.push_back(a);
  return hexes;
}

}  // namespace

TEST(VtkBezier, PointIndexMatchesVtk) {
  for (const std::array<int, 3>& deg : {std::array<int, 3>{1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {2, 3, 4}, {4, 3, 2},
                                         {1, 2, 3}, {5, 1, 2}}) {
    std::set<int> seen;
    for (int k = 0; k <= deg[2]; ++k)
      for (int j = 0; j <= deg[1]; ++j)
        for (int i = 0; i <= deg[0]; ++i) {
          const int ours = vtk_hex_point_index(i, j, k, deg);
          EXPECT_EQ(ours, vtkHigherOrderHexahedron::PointIndexFromIJK(i, j, k, deg.data()))
              << "degree " << deg[0] << deg[1] << deg[2] << " ijk " << i << j << k;
          seen.insert(ours);
        }
    // A bijection onto 0..N-1.
    EXPECT_EQ(seen.size(), static_cast<std::size_t>((deg[0] + 1) * (deg[1] + 1) * (deg[2] + 1)));
    EXPECT_EQ(*seen.begin(), 0);
    EXPECT_EQ(*seen.rbegin(), static_cast<int>(seen.size()) - 1);
  }
  EXPECT_THROW(vtk_hex_point_index(4, 0, 0, {3, 3, 3}), core::InvalidInputError);
}

TEST(VtkBezier, WrittenFileReadsBackAndVtkEvaluatesLikeUs) {
  const auto hexes = sample_hexes();
  ASSERT_EQ(hexes.size(), 5u);
  std::vector<double> quality, id3;
  for (std::size_t h = 0; h < hexes.size(); ++h) {
    quality.push_back(sample_jacobian(hexes[h], 4).min_scaled);
    id3.insert(id3.end(), {double(h), 2.0 * h, -1.0 * h});
  }
  const fs::path file = output_dir("roundtrip") / "hexes.vtu";
  write_bezier_vtu(file.string(), hexes, {{"min_scaled_jacobian", 1, quality}, {"id3", 3, id3}});

  const std::string text = core::read_text_file(file.string());
  const std::string header = text.substr(0, text.find("<AppendedData"));
  EXPECT_NE(header.find("version=\"2.2\""), std::string::npos) << header.substr(0, 200);
  EXPECT_NE(header.find("<PointData RationalWeights=\"RationalWeights\""), std::string::npos);
  EXPECT_NE(header.find("<CellData HigherOrderDegrees=\"HigherOrderDegrees\""), std::string::npos);
  EXPECT_NE(header.find("type=\"Float64\" Name=\"Points\""), std::string::npos);

  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  ASSERT_EQ(grid->GetNumberOfCells(), static_cast<vtkIdType>(hexes.size()));
  // The arrays must come back *active*: that is what VTK's cells (and ParaView) look at.
  vtkDataArray* weights = grid->GetPointData()->GetRationalWeights();
  vtkDataArray* degrees = grid->GetCellData()->GetHigherOrderDegrees();
  ASSERT_NE(weights, nullptr);
  ASSERT_NE(degrees, nullptr);
  ASSERT_EQ(degrees->GetNumberOfComponents(), 3);
  vtkDataArray* q = grid->GetCellData()->GetArray("min_scaled_jacobian");
  vtkDataArray* i3 = grid->GetCellData()->GetArray("id3");
  ASSERT_NE(q, nullptr);
  ASSERT_NE(i3, nullptr);
  ASSERT_EQ(i3->GetNumberOfComponents(), 3);

  std::mt19937 rng(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  vtkNew<vtkGenericCell> cell;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    const BezierHex& h = hexes[c];
    EXPECT_EQ(grid->GetCellType(c), VTK_BEZIER_HEXAHEDRON);
    EXPECT_EQ(q->GetTuple1(c), quality[c]);
    EXPECT_EQ(i3->GetComponent(c, 2), id3[3 * c + 2]);
    for (int d = 0; d < 3; ++d) EXPECT_EQ(degrees->GetComponent(c, d), h.degree[d]);
    // Points and weights equal, in VTK's order.
    grid->GetCell(c, cell);
    ASSERT_EQ(cell->GetNumberOfPoints(), h.num_points());
    for (int m = 0; m < h.num_points(); ++m) {
      const auto [i, j, k] = h.ijk(m);
      const vtkIdType id = cell->GetPointId(vtk_hex_point_index(i, j, k, h.degree));
      double x[3];
      grid->GetPoint(id, x);
      EXPECT_EQ(Vector3d(x[0], x[1], x[2]), h.points[m]);
      EXPECT_EQ(weights->GetTuple1(id), h.weight(m));
    }
    // VTK's own Bézier hexahedron (order and weights set by the grid from the active arrays).
    auto* bezier = vtkBezierHexahedron::SafeDownCast(cell->GetRepresentativeCell());
    ASSERT_NE(bezier, nullptr);
    for (int d = 0; d < 3; ++d) EXPECT_EQ(bezier->GetOrder(d), h.degree[d]);
    EXPECT_EQ(bezier->GetRationalWeights()->GetNumberOfTuples(), static_cast<vtkIdType>(h.num_points()));
    std::vector<double> interp(h.num_points());
    for (int s = 0; s < 10; ++s) {
      const double pc[3] = {unit(rng), unit(rng), unit(rng)};
      double x[3];
      int sub = 0;
      cell->EvaluateLocation(sub, pc, x, interp.data());
      const Vector3d ours = evaluate(h, Vector3d(pc[0], pc[1], pc[2]));
      EXPECT_LT((Vector3d(x[0], x[1], x[2]) - ours).norm(), 1e-12) << "cell " << c << " sample " << s;
    }
  }
}

TEST(VtkBezier, UnwritablePathThrowsIoErrorAndLeavesNoTemporary) {
  const fs::path dir = output_dir("unwritable");
  const auto hexes = sample_hexes();
  // Parent "directory" is a regular file.
  const fs::path blocker = dir / "not_a_directory";
  core::write_text_atomically(blocker.string(), "x");
  EXPECT_THROW(write_bezier_vtu((blocker / "out.vtu").string(), hexes), core::IoError);
  // Target is an existing (non-empty) directory: the final rename fails.
  const fs::path target = dir / "taken.vtu";
  fs::create_directories(target / "inside");
  EXPECT_THROW(write_bezier_vtu(target.string(), hexes), core::IoError);
  // Bad input: nothing written at all.
  EXPECT_THROW(write_bezier_vtu((dir / "bad.vtu").string(), hexes, {{"q", 1, {1.0}}}), core::InvalidInputError);
  EXPECT_FALSE(fs::exists(dir / "bad.vtu"));
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
  const std::set<std::string> expected{"not_a_directory", "taken.vtu"};
  std::set<std::string> found;
  for (const auto& entry : fs::directory_iterator(dir)) found.insert(entry.path().filename().string());
  EXPECT_EQ(found, expected);
}
