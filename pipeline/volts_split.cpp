// volts-split: stage 2 (Liu et al. §4.1). Reads classify.stage.json, decomposes the surface into
// cube (and, later, torus) components; writes split.stage.json and split.vtp.
#include "core/log.h"
#include "split/split.h"
#include "stage_main.h"
#include "surface/mesh_json.h"

using namespace volts;

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "split",
      "Stage 2 (Liu et al. 2013 §4.1): split the classified surface into components that are\n"
      "topologically cubes: one cube, a torus as a ring of cubes, or a cube minus a virtual component\n"
      "(a through hole). Input: DIR/classify.stage.json. Output: DIR/split.stage.json, DIR/split.vtp.",
      [](pipeline::StageContext& ctx) {
        const std::string in = ctx.input_file("classify");
        const core::Json j = core::read_stage_file(in, "volts-classify", 1);
        pipeline::check_integer_members(in, j);
        const surface::Mesh mesh = surface::mesh_from_json(core::require(j, "surface", in), in);
        const classify::Classification c = classify::from_json(core::require(j, "classification", in), in);
        pipeline::check_classification(in, mesh, c);
        split::Decomposition d;
        {
          core::LogSection s("decompose");
          d = split::split(mesh, c, ctx.config.split);
        }
        {
          core::LogSection s("write");
          core::write_stage_file(ctx.output_file(), "volts-split", 2,
                                 {{"surface", j["surface"]}, {"classification", j["classification"]}, {"decomposition", split::to_json(d)}});
          split::write_vtp(ctx.path("split.vtp"), d);
        }
        core::log(std::to_string(d.components.size()) + " component(s), " + std::to_string(d.tori.size()) + " tori, " +
                  std::to_string(d.quad_patches) + " quad patches");
        return split::report_figures(d);
      });
}
