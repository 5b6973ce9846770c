// volts-split: stage 2 (Liu et al. §4.1). Reads classify.stage.json, decomposes the surface into
// cube (and, later, torus) components; writes split.stage.json and split.vtp.
#include "core/log.h"
#include "split/split.h"
#include "stage_main.h"

using namespace volts;

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "split",
      "Stage 2 (Liu et al. 2013 §4.1): split the classified surface into components that are\n"
      "topologically cubes: one cube, a torus as a ring of cubes, or a cube minus a virtual component\n"
      "(a through hole). Input: DIR/classify.stage.json. Output: DIR/split.stage.json, DIR/split.vtp.",
      [](pipeline::StageContext& ctx) {
        const pipeline::ClassifyInput in = pipeline::read_classify_input(ctx);
        const core::Json& j = in.json;
        const surface::Mesh& mesh = in.mesh;
        const classify::Classification& c = in.classification;
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
