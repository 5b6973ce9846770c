// volts-polycube as a user runs it: the stage-file contract of kind "tori" (two tori on a disk,
// docs/formats.md) and of kind "torus" (unchanged: the tmesh stage reads it), the report's keys,
// the polycube structure of every kind (`structure`, polycube_structure.vtu), and an unrealizable
// component graph as a topology error (exit 5) naming the components.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>

#include "common/test_util.h"
#include "core/atomic_file.h"
#include "core/stage_file.h"

using namespace volts;

namespace {

core::Json read_json(const std::filesystem::path& p) { return core::Json::parse(std::ifstream(p)); }

std::filesystem::path run_to_polycube(const std::string& name, const std::string& yaml) {
  const auto dir = test::fresh_dir("polycube_stage", name);
  test::write_text(dir / "c.yaml", yaml);
  const auto r = test::run(test::bin("volts") + " run " + (dir / "c.yaml").string() + " --workdir " + dir.string() + " --to polycube");
  EXPECT_EQ(r.code, 0) << r.output;
  return dir;
}

// The structure member of the stage file (structure.h's JSON) with these counts, the report's
// counts the same, one cube per non-virtual component labelled after it, and
// polycube_structure.vtu beside the stage file. (That it parses and checks: volts-polycube checks
// it before writing, volts-tmesh reads it with structure_from_json + check — tests/hardening and
// the pipeline tests run that reader; this test links no polycube library.)
core::Json expect_structure(const std::filesystem::path& dir, int cubes, int tori, int virt, int gluings, int contacts) {
  const core::Json j = read_json(dir / "polycube.stage.json");
  EXPECT_EQ(j["version"], 2);
  const core::Json& s = j["structure"];
  for (const char* member : {"cubes", "primitives", "gluings", "virtual_components", "contacts"}) EXPECT_TRUE(s[member].is_array()) << member;
  EXPECT_EQ(s["cubes"].size(), static_cast<std::size_t>(cubes));
  EXPECT_EQ(std::count_if(s["primitives"].begin(), s["primitives"].end(), [](const core::Json& p) { return p["torus"] == true; }), tori);
  EXPECT_EQ(s["virtual_components"].size(), static_cast<std::size_t>(virt));
  EXPECT_EQ(s["gluings"].size(), static_cast<std::size_t>(gluings));
  EXPECT_EQ(s["contacts"].size(), static_cast<std::size_t>(contacts));
  const core::Json rep = read_json(dir / "report.json")["stages"]["polycube"];
  EXPECT_EQ(rep["cubes"], cubes);
  EXPECT_EQ(rep["tori"], tori);
  EXPECT_EQ(rep["virtual_components"], virt);
  EXPECT_EQ(rep["gluings"], gluings);
  EXPECT_EQ(rep["contacts"], contacts);
  std::set<std::string> labels, components;
  for (const auto& c : s["cubes"]) labels.insert(c["label"].get<std::string>());
  const core::Json& comps = j["decomposition"]["components"];
  for (std::size_t c = 0; c < comps.size(); ++c)
    if (comps[c]["type"] != "virtual") components.insert("component " + std::to_string(c));
  EXPECT_EQ(labels, components);
  EXPECT_TRUE(std::filesystem::exists(dir / "polycube_structure.vtu"));
  return j;
}

}  // namespace

TEST(PolycubeStage, TwoToriWriteOneRingEachWithTheirOwnIds) {
  const auto dir = test::fresh_dir("polycube_stage", "eight");
  test::write_text(dir / "c.yaml", "input: {file: " + std::string(VOLTS_SHARED_MODELS) + "/cfwen_eight.off}\nsplit: {genus2: disk}\n");
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

  // The structure: both tori (eight cubes, four ring gluings each) and the disk as a contact that
  // is not a gluing, on a face around the tube (not a cross section, a = faces 0, 1) of a cube of each.
  const core::Json stage = expect_structure(dir, 8, 2, 0, 8, 1);
  const core::Json& st = stage["structure"];
  const core::Json& disk = st["contacts"][0];
  EXPECT_EQ(disk["conforming"], false);
  EXPECT_NE(st["cubes"][disk["a"].get<int>()]["primitive"], st["cubes"][disk["b"].get<int>()]["primitive"]);
  EXPECT_GE(disk["fa"].get<int>(), 2);
  EXPECT_GE(disk["fb"].get<int>(), 2);

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
  expect_structure(dir, 4, 1, 0, 4, 0);
}

TEST(PolycubeStage, BoxAndCubeWithHoleWriteTheirStructure) {
  const auto box = run_to_polycube("box_structure", "input: {generate: box, resolution: 4}\n");
  EXPECT_EQ(expect_structure(box, 1, 0, 0, 0, 0)["kind"], "cube");
  // The hole: a virtual component of the cube, its box exactly the map's hole box.
  const auto hole = run_to_polycube("hole_structure", "input: {generate: cube-with-hole, resolution: 16}\n");
  const core::Json j = expect_structure(hole, 1, 0, 1, 0, 0);
  EXPECT_EQ(j["kind"], "difference");
  const core::Json& v = j["structure"]["virtual_components"][0];
  EXPECT_EQ(v["label"], "component " + std::to_string(j["polycube"]["virtual_component"].get<int>()));
  EXPECT_EQ(j["structure"]["cubes"][0]["label"], "component " + std::to_string(j["polycube"]["cube"].get<int>()));
  ASSERT_EQ(v["boxes"].size(), 1u);
  EXPECT_EQ(v["boxes"][0]["lo"], j["polycube"]["hole_lo"]);
  EXPECT_EQ(v["boxes"][0]["hi"], j["polycube"]["hole_hi"]);
  EXPECT_EQ(j["structure"]["cubes"][0]["lo"], (core::Json{0.0, 0.0, 0.0}));
  EXPECT_EQ(j["structure"]["cubes"][0]["hi"], (core::Json{1.0, 1.0, 1.0}));
}

// split.torus_cubes (4..16): one torus primitive of that many cubes, its ring closed once by a
// translation of minus n unit cubes along a; a ring split did not close is a topology error.
TEST(PolycubeStage, TorusOfSixCubesAndARingThatDoesNotClose) {
  const auto dir = run_to_polycube("torus6", "input: {generate: torus, resolution: 16}\nsplit: {torus_cubes: 6}\n");
  const core::Json j = expect_structure(dir, 6, 1, 0, 6, 0);
  EXPECT_EQ(j["polycube"]["ring"], 6);
  int closing = 0;
  for (const auto& g : j["structure"]["gluings"])
    if (g["closes_torus"] == 0) {
      ++closing;
      EXPECT_EQ(g["offset"], (core::Json{-6.0, 0.0, 0.0}));
    }
  EXPECT_EQ(closing, 1);

  // split's contact between components 1 and 2 lost: the ring does not close.
  const std::string before = core::read_text_file((dir / "polycube.stage.json").string());
  core::Json s = read_json(dir / "split.stage.json");
  core::Json kept = core::Json::array();
  for (const auto& c : s["decomposition"]["contacts"])
    if (!(c["a"] == 1 && c["b"] == 2)) kept.push_back(c);
  ASSERT_EQ(kept.size(), 5u);
  s["decomposition"]["contacts"] = kept;
  std::ofstream(dir / "split.stage.json") << s.dump();
  const auto e = test::run(test::bin("volts-polycube") + " --config " + (dir / "c.yaml").string() + " --workdir " + dir.string());
  EXPECT_EQ(e.code, 5) << e.output;
  EXPECT_NE(e.output.find("split's decomposition cannot be realized as a polycube: torus 'torus 0': cube 'component 1' and cube "
                          "'component 2' are not glued on whole faces"),
            std::string::npos)
      << e.output;
  EXPECT_EQ(core::read_text_file((dir / "polycube.stage.json").string()), before) << "nothing written";
}
