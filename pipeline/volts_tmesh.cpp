// volts-tmesh: stage 4 (Liu et al. §5.1–5.2). Reads polycube.stage.json, builds the octree T-mesh
// (control mesh) through the volume map; writes tmesh.stage.json and tmesh.vtu.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>

#include "core/errors.h"
#include "core/log.h"
#include "core/parallel.h"
#include "polycube_input.h"
#include "stage_main.h"
#include "surface/mesh_json.h"
#include "tmesh/continuity.h"
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

// The worst T-mesh element as a trilinear hex (eq. (1)-(2)), each block's element spans split as
// `splits` says first (tmesh::refinement_splits: the net h-refined by knot insertion; none: as
// they are); blocks in parallel.
double min_corner_figure(const std::vector<tmesh::TMesh>& ts, const std::vector<tmesh::SpanSplits>* splits = nullptr) {
  std::vector<double> per(ts.size());
  core::parallel_for(ts.size(), [&](std::size_t b) { per[b] = splits ? tmesh::min_element_scaled_jacobian(ts[b], (*splits)[b]) : tmesh::min_element_scaled_jacobian(ts[b]); }, 1);
  double worst = std::numeric_limits<double>::infinity();
  for (const double x : per) worst = std::min(worst, x);
  return worst;
}

// tmesh.h_refine: the T-mesh is laid out and optimized h levels coarser than tmesh.level (its
// adaptive bound max_level too) and refined to it by knot insertion afterwards.
tmesh::Params coarser(const tmesh::Params& want, int h) {
  tmesh::Params p = want;
  p.level = want.level - h;
  p.max_level = std::max(p.level, want.max_level - h);
  p.h_refine = h;
  return p;
}

// Blocks, optimization, files and report: the same for every kind of polycube. The layout is
// tried h_refine levels coarser first, then one level finer at a time where it does not fit
// (a hole's pillow needs room: TopologyError), down to tmesh.level itself.
core::Json build_and_write(pipeline::StageContext& ctx) {
  const tmesh::Params& want = ctx.config.tmesh;
  int h = std::max(0, std::min(want.h_refine, want.level - 1));
  if (h < want.h_refine)
    core::log("tmesh.h_refine " + std::to_string(want.h_refine) + " at tmesh.level " + std::to_string(want.level) + ": optimized at level " +
              std::to_string(want.level - h) + ", refined " + std::to_string(h) + " time(s)");
  tmesh::Params params = coarser(want, h);
  pipeline::PolycubeInput in;
  std::vector<tmesh::TMesh> ts;
  tmesh::Levels levels;
  // The input surface as closest-point queries, built once: the adaptive levels' deviation
  // (measured whenever epsilon_rel > 0, report key levels) and the sliding surface nodes.
  const bool slide_nodes = params.optimize_sweeps > 0 && params.slide_surface;
  std::unique_ptr<tmesh::SlideSurface> input;
  double diagonal = 0;
  for (;;) {
    try {
      in = pipeline::read_polycube_input(ctx.input_file("polycube"), params);
      if (!input && (params.epsilon_rel > 0 || slide_nodes)) {
        const surface::Mesh mesh = surface::mesh_from_json(in.surface, ctx.input_file("polycube"));
        input = std::make_unique<tmesh::SlideSurface>(surface::vertex_array(mesh), surface::triangle_triples(mesh));
        Eigen::AlignedBox3d box;
        for (const auto& v : surface::vertex_array(mesh)) box.extend(Eigen::Vector3d(v[0], v[1], v[2]));
        diagonal = box.diagonal().norm();
      }
      if (params.epsilon_rel > 0) {
        in.maps.surface_distance = [&input](const tmesh::Vec3& x) {
          const tmesh::Vec3 y = input->closest(x);
          return std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]);
        };
        in.maps.diagonal = diagonal;
      }
      core::LogSection s("octree, pillow and control points");
      ts = tmesh::build(in.maps, params, &levels);
      break;
    } catch (const core::TopologyError& e) {
      if (h == 0) throw;
      core::log("the layout does not fit at level " + std::to_string(params.level) + " (" + e.what() + "): built at level " +
                std::to_string(params.level + 1) + ", h-refined " + std::to_string(h - 1) + " time(s)");
      params = coarser(want, --h);
    }
  }
  const core::Json& surface = in.surface;
  const tmesh::PolycubeMaps& maps = in.maps;
  {
    std::map<int, int> per_level;
    for (const int l : levels.level) ++per_level[l];
    std::string counts;
    for (const auto& [l, k] : per_level) counts += (counts.empty() ? "" : ", ") + std::to_string(k) + " at level " + std::to_string(l);
    if (params.refine == "spans" && levels.knots_inserted > 0)
      core::log("adaptive spans: " + std::to_string(levels.knots_inserted) + " knots inserted in " + std::to_string(levels.refined_blocks) + " blocks over " +
                std::to_string(levels.refinements) + " round(s)");
    core::log("cubes: " + counts + " (adaptive levels: " + levels.stop + ", boundary deviation " + std::to_string(levels.deviation_rel) +
              " of the diagonal, epsilon_rel " + std::to_string(params.epsilon_rel) + ")");
  }
  // The control net's figure before optimization, on the mesh the figure after is taken on: the
  // unoptimized T-mesh refined alike (knot insertion moves the net, not the spline).
  // Its elements are split alike on the unrefined blocks: no h-refined copy is built.
  const std::vector<tmesh::SpanSplits> splits = tmesh::refinement_splits(maps, params, ts, params.h_refine);
  const double before = min_corner_figure(ts, &splits);
  const bool refine = params.h_refine > 0 || params.pillow_splits > 1;
  double after = before;
  tmesh::OptimizeResult opt;
  opt.stop_reason = "disabled";
  tmesh::OptimizeParams op;
  const tmesh::SlideSurface* slide = slide_nodes ? input.get() : nullptr;
  if (params.optimize_sweeps > 0) {
    core::LogSection s("optimization of the worst Jacobian");
    op.sweeps = params.optimize_sweeps;
    op.stop_at = params.stop_at;
    op.joint_rounds = params.joint_rounds;
    op.cycles = params.optimize_cycles;
    op.trilinear_sweeps = params.trilinear_sweeps;
    op.trilinear_guard = params.trilinear_guard;
    op.joint_evaluations = params.joint_evaluations;
    op.grid_points = params.grid_points;
    op.check_points = params.check_points;
    op.check_tolerance = params.check_tolerance;
    op.joint_sharpness = params.joint_sharpness;
    op.joint_window = params.joint_window;
    op.joint_method = params.joint_method == "lbfgs" ? tmesh::OptimizeParams::JointMethod::lbfgs : tmesh::OptimizeParams::JointMethod::ccsaq;
    op.slide_from = params.slide_from == "start"   ? tmesh::OptimizeParams::SlideFrom::start
                    : params.slide_from == "valid" ? tmesh::OptimizeParams::SlideFrom::valid
                                                   : tmesh::OptimizeParams::SlideFrom::stall;
    op.slide_sharp_curves = params.slide_sharp_curves;
    op.fold_retry = params.fold_retry;
    // Sliding may not take the boundary past epsilon_rel (issue 8's hausdorff_rel), on the grid
    // the adaptive levels measure it on (on the h-refined net, where repair_folds runs with these
    // parameters, a finer grid that holds extract's).
    op.max_boundary_deviation = params.epsilon_rel * diagonal;
    op.deviation_points = tmesh::deviation_points(params);
    // Optimize the figure extract reports: its Gauss points (0 = degree + 1) and the corners.
    op.gauss_points = ctx.config.extract.gauss_points > 0 ? ctx.config.extract.gauss_points : params.degree + 1;
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
  if (refine) {
    core::LogSection s("h-refinement by knot insertion");
    std::vector<int> parent;
    ts = tmesh::h_refine(maps, params, ts, params.h_refine, &parent);
    for (auto* field : {&opt.element_before, &opt.element_after}) {
      if (field->empty()) continue;
      std::vector<double> fine;
      for (const int e : parent) fine.push_back((*field)[static_cast<std::size_t>(e)]);
      field->swap(fine);
    }
    core::log("every element split in " + std::to_string(1 << (3 * params.h_refine)) +
              (params.pillow_splits > 1 ? ", the pillow slabs' also in " + std::to_string(params.pillow_splits) + " across the surface" : std::string()) + ": " +
              std::to_string(optimized_elements) + " -> " + std::to_string(parent.size()) + " elements");
  }
  // tmesh.continuity c2 (continuity.h): on the net as it goes out (optimized, h-refined), rows
  // across the faces between blocks of one level make them C2 away from their rims; the spline is
  // projected onto them (each face's knot-interval ratio fitted: the nearest C2 spline), and the
  // optimizer runs again from there, checking between the samples only the elements that moved.
  // On the optimized net before refinement the rows covered a third as many lines (two face
  // points of margin at level 2) and slowed the optimization down (docs/status.md "Session 50").
  const std::string continuity_mode = tmesh::continuity_mode(params);
  core::Json continuity = {{"mode", continuity_mode}};
  if (continuity_mode == "c2") {
    core::LogSection s("C2 across block faces");
    tmesh::ContinuityParams cp;
    cp.fit_ratio = true;
    // Lines that would move an extra more than half its nearest neighbour's distance keep C0:
    // without this bound the rod's thin slabs folded (88 elements at -0.9998 that the second
    // optimization took 5.5 s to repair); with it none fold and 72-92 % of the lines stay C2.
    cp.max_move_rel = 0.5;
    // Up to the surface too, where a surface point moves by at most a tenth of epsilon_rel (the
    // boundary moves by no more: hausdorff_rel grows by at most 0.1 epsilon_rel; measured: by
    // nothing on the bench models, 0.3 epsilon_rel the same); a sharp rim would move more and
    // keeps C0. Without an input surface (epsilon_rel 0, no sliding) the surface keeps C0.
    cp.surface_layer = true;
    cp.surface_move_max = 0.1 * params.epsilon_rel * diagonal;
    // Around regular edges (four blocks, 2 x 2) too: C0 stays only around irregular nodes.
    cp.regular_edges = true;
    // Knot intervals in the units the spline's knots are uniform in: with adaptive spans the
    // optimized net's units (times 2^h_refine once refined); with the pillow layer split further,
    // the uniform refinement's (its knot intervals there 1/pillow_splits of those).
    if (!levels.span_units.empty())
      for (const auto& u : levels.span_units) cp.lengths.push_back({std::ldexp(u[0], params.h_refine), std::ldexp(u[1], params.h_refine), std::ldexp(u[2], params.h_refine)});
    else if (params.pillow_splits > 1)
      for (const auto& sp : splits)
        cp.lengths.push_back({double(sp[0].size() << params.h_refine), double(sp[1].size() << params.h_refine), double(sp[2].size() << params.h_refine)});
    const std::vector<tmesh::TMesh> settled = ts;
    const tmesh::ContinuityResult c = [&] {
      core::LogSection p("rows and projection");
      return tmesh::raise_continuity(ts, cp);
    }();
    core::log(std::to_string(c.faces) + " block faces C2 across (" + std::to_string(c.lines) + " lines of control points, " + std::to_string(c.constrained) +
              " clamped extras now rows, moved up to " + std::to_string(c.moved_max) + "), " + std::to_string(c.faces_kept) + " kept C0; " +
              std::to_string(c.edge_points) + " points of regular edges C2 around");
    continuity.update({{"faces", c.faces}, {"lines", c.lines}, {"constrained", c.constrained}, {"faces_kept", c.faces_kept}, {"moved_max", c.moved_max}, {"lines_kept", c.lines_kept}, {"surface_lines", c.surface_lines}, {"edge_points", c.edge_points}});
    continuity["reoptimization"] = nullptr;
    if (params.optimize_sweeps > 0) {
      core::LogSection p("optimization again");
      // Nearly every element moves (the assembly: 44,738 of 47,488, most by 0.1-10 % of its
      // diagonal), so every one is sampled and checked: at the Gauss points and corners, checked
      // on extract's 7^3 grid (extract.dense_points; a dip found there is sampled on it from then
      // on). The optimization's own 5^3 and 13^3 took the assembly 2.1 s against 1.1 s at 2 and
      // 9^3, same worst, extract's 7^3 0.499 against 0.497.
      tmesh::OptimizeParams again_params = op;
      again_params.grid_points = 2;
      again_params.check_points = std::min(op.check_points, ctx.config.extract.dense_points > 1 ? ctx.config.extract.dense_points : 7);
      const tmesh::OptimizeResult again = tmesh::optimize_moved(ts, settled, again_params, slide);
      continuity["reoptimization"] = {{"bezier_min_scaled_jacobian_before", again.min_before}, {"bezier_min_scaled_jacobian_after", again.min_after},
                                      {"not_certified_valid_before", again.invalid_before}, {"not_certified_valid_after", again.invalid_after},
                                      {"joint_rounds", again.joint_rounds}, {"cycles", again.cycles}, {"stop_reason", again.stop_reason}};
      opt.element_after = again.element_after;
      opt.invalid_after = again.invalid_after, opt.min_after = again.min_after;
    }
  }
  // Folds the optimization left are repaired on the refined net: there every optimized element
  // has 8 (or 64) of its own, with their own control points, where the coarse net had too few (the
  // rod at joint_evaluations 325: 3 optimized elements folded in the connector's pillow).
  core::Json repair = nullptr;
  if (refine && params.optimize_sweeps > 0 && opt.invalid_after > 0) {
    core::LogSection s("repair of the folds on the refined net");
    core::log(std::to_string(opt.invalid_after) + " optimized elements not certified valid: their folds are repaired on the refined net");
    const tmesh::OptimizeResult rr = tmesh::repair_folds(ts, op, slide);
    opt.element_after = rr.element_after;
    repair = {{"not_certified_valid_before", rr.invalid_before}, {"not_certified_valid_after", rr.invalid_after},
              {"bezier_min_scaled_jacobian_before", rr.min_before}, {"bezier_min_scaled_jacobian_after", rr.min_after},
              {"joint_rounds", rr.joint_rounds}, {"stop_reason", rr.stop_reason}};
    opt.invalid_after = rr.invalid_after, opt.min_after = rr.min_after;
  }
  // Knot insertion keeps the spline, not the control net's corner hexes (the T-mesh elements as
  // trilinear hexes, eq. (1)-(2)): where the refined net folds one, the trilinear pass runs again
  // on it (Bezier elements kept certified valid and above the worst; the rod at the defaults:
  // coarse +0.144, refined -0.10).
  core::Json refined_pass = nullptr;
  if (refine && params.optimize_sweeps > 0 && params.trilinear_sweeps > 0) {
    const double fold = min_corner_figure(ts);
    if (fold < 0) {
      core::LogSection s("trilinear pass on the refined net");
      core::log("the refined net's worst corner hex is " + std::to_string(fold) + " (the optimized net's: " + std::to_string(opt.trilinear_after) + ")");
      tmesh::OptimizeParams tp = op;
      tp.sweeps = 0, tp.joint_rounds = 0, tp.cycles = 1;
      // The floor it keeps is on extract's samples of the refined elements: the Gauss points and
      // the 7³ grid (extract.dense_points' default, corners included). At 2 (the corners alone)
      // the pass lowered the field between them: the rod at joint_evaluations 325, 0.50 after the
      // optimizer, 0.337 on extract's 7³ grid (session 39).
      tp.grid_points = 7;
      const tmesh::OptimizeResult tr = tmesh::optimize(ts, tp, nullptr);
      opt.element_after = tr.element_after;  // the pass's sample (Gauss points and the 7³ grid) from here on
      refined_pass = {{"trilinear_before", tr.trilinear_before}, {"trilinear_after", tr.trilinear_after},
                      {"nodes_moved", tr.trilinear_nodes_moved}, {"bezier_min_scaled_jacobian_before", tr.min_before},
                      {"bezier_min_scaled_jacobian_after", tr.min_after},
                      {"not_certified_valid_after", tr.invalid_after}};
    }
  }
  // The smooth rows in the C2 spline's B-spline basis (same spline, non-negative functions; after
  // every optimization: the optimizer moves block points and their rows' nodes, not free nodes).
  if (continuity_mode == "c2") {
    core::LogSection s("B-spline basis of the C2 rows");
    const int lines = tmesh::smooth_rows_as_bsplines(ts);
    core::log(std::to_string(lines) + " of " + std::to_string(continuity.value("lines", 0)) + " C2 lines written in the B-spline basis (a free node each)");
    continuity["bspline_lines"] = lines;
  }
  {
    core::LogSection s("write");
    std::vector<std::pair<std::string, std::vector<double>>> extra;
    if (!opt.element_before.empty())
      extra = {{"bezier_scaled_jacobian_before", opt.element_before}, {"bezier_scaled_jacobian_after", opt.element_after}};
    // The stage file and the ParaView file share nothing: written side by side (each to a
    // temporary name first; a failure of either is rethrown once both are done).
    core::parallel_tasks({[&] {
                            core::Json list = core::Json::array();
                            for (const auto& t : ts) list.push_back(tmesh::to_json(t));
                            // Moved in: an initializer list would copy the whole tree (the assembly's write 0.30 -> 0.23 s).
                            core::Json payload = core::Json::object();
                            payload["surface"] = surface;
                            payload["tmeshes"] = std::move(list);
                            core::write_stage_file(ctx.output_file(), "volts-tmesh", 3, std::move(payload));
                          },
                          [&] { after = tmesh::write_vtu(ctx.path("tmesh.vtu"), ts, extra); }});
  }
  core::Json fig = tmesh::report_figures(ts, before, after);
  fig["levels"] = {{"stop", levels.stop}, {"refinements", levels.refinements}, {"refined_blocks", levels.refined_blocks},
                   {"refine", params.refine}, {"knots_inserted", levels.knots_inserted}, {"cube_levels", levels.level},
                   {"boundary_deviation_rel", levels.deviation_rel}, {"cube_deviation_rel", levels.cube_deviation_rel},
                   {"epsilon_rel", params.epsilon_rel}};
  // The Bézier elements' sampled scaled Jacobian around optimization (trilinear figures above).
  fig["optimization"] = {{"sweeps", opt.sweeps}, {"nodes_moved", opt.nodes_moved},
                         {"bezier_min_scaled_jacobian_before", opt.min_before}, {"bezier_min_scaled_jacobian_after", opt.min_after},
                         {"not_certified_valid_before", opt.invalid_before}, {"not_certified_valid_after", opt.invalid_after},
                         {"stop_reason", opt.stop_reason}, {"sweeps_cut_at_node_bound", opt.sweeps_cut_at_node_bound},
                         {"trilinear_nodes_moved", opt.trilinear_nodes_moved}, {"joint_rounds", opt.joint_rounds}, {"cycles", opt.cycles}, {"cycle_kept", opt.cycle_kept},
                         {"surface_nodes_slid", opt.surface_nodes_slid}, {"elements_on_check_grid", opt.elements_on_check_grid},
                         {"folds_between_samples", opt.folds_between_samples},
                         {"bezier_min_scaled_jacobian_after_checked", opt.min_after_checked},
                         {"worst_blocks", worst}};
  fig["optimization"]["joint_method"] = params.joint_method;
  fig["optimization"]["boundary_deviation_bound"] = op.max_boundary_deviation;
  fig["optimization"]["deviation_put_back"] = opt.deviation_put_back;
  fig["optimization"]["refined_trilinear_pass"] = refined_pass;
  fig["optimization"]["refined_repair"] = repair;
  fig["optimization"]["retry"] = nullptr;
  if (opt.retry.ran)
    fig["optimization"]["retry"] = {{"slide_from", "start"}, {"kept", opt.retry.kept}, {"not_certified_valid_after", opt.retry.invalid_after},
                                    {"bezier_min_scaled_jacobian_after", opt.retry.min_after}, {"time_s", opt.retry.seconds}};
  fig["h_refine"] = params.h_refine;
  fig["pillow_splits"] = params.pillow_splits;
  fig["continuity"] = continuity;
  fig["level_optimized"] = params.level;
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
        return build_and_write(ctx);
      });
}
