// volts-fit: route `fit` (Lin, Huang & Hu 2018). Reads classify.stage.json; maps the solid onto
// the unit cube (six patches from classify when it found six quad patches, else the automatic
// segmentation), pillows the cube into seven sub-domains, fits one trivariate B-spline solid to
// each with every move kept inside the validity condition, improves G1 across their faces; writes
// fit.stage.json, the ParaView views and the solver exports of extract with extract's report keys.
#include "core/log.h"
#include "exports.h"
#include "fit/route.h"
#include "stage_main.h"
#include "tmesh/tmesh.h"

using namespace volts;

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "fit",
      "Route fit (Lin, Huang & Hu 2018): a closed genus-0 surface -> the solid mapped onto a cube (six\n"
      "patches: classify's if it found six quad patches, else segmented by normal direction) -> seven\n"
      "pillowed trivariate B-spline solids (core [1/3,2/3]^3 and six frusta) fitted to the map curves first,\n"
      "then surfaces, then solids, every move kept inside the validity condition (Prop. 3) -> G1 improved\n"
      "across the solids' faces -> Bezier extraction and the exports of extract.\n"
      "Input: DIR/classify.stage.json. Output: DIR/fit.stage.json (the solids' control nets), DIR/fit_patches.vtp\n"
      "(the six patches), DIR/fit_tets.vtu and DIR/fit_tets_mapped.vtu (the volume map onto the cube),\n"
      "DIR/fit.vtu (control nets as hexes with scaled_jacobian and block), and extract.exports (bezier.vtu, ...).",
      [](pipeline::StageContext& ctx) {
        const pipeline::ClassifyInput in = pipeline::read_classify_input(ctx);
        pipeline::check_exports(ctx, ctx.config.fit.pillow.degree, "fit.degree");
        const fit::Result r = fit::run(in.mesh, in.classification, ctx.config.fit);
        const extract::Result e = extract::extract(r.solids, in.mesh, ctx.config.extract);
        {
          core::LogSection s("write fit files");
          core::Json list = core::Json::array();
          for (const auto& t : r.solids) list.push_back(tmesh::to_json(t));
          core::write_stage_file(ctx.output_file(), "volts-fit", 1, {{"surface", in.json["surface"]}, {"tmeshes", list}});
          classify::write_vtp(ctx.path("fit_patches.vtp"), r.cube.mesh, r.cube.patches);
          volmap::write_vtu(ctx.path("fit_tets.vtu"), r.cube.volume);
          volmap::write_parameter_vtu(ctx.path("fit_tets_mapped.vtu"), r.cube.volume);
          tmesh::write_vtu(ctx.path("fit.vtu"), r.solids);
        }
        core::Json fig = pipeline::write_exports(ctx, e);
        const core::Json own = fit::report_figures(r);
        fig.update(own);  // extract's keys, plus the fit's own
        return fig;
      });
}
