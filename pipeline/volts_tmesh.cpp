// volts-tmesh: stage 4 (Liu et al. §5.1–5.2). Reads polycube.stage.json, builds the octree T-mesh
// (control mesh) through the volume map; writes tmesh.stage.json and tmesh.vtu.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>

#include "core/log.h"
#include "polycube_input.h"
#include "stage_main.h"
#include "surface/mesh_json.h"
#include "tmesh/optimize.h"
#include "tmesh/tmesh.h"

using namespace volts;

namespace {

// The blocks whose elements started worst (lowest mean sampled scaled Jacobian before
// optimization), at most 10: where the polycube map or the block layout is poor, which the
// optimizer then has to make up for (docs/formats.md, report key tmesh.optimization.worst_blocks).
core::Json worst_blocks(const std::vector<tmesh::TMesh>& ts, const tmesh::OptimizeResult& opt) {
  core::Json out = core::Json::array();
  if (opt.element_before.empty()) return out;
  struct Row {
    std::size_t block;
    int elements;
    double mean_before, min_before, mean_after, min_after;
  };
  std::vector<Row> rows;
  std::size_t e = 0;
  for (std::size_t b = 0; b < ts.size(); ++b) {
    Row r{b, ts[b].elements(), 0, std::numeric_limits<double>::infinity(), 0, std::numeric_limits<double>::infinity()};
    for (int k = 0; k < r.elements; ++k, ++e) {
      r.mean_before += opt.element_before[e] / r.elements, r.min_before = std::min(r.min_before, opt.element_before[e]);
      r.mean_after += opt.element_after[e] / r.elements, r.min_after = std::min(r.min_after, opt.element_after[e]);
    }
    rows.push_back(r);
  }
  std::stable_sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.mean_before < b.mean_before; });
  rows.resize(std::min<std::size_t>(rows.size(), 10));
  for (const Row& r : rows) {
    const tmesh::TMesh& t = ts[r.block];
    int surface_faces = 0;
    for (const int f : t.boundary) surface_faces += f;
    out.push_back({{"block", r.block}, {"component", t.component}, {"kind", t.kind}, {"surface_faces", surface_faces},
                   {"elements", r.elements}, {"mean_before", r.mean_before}, {"min_before", r.min_before},
                   {"mean_after", r.mean_after}, {"min_after", r.min_after}});
  }
  return out;
}

// Blocks, optimization, files and report: the same for every kind of polycube.
core::Json build_and_write(pipeline::StageContext& ctx, const core::Json& surface, tmesh::PolycubeMaps maps) {
  std::vector<tmesh::TMesh> ts;
  tmesh::Levels levels;
  // The input surface as closest-point queries, built once: the adaptive levels' deviation
  // (measured whenever epsilon_rel > 0, report key levels) and the sliding surface nodes.
  const bool slide_nodes = ctx.config.tmesh.optimize_sweeps > 0 && ctx.config.tmesh.slide_surface;
  std::unique_ptr<tmesh::SlideSurface> input;
  if (ctx.config.tmesh.epsilon_rel > 0 || slide_nodes) {
    const surface::Mesh mesh = surface::mesh_from_json(surface, ctx.input_file("polycube"));
    input = std::make_unique<tmesh::SlideSurface>(surface::vertex_array(mesh), surface::triangle_triples(mesh));
    if (ctx.config.tmesh.epsilon_rel > 0) {
      maps.surface_distance = [&input](const tmesh::Vec3& x) {
        const tmesh::Vec3 y = input->closest(x);
        return std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]);
      };
      Eigen::AlignedBox3d box;
      for (const auto& v : surface::vertex_array(mesh)) box.extend(Eigen::Vector3d(v[0], v[1], v[2]));
      maps.diagonal = box.diagonal().norm();
    }
  }
  {
    core::LogSection s("octree, pillow and control points");
    ts = tmesh::build(maps, ctx.config.tmesh, &levels);
    std::map<int, int> per_level;
    for (const int l : levels.level) ++per_level[l];
    std::string counts;
    for (const auto& [l, k] : per_level) counts += (counts.empty() ? "" : ", ") + std::to_string(k) + " at level " + std::to_string(l);
    core::log("cubes: " + counts + " (adaptive levels: " + levels.stop + ", boundary deviation " + std::to_string(levels.deviation_rel) +
              " of the diagonal, epsilon_rel " + std::to_string(ctx.config.tmesh.epsilon_rel) + ")");
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
    op.cycles = ctx.config.tmesh.optimize_cycles;
    op.trilinear_sweeps = ctx.config.tmesh.trilinear_sweeps;
    op.trilinear_guard = ctx.config.tmesh.trilinear_guard;
    op.joint_evaluations = ctx.config.tmesh.joint_evaluations;
    op.grid_points = ctx.config.tmesh.grid_points;
    op.joint_sharpness = ctx.config.tmesh.joint_sharpness;
    op.joint_window = ctx.config.tmesh.joint_window;
    op.slide_from_start = ctx.config.tmesh.slide_from == "start";
    op.slide_sharp_curves = ctx.config.tmesh.slide_sharp_curves;
    // Optimize the figure extract reports: its Gauss points (0 = degree + 1) and the corners.
    op.gauss_points = ctx.config.extract.gauss_points > 0 ? ctx.config.extract.gauss_points : ctx.config.tmesh.degree + 1;
    const tmesh::SlideSurface* slide = slide_nodes ? input.get() : nullptr;
    if (slide)
      core::log("surface nodes slide along the input surface (" + std::to_string(slide->sharp_edges()) + " sharp edges, " +
                std::to_string(slide->sharp_corners()) + " sharp corners" + (op.slide_sharp_curves ? ", sharp-curve nodes along their curve)" : " keep theirs)"));
    opt = tmesh::optimize(ts, op, slide);
  }
  // The optimized spline, h-refined for analysis (same map; per-element figures go to the
  // refined elements of each optimized one).
  const core::Json worst = worst_blocks(ts, opt);
  const int optimized_elements = [&] {
    int n = 0;
    for (const auto& t : ts) n += t.elements();
    return n;
  }();
  if (ctx.config.tmesh.h_refine > 0) {
    core::LogSection s("h-refinement by knot insertion");
    std::vector<int> parent;
    ts = tmesh::h_refine(maps, ctx.config.tmesh, ts, ctx.config.tmesh.h_refine, &parent);
    for (auto* field : {&opt.element_before, &opt.element_after}) {
      if (field->empty()) continue;
      std::vector<double> fine;
      for (const int e : parent) fine.push_back((*field)[static_cast<std::size_t>(e)]);
      field->swap(fine);
    }
    core::log("every element split in " + std::to_string(1 << (3 * ctx.config.tmesh.h_refine)) + ": " + std::to_string(optimized_elements) + " -> " +
              std::to_string(parent.size()) + " elements");
  }
  {
    core::LogSection s("write");
    core::Json list = core::Json::array();
    for (const auto& t : ts) list.push_back(tmesh::to_json(t));
    core::write_stage_file(ctx.output_file(), "volts-tmesh", 3, {{"surface", surface}, {"tmeshes", list}});
    std::vector<std::pair<std::string, std::vector<double>>> extra;
    if (!opt.element_before.empty())
      extra = {{"bezier_scaled_jacobian_before", opt.element_before}, {"bezier_scaled_jacobian_after", opt.element_after}};
    after = tmesh::write_vtu(ctx.path("tmesh.vtu"), ts, extra);
  }
  core::Json fig = tmesh::report_figures(ts, before, after);
  fig["levels"] = {{"stop", levels.stop}, {"refinements", levels.refinements}, {"refined_blocks", levels.refined_blocks}, {"cube_levels", levels.level},
                   {"boundary_deviation_rel", levels.deviation_rel}, {"cube_deviation_rel", levels.cube_deviation_rel},
                   {"epsilon_rel", ctx.config.tmesh.epsilon_rel}};
  // The Bézier elements' sampled scaled Jacobian around optimization (trilinear figures above).
  fig["optimization"] = {{"sweeps", opt.sweeps}, {"nodes_moved", opt.nodes_moved},
                         {"bezier_min_scaled_jacobian_before", opt.min_before}, {"bezier_min_scaled_jacobian_after", opt.min_after},
                         {"not_certified_valid_before", opt.invalid_before}, {"not_certified_valid_after", opt.invalid_after},
                         {"stop_reason", opt.stop_reason}, {"sweeps_cut_at_node_bound", opt.sweeps_cut_at_node_bound},
                         {"trilinear_nodes_moved", opt.trilinear_nodes_moved}, {"joint_rounds", opt.joint_rounds}, {"cycles", opt.cycles},
                         {"surface_nodes_slid", opt.surface_nodes_slid}, {"worst_blocks", worst}};
  fig["h_refine"] = ctx.config.tmesh.h_refine;
  fig["elements_optimized"] = optimized_elements;
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
