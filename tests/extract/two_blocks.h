// A hand-built two-block spline for the extract tests: cubic blocks of 2x2x2 elements on [0,1]^3
// and [1,2]x[0,1]^2 (5^3 control points each), control points a smooth bent map of their Greville
// points, sharing the face x = 1 with the same function ids (125 + 100 = 225 global functions).
#pragma once

#include <cmath>
#include <vector>

#include "bezier/bspline.h"
#include "bezier/bspline_volume.h"
#include "extract/extract.h"
#include "tmesh/tmesh.h"

namespace volts::test {

inline std::array<double, 3> bent(double x, double y, double z) {
  return {x + 0.05 * std::sin(3 * y), y + 0.1 * x * (2 - x) * z, z + 0.05 * x * y};
}

/// Blocks 0 and 1; if `share` is false, function_ids stay empty (numbered block after block).
inline std::vector<tmesh::TMesh> two_blocks(bool share = true) {
  std::vector<tmesh::TMesh> ts(2);
  for (int b = 0; b < 2; ++b) {
    tmesh::TMesh& t = ts[b];
    t.degree = 3;
    for (int d = 0; d < 3; ++d) t.knots[d] = bezier::open_uniform_knots(2, 3);
    t.size = {5, 5, 5};
    const auto g = bezier::greville_abscissae(t.knots[0], 3);
    for (int k = 0; k < 5; ++k)
      for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) {
          t.control_points.push_back(bent(b + g[i], g[j], g[k]));
          if (!share) continue;
          if (b == 0) t.function_ids.push_back(i + 5 * (j + 5 * k));
          else t.function_ids.push_back(i == 0 ? 4 + 5 * (j + 5 * k) : 125 + (i - 1) + 4 * (j + 5 * k));
        }
    t.boundary = {b == 0, b == 1, 1, 1, 1, 1};
  }
  return ts;
}

/// The Bézier hexes of the blocks, block after block (as extract() orders them).
inline std::vector<bezier::BezierHex> hexes_of(const std::vector<tmesh::TMesh>& ts) {
  std::vector<bezier::BezierHex> hexes;
  for (const auto& t : ts) {
    bezier::TensorBSplineVolume v;
    v.degree = {t.degree, t.degree, t.degree};
    v.knots = t.knots;
    for (const auto& p : t.control_points) v.points.emplace_back(p[0], p[1], p[2]);
    const auto h = bezier::extract_bezier_hexes(v);
    hexes.insert(hexes.end(), h.begin(), h.end());
  }
  return hexes;
}

/// A Result with hexes, basis and per-element figures filled as extract() would (no surface needed).
inline extract::Result two_block_result() {
  extract::Result r;
  const auto ts = two_blocks();
  r.hexes = hexes_of(ts);
  r.basis = extract::global_basis(ts, r.hexes);
  r.degree = 3;
  for (std::size_t e = 0; e < r.hexes.size(); ++e) {
    r.min_scaled_jacobian.push_back(0.05 * static_cast<double>(e));  // 0 .. 0.75: spread over the histogram
    r.status.push_back(1);
  }
  return r;
}

}  // namespace volts::test
