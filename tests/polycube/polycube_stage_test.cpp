// volts-polycube as a user runs it: the stage-file contract of kind "tori" (two tori on a disk,
// docs/formats.md) and of kind "torus" (unchanged: the tmesh stage reads it), the report's keys,
// and an unrealizable component graph as a topology error (exit 5) naming the components.
#include <gtest/gtest.h>

#include <fstream>

#include "common/test_util.h"
#include "core/stage_file.h"

using namespace volts;

namespace {

core::Json read_json(const std::filesystem::path& p) { return core::Json::parse(std::ifstream(p)); }

}  // namespace

TEST(PolycubeStage, TwoToriWriteOneRingEachWithTheirOwnIds) {
  const auto dir = test::fresh_dir("polycube_stage", "eight");
  test::write_text(dir / "c.yaml", "input: {file: " + std::string(VOLTS_SHARED_MODELS) + "/cfwen_eight.off}\n");
  const auto r = test::run(test::bin("volts") + " run " + (dir / "c.yaml").string() + " --workdir " + dir.string() + " --to polycube");
  ASSERT_EQ(r.code, 0) << r.output;
  const core::Json j = read_json(dir / "polycube.stage.json");
  EXPECT_EQ(j["kind"], "tori");
  EXPECT_EQ(j["version"], 2);
  EXPECT_FALSE(j.contains("polycube") || j.contains("volume_map"));
  const core::Json& d = j["decomposition"];
  const auto points = d["layout"]["points"].get<std::vector<double>>();
  ASSERT_EQ(j["rings"].size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const core::Json& ring = j["rings"][i];
    EXPECT_EQ(ring["components"], d["tori"][i]["components"]);
    const auto lv = ring["layout_vertex"].get<std::vector<int>>();
    const std::size_t n = lv.size();
    EXPECT_TRUE(std::is_sorted(lv.begin(), lv.end()));
    EXPECT_EQ(ring["polycube"]["ring"], 4);
    EXPECT_EQ(ring["polycube"]["points"].size(), 3 * n);
    for (const auto& corners : ring["polycube"]["corner_vertex"])
      for (int v : corners) EXPECT_LT(v, static_cast<int>(n));
    // The volume map's surface vertices are the ring's vertices: same ids, same physical points,
    // parameters = the ring's embedding points.
    const core::Json& vm = ring["volume_map"];
    ASSERT_EQ(vm["surface_vertices"], static_cast<int>(n));
    const auto phys = vm["physical"].get<std::vector<double>>(), par = vm["parameter"].get<std::vector<double>>();
    const auto emb = ring["polycube"]["points"].get<std::vector<double>>();
    for (std::size_t v = 0; v < n; ++v)
      for (int k = 0; k < 3; ++k) {
        ASSERT_EQ(phys[3 * v + k], points[3 * lv[v] + k]) << "ring " << i << " vertex " << v;
        ASSERT_EQ(par[3 * v + k], emb[3 * v + k]) << "ring " << i << " vertex " << v;
      }
    EXPECT_EQ(vm["flipped_tets"], 0);
  }
  const core::Json rep = read_json(dir / "report.json")["stages"]["polycube"];
  EXPECT_EQ(rep["cubes"], 8);
  EXPECT_EQ(rep["tori"], 2);
  EXPECT_EQ(rep["virtual_components"], 0);
  EXPECT_EQ(rep["flipped_surface_triangles"], 0);
  EXPECT_EQ(rep["flipped_tets"], 0);
  EXPECT_EQ(rep["rings"].size(), 2u);
  EXPECT_EQ(rep["tets"], rep["rings"][0]["tets"].get<int>() + rep["rings"][1]["tets"].get<int>());
  EXPECT_GT(rep["max_angle_distortion_deg"].get<double>(), 0);
  EXPECT_GT(rep["time_s"].get<double>(), 0);
  for (const char* f : {"polycube.vtp", "polycube_mapped.vtp", "polycube_tets.vtu", "polycube_tets_mapped.vtu"}) EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;

  // The tori no longer meeting on the disk: a topology error naming the components.
  core::Json s = read_json(dir / "split.stage.json");
  core::Json kept = core::Json::array();
  for (const auto& c : s["decomposition"]["contacts"])
    if (c["via"] != "filled_patch") kept.push_back(c);
  s["decomposition"]["contacts"] = kept;
  std::ofstream(dir / "split.stage.json") << s.dump();
  const auto e = test::run(test::bin("volts-polycube") + " --config " + (dir / "c.yaml").string() + " --workdir " + dir.string());
  EXPECT_EQ(e.code, 5) << e.output;
  EXPECT_NE(e.output.find("meet on 0 filled disks (torus 0: components 0, 1, 2, 3; torus 1: components 4, 5, 6, 7)"), std::string::npos) << e.output;
}

TEST(PolycubeStage, OneTorusKeepsKindTorus) {
  const auto dir = test::fresh_dir("polycube_stage", "torus");
  test::write_text(dir / "c.yaml", "input: {generate: torus, resolution: 16}\n");
  const auto r = test::run(test::bin("volts") + " run " + (dir / "c.yaml").string() + " --workdir " + dir.string() + " --to polycube");
  ASSERT_EQ(r.code, 0) << r.output;
  const core::Json j = read_json(dir / "polycube.stage.json");
  EXPECT_EQ(j["kind"], "torus");
  EXPECT_FALSE(j.contains("rings"));
  EXPECT_EQ(j["polycube"]["ring"], 4);
  EXPECT_EQ(j["volume_map"]["flipped_tets"], 0);
  EXPECT_EQ(j["volume_map"]["surface_vertices"].get<std::size_t>() * 3, j["polycube"]["points"].size());
  EXPECT_EQ(read_json(dir / "report.json")["stages"]["polycube"]["tori"], 1);
}
