#include "stage_main.h"

#include <cstring>
#include <filesystem>
#include <iostream>

#include "core/errors.h"
#include "core/log.h"
#include "models/models.h"

namespace fs = std::filesystem;

namespace volts::pipeline {

std::string stage_file(const std::string& workdir, const std::string& stage) {
  return (fs::path(workdir) / (stage + ".stage.json")).string();
}

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

}  // namespace volts::pipeline
