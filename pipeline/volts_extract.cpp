// volts-extract: stage 5 (Liu et al. §5.3, §6). Reads tmesh.stage.json, builds the spline,
// extracts its Bézier elements and the global basis, measures them; writes the files of
// extract.exports: bezier.vtu, bezier.bext + bezier.k, bezier.json, bezier.msh and
// scaled_jacobian_histogram.png.
#include "core/errors.h"
#include "core/log.h"
#include "exports.h"
#include "stage_main.h"
#include "surface/mesh_json.h"

using namespace volts;

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "extract",
      "Stage 5 (Liu et al. 2013 §5.3): spline from the T-mesh, Bézier extraction, quality figures.\n"
      "Input: DIR/tmesh.stage.json. Output (extract.exports): DIR/bezier.vtu (VTK_BEZIER_HEXAHEDRON; open in\n"
      "ParaView and raise 'Nonlinear Subdivision Level' to see the curved elements), bezier.bext and bezier.k\n"
      "(LS-DYNA *IGA_INCLUDE_BEZIER), bezier.json (global basis and extraction operators), bezier.msh (Gmsh\n"
      "Lagrange hexahedra) and scaled_jacobian_histogram.png. --output FILE.vtu names the .vtu; the\n"
      "other files take its stem.",
      [](pipeline::StageContext& ctx) {
        const std::string in = ctx.input_file("tmesh");
        // The stage file's JSON tree is freed inside the section (the assembly's peak memory 342 -> 234 MB).
        surface::Mesh mesh;
        std::vector<tmesh::TMesh> t;
        {
          core::LogSection reading("read");
          const core::Json j = core::read_stage_file(in, "volts-tmesh", 3);
          pipeline::check_integer_members(in, j);
          mesh = surface::mesh_from_json(core::require(j, "surface", in), in);
          try {
            const core::Json& list = core::require(j, "tmeshes", in);
            if (!list.is_array() || list.empty()) throw core::InvalidInputError(in + ": tmeshes must be a non-empty list of T-meshes");
            for (const auto& x : list) t.push_back(tmesh::from_json(x, in));
          } catch (const core::Json::exception& e) {
            throw core::InvalidInputError(in + ": malformed tmeshes: " + e.what());
          }
        }
        pipeline::check_exports(ctx, t[0].degree, "tmesh.degree");  // before any work: a bad list costs nothing
        extract::Result r;
        try {
          r = extract::extract(t, mesh, ctx.config.extract);
        } catch (const core::InvalidInputError& e) {  // what extract finds wrong in the blocks is the file's fault
          throw core::InvalidInputError(in + ": " + e.what());
        }
        const core::Json fig = pipeline::write_exports(ctx, r);
        return fig;
      });
}
