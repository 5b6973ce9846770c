// The octree refinement families shared by the T-spline tests (tests/tspline) and bench_tspline
// (header-only): refinement toward a fixed point, plane and sphere surface (predicates from
// octree/refine.h), and the Greville identity error at random points they are measured with.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "octree/refine.h"
#include "tspline/suitable.h"
#include "tspline/tspline.h"

namespace volts::test {

/// Cells holding the point (0.3, 0.61, 0.77).
inline bool toward_point(const octree::Cell& c) { return octree::contains_point(c, {0.3, 0.61, 0.77}); }
/// Cells meeting the plane x + 2y - z = 0.7.
inline bool toward_plane(const octree::Cell& c) { return octree::crosses_plane(c, {1, 2, -1}, 0.7); }
/// Cells meeting the sphere surface |x - (0.45, 0.5, 0.55)| = 0.3.
inline bool toward_sphere(const octree::Cell& c) { return octree::crosses_sphere(c, {0.45, 0.5, 0.55}, 0.3); }

/// Max |Σ N_i g_i - u| and |Σ R_i g_i - u| over `samples` random points u (std::mt19937(seed)),
/// g the Greville points: both 0 when the spline reproduces linears.
inline std::pair<double, double> random_identity_errors(const tspline::TSpline& ts, int samples, unsigned seed) {
  const std::vector<Eigen::Vector3d> g = tspline::greville_points(ts);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  double poly = 0, rat = 0;
  for (int s = 0; s < samples; ++s) {
    const Eigen::Vector3d u(U(rng), U(rng), U(rng));
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (const auto& [i, v] : ts.basis(u)) x += v * g[i];
    poly = std::max(poly, (x - u).cwiseAbs().maxCoeff());
    rat = std::max(rat, (ts.evaluate(g, u) - u).cwiseAbs().maxCoeff());
  }
  return {poly, rat};
}

}  // namespace volts::test
