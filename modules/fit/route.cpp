#include "fit/route.h"

#include <chrono>
#include <cmath>
#include <optional>

#include "core/errors.h"
#include "core/log.h"

namespace volts::fit {

Result run(const surface::Mesh& mesh, const classify::Classification& c, const Params& params) {
  Result r;
  auto t0 = std::chrono::steady_clock::now();
  {
    core::LogSection s("map onto the cube");
    r.cube = map_to_cube(mesh, c, params.cube);
    core::log("six patches from " + r.cube.patch_source + ", " + std::to_string(r.cube.volume.tets.size()) + " tets, max angle distortion " +
              std::to_string(r.cube.surface.max_angle_distortion_deg) + " degrees, min volume ratio " +
              std::to_string(r.cube.volume.min_volume_ratio));
  }
  const volmap::Locator locate(r.cube.volume);
  const auto map = [&](const tmesh::Vec3& uvw) {
    const std::optional<std::array<double, 3>> x = locate.physical(uvw);
    if (!x) throw core::NumericalError("fit: the cube point (" + std::to_string(uvw[0]) + ", " + std::to_string(uvw[1]) + ", " +
                                       std::to_string(uvw[2]) + ") is outside the volume map");
    return *x;
  };
  r.time_map_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  t0 = std::chrono::steady_clock::now();
  {
    core::LogSection s("pillow partition and initial solids");
    r.solids = initial_solids(map, params.pillow);
  }
  r.gfd = fit_solids(r.solids, map, params.gfd);
  r.optimization.stop_reason = "disabled";
  if (params.optimize_sweeps > 0) {
    core::LogSection s("optimization of the worst Jacobian");
    tmesh::OptimizeParams op;
    op.sweeps = params.optimize_sweeps;
    op.trilinear_sweeps = 0;  // the fit route reports the Bézier figures only (issue 9's figures stand)
    op.gauss_points = params.pillow.degree + 1;  // extract's sample
    r.optimization = tmesh::optimize(r.solids, op);
  }
  r.time_fit_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

core::Json report_figures(const Result& r) {
  int points = 0;
  for (const auto& t : r.solids)
    for (const int id : t.function_ids) points = std::max(points, id + 1);
  core::Json phases = core::Json::array();
  for (const auto& p : r.gfd.phases)
    phases.push_back({{"name", p.name}, {"points", p.points}, {"sweeps", p.sweeps}, {"moves", p.moves}, {"shortened", p.shortened},
                      {"refused", p.refused}, {"rms_before", p.rms_before}, {"rms_after", p.rms_after}, {"max_before", p.max_before},
                      {"max_after", p.max_after}});
  core::Json g1 = core::Json::array();
  double before = 0, after = 0;
  for (std::size_t i = 0; i < r.gfd.g1_after.size(); ++i) {
    const auto& b = r.gfd.g1_before[i];
    const auto& a = r.gfd.g1_after[i];
    g1.push_back({{"solids", {a.first, a.second}}, {"points", a.points}, {"max_angle_deg_before", b.max_angle_deg},
                  {"max_angle_deg_after", a.max_angle_deg}, {"mean_angle_deg_before", b.mean_angle_deg},
                  {"mean_angle_deg_after", a.mean_angle_deg}, {"alpha", a.alpha}});
    before = std::max(before, b.max_angle_deg), after = std::max(after, a.max_angle_deg);
  }
  return {{"patch_source", r.cube.patch_source},
          {"solids", r.solids.size()},
          {"control_points", points},
          {"flipped_surface_triangles", r.cube.surface.flipped_surface_triangles},
          {"max_angle_distortion_deg", r.cube.surface.max_angle_distortion_deg},
          {"tets", r.cube.volume.tets.size()},
          {"flipped_tets", r.cube.volume.flipped_tets},
          {"min_volume_ratio", r.cube.volume.min_volume_ratio},
          {"start", {{"not_certified_valid", r.gfd.start_not_valid}, {"rounds", r.gfd.start_rounds},
                     {"blended_points", r.gfd.start_blended_points}, {"max_shift_rel", r.gfd.start_max_shift}}},
          {"initial_failing_subgrids", r.gfd.initial_failing_subgrids},
          {"final_failing_subgrids", r.gfd.final_failing_subgrids},
          {"initial_margin", r.gfd.initial_margin},
          {"final_margin", r.gfd.final_margin},
          {"phases", phases},
          {"g1", g1},
          {"g1_max_angle_deg_before", before},
          {"g1_max_angle_deg_after", after},
          {"optimization", {{"sweeps", r.optimization.sweeps}, {"nodes_moved", r.optimization.nodes_moved},
                            {"bezier_min_scaled_jacobian_before", r.optimization.min_before},
                            {"bezier_min_scaled_jacobian_after", r.optimization.min_after},
                            {"not_certified_valid_before", r.optimization.invalid_before},
                            {"not_certified_valid_after", r.optimization.invalid_after}, {"stop_reason", r.optimization.stop_reason}}},
          {"time_map_s", r.time_map_s},
          {"time_fit_s", r.time_fit_s}};
}

}  // namespace volts::fit
