// volts-classify: stage 1 (Liu et al. §3). Reads the input surface (a file, or a generated model),
// validates it, finds corners, curves and patches; writes classify.stage.json and classify.vtp.
#include "classify/classify.h"
#include "core/errors.h"
#include "core/log.h"
#include "stage_main.h"
#include "surface/mesh_json.h"

using namespace volts;

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "classify",
      "Stage 1 (Liu et al. 2013 §3): validate the input surface and classify corners, sharp curves\n"
      "(feature / difference) and patches. Input: config 'input.file' or 'input.generate', or --input FILE.\n"
      "Output: DIR/classify.stage.json, DIR/classify.vtp (patch_id, curve_id, curve_kind, corner_id).",
      [](pipeline::StageContext& ctx) {
        surface::Mesh mesh;
        core::Json input_info;
        {
          core::LogSection s("read input");
          mesh = pipeline::load_input_surface(ctx, &input_info);
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
