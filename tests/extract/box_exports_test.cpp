// volts-extract's solver exports on the box pipeline (generated box, octree level 2, no
// optimization sweeps: seconds), as a user runs it: report figures of the global basis, functions
// shared by blocks, every file of extract.exports next to bezier.vtu and read back (exports_check.h),
// the .msh conforming; extract.exports limits what is written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "common/test_util.h"
#include "core/stage_file.h"
#include "extract/export.h"
#include "extract/exports_check.h"
#include "extract/readers.h"

namespace fs = std::filesystem;
using namespace volts;

namespace {

class Box : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir = test::fresh_dir("extract", "box");
    test::write_text(dir / "run.yaml", "input: {generate: box, resolution: 8}\ntmesh: {level: 2, optimize_sweeps: 0}\n");
    result = test::run(test::bin("volts") + " run " + (dir / "run.yaml").string() + " --workdir " + (dir / "work").string());
  }
  static fs::path dir;
  static test::Outcome result;
};
fs::path Box::dir;
test::Outcome Box::result;

}  // namespace

TEST_F(Box, ReportHasTheGlobalBasisFigures) {
  ASSERT_EQ(result.code, 0) << result.output;
  const auto s = core::read_report((dir / "work").string())["stages"];
  const auto& x = s["extract"];
  EXPECT_LT(x["partition_of_unity_error"].get<double>(), 1e-12);
  EXPECT_GE(x["partition_of_unity_error"].get<double>(), 0.0);
  // tmesh.continuity auto is c2 for cubics: a function fewer per clamped extra of its C2 rows.
  const auto& t = s["tmesh"];
  EXPECT_EQ(t["continuity"]["mode"], "c2");
  EXPECT_GT(t["continuity"]["lines"].get<int>(), 0);
  EXPECT_EQ(x["global_functions"], t["functions"]);
  EXPECT_EQ(t["functions"].get<int>(), t["nodes"].get<int>() - t["t_junctions"].get<int>() - t["continuity"]["constrained"].get<int>());
  EXPECT_GT(x["global_functions"].get<int>(), 0);
  const double frac = x["frac_scaled_jacobian_above_0_5"].get<double>();
  EXPECT_GT(frac, 0.5);  // a box: nearly all elements are good
  EXPECT_LE(frac, 1.0);
  for (const char* k : {"vtu", "bext", "k", "json", "msh", "png"}) EXPECT_TRUE(x["outputs"].contains(k)) << k;
}

// Blocks sharing faces (the pillowed cube) share functions: fewer global functions than control
// points, and every global function is used by some element of bezier.json.
TEST_F(Box, BlocksShareTheirFaceFunctions) {
  ASSERT_EQ(result.code, 0) << result.output;
  const fs::path w = dir / "work";
  const core::Json t = core::read_stage_file((w / "tmesh.stage.json").string(), "volts-tmesh", 3);
  std::size_t control_points = 0;
  for (const auto& b : t["tmeshes"]) control_points += b["control_points"].size() / 3;
  const core::Json j = core::read_stage_file((w / "bezier.json").string(), "volts-bezier", 1);
  const std::size_t functions = j["global_functions"]["count"].get<std::size_t>();
  if (t["tmeshes"].size() > 1) EXPECT_LT(functions, control_points);
  else EXPECT_EQ(functions, control_points);
  std::vector<int> used(functions, 0);
  for (const auto& e : j["elements"])
    for (const int f : e["functions"]) ++used.at(f);
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);
}

// Every export parses with the report's counts (exports_check.h), and the box's extra checks:
// every function row of the bext has mass, and the .msh is conforming.
TEST_F(Box, EveryExportParsesAndTheMshIsConforming) {
  ASSERT_EQ(result.code, 0) << result.output;
  const fs::path w = dir / "work";
  test::expect_every_export_parses(w);
  const test::Bext b = test::read_bext((w / "bezier.bext").string());
  for (const auto& v : b.coefficient_vectors) {
    double sum = 0;
    for (const double c : v) sum += c;
    EXPECT_GT(sum, 0.0);  // a function's row has mass somewhere
  }
  const test::Msh m = test::read_msh((w / "bezier.msh").string());
  // Conforming: every element face (its 16 node tags) is shared by two elements, or lies on the
  // box's surface (the box's faces are planes: all its nodes on one bounding plane).
  Eigen::AlignedBox3d box;
  for (const auto& [tag, p] : m.nodes) box.extend(p);
  const auto lattice = extract::gmsh_hex_nodes(3);
  std::map<std::vector<long>, int> faces;
  for (const auto& el : m.elements)
    for (int axis = 0; axis < 3; ++axis)
      for (const int side : {0, 3}) {
        std::vector<long> f;
        for (int n = 0; n < 64; ++n)
          if (lattice[n][axis] == side) f.push_back(el[n]);
        std::sort(f.begin(), f.end());
        ++faces[f];
      }
  int inner = 0;
  for (const auto& [f, count] : faces) {
    ASSERT_LE(count, 2);
    if (count == 2) {
      ++inner;
      continue;
    }
    bool on_plane = false;
    for (int d = 0; d < 3 && !on_plane; ++d)
      for (const double plane : {box.min()[d], box.max()[d]}) {
        bool all = true;
        for (const long t : f) all = all && std::abs(m.nodes.at(t)[d] - plane) < 1e-9 * box.diagonal().norm();
        on_plane = on_plane || all;
      }
    EXPECT_TRUE(on_plane) << "a face of one element only, inside the box: the mesh is not conforming";
  }
  EXPECT_GT(inner, 0);
}

TEST_F(Box, ExportsListLimitsTheFilesAndRefusesUnknownNames) {
  ASSERT_EQ(result.code, 0) << result.output;
  const fs::path w = dir / "only";
  fs::create_directories(w);
  fs::copy_file(dir / "work" / "tmesh.stage.json", w / "tmesh.stage.json");
  test::write_text(dir / "only.yaml", "extract: {exports: [json]}\n");
  const auto ok = test::run(test::bin("volts-extract") + " --config " + (dir / "only.yaml").string() + " --workdir " + w.string());
  ASSERT_EQ(ok.code, 0) << ok.output;
  EXPECT_TRUE(fs::exists(w / "bezier.json"));
  for (const char* f : {"bezier.vtu", "bezier.bext", "bezier.k", "bezier.msh", "scaled_jacobian_histogram.png"})
    EXPECT_FALSE(fs::exists(w / f)) << f;
  test::write_text(dir / "bad.yaml", "extract: {exports: [vtu, stl]}\n");
  const auto bad = test::run(test::bin("volts-extract") + " --config " + (dir / "bad.yaml").string() + " --workdir " + w.string());
  EXPECT_EQ(bad.code, 3) << bad.output;
  EXPECT_NE(bad.output.find("extract.exports"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("'stl'"), std::string::npos) << bad.output;
}
