// The catalogue of bad inputs (issue 10, docs/errors.md): each one goes through the real executable
// a user would run, and each test asserts three things: the message names the file and the
// problem, the exit code is the documented non-zero one, and the work directory holds exactly what
// it held before (no output, no half file, no temporary file).
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "common/test_util.h"
#include "core/atomic_file.h"
#include "core/stage_file.h"

namespace fs = std::filesystem;
using namespace volts;

namespace {

/// A run of the box pipeline at the smallest sizes (level 1, degree 1): valid stage files and a
/// valid bezier.vtu for the cases to break. Made once per test process.
const fs::path& good_run() {
  static const fs::path dir = [] {
    const fs::path d = test::fresh_dir("hardening", "good");
    test::write_text(d / "run.yaml", "input: {generate: box, resolution: 4}\ntmesh: {level: 1, degree: 1}\n");
    const test::Outcome r = test::run(test::bin("volts") + " run " + (d / "run.yaml").string() + " --workdir " +
                                      (d / "w").string() + " -q");
    if (r.code != 0) throw std::runtime_error("the good run failed: " + r.output);
    return d / "w";
  }();
  return dir;
}

core::Json good_stage(const std::string& stage) {
  return core::Json::parse(core::read_text_file((good_run() / (stage + ".stage.json")).string()));
}

std::string good_text(const std::string& name) { return core::read_text_file((good_run() / name).string()); }

/// Every file under `dir` (hidden ones too) with its content.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    files[fs::relative(e.path(), dir).string()] = e.is_regular_file() ? core::read_text_file(e.path().string()) : "<dir>";
  return files;
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) s.replace(p, from.size(), to);
  return s;
}

// ---- The bad inputs -------------------------------------------------------------------------

/// One bad input: `setup` writes it into the work directory W; `command` is run with "{W}" replaced
/// by W and "{BIN}" by the executables' folder; the output must contain every fragment of `expect`
/// (with "{W}" replaced) and the exit code must be `code`.
struct BadInput {
  std::string name;
  std::function<void(const fs::path& w)> setup;
  std::string command;
  int code;
  std::vector<std::string> expect;
};

std::ostream& operator<<(std::ostream& o, const BadInput& b) { return o << b.name; }

const std::string tet_vertices = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
const std::string tet_faces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

/// A surface file given to volts-classify: exit 4, the message names the file.
BadInput surface(const std::string& name, const std::string& file, const std::string& content, const std::string& problem) {
  return {name, [=](const fs::path& w) { test::write_text(w / file, content); },
          "{BIN}/volts-classify --input {W}/" + file + " --workdir {W}", 4, {"{W}/" + file + ": ", problem}};
}

/// A config given to `volts run` (which checks it before any stage runs): exit `code`.
BadInput config(const std::string& name, const std::string& yaml, const std::string& problem, int code = 3) {
  return {name, [=](const fs::path& w) { test::write_text(w / "run.yaml", yaml); },
          "{BIN}/volts run {W}/run.yaml --workdir {W}/out", code, {"{W}/run.yaml: ", problem}};
}

/// A stage file of the good run, changed by `edit` (as text), read by the next stage's executable.
BadInput stage(const std::string& name, const std::string& file, const std::string& tool,
               const std::function<std::string()>& content, const std::string& problem) {
  return {name, [=](const fs::path& w) { test::write_text(w / file, content()); }, "{BIN}/" + tool + " --workdir {W}", 4,
          {"{W}/" + file + ": ", problem}};
}

/// The same with the stage file's JSON changed by `edit`.
BadInput stage_json(const std::string& name, const std::string& stage_name, const std::string& tool,
                    const std::function<void(core::Json&)>& edit, const std::string& problem) {
  return stage(name, stage_name + ".stage.json", tool, [=] {
    core::Json j = good_stage(stage_name);
    edit(j);
    return j.dump();
  }, problem);
}

/// A .vtu given to volts-check: exit 4, and no FILE.check.vtu.
BadInput vtu(const std::string& name, const std::function<std::string()>& content, const std::string& problem) {
  return {name, [=](const fs::path& w) { test::write_text(w / "mesh.vtu", content()); }, "{BIN}/volts-check {W}/mesh.vtu", 4,
          {"{W}/mesh.vtu: ", problem}};
}

std::string binary_stl_tetrahedron() {
  const float corners[4][3][3] = {{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}, {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}},
                                  {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  std::string s(80, ' ');
  const std::uint32_t n = 4;
  s.append(reinterpret_cast<const char*>(&n), 4);  // little endian on every machine volts builds on
  for (const auto& t : corners) {
    s.append(12, '\0');  // normal: unused
    s.append(reinterpret_cast<const char*>(t), sizeof t);
    s.append(2, '\0');
  }
  return s;
}

std::string garbage(std::size_t n) {
  std::string s;
  std::uint32_t x = 12345;
  for (std::size_t i = 0; i < n; ++i) {
    x = x * 1103515245u + 12345u;
    s += static_cast<char>(x >> 24);
  }
  return s;
}

std::string ascii_vtu(const std::string& points, long long npoints, const std::string& connectivity, const std::string& offsets,
                      const std::string& types, int ncells, const std::string& cell_data = "") {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"2.2\" byte_order=\"LittleEndian\">\n"
         "<UnstructuredGrid><Piece NumberOfPoints=\"" + std::to_string(npoints) + "\" NumberOfCells=\"" + std::to_string(ncells) +
         "\">\n" + cell_data + "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">" + points +
         "</DataArray></Points>\n<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">" + connectivity +
         "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">" + offsets +
         "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">" + types +
         "</DataArray></Cells>\n</Piece></UnstructuredGrid></VTKFile>\n";
}

/// A linear tet whose last point is NaN: the points as raw appended data (an ASCII NaN would not
/// even parse), the rest ASCII.
std::string nan_point_vtu() {
  const double xyz[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, std::numeric_limits<double>::quiet_NaN()};
  const std::uint32_t bytes = sizeof xyz;
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"2.2\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt32\">\n<UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n"
         "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/></Points>\n"
         "<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3</DataArray>\n"
         "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4</DataArray>\n"
         "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray></Cells>\n</Piece></UnstructuredGrid>\n"
         "<AppendedData encoding=\"raw\">\n_" +
         std::string(reinterpret_cast<const char*>(&bytes), 4) + std::string(reinterpret_cast<const char*>(xyz), bytes) +
         "\n</AppendedData>\n</VTKFile>\n";
}

const std::string cube_points = "0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1";

std::vector<BadInput> catalogue() {
  std::vector<BadInput> c = {
      // ---- surfaces (volts-classify, exit 4) ----
      surface("OpenSurface", "open.off", "OFF\n4 2 0\n" + tet_vertices + "3 0 2 1\n3 0 1 3\n", "boundary edge"),
      surface("NonManifoldEdge", "fin.off",
              "OFF\n5 6 0\n" + tet_vertices + "0 0 -1\n" + tet_faces + "3 0 1 4\n3 1 0 4\n", "non-manifold edge"),
      surface("NonManifoldVertex", "bowtie.off",
              "OFF\n7 8 0\n" + tet_vertices + "-1 0 0\n0 -1 0\n0 0 -1\n" + tet_faces + "3 0 4 5\n3 0 6 4\n3 0 5 6\n3 4 6 5\n",
              "non-manifold vert"),
      surface("InconsistentOrientation", "misoriented.off", "OFF\n4 4 0\n" + tet_vertices + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 3 2\n",
              "orient"),
      surface("ZeroAreaFace", "degenerate.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n2 0 0\n0 0 1\n" + tet_faces, "zero-area"),
      surface("NaNCoordinate", "nan.off", "OFF\n4 4 0\n0 0 0\n1 0 0\nnan 1 0\n0 0 1\n" + tet_faces, "NaN/Inf"),
      surface("InfCoordinate", "inf.obj", "v 0 0 0\nv 1 0 0\nv 0 inf 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n", "NaN/Inf"),
      surface("EmptyFile", "empty.off", "", "empty file"),
      surface("BlankFile", "blank.stl", " \n\n\t\n", "empty file"),
      surface("TruncatedOff", "truncated.off", "OFF\n4 4 0\n" + tet_vertices + "3 0 2 1\n3 0 1", "truncated OFF file"),
      surface("TruncatedBinaryStl", "truncated.stl", binary_stl_tetrahedron().substr(0, 150), "truncated binary STL file"),
      surface("TrailingBytesBinaryStl", "trailing.stl", binary_stl_tetrahedron() + "garbage", "malformed binary STL file"),
      surface("StlFacetWithTwoVertices", "two.stl",
              "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid t\n", "STL needs 3"),
      surface("AsciiStlWithoutEndsolid", "cut.stl",
              "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n",
              "does not end with 'endsolid'"),
      surface("BinaryGarbagePly", "garbage.ply", garbage(600), "not a PLY file"),
      surface("BinaryGarbageOff", "garbage.off", garbage(600), "not an OFF file"),
      surface("HugeVertexCountOff", "huge.off", "OFF\n2000000000 1 0\n0 0 0\n",
              "declares 2000000000 vertices, more than this machine can hold"),
      surface("HugeVertexCountPly", "huge.ply",
              "ply\nformat binary_little_endian 1.0\nelement vertex 3000000000\nproperty float x\nproperty float y\n"
              "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n",
              "declares 3000000000 vertex elements, more than this machine can hold"),
      surface("IntegerPlyCoordinates", "int.ply",
              "ply\nformat ascii 1.0\nelement vertex 4\nproperty int x\nproperty int y\nproperty int z\nelement face 4\n"
              "property list uchar int vertex_indices\nend_header\n" + tet_vertices + tet_faces,
              "only float and double are read"),
      surface("UnknownExtension", "part.txt", "OFF\n4 4 0\n" + tet_vertices + tet_faces, "unknown extension '.txt'"),
      {"MissingSurfaceFile", [](const fs::path&) {}, "{BIN}/volts-classify --input {W}/nowhere.off --workdir {W}", 4,
       {"{W}/nowhere.off: ", "cannot open file"}},
      surface("TwoComponents", "two.off",
              "OFF\n8 8 0\n" + tet_vertices + "5 5 5\n6 5 5\n5 6 5\n5 5 6\n" + tet_faces + "3 4 6 5\n3 4 5 7\n3 4 7 6\n3 5 6 7\n",
              "component"),
      surface("FlatSurface", "flat.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n", "encloses no volume"),
      surface("ObjIndexOutOfRange", "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 9\n",
              "out of range"),
      surface("ObjNotANumber", "word.obj", "v 0 0 0\nv 1 0 zero\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
              "'zero' is not a number"),

      // ---- config (volts run, checked before any stage; exit 3) ----
      config("ConfigUnknownKey", "input: {generate: box}\ntmesh: {levle: 3}\n", "unknown key 'tmesh.levle'"),
      config("ConfigOutOfRange", "input: {generate: box}\ntmesh: {level: 9}\n", "tmesh.level: 9 is out of range [1, 7]"),
      config("ConfigWrongType", "input: {generate: box}\ntmesh: {level: three}\n", "tmesh.level: must be an integer, got 'three'"),
      config("ConfigNaNValue", "input: {generate: bulged-box, bulge: .nan}\n", "input.bulge: nan is out of range [0, 0.35]"),
      config("ConfigNotYaml", "input: [generate\n", "not valid YAML"),
      config("ConfigFileAndGenerate", "input: {generate: box, file: part.off}\n", "give either 'file' or 'generate'"),
      config("ConfigUnknownRoute", "route: bogus\ninput: {generate: box}\n", "route: 'bogus' is not one of"),
      config("ConfigTetVolumeTooSmall", "route: tet\ninput: {generate: box}\ntet2hex: {max_volume_rel: 1e-9}\n",
             "tet2hex.max_volume_rel: must be 0 (off) or in [1e-05, 1]"),
      config("ConfigNestedTooDeep", "input: " + std::string(100000, '[') + "\n", "line 1 is nested too deeply"),
      config("ConfigNotAMapping", "- a\n- b\n", "the config must be a mapping"),
      {"ConfigFileMissing", [](const fs::path&) {}, "{BIN}/volts run {W}/absent.yaml --workdir {W}/out", 4,
       {"{W}/absent.yaml: ", "cannot open file"}},

      // ---- stage files (exit 4) ----
      stage_json("StageVersionTooNew", "classify", "volts-split", [](core::Json& j) { j["version"] = 99; },
                 "volts-classify version 99 is newer than this volts reads (up to 1)"),
      stage("StageOfAnotherStage", "classify.stage.json", "volts-split", [] { return good_text("split.stage.json"); },
            "is a volts-split file, expected volts-classify"),
      stage("StageTruncated", "classify.stage.json", "volts-split",
            [] { const std::string t = good_text("classify.stage.json"); return t.substr(0, t.size() / 2); },
            "truncated or malformed JSON at byte"),
      stage("StageEmpty", "classify.stage.json", "volts-split", [] { return std::string(); }, "file is empty"),
      stage("StageBinaryGarbage", "tmesh.stage.json", "volts-extract", [] { return garbage(300); }, "malformed JSON"),
      {"StageMissing", [](const fs::path&) {}, "{BIN}/volts-split --workdir {W}", 4, {"{W}/classify.stage.json: ", "cannot open file"}},
      stage_json("StageWithoutClassification", "split", "volts-polycube", [](core::Json& j) { j.erase("classification"); },
                 "missing \"classification\""),
      stage_json("StageSurfaceNotClosed", "classify", "volts-split",
                 [](core::Json& j) {
                   auto& f = j["surface"]["faces"];
                   f.erase(f.end() - 3, f.end());
                 },
                 "the surface in the stage file is not closed"),
      stage("StageInfiniteCoordinate", "classify.stage.json", "volts-split",
            [] {
              core::Json j = good_stage("classify");
              j["surface"]["vertices"][0] = 12345.5;
              return replace_all(j.dump(), "12345.5", "1e999");
            },
            "malformed JSON: [json.exception.out_of_range.406] number overflow parsing '1e999'"),
      stage_json("StageFloatWhereIntegerExpected", "classify", "volts-split",
                 [](core::Json& j) { j["classification"]["patches"] = 1e30; },
                 "classification.patches must hold integers, got 1e+30"),
      stage_json("MismatchedStagesClassification", "classify", "volts-split",
                 [](core::Json& j) { j["classification"]["face_patch"].erase(j["classification"]["face_patch"].begin()); },
                 "stage data do not match: classification.face_patch has"),
      // volts-fit (route fit) reads the same classify.stage.json as volts-split, through its own executable.
      stage("FitStageTruncated", "classify.stage.json", "volts-fit",
            [] { const std::string t = good_text("classify.stage.json"); return t.substr(0, t.size() / 3); },
            "truncated or malformed JSON at byte"),
      stage_json("FitStageClassificationMismatch", "classify", "volts-fit",
                 [](core::Json& j) { j["classification"]["face_patch"].erase(j["classification"]["face_patch"].begin()); },
                 "stage data do not match: classification.face_patch has"),
      stage_json("FitStageSurfaceNotClosed", "classify", "volts-fit",
                 [](core::Json& j) {
                   auto& f = j["surface"]["faces"];
                   f.erase(f.end() - 3, f.end());
                 },
                 "the surface in the stage file is not closed"),
      stage_json("MismatchedStagesPatchIndex", "split", "volts-polycube",
                 [](core::Json& j) { j["decomposition"]["components"][0]["patches"][0] = 6000; },
                 "patch 6000"),  // split::from_json or pipeline::check_decomposition, whichever reads it first
      stage_json("MismatchedStagesPolycube", "polycube", "volts-tmesh",
                 [](core::Json& j) {
                   auto& u = j["polycube"]["vertex_uvw"];
                   u.erase(u.end() - 3, u.end());
                 },
                 "polycube.vertex_uvw has"),
      // The polycube structure (polycube/structure.h), read and checked again by volts-tmesh.
      stage_json("PolycubeStructureMalformed", "polycube", "volts-tmesh", [](core::Json& j) { j["structure"]["cubes"][0]["hi"][0] = 0; },
                 "structure.cubes[0]: lo < hi must hold on every axis"),
      stage_json("PolycubeStructureNotAPolycube", "polycube", "volts-tmesh",
                 [](core::Json& j) {
                   j["structure"]["cubes"].push_back({{"label", "stray"}, {"lo", {2, 0, 0}}, {"hi", {3, 1, 1}}, {"primitive", 1}});
                   j["structure"]["primitives"].push_back({{"label", "stray"}, {"torus", false}, {"cubes", core::Json::array({1})}});
                 },
                 "structure is not a polycube: the structure is not connected: no gluings join cube 'stray' to cube 'component 0'"),
      stage_json("PolycubeStructureOfAnotherKind", "polycube", "volts-tmesh",
                 [](core::Json& j) {
                   j["structure"]["virtual_components"].push_back(
                       {{"label", "hole"}, {"cube", 0}, {"torus", false}, {"boxes", core::Json::array({{{"lo", {0.25, 0.25, 0}}, {"hi", {0.75, 0.75, 1}}}})}});
                 },
                 "structure does not match kind 'cube': it has 1 cubes, 0 tori and 1 virtual components"),
      stage_json("TmeshSizeAndKnotsDisagree", "tmesh", "volts-extract", [](core::Json& j) { j["tmeshes"][0]["size"][0] = 4; },
                 "does not match its 5 knots"),
      stage_json("TmeshFunctionIdsShort", "tmesh", "volts-extract", [](core::Json& j) { j["tmeshes"][0]["function_ids"].erase(j["tmeshes"][0]["function_ids"].begin()); },
                 "tmesh function_ids has"),
      // T-junctions (tmesh stage file v3, adaptive levels): a row off one, and rows naming each other.
      stage_json("TmeshJunctionWeightsOffOne", "tmesh", "volts-extract",
                 [](core::Json& j) {
                   auto& t = j["tmeshes"][0];
                   t["constraints"] = core::Json::array({{{"point", 0}, {"ids", {t["function_ids"][1]}}, {"weights", {0.5}}}});
                 },
                 "weights summing to 0.5"),
      stage_json("TmeshJunctionsNameEachOther", "tmesh", "volts-extract",
                 [](core::Json& j) {
                   auto& t = j["tmeshes"][0];
                   t["constraints"] = core::Json::array({{{"point", 0}, {"ids", {t["function_ids"][1]}}, {"weights", {1.0}}},
                                                         {{"point", 1}, {"ids", {t["function_ids"][0]}}, {"weights", {1.0}}}});
                 },
                 "which is no function"),
      // A smooth row (tmesh.continuity c2, session 39) whose flag is not a boolean.
      stage_json("TmeshSmoothFlagNotBoolean", "tmesh", "volts-extract",
                 [](core::Json& j) {
                   auto& t = j["tmeshes"][0];
                   t["constraints"] = core::Json::array({{{"point", 0}, {"ids", {t["function_ids"][1]}}, {"weights", {1.0}}, {"smooth", "yes"}}});
                 },
                 "tmesh constraint key \"smooth\" is not a boolean"),
      // A C2 face's free node (session 50) that is not [id, x, y, z], and one whose point differs
      // between the blocks that name it.
      stage_json("TmeshFreeNodeMalformed", "tmesh", "volts-extract",
                 [](core::Json& j) { j["tmeshes"][0]["free_nodes"] = core::Json::array({core::Json::array({7, 0.5})}); },
                 "tmesh free node is not [id, x, y, z]"),
      stage_json("TmeshFreeNodeOnABlockPoint", "tmesh", "volts-extract",
                 [](core::Json& j) {
                   auto& t = j["tmeshes"][0];
                   t["free_nodes"] = core::Json::array({core::Json::array({t["function_ids"][0], 1e3, 1e3, 1e3})});
                 },
                 "or is a block's control point elsewhere"),
      stage_json("TmeshUnknownBlockKind", "tmesh", "volts-extract", [](core::Json& j) { j["tmeshes"][0]["kind"] = "wedge"; },
                 "unknown tmesh block kind 'wedge'"),
      stage_json("TmeshBlockCornerOutsideCube", "tmesh", "volts-extract", [](core::Json& j) { j["tmeshes"][1]["corners"][7][0] = 1.6; },
                 "tmesh block corner outside [-0.5, 1.5]^3"),
      stage_json("TmeshHugeLevel", "tmesh", "volts-extract", [](core::Json& j) { j["tmeshes"][0]["level"] = 40; },
                 "tmesh level 40 or degree 1 out of range"),
      // A difference polycube (the fuzz seed: 8 columns around a square hole) whose hole pokes out of the cube.
      stage("PolycubeDifferenceHoleOutsideCube", "polycube.stage.json", "volts-tmesh",
            [] {
              core::Json j = core::Json::parse(core::read_text_file(std::string(VOLTS_SOURCE_DIR) +
                                                                    "/fuzz/corpus/stage_polycube/hole_columns.polycube.stage.json"));
              j["polycube"]["hole_lo"][0] = -0.2;
              return j.dump();
            },
            "polycube.hole_lo/hole_hi is not a box through the unit cube along its axis"),
      {"ResumeWithoutEarlierStage",
       [](const fs::path& w) { test::write_text(w / "run.yaml", "input: {generate: box}\n"); },
       "{BIN}/volts run {W}/run.yaml --workdir {W} --from tmesh", 4,
       {"{W}/polycube.stage.json: ", "missing; run the earlier stages first"}},

      // ---- .vtu files (volts-check, exit 4) ----
      vtu("VtuBinaryGarbage", [] { return garbage(400); }, "not a VTK XML unstructured grid"),
      vtu("VtuTruncated", [] { const std::string t = good_text("bezier.vtu"); return t.substr(0, t.size() * 2 / 3); },
          "malformed .vtu file"),
      vtu("VtuUnsupportedCell", [] { return ascii_vtu("0 0 0 1 0 0 0 1 0", 3, "0 1 2", "3", "5", 1); },
          "unsupported cell type"),
      vtu("VtuDegreesDoNotMatchPoints",
          [] {
            return ascii_vtu(cube_points, 8, "0 1 2 3 4 5 6 7", "8", "79", 1,
                             "<CellData HigherOrderDegrees=\"HigherOrderDegrees\"><DataArray type=\"Int32\" "
                             "Name=\"HigherOrderDegrees\" NumberOfComponents=\"3\" format=\"ascii\">2 2 2</DataArray></CellData>\n");
          },
          "the point count does not match degrees 2,2,2"),
      vtu("VtuHugeDegrees",
          [] {
            return ascii_vtu(cube_points, 8, "0 1 2 3 4 5 6 7", "8", "79", 1,
                             "<CellData HigherOrderDegrees=\"HigherOrderDegrees\"><DataArray type=\"Float64\" "
                             "Name=\"HigherOrderDegrees\" NumberOfComponents=\"3\" format=\"ascii\">1e30 1e30 1e30</DataArray></CellData>\n");
          },
          "degree"),
      vtu("VtuNaNPoint", nan_point_vtu, "point 3 is not finite"),
      // Sizes that VTK would allocate before reading any data: refused by the pre-scan, which
      // names what asked for the memory and the file's size.
      vtu("VtuHugePointCount", [] { return ascii_vtu("0 0 0 1 0 0 0 1 0 0 0 1", 4000000000000, "0 1 2 3", "4", "10", 1); },
          "implausible sizes (NumberOfPoints needs 96000000000000 bytes"),
      vtu("VtuHugeComponentCount",
          [] {
            return ascii_vtu("0 0 0 1 0 0 0 1 0 0 0 1", 4, "0 1 2 3", "4", "10", 1,
                             "<CellData><DataArray type=\"Float64\" Name=\"x\" NumberOfComponents=\"900000000000\" "
                             "format=\"ascii\">1</DataArray></CellData>\n");
          },
          "implausible sizes (a DataArray"),
      vtu("VtuHugeCompressedBlockTable",
          [] {
            // A zlib-compressed bezier.vtu whose first block header says 587 million blocks (fuzz_vtu).
            std::ifstream in(std::string(VOLTS_SOURCE_DIR) + "/tests/hardening/fuzz_regressions/vtu/block_count_4_gb.vtu", std::ios::binary);
            return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
          },
          "implausible sizes (a compressed DataArray's block table needs 4697620488 bytes; the file is 3237 bytes)"),
  };
  return c;
}

class BadInputs : public ::testing::TestWithParam<BadInput> {};

TEST_P(BadInputs, AreRefusedWithTheirMessageAndExitCodeAndLeaveNoFile) {
  const BadInput& b = GetParam();
  const fs::path w = test::fresh_dir("hardening", b.name);
  b.setup(w);
  const auto before = snapshot(w);
  const std::string bin = test::bin("");
  const std::string cmd = replace_all(replace_all(b.command, "{BIN}/", bin), "{W}", w.string());
  const test::Outcome r = test::run(cmd);
  EXPECT_EQ(r.code, b.code) << cmd << "\n" << r.output;
  for (const std::string& e : b.expect)
    EXPECT_NE(r.output.find(replace_all(e, "{W}", w.string())), std::string::npos)
        << "expected '" << replace_all(e, "{W}", w.string()) << "' in:\n" << r.output;
  EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
  const auto after = snapshot(w);
  for (const auto& [name, content] : after) {
    const auto it = before.find(name);
    EXPECT_TRUE(it != before.end()) << "left behind: " << name;
    if (it != before.end()) {
      EXPECT_EQ(content, it->second) << name << " was changed";
    }
  }
  EXPECT_EQ(after.size(), before.size());
}

INSTANTIATE_TEST_SUITE_P(Catalogue, BadInputs, ::testing::ValuesIn(catalogue()),
                         [](const ::testing::TestParamInfo<BadInput>& i) { return i.param.name; });

TEST(BadInputCatalogue, HasAtLeastThirtyDistinctInputs) {
  const auto c = catalogue();
  std::set<std::string> names;
  for (const auto& b : c) names.insert(b.name);
  EXPECT_EQ(names.size(), c.size());
  EXPECT_GE(c.size(), 30u);
}

}  // namespace
