// volts-classify: stage 1 (Liu et al. §3). Reads the input surface (a file, or a generated model),
// validates it, finds corners, curves and patches; writes classify.stage.json and classify.vtp.
#include "classify/classify.h"
#include "core/errors.h"
#include "core/log.h"
#include "models/models.h"
#include "stage_main.h"
#include "surface/mesh_json.h"

using namespace volts;

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "classify",
      "Stage 1 (Liu et al. 2013 §3): validate the input surface and classify corners, sharp curves\n"
      "(feature / difference) and patches. Input: config 'input.file' or 'input.generate', or --input FILE.\n"
      "Output: DIR/classify.stage.json, DIR/classify.vtp (patch_id, curve_id, curve_kind, corner_id).",
      [](pipeline::StageContext& ctx) {
        const auto& in = ctx.config.input;
        surface::Mesh mesh;
        core::Json input_info;
        {
          core::LogSection s("read input");
          if (!ctx.input.empty() || !in.file.empty()) {
            const std::string file = ctx.input.empty() ? in.file : ctx.input;
            surface::ReadInfo info;
            mesh = surface::read_surface(file, &info);
            if (info.flipped) core::log_warning(file + ": the surface was inside out (inward normals); flipped it");
            if (info.welded_vertices) core::log(file + ": welded " + std::to_string(info.welded_vertices) + " duplicate vertices");
            input_info = {{"file", file}, {"format", info.format}, {"flipped", info.flipped}, {"welded_vertices", info.welded_vertices}};
          } else if (!in.generate.empty()) {
            models::ModelParams mp;
            mp.name = in.generate;
            mp.resolution = in.resolution;
            mp.bulge = in.bulge;
            mesh = models::make_model(mp);
            input_info = {{"generate", in.generate}, {"resolution", in.resolution}};
          } else {
            throw core::ConfigError("no input: set input.file or input.generate in the config, or pass --input FILE");
          }
          input_info["vertices"] = mesh.number_of_vertices();
          input_info["faces"] = mesh.number_of_faces();
          core::log(std::to_string(mesh.number_of_vertices()) + " vertices, " + std::to_string(mesh.number_of_faces()) + " triangles");
        }
        classify::Classification c;
        {
          core::LogSection s("classify corners, curves, patches");
          c = classify::classify(mesh, ctx.config.classify);
        }
        {
          core::LogSection s("write");
          core::write_stage_file(ctx.output_file(), "volts-classify", 1,
                                 {{"surface", surface::mesh_to_json(mesh)}, {"classification", classify::to_json(c)}});
          classify::write_vtp(ctx.path("classify.vtp"), mesh, c);
        }
        core::Json fig = classify::report_figures(c);
        core::log("corners " + fig["corners"].dump() + ", curves " + fig["curves"].dump() + " (" + fig["feature_curves"].dump() +
                  " feature, " + fig["difference_curves"].dump() + " difference), patches " + fig["patches"].dump() +
                  ", genus " + fig["genus"].dump());
        fig["input"] = input_info;
        return fig;
      });
}
