// Shared helpers of the volts::tet2hex tests: seeded random Bézier tets (in volts::test, beside
// the helpers of common/test_util.h).
#pragma once

#include <random>

#include "bezier/bezier_tet.h"

namespace volts::test {

/// A random Bézier tet of degree n: a random positive linear tet (edge lengths ~1, not too flat)
/// elevated to n, every control point moved by up to `wobble` (absolute), optionally with random
/// weights in [0.5, 2].
inline bezier::BezierTet random_tet(std::mt19937& rng, int n, double wobble, bool rational = false) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), w(0.5, 2.0);
  Eigen::Vector3d c[4];
  do {
    for (auto& x : c) x = Eigen::Vector3d(u(rng), u(rng), u(rng));
  } while ((c[1] - c[0]).cross(c[2] - c[0]).dot(c[3] - c[0]) < 0.3);
  bezier::BezierTet t;
  t.degree = n;
  for (const auto& a : bezier::simplex_multi_indices(3, n)) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int v = 0; v < 4; ++v) x += a[v] * c[v];
    t.points.push_back(x / n + wobble * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    if (rational) t.weights.push_back(w(rng));
  }
  return t;
}

/// Bounding-box diagonal of the control points (the element size of the tolerances).
inline double size(const bezier::BezierTet& t) {
  Eigen::Vector3d lo = t.points[0], hi = t.points[0];
  for (const auto& p : t.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return (hi - lo).norm();
}

/// A uniform random point of the unit tet (barycentric sorting trick).
inline Eigen::Vector3d random_uvw(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double s[3] = {u(rng), u(rng), u(rng)};
  std::sort(s, s + 3);
  return {s[0], s[1] - s[0], s[2] - s[1]};
}

}  // namespace volts::test
