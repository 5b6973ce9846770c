// volts-tet2hex: the tet route (Xu et al. 2018). Reads a closed surface (config input, or
// --input FILE) or a .vtu of linear/Bézier tets (--input FILE.vtu); tetrahedralizes a surface with
// TetGen, converts every Bézier tet into four Bézier hexes (Theorem 3), certifies each; writes
// bezier.vtu, the solver exports of extract.exports (their global basis: the hexes' distinct
// control points, extract::bezier_basis) and the extract stage's report keys under "tet2hex".
#include <algorithm>
#include <filesystem>
#include <utility>

#include "core/errors.h"
#include "core/log.h"
#include "exports.h"
#include "extract/extract.h"
#include "stage_main.h"
#include "surface/surface.h"
#include "tet2hex/tet2hex.h"

using namespace volts;

namespace {

// The route's hexes as extract's result, for its solver exports; the hexes are moved out of `r`.
extract::Result as_extract_result(tet2hex::Result& r, bool keep_operators) {
  extract::Result e;
  e.basis = extract::bezier_basis(r.hexes, keep_operators);
  e.hexes = std::move(r.hexes);
  e.degree = r.degree;
  e.min_scaled_jacobian = r.min_scaled_jacobian, e.max_scaled_jacobian = r.max_scaled_jacobian;
  e.boundary_distance = r.boundary_distance;
  e.status = r.validity;
  e.certified_valid = r.certified_valid, e.certified_invalid = r.certified_invalid, e.undecided = r.undecided;
  e.min_scaled = r.min_scaled, e.max_scaled = r.max_scaled;
  e.hausdorff_rel = r.hausdorff_rel;
  e.spline_volume = r.spline_volume, e.surface_volume = r.surface_volume, e.volume_rel_error = r.volume_rel_error;
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "tet2hex",
      "The tet route (Xu et al. 2018, Theorem 3): any closed surface -> TetGen tets -> Bezier tets of\n"
      "degree n (boundary curved onto the surface, kept only where certified valid) -> four Bezier hexes\n"
      "per tet, each certified (det J > 0). Input: config 'input.file' or 'input.generate', or --input FILE\n"
      "(OFF/OBJ/STL/PLY surface, or a .vtu of VTK_TETRA / VTK_BEZIER_TETRAHEDRON cells).\n"
      "Output: DIR/bezier.vtu (VTK_BEZIER_HEXAHEDRON; cell arrays min/max_scaled_jacobian,\n"
      "boundary_distance, status (1 valid, -1 invalid, 0 undecided), tet) and, as extract.exports asks,\n"
      "bezier.bext + bezier.k (LS-DYNA), bezier.json, bezier.msh (Gmsh) and scaled_jacobian_histogram.png\n"
      "(global functions: the hexes' distinct control points, C0). --output FILE replaces DIR/bezier.vtu.",
      [](pipeline::StageContext& ctx) {
        const auto& params = ctx.config.tet2hex;
        pipeline::check_exports(ctx, params.degree, "tet2hex.degree");
        const std::string file = ctx.input.empty() ? ctx.config.input.file : ctx.input;
        core::Json input_info;
        tet2hex::Result r;
        if (!file.empty() && std::filesystem::path(file).extension() == ".vtu") {
          std::vector<bezier::BezierTet> tets;
          {
            core::LogSection s("read tets");
            tets = tet2hex::read_tet_vtu(file);
            core::log(file + ": " + std::to_string(tets.size()) + " tets of degree " + std::to_string(tets[0].degree));
          }
          input_info = {{"file", file}, {"tets", tets.size()}, {"degree", tets[0].degree}};
          r = tet2hex::run(tets, params);
        } else {
          surface::Mesh mesh;
          {
            core::LogSection s("read input");
            mesh = pipeline::load_input_surface(ctx, &input_info);
          }
          r = tet2hex::run(mesh, params);
        }
        if (r.certified_valid != static_cast<int>(r.hexes.size()))
          core::log_warning(std::to_string(r.certified_invalid) + " hexes certified invalid, " + std::to_string(r.undecided) + " undecided");
        const auto& exports = ctx.config.extract.exports;
        const auto wanted = [&](const char* name) { return std::find(exports.begin(), exports.end(), name) != exports.end(); };
        const std::string out = pipeline::vtu_path(ctx);
        core::log(std::to_string(r.tets.size()) + " tets -> " + std::to_string(r.hexes.size()) + " Bezier hexes of degree " +
                  std::to_string(r.degree) + ", " + std::to_string(r.certified_valid) + " certified valid, scaled Jacobian [" +
                  std::to_string(r.min_scaled) + ", " + std::to_string(r.max_scaled) + "], hausdorff_rel " + std::to_string(r.hausdorff_rel) +
                  ", boundary faces curved " + std::to_string(r.boundary_faces_curved) + ", reverted " + std::to_string(r.boundary_faces_reverted));
        core::Json fig = tet2hex::report_figures(r);
        core::Json files = core::Json::object();
        {
          core::LogSection s("write");
          if (wanted("vtu")) tet2hex::write_bezier_vtu(out, r), files["vtu"] = out;
          if (wanted("bext") || wanted("json") || wanted("msh") || wanted("png")) {
            const extract::Result e = as_extract_result(r, wanted("bext") || wanted("json"));
            fig["global_functions"] = e.basis.points.size();
            fig["partition_of_unity_error"] = e.basis.partition_of_unity_error;
            core::log(std::to_string(e.basis.points.size()) + " global functions (the hexes' distinct control points)");
            files.update(pipeline::write_solver_exports(ctx, e));
          }
        }
        if (wanted("vtu")) {
          core::log("open in ParaView: " + out);
          fig["output"] = out;
        }
        fig["outputs"] = files;
        fig["input"] = input_info;
        return fig;
      });
}
