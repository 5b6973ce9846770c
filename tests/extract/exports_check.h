// Every solver export of a finished run (extract.exports' default: vtu, bext, k, json, msh, png)
// exists next to report.json and parses, with the report's element and function counts: what a
// user's script relies on after `volts run` (issue 8's end-to-end check). With `gmsh_check`, Gmsh's
// own `gmsh bezier.msh -check` too when gmsh is installed (scripts/install-deps.sh installs it);
// it is slow on large files (43 s on the torus's 87,648 nodes), bench_pipeline runs it per model.
// `stage`: the report section with the figures (extract; tet2hex for the tet route).
#pragma once

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "common/test_util.h"
#include "core/atomic_file.h"
#include "core/stage_file.h"
#include "extract/readers.h"

namespace volts::test {

inline void expect_every_export_parses(const std::filesystem::path& work, bool gmsh_check = true, const std::string& stage = "extract") {
  const core::Json x = core::read_report(work.string())["stages"][stage];
  const long elements = x["bezier_elements"].get<long>(), functions = x["global_functions"].get<long>();
  ASSERT_GT(elements, 0);
  for (const char* k : {"vtu", "bext", "k", "json", "msh", "png"}) EXPECT_TRUE(x["outputs"].contains(k)) << k;

  // bezier.vtu: VTK's reader, one Bézier hexahedron (79) per element, with degrees and weights.
  vtkNew<vtkXMLUnstructuredGridReader> vtu;
  vtu->SetFileName((work / "bezier.vtu").c_str());
  vtu->Update();
  vtkUnstructuredGrid* g = vtu->GetOutput();
  ASSERT_EQ(g->GetNumberOfCells(), elements);
  for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c) ASSERT_EQ(g->GetCellType(c), 79) << "cell " << c;
  for (const char* a : {"HigherOrderDegrees", "min_scaled_jacobian", "status"}) EXPECT_NE(g->GetCellData()->GetArray(a), nullptr) << a;
  EXPECT_NE(g->GetPointData()->GetArray("RationalWeights"), nullptr);

  // bezier.bext: the global functions and, per element, operator rows whose Bernstein columns sum to 1.
  const Bext b = read_bext((work / "bezier.bext").string());
  EXPECT_EQ(b.nodes, functions);
  ASSERT_EQ(b.elements, elements);
  double pou = 0;
  for (long e = 0; e < b.elements; ++e)
    for (std::size_t c = 0; c < b.coefficient_vectors.at(b.element_vectors[e].at(0)).size(); ++c) {
      double sum = 0;
      for (const long v : b.element_vectors[e]) sum += b.coefficient_vectors[v][c];
      pou = std::max(pou, std::abs(sum - 1));
    }
  EXPECT_LT(pou, 1e-12) << "partition of unity read back from bezier.bext";

  // bezier.k includes the bext by name.
  const std::string k = core::read_text_file((work / "bezier.k").string());
  const auto inc = k.find("*IGA_INCLUDE_BEZIER\n");
  ASSERT_NE(inc, std::string::npos);
  EXPECT_NE(k.find("\nbezier.bext\n", inc), std::string::npos);

  // bezier.json: the versioned file for users' own solvers; either operator encoding (version 1:
  // triplets; 2: Kronecker factors where the operator is a product) decodes to a partition of
  // unity (every Bernstein column sums to one over the element's functions).
  const core::Json j = core::read_stage_file((work / "bezier.json").string(), "volts-bezier", 2);
  EXPECT_EQ(static_cast<long>(j["elements"].size()), elements);
  EXPECT_EQ(j["global_functions"]["count"].get<long>(), functions);
  double column_gap = 0;
  for (const auto& el : j["elements"]) {
    const auto& op = el["operator"];
    const int rows = op["rows"].get<int>(), cols = op["columns"].get<int>();
    EXPECT_EQ(static_cast<int>(el["functions"].size()), rows);
    std::vector<double> sum(static_cast<std::size_t>(cols), 0.0);
    if (op.contains("kronecker")) {
      EXPECT_EQ(j["version"], 2);
      const int n = el["degree"][0].get<int>() + 1;
      std::array<std::vector<double>, 3> k;
      for (std::size_t d = 0; d < 3; ++d) k[d] = op["kronecker"][d].get<std::vector<double>>();
      for (int t = 0; t < rows; ++t)
        for (int c = 0; c < cols; ++c)
          sum[static_cast<std::size_t>(c)] += k[0][static_cast<std::size_t>(n * (t % n) + c % n)] * k[1][static_cast<std::size_t>(n * (t / n % n) + c / n % n)] *
                                              k[2][static_cast<std::size_t>(n * (t / (n * n)) + c / (n * n))];
    } else {
      for (const auto& tr : op["triplets"]) sum[tr[1].get<std::size_t>()] += tr[2].get<double>();
    }
    for (const double x : sum) column_gap = std::max(column_gap, std::abs(x - 1));
  }
  EXPECT_LT(column_gap, 1e-12);

  // bezier.msh: Gmsh 4.1, one cubic Lagrange hexahedron (type 92) per element; gmsh accepts it.
  const Msh m = read_msh((work / "bezier.msh").string());
  ASSERT_EQ(static_cast<long>(m.elements.size()), elements);
  for (const int t : m.types) ASSERT_EQ(t, 92);
  // bezier.vtu is one connected mesh, as bezier.msh is: the element faces (by their corners) of
  // one element only — what ParaView shows as the surface — are the same number in both, and
  // fewer than all faces wherever elements meet.
  auto faces_of_one_element = [](const std::vector<std::array<long, 8>>& corners) {
    static const int kFace[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    std::map<std::array<long, 4>, int> count;
    for (const auto& c : corners)
      for (const auto& f : kFace) {
        std::array<long, 4> key = {c[f[0]], c[f[1]], c[f[2]], c[f[3]]};
        std::sort(key.begin(), key.end());
        ++count[key];
      }
    return std::count_if(count.begin(), count.end(), [](const auto& x) { return x.second == 1; });
  };
  std::vector<std::array<long, 8>> vtu_corners, msh_corners;
  for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c) {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    g->GetCellPoints(c, n, ids);
    std::array<long, 8> corner{};
    for (int i = 0; i < 8; ++i) corner[static_cast<std::size_t>(i)] = static_cast<long>(ids[i]);
    vtu_corners.push_back(corner);
  }
  for (const auto& el : m.elements) {
    std::array<long, 8> corner{};
    for (int i = 0; i < 8; ++i) corner[static_cast<std::size_t>(i)] = el.at(static_cast<std::size_t>(i));
    msh_corners.push_back(corner);
  }
  const long surface_faces = faces_of_one_element(vtu_corners);
  EXPECT_EQ(surface_faces, faces_of_one_element(msh_corners)) << "bezier.vtu and bezier.msh disagree on the surface";
  if (elements > 1) {
    EXPECT_LT(surface_faces, 6 * elements) << "bezier.vtu: no two elements share a face";
  }
  if (gmsh_check && run("gmsh --version").code == 0) {
    const Outcome check = run("gmsh " + (work / "bezier.msh").string() + " -check");
    EXPECT_EQ(check.code, 0) << check.output;
    EXPECT_EQ(check.output.find("rror"), std::string::npos) << check.output;
    EXPECT_NE(check.output.find(std::to_string(elements) + " elements"), std::string::npos) << check.output;
  }

  // The scaled Jacobian histogram next to the report.
  vtkNew<vtkPNGReader> png;
  png->SetFileName((work / "scaled_jacobian_histogram.png").c_str());
  png->Update();
  int dims[3];
  png->GetOutput()->GetDimensions(dims);
  EXPECT_EQ(dims[0], 420);
  EXPECT_EQ(dims[1], 260);
}

}  // namespace volts::test
