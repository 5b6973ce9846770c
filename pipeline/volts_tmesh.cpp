// volts-tmesh: stage 4 (Liu et al. §5.1–5.2). Reads polycube.stage.json, builds the octree T-mesh
// (control mesh) through the volume map; writes tmesh.stage.json and tmesh.vtu.
#include <limits>
#include <memory>

#include "core/log.h"
#include "polycube_input.h"
#include "stage_main.h"
#include "surface/mesh_json.h"
#include "tmesh/optimize.h"
#include "tmesh/tmesh.h"

using namespace volts;

namespace {

// Blocks, optimization, files and report: the same for every kind of polycube.
core::Json build_and_write(pipeline::StageContext& ctx, const core::Json& surface, const tmesh::PolycubeMaps& maps) {
  std::vector<tmesh::TMesh> ts;
  {
    core::LogSection s("octree, pillow and control points");
    ts = tmesh::build(maps, ctx.config.tmesh);
  }
  double before = std::numeric_limits<double>::infinity();
  for (const auto& t : ts) before = std::min(before, tmesh::min_element_scaled_jacobian(t));
  double after = before;
  tmesh::OptimizeResult opt;
  opt.stop_reason = "disabled";
  if (ctx.config.tmesh.optimize_sweeps > 0) {
    core::LogSection s("optimization of the worst Jacobian");
    tmesh::OptimizeParams op;
    op.sweeps = ctx.config.tmesh.optimize_sweeps;
    op.joint_rounds = ctx.config.tmesh.joint_rounds;
    op.joint_evaluations = ctx.config.tmesh.joint_evaluations;
    op.joint_sharpness = ctx.config.tmesh.joint_sharpness;
    op.joint_window = ctx.config.tmesh.joint_window;
    op.slide_from_start = ctx.config.tmesh.slide_from == "start";
    op.slide_sharp_curves = ctx.config.tmesh.slide_sharp_curves;
    // Optimize the figure extract reports: its Gauss points (0 = degree + 1) and the corners.
    op.gauss_points = ctx.config.extract.gauss_points > 0 ? ctx.config.extract.gauss_points : ctx.config.tmesh.degree + 1;
    std::unique_ptr<tmesh::SlideSurface> slide;
    if (ctx.config.tmesh.slide_surface) {
      const surface::Mesh mesh = surface::mesh_from_json(surface, ctx.input_file("polycube"));
      std::vector<std::array<int, 3>> triangles;
      for (const auto& f : surface::triangle_array(mesh)) triangles.push_back({f.at(0), f.at(1), f.at(2)});
      slide = std::make_unique<tmesh::SlideSurface>(surface::vertex_array(mesh), triangles);
      core::log("surface nodes slide along the input surface (" + std::to_string(slide->sharp_edges()) + " sharp edges, " +
                std::to_string(slide->sharp_corners()) + " sharp corners" + (op.slide_sharp_curves ? ", sharp-curve nodes along their curve)" : " keep theirs)"));
    }
    opt = tmesh::optimize(ts, op, slide.get());
  }
  {
    core::LogSection s("write");
    core::Json list = core::Json::array();
    for (const auto& t : ts) list.push_back(tmesh::to_json(t));
    core::write_stage_file(ctx.output_file(), "volts-tmesh", 2, {{"surface", surface}, {"tmeshes", list}});
    after = tmesh::write_vtu(ctx.path("tmesh.vtu"), ts);
  }
  core::Json fig = tmesh::report_figures(ts, before, after);
  // The Bézier elements' sampled scaled Jacobian around optimization (trilinear figures above).
  fig["optimization"] = {{"sweeps", opt.sweeps}, {"nodes_moved", opt.nodes_moved},
                         {"bezier_min_scaled_jacobian_before", opt.min_before}, {"bezier_min_scaled_jacobian_after", opt.min_after},
                         {"not_certified_valid_before", opt.invalid_before}, {"not_certified_valid_after", opt.invalid_after},
                         {"stop_reason", opt.stop_reason}, {"sweeps_cut_at_node_bound", opt.sweeps_cut_at_node_bound},
                         {"trilinear_nodes_moved", opt.trilinear_nodes_moved}, {"joint_rounds", opt.joint_rounds},
                         {"surface_nodes_slid", opt.surface_nodes_slid}};
  core::log(std::to_string(fig["blocks"].get<int>()) + " blocks, " + std::to_string(fig["elements"].get<int>()) + " elements, " +
            std::to_string(fig["nodes"].get<int>()) + " nodes, min control-net scaled Jacobian " + std::to_string(after));
  return fig;
}

}  // namespace

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "tmesh",
      "Stage 4 (Liu et al. 2013 §5.1-5.2): octree T-mesh of the polycube, pillowed under the surface,\n"
      "control points through the volume map. Input: DIR/polycube.stage.json. Output: DIR/tmesh.stage.json,\n"
      "DIR/tmesh.vtu (the control net with scaled_jacobian, component, block and pillow per hex).",
      [](pipeline::StageContext& ctx) {
        const pipeline::PolycubeInput in = pipeline::read_polycube_input(ctx.input_file("polycube"), ctx.config.tmesh);
        return build_and_write(ctx, in.surface, in.maps);
      });
}
