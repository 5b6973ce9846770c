// volts-extract: stage 5 (Liu et al. §5.3, §6). Reads tmesh.stage.json, builds the spline,
// extracts its Bézier elements, measures them; writes bezier.vtu.
#include "core/errors.h"
#include "core/log.h"
#include "extract/extract.h"
#include "stage_main.h"
#include "surface/mesh_json.h"

using namespace volts;

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "extract",
      "Stage 5 (Liu et al. 2013 §5.3): spline from the T-mesh, Bézier extraction, quality figures.\n"
      "Input: DIR/tmesh.stage.json. Output: DIR/bezier.vtu (VTK_BEZIER_HEXAHEDRON; open in ParaView and\n"
      "raise 'Nonlinear Subdivision Level' to see the curved elements).",
      [](pipeline::StageContext& ctx) {
        const std::string in = ctx.input_file("tmesh");
        const core::Json j = core::read_stage_file(in, "volts-tmesh", 2);
        pipeline::check_integer_members(in, j);
        const surface::Mesh mesh = surface::mesh_from_json(core::require(j, "surface", in), in);
        std::vector<tmesh::TMesh> t;
        try {
          const core::Json& list = core::require(j, "tmeshes", in);
          if (!list.is_array() || list.empty()) throw core::InvalidInputError(in + ": tmeshes must be a non-empty list of T-meshes");
          for (const auto& x : list) t.push_back(tmesh::from_json(x, in));
        } catch (const core::Json::exception& e) {
          throw core::InvalidInputError(in + ": malformed tmeshes: " + e.what());
        }
        const extract::Result r = extract::extract(t, mesh, ctx.config.extract);
        const std::string out = ctx.output.empty() ? ctx.path("bezier.vtu") : ctx.output;
        {
          core::LogSection s("write");
          extract::write_bezier_vtu(out, r);
        }
        core::log(std::to_string(r.hexes.size()) + " Bézier elements of degree " + std::to_string(r.degree) +
                  ", scaled Jacobian [" + std::to_string(r.min_scaled) + ", " + std::to_string(r.max_scaled) +
                  "], hausdorff_rel " + std::to_string(r.hausdorff_rel) + ", volume_rel_error " + std::to_string(r.volume_rel_error));
        core::log("open in ParaView: " + out);
        core::Json fig = extract::report_figures(r);
        fig["output"] = out;
        return fig;
      });
}
