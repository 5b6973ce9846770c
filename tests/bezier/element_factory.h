// Shared helpers of the Jacobian/certification tests: seeded random Bézier elements near the
// identity map (valid unless perturbed on purpose).
#pragma once

#include <random>

#include "bezier/bezier_hex.h"
#include "bezier/bezier_tet.h"

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
