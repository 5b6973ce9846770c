// volts-tmesh: stage 4 (Liu et al. §5.1–5.2). Reads polycube.stage.json, builds the octree T-mesh
// (control mesh) through the volume map; writes tmesh.stage.json and tmesh.vtu.
#include "core/errors.h"
#include "core/log.h"
#include "stage_main.h"
#include "surface/mesh_json.h"
#include "tmesh/tmesh.h"

using namespace volts;

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "tmesh",
      "Stage 4 (Liu et al. 2013 §5.1-5.2): octree T-mesh of the polycube, control points through the\n"
      "volume map. Input: DIR/polycube.stage.json. Output: DIR/tmesh.stage.json, DIR/tmesh.vtu\n"
      "(octree elements with level and scaled_jacobian).",
      [](pipeline::StageContext& ctx) {
        const std::string in = ctx.input_file("polycube");
        const core::Json j = core::read_stage_file(in, "volts-polycube", 2);
        if (j.value("kind", "cube") != "cube")
          throw core::TopologyError("tmesh: the T-mesh of a " + j.value("kind", std::string("?")) +
                                    " polycube is not implemented yet (issue 7); set `route: tet` to mesh this model");
        pipeline::check_integer_members(in, j);
        const surface::Mesh mesh = surface::mesh_from_json(core::require(j, "surface", in), in);
        const classify::Classification c = classify::from_json(core::require(j, "classification", in), in);
        const polycube::Polycube p = polycube::from_json(core::require(j, "polycube", in), in);
        pipeline::check_classification(in, mesh, c);
        pipeline::check_polycube(in, mesh, c, p);
        std::unique_ptr<polycube::VolumeMap> map;
        {
          core::LogSection s("volume map");
          map = std::make_unique<polycube::VolumeMap>(mesh, c, p);
        }
        tmesh::TMesh t;
        {
          core::LogSection s("octree and control points");
          t = tmesh::build(*map, ctx.config.tmesh);
        }
        double min_sj = 0;
        {
          core::LogSection s("write");
          core::write_stage_file(ctx.output_file(), "volts-tmesh", 1, {{"surface", j["surface"]}, {"tmesh", tmesh::to_json(t)}});
          min_sj = tmesh::write_vtu(ctx.path("tmesh.vtu"), t, *map);
        }
        core::log(std::to_string(t.elements()) + " elements, " + std::to_string(t.control_points.size()) +
                  " control points, min trilinear scaled Jacobian " + std::to_string(min_sj));
        return tmesh::report_figures(t, min_sj);
      });
}
