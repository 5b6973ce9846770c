// `volts run` with route: tet on a generated tetrahedron (the shape the polycube route cannot take),
// volts-tet2hex on a .vtu of tets, and on bad input: a clear message naming the file, a non-zero
// exit code, and no bezier.vtu.
#include <gtest/gtest.h>

#include <filesystem>

#include "common/test_util.h"
#include "core/stage_file.h"
#include "extract/exports_check.h"

namespace fs = std::filesystem;
using namespace volts;

TEST(TetRoutePipeline, VoltsRunOnATetrahedron) {
  const fs::path dir = test::fresh_dir("tetroute", "run");
  test::write_text(dir / "run.yaml", "route: tet\ninput: {generate: tetrahedron, resolution: 4}\ntet2hex: {degree: 2}\n");
  const test::Outcome r = test::run(test::bin("volts") + " run " + (dir / "run.yaml").string() + " --workdir " + (dir / "work").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("tet2hex"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("open in ParaView: "), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(dir / "work" / "bezier.vtu"));
  EXPECT_FALSE(fs::exists(dir / "work" / "classify.stage.json"));  // the polycube stages did not run
  const auto rep = core::read_report((dir / "work").string());
  ASSERT_TRUE(rep["stages"].contains("tet2hex")) << rep.dump();
  const auto& s = rep["stages"]["tet2hex"];
  for (const char* k : {"bezier_elements", "degree", "min_scaled_jacobian", "max_scaled_jacobian", "hausdorff_rel", "volume_rel_error", "time_s"})
    EXPECT_TRUE(s.contains(k)) << k;
  EXPECT_EQ(s["degree"], 2);
  EXPECT_GT(s["bezier_elements"].get<int>(), 0);
  EXPECT_EQ(s["bezier_elements"].get<int>(), 4 * s["tets"].get<int>());
  EXPECT_EQ(s["certified_valid"], s["bezier_elements"]);
  EXPECT_GT(s["min_scaled_jacobian"].get<double>(), 0);
  EXPECT_LT(s["volume_rel_error"].get<double>(), 1e-10);
  // --from/--to name the route's stage; a polycube stage is refused for this route.
  const test::Outcome again = test::run(test::bin("volts") + " run " + (dir / "run.yaml").string() + " --workdir " + (dir / "work").string() + " --from tet2hex --to tet2hex");
  EXPECT_EQ(again.code, 0) << again.output;
  const test::Outcome wrong = test::run(test::bin("volts") + " run " + (dir / "run.yaml").string() + " --workdir " + (dir / "work").string() + " --from tmesh");
  EXPECT_EQ(wrong.code, 2) << wrong.output;
  EXPECT_NE(wrong.output.find("tet2hex"), std::string::npos) << wrong.output;
  fs::remove_all(dir);
}

// The route writes every solver export of extract.exports (global functions: the hexes' distinct
// control points), and each parses with the report's counts.
TEST(TetRoutePipeline, EveryExportParses) {
  const fs::path dir = test::fresh_dir("tetroute", "exports");
  test::write_text(dir / "run.yaml", "route: tet\ninput: {generate: tetrahedron, resolution: 4}\n");
  const test::Outcome r = test::run(test::bin("volts") + " run " + (dir / "run.yaml").string() + " --workdir " + (dir / "work").string());
  ASSERT_EQ(r.code, 0) << r.output;
  test::expect_every_export_parses(dir / "work", /*gmsh_check=*/true, "tet2hex");
  const auto s = core::read_report((dir / "work").string())["stages"]["tet2hex"];
  EXPECT_EQ(s["partition_of_unity_error"].get<double>(), 0.0);
  // Neighbouring hexes share their face's functions: far fewer than 64 per hex.
  EXPECT_LT(s["global_functions"].get<long>(), 40 * s["bezier_elements"].get<long>());
  // extract.exports chooses the files here too.
  test::write_text(dir / "vtu.yaml", "route: tet\ninput: {generate: tetrahedron, resolution: 4}\nextract: {exports: [vtu]}\n");
  ASSERT_EQ(test::run(test::bin("volts") + " run " + (dir / "vtu.yaml").string() + " --workdir " + (dir / "lean").string()).code, 0);
  EXPECT_TRUE(fs::exists(dir / "lean" / "bezier.vtu"));
  EXPECT_FALSE(fs::exists(dir / "lean" / "bezier.bext"));
  EXPECT_FALSE(fs::exists(dir / "lean" / "bezier.msh"));
  fs::remove_all(dir);
}

TEST(TetRoutePipeline, BadInputNamesTheFileAndWritesNothing) {
  const fs::path dir = test::fresh_dir("tetroute", "bad");
  test::write_text(dir / "open.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  const test::Outcome r = test::run(test::bin("volts-tet2hex") + " --workdir " + (dir / "work").string() + " --input " + (dir / "open.off").string());
  EXPECT_EQ(r.code, 4) << r.output;
  EXPECT_NE(r.output.find("open.off"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "work" / "bezier.vtu"));
  test::write_text(dir / "bad.vtu", "<VTKFile>truncated");
  const test::Outcome v = test::run(test::bin("volts-tet2hex") + " --workdir " + (dir / "work").string() + " --input " + (dir / "bad.vtu").string());
  EXPECT_EQ(v.code, 4) << v.output;
  EXPECT_NE(v.output.find("bad.vtu"), std::string::npos) << v.output;
  EXPECT_FALSE(fs::exists(dir / "work" / "bezier.vtu"));
  test::write_text(dir / "cfg.yaml", "route: tet\ntet2hex: {degree: 9}\n");
  const test::Outcome c = test::run(test::bin("volts-tet2hex") + " --config " + (dir / "cfg.yaml").string() + " --workdir " + (dir / "work").string());
  EXPECT_EQ(c.code, 3) << c.output;
  EXPECT_NE(c.output.find("tet2hex.degree"), std::string::npos) << c.output;
  // Degree 4 with Gmsh's file asked for (the default list): refused before any work, naming both keys.
  test::write_text(dir / "d4.yaml", "route: tet\ninput: {generate: tetrahedron, resolution: 4}\ntet2hex: {degree: 4}\n");
  const test::Outcome d4 = test::run(test::bin("volts-tet2hex") + " --config " + (dir / "d4.yaml").string() + " --workdir " + (dir / "work").string());
  EXPECT_EQ(d4.code, 3) << d4.output;
  EXPECT_NE(d4.output.find("extract.exports"), std::string::npos) << d4.output;
  EXPECT_NE(d4.output.find("tet2hex.degree"), std::string::npos) << d4.output;
  EXPECT_FALSE(fs::exists(dir / "work" / "bezier.vtu"));
  fs::remove_all(dir);
}

// The route's output is itself valid input: bezier.vtu's hexes are not tets, but a .vtu of tets
// is converted as given (here: the degree-1 tets TetGen would give, written by hand).
TEST(TetRoutePipeline, VtuOfLinearTets) {
  const fs::path dir = test::fresh_dir("tetroute", "vtu");
  test::write_text(dir / "two.vtu",
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
        "<UnstructuredGrid><Piece NumberOfPoints=\"5\" NumberOfCells=\"2\">\n"
        "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1 1 1 1</DataArray></Points>\n"
        "<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3 1 4 2 3</DataArray>\n"
        "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4 8</DataArray>\n"
        "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10 10</DataArray></Cells>\n"
        "</Piece></UnstructuredGrid></VTKFile>\n");
  test::write_text(dir / "cfg.yaml", "route: tet\ntet2hex: {degree: 2}\n");
  const test::Outcome r = test::run(test::bin("volts-tet2hex") + " --config " + (dir / "cfg.yaml").string() + " --workdir " + (dir / "work").string() +
                        " --input " + (dir / "two.vtu").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto s = core::read_report((dir / "work").string())["stages"]["tet2hex"];
  EXPECT_EQ(s["bezier_elements"], 8);
  EXPECT_EQ(s["certified_valid"], 8);
  EXPECT_EQ(s["boundary_faces"], 6);
  EXPECT_LT(s["volume_rel_error"].get<double>(), 1e-12);
  fs::remove_all(dir);
}
