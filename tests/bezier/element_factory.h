// Shared helpers of the Jacobian/certification tests: seeded random Bézier elements near the
// identity map (valid unless perturbed on purpose).
#pragma once

#include <random>

#include "bezier/bezier_hex.h"
#include "bezier/bezier_tet.h"
#include "bezier/bspline.h"
#include "bezier/bspline_volume.h"

namespace volts::bezier::testing {

/// Degree-(p,q,r) hex: Greville grid of [0,1]^3 jittered by ±amp, optional random weights.
inline BezierHex perturbed_hex(std::mt19937& rng, std::array<int, 3> d, double amp, bool rational) {
  std::uniform_real_distribution<double> j(-amp, amp), w(0.85, 1.2);
  BezierHex h;
  h.degree = d;
  for (int n = 0; n < h.num_points(); ++n) {
    const auto [a, b, c] = h.ijk(n);
    h.points.push_back(Eigen::Vector3d(double(a) / d[0], double(b) / d[1], double(c) / d[2]) +
                       Eigen::Vector3d(j(rng), j(rng), j(rng)));
    if (rational) h.weights.push_back(w(rng));
  }
  return h;
}

/// A curved rational cubic B-spline volume of 2 x 2 x 1 elements over about [0,1]² x [0,0.5]:
/// control points bent (y + 0.3 x²) and jittered by ±0.08, weights in [0.5, 2].
inline TensorBSplineVolume curved_rational_volume(std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-0.08, 0.08), weight(0.5, 2.0);
  TensorBSplineVolume v;
  v.degree = {3, 3, 3};
  v.knots = {open_uniform_knots(2, 3), open_uniform_knots(2, 3), open_uniform_knots(1, 3)};
  const auto n = v.num_points();
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const double u = double(i) / (n[0] - 1), s = double(j) / (n[1] - 1), w = double(k) / (n[2] - 1);
        v.points.emplace_back(u + jitter(rng), s + 0.3 * u * u + jitter(rng), 0.5 * w + jitter(rng));
        v.weights.push_back(weight(rng));
      }
  return v;
}

/// Degree-n tet: the unit tet's domain points jittered by ±amp, optional random weights.
inline BezierTet perturbed_tet(std::mt19937& rng, int n, double amp, bool rational) {
  std::uniform_real_distribution<double> j(-amp, amp), w(0.85, 1.2);
  BezierTet t;
  t.degree = n;
  for (const auto& a : simplex_multi_indices(3, n)) {
    t.points.push_back(Eigen::Vector3d(a[1], a[2], a[3]) / n + Eigen::Vector3d(j(rng), j(rng), j(rng)));
    if (rational) t.weights.push_back(w(rng));
  }
  return t;
}

inline Eigen::Vector3d random_in_tet(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::Vector3d x(unit(rng), unit(rng), unit(rng));
  while (x.sum() > 1) x = Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
  return x;
}

}  // namespace volts::bezier::testing
