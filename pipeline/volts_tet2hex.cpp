// volts-tet2hex: the tet route (Xu et al. 2018). Reads a closed surface (config input, or
// --input FILE) or a .vtu of linear/Bézier tets (--input FILE.vtu); tetrahedralizes a surface with
// TetGen, converts every Bézier tet into four Bézier hexes (Theorem 3), certifies each; writes
// bezier.vtu and the extract stage's report keys under "tet2hex".
#include <filesystem>

#include "core/errors.h"
#include "core/log.h"
#include "stage_main.h"
#include "surface/surface.h"
#include "tet2hex/tet2hex.h"

using namespace volts;

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "tet2hex",
      "The tet route (Xu et al. 2018, Theorem 3): any closed surface -> TetGen tets -> Bezier tets of\n"
      "degree n (boundary curved onto the surface, kept only where certified valid) -> four Bezier hexes\n"
      "per tet, each certified (det J > 0). Input: config 'input.file' or 'input.generate', or --input FILE\n"
      "(OFF/OBJ/STL/PLY surface, or a .vtu of VTK_TETRA / VTK_BEZIER_TETRAHEDRON cells).\n"
      "Output: DIR/bezier.vtu (VTK_BEZIER_HEXAHEDRON; cell arrays min/max_scaled_jacobian,\n"
      "boundary_distance, status (1 valid, -1 invalid, 0 undecided), tet). --output FILE replaces DIR/bezier.vtu.",
      [](pipeline::StageContext& ctx) {
        const auto& params = ctx.config.tet2hex;
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
        const std::string out = ctx.output.empty() ? ctx.path("bezier.vtu") : ctx.output;
        {
          core::LogSection s("write");
          tet2hex::write_bezier_vtu(out, r);
        }
        core::log(std::to_string(r.tets.size()) + " tets -> " + std::to_string(r.hexes.size()) + " Bezier hexes of degree " +
                  std::to_string(r.degree) + ", " + std::to_string(r.certified_valid) + " certified valid, scaled Jacobian [" +
                  std::to_string(r.min_scaled) + ", " + std::to_string(r.max_scaled) + "], hausdorff_rel " + std::to_string(r.hausdorff_rel) +
                  ", boundary faces curved " + std::to_string(r.boundary_faces_curved) + ", reverted " + std::to_string(r.boundary_faces_reverted));
        core::log("open in ParaView: " + out);
        core::Json fig = tet2hex::report_figures(r);
        fig["output"] = out;
        fig["input"] = input_info;
        return fig;
      });
}
