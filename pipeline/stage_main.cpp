#include "stage_main.h"

#include <climits>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <iostream>

#include "core/errors.h"
#include "core/log.h"
#include "models/models.h"
#include "surface/mesh_json.h"

namespace fs = std::filesystem;

namespace volts::pipeline {

std::string StageContext::path(const std::string& name) const { return (fs::path(workdir) / name).string(); }
std::string StageContext::input_file(const std::string& previous) const {
  return input.empty() ? stage_file(workdir, previous) : input;
}
std::string StageContext::output_file() const { return output.empty() ? stage_file(workdir, stage) : output; }

surface::Mesh load_input_surface(const StageContext& ctx, core::Json* info) {
  const auto& in = ctx.config.input;
  const std::string file = ctx.input.empty() ? in.file : ctx.input;
  surface::Mesh mesh;
  core::Json j;
  if (!file.empty()) {
    surface::ReadInfo ri;
    mesh = surface::read_surface(file, &ri);
    if (ri.flipped) core::log_warning(file + ": the surface was inside out (inward normals); flipped it");
    if (ri.welded_vertices) core::log(file + ": welded " + std::to_string(ri.welded_vertices) + " duplicate vertices");
    j = {{"file", file}, {"format", ri.format}, {"flipped", ri.flipped}, {"welded_vertices", ri.welded_vertices}};
  } else if (!in.generate.empty()) {
    models::ModelParams mp;
    mp.name = in.generate;
    mp.resolution = in.resolution;
    mp.bulge = in.bulge;
    mesh = models::make_model(mp);
    j = {{"generate", in.generate}, {"resolution", in.resolution}};
  } else {
    throw core::ConfigError("no input: set input.file or input.generate in the config, or pass --input FILE");
  }
  j["vertices"] = mesh.number_of_vertices();
  j["faces"] = mesh.number_of_faces();
  core::log(std::to_string(mesh.number_of_vertices()) + " vertices, " + std::to_string(mesh.number_of_faces()) + " triangles");
  if (info) *info = j;
  return mesh;
}

namespace {

[[noreturn]] void mismatch(const std::string& file, const std::string& what) {
  throw core::InvalidInputError(file + ": stage data do not match: " + what);
}

void check_index(const std::string& file, const std::string& what, long long index, std::size_t size) {
  if (index < 0 || static_cast<std::size_t>(index) >= size)
    mismatch(file, what + " " + std::to_string(index) + " is out of range [0, " + std::to_string(size) + ")");
}

/// `v` (a number, or arrays of numbers at any depth) holds only integers that fit an int.
void check_integers(const std::string& file, const std::string& name, const core::Json& v) {
  if (v.is_array()) {
    for (const auto& x : v) check_integers(file, name, x);
    return;
  }
  if (!v.is_number_integer() || (v.is_number_unsigned() ? v.get<std::uint64_t>() > INT_MAX
                                                          : v.get<std::int64_t>() < INT_MIN || v.get<std::int64_t>() > INT_MAX))
    throw core::InvalidInputError(file + ": " + name + " must hold integers, got " + v.dump().substr(0, 40));
}

}  // namespace

void check_integer_members(const std::string& file, const core::Json& j) {
  static const std::vector<std::pair<const char*, std::vector<const char*>>> members = {
      {"classification", {"corners", "face_patch", "patches", "sharp_edges", "genus"}},
      {"decomposition", {"quad_patches"}},
      {"polycube", {"corner_cube_coords", "patch_face", "flipped_surface_triangles"}},
      {"tmesh", {"level", "degree", "size"}}};
  for (const auto& [payload, keys] : members) {
    const auto p = j.find(payload);
    if (p == j.end() || !p->is_object()) continue;  // the payload reader reports it
    for (const char* k : keys)
      if (p->contains(k)) check_integers(file, std::string(payload) + "." + k, (*p)[k]);
    // Lists of objects with integer members.
    const char* list = std::string(payload) == "classification" ? "curves" : std::string(payload) == "decomposition" ? "components" : nullptr;
    if (!list || !p->contains(list) || !(*p)[list].is_array()) continue;
    for (const auto& item : (*p)[list]) {
      if (!item.is_object()) continue;
      for (const char* k : {"vertices", "patches"})
        if (item.contains(k)) check_integers(file, std::string(payload) + "." + list + "[]." + k, item[k]);
    }
  }
}

ClassifyInput read_classify_input(const StageContext& ctx) {
  ClassifyInput in;
  in.file = ctx.input_file("classify");
  in.json = core::read_stage_file(in.file, "volts-classify", 1);
  check_integer_members(in.file, in.json);
  in.mesh = surface::mesh_from_json(core::require(in.json, "surface", in.file), in.file);
  in.classification = classify::from_json(core::require(in.json, "classification", in.file), in.file);
  check_classification(in.file, in.mesh, in.classification);
  return in;
}

void check_classification(const std::string& file, const surface::Mesh& mesh, const classify::Classification& c) {
  const std::size_t nv = mesh.number_of_vertices(), nf = mesh.number_of_faces();
  if (c.face_patch.size() != nf)
    mismatch(file, "classification.face_patch has " + std::to_string(c.face_patch.size()) + " entries, the surface " +
                       std::to_string(nf) + " faces");
  if (c.patches < 1 || static_cast<std::size_t>(c.patches) > nf)
    mismatch(file, "classification.patches " + std::to_string(c.patches) + " is not in [1, " + std::to_string(nf) + "]");
  const std::size_t patches = static_cast<std::size_t>(c.patches);
  for (const int p : c.face_patch) check_index(file, "classification.face_patch: patch", p, patches);
  for (const int v : c.corners) check_index(file, "classification.corners: vertex", v, nv);
  if (c.sharp_edge_vertices.size() % 2) mismatch(file, "classification.sharp_edges has an odd number of vertices");
  for (const int v : c.sharp_edge_vertices) check_index(file, "classification.sharp_edges: vertex", v, nv);
  if (c.genus < 0) mismatch(file, "classification.genus is negative");
  for (const classify::Curve& k : c.curves) {
    if (k.vertices.empty()) mismatch(file, "a classification curve has no vertices");
    for (const int v : k.vertices) check_index(file, "classification curve: vertex", v, nv);
    for (const int p : {k.patch_left, k.patch_right})
      if (p != -1) check_index(file, "classification curve: patch", p, patches);
  }
}

void check_decomposition(const std::string& file, const classify::Classification& c, const split::Decomposition& d) {
  (void)c;
  const std::size_t patches = d.layout.patches.size();
  if (d.quad_patches < 0 || static_cast<std::size_t>(d.quad_patches) > patches) mismatch(file, "decomposition.quad_patches is out of range");
  for (const split::Component& k : d.components)
    for (const int p : k.patches) check_index(file, "decomposition component: patch", p, patches);
}

void check_polycube(const std::string& file, const surface::Mesh& mesh, const classify::Classification& c,
                    const polycube::Polycube& p) {
  if (p.vertex_uvw.size() != mesh.number_of_vertices())
    mismatch(file, "polycube.vertex_uvw has " + std::to_string(p.vertex_uvw.size()) + " points, the surface " +
                       std::to_string(mesh.number_of_vertices()) + " vertices");
  if (p.patch_face.size() != static_cast<std::size_t>(c.patches))
    mismatch(file, "polycube.patch_face has " + std::to_string(p.patch_face.size()) + " entries for " +
                       std::to_string(c.patches) + " patches");
  if (p.corner_cube_coords.size() != c.corners.size())
    mismatch(file, "polycube.corner_cube_coords has " + std::to_string(p.corner_cube_coords.size()) + " entries for " +
                       std::to_string(c.corners.size()) + " corners");
  for (const auto& cc : p.corner_cube_coords)
    for (const int x : cc)
      if (x != 0 && x != 1) mismatch(file, "polycube.corner_cube_coords must be 0 or 1");
  for (const auto& uvw : p.vertex_uvw)
    for (const double x : uvw)
      if (!(x >= -1e-9 && x <= 1 + 1e-9)) mismatch(file, "polycube.vertex_uvw must lie in the unit cube");
}

int run_stage(int argc, char** argv, const std::string& stage, const std::string& help,
              const std::function<core::Json(StageContext&)>& body) {
  const std::string tool = "volts-" + stage;
  core::set_log_tool(tool);
  try {
    StageContext ctx;
    ctx.stage = stage;
    std::string config_path;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw core::UsageError(a + " needs a value (see --help)");
        return argv[++i];
      };
      if (a == "-h" || a == "--help") {
        std::cout << "usage: " << tool << " [--config FILE] [--workdir DIR] [--input FILE] [--output FILE] [-v|-q]\n\n"
                  << help << "\n\n"
                  << "  --config FILE   run configuration (YAML, see configs/default.yaml); defaults if omitted\n"
                  << "  --workdir DIR   work directory with the stage files and report.json (default: .)\n"
                  << "  --input FILE    input file (default: the previous stage's file in DIR)\n"
                  << "  --output FILE   output stage file (default: DIR/" << stage << ".stage.json)\n"
                  << "  -v, -q          verbose / quiet logging\n\n"
                  << "Exit codes: 0 ok, 2 usage, 3 config, 4 invalid input, 5 topology, 6 output, 7 numerical, 1 bug.\n";
        return 0;
      } else if (a == "--config") {
        config_path = value();
      } else if (a == "--workdir") {
        ctx.workdir = value();
      } else if (a == "--input") {
        ctx.input = value();
      } else if (a == "--output") {
        ctx.output = value();
      } else if (a == "-v" || a == "--verbose") {
        core::set_log_level(core::LogLevel::verbose);
      } else if (a == "-q" || a == "--quiet") {
        core::set_log_level(core::LogLevel::quiet);
      } else {
        throw core::UsageError("unknown argument '" + a + "' (see --help)");
      }
    }
    if (!config_path.empty()) ctx.config = config::load_config(config_path);
    fs::create_directories(ctx.workdir);
    core::Stopwatch watch;
    core::Json figures = body(ctx);
    figures["time_s"] = watch.seconds();
    core::update_report(ctx.workdir, stage, figures);
    core::log("done in " + std::to_string(watch.seconds()) + " s");
    return 0;
  } catch (const core::Error& e) {
    std::cerr << tool << ": error: " << e.what() << "\n";
    return e.exit_code();
  } catch (const std::exception& e) {
    std::cerr << tool << ": internal error (please report): " << e.what() << "\n";
    return static_cast<int>(core::ExitCode::internal);
  }
}

std::vector<std::string> stage_environment(char** vars) {
  std::vector<std::string> env;
  bool tunables = false;
  for (char** e = vars; e != nullptr && *e != nullptr; ++e) {
    std::string v = *e;
    if (v.rfind("GLIBC_TUNABLES=", 0) == 0) {
      tunables = true;
      if (v.find("glibc.malloc.hugetlb=") == std::string::npos)
        v += (v.size() > std::string("GLIBC_TUNABLES=").size() ? ":" : "") + std::string("glibc.malloc.hugetlb=1");
    }
    env.push_back(std::move(v));
  }
  if (!tunables) env.emplace_back("GLIBC_TUNABLES=glibc.malloc.hugetlb=1");
  return env;
}

}  // namespace volts::pipeline
