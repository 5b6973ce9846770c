// volts::fit — route `fit` as one call: Lin, Huang & Hu 2018 from a closed genus-0 surface to
// seven fitted trivariate B-spline solids (cube_map.h → pillow.h → gfd.h). volts-fit wraps it and
// hands the solids to extract's exporters.
#pragma once

#include "classify/classify.h"
#include "core/stage_file.h"
#include "fit/cube_map.h"
#include "fit/gfd.h"
#include "fit/pillow.h"
#include "tmesh/optimize.h"

namespace volts::fit {

struct Params {
  CubeMapParams cube;
  PillowParams pillow;
  GfdParams gfd;
  /// Sweeps of tmesh::optimize after the fitting [0, 100]; 0 = none. It moves interior control
  /// points to raise the worst scaled Jacobian and repairs elements not certified valid (never
  /// loses a certified-valid one), but it does not keep Proposition 3: for nets whose initial
  /// map was too distorted for it (route fit on the fandisk: 18 of 448 elements not certified
  /// valid after fitting, 3 after 10 sweeps).
  int optimize_sweeps = 0;
};

struct Result {
  CubeMap cube;
  std::vector<tmesh::TMesh> solids;  ///< core, then the six frusta
  GfdReport gfd;
  tmesh::OptimizeResult optimization;  ///< stop_reason "disabled" unless optimize_sweeps > 0
  double time_map_s = 0, time_fit_s = 0;
};

/// Maps the solid onto the cube, builds the seven initial solids and fits them. Throws what
/// map_to_cube, initial_solids and fit_solids throw.
Result run(const surface::Mesh& mesh, const classify::Classification& c, const Params& params);

/// Report keys (under "fit" in report.json): patch_source, solids, control_points,
/// flipped_surface_triangles, max_angle_distortion_deg, tets, flipped_tets, min_volume_ratio,
/// initial_failing_subgrids, final_failing_subgrids, initial_margin, final_margin, phases (per
/// phase: name, points, sweeps, moves, shortened, refused, rms/max before/after), g1 (per common
/// face: solids, points, max/mean angle before and after, alpha), g1_max_angle_deg_before/after,
/// optimization (as tmesh's), time_map_s, time_fit_s.
core::Json report_figures(const Result& r);

}  // namespace volts::fit
