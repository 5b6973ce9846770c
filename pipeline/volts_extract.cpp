// volts-extract: stage 5 (Liu et al. §5.3, §6). Reads tmesh.stage.json, builds the spline,
// extracts its Bézier elements and the global basis, measures them; writes the files of
// extract.exports: bezier.vtu, bezier.bext + bezier.k, bezier.json, bezier.msh and
// scaled_jacobian_histogram.png.
#include <algorithm>
#include <filesystem>

#include "core/errors.h"
#include "core/log.h"
#include "extract/export.h"
#include "extract/extract.h"
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
        const auto& exports = ctx.config.extract.exports;
        extract::check_exports(exports, t[0].degree);  // before any work: a bad list costs nothing
        const auto wanted = [&](const char* name) { return std::find(exports.begin(), exports.end(), name) != exports.end(); };
        const extract::Result r = extract::extract(t, mesh, ctx.config.extract);
        const std::string out = ctx.output.empty() ? ctx.path("bezier.vtu") : ctx.output;
        const std::filesystem::path stem = std::filesystem::path(out).replace_extension();
        const auto beside = [&](const char* ext) { return stem.string() + ext; };
        core::Json files = core::Json::object();
        {
          core::LogSection s("write");
          if (wanted("vtu")) extract::write_bezier_vtu(out, r), files["vtu"] = out;
          if (wanted("bext")) {
            extract::write_bext(beside(".bext"), r);
            extract::write_lsdyna_deck(beside(".k"), stem.filename().string() + ".bext");
            files["bext"] = beside(".bext"), files["k"] = beside(".k");
          }
          if (wanted("json")) extract::write_bezier_json(beside(".json"), r), files["json"] = beside(".json");
          if (wanted("msh")) {
            const std::size_t nodes = extract::write_gmsh(beside(".msh"), r.hexes);
            core::log("bezier.msh: " + std::to_string(nodes) + " nodes (shared between neighbouring elements)");
            files["msh"] = beside(".msh");
          }
          if (wanted("png")) {
            const std::string png = ctx.path("scaled_jacobian_histogram.png");
            extract::write_histogram_png(png, r.min_scaled_jacobian);
            files["png"] = png;
          }
        }
        core::log(std::to_string(r.hexes.size()) + " Bézier elements of degree " + std::to_string(r.degree) +
                  ", scaled Jacobian [" + std::to_string(r.min_scaled) + ", " + std::to_string(r.max_scaled) +
                  "], hausdorff_rel " + std::to_string(r.hausdorff_rel) + ", volume_rel_error " + std::to_string(r.volume_rel_error));
        if (wanted("vtu")) core::log("open in ParaView: " + out);
        core::Json fig = extract::report_figures(r);
        if (wanted("vtu")) fig["output"] = out;
        fig["outputs"] = files;
        return fig;
      });
}
