// volts-polycube: stage 3 (Liu et al. §4.2–4.3). Reads split.stage.json, builds the polycube and
// maps the surface onto it; writes polycube.stage.json, polycube.vtp and polycube_mapped.vtp.
#include "core/log.h"
#include "polycube/polycube.h"
#include "stage_main.h"
#include "surface/mesh_json.h"

using namespace volts;

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "polycube",
      "Stage 3 (Liu et al. 2013 §4.2-4.3): build the polycube and map the surface onto it\n"
      "(bijective disk map per patch). Input: DIR/split.stage.json. Output: DIR/polycube.stage.json,\n"
      "DIR/polycube.vtp (surface with cube coordinates 'uvw'), DIR/polycube_mapped.vtp (the surface on the cube).",
      [](pipeline::StageContext& ctx) {
        const std::string in = ctx.input_file("split");
        const core::Json j = core::read_stage_file(in, "volts-split", 2);
        pipeline::check_integer_members(in, j);
        const surface::Mesh mesh = surface::mesh_from_json(core::require(j, "surface", in), in);
        const classify::Classification c = classify::from_json(core::require(j, "classification", in), in);
        const split::Decomposition d = split::from_json(core::require(j, "decomposition", in), in);
        pipeline::check_classification(in, mesh, c);
        pipeline::check_decomposition(in, c, d);
        polycube::Polycube p;
        {
          core::LogSection s("surface map");
          p = polycube::map_surface(mesh, c, d, ctx.config.polycube);
        }
        if (p.flipped_surface_triangles > 0)
          core::log_warning(std::to_string(p.flipped_surface_triangles) + " surface triangles are flipped by the map");
        {
          core::LogSection s("write");
          core::write_stage_file(ctx.output_file(), "volts-polycube", 1,
                                 {{"surface", j["surface"]}, {"classification", j["classification"]},
                                  {"decomposition", j["decomposition"]}, {"polycube", polycube::to_json(p)}});
          polycube::write_vtp(ctx.path("polycube.vtp"), mesh, c, p);
          polycube::write_mapped_vtp(ctx.path("polycube_mapped.vtp"), mesh, c, p);
        }
        return polycube::report_figures(p, d);
      });
}
