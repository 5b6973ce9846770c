// Test helpers: rings of k cubes (a square-section torus cut into k sectors) as tmesh::PolycubeMaps,
// and evaluation of the blocks' splines (levels_test.cpp, h_refine_test.cpp).
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bezier/bspline_volume.h"
#include "tmesh/optimize.h"
#include "tmesh/pillow.h"
#include "tmesh/tmesh.h"

namespace volts::test {

using tmesh::Vec3;

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInner = 2.0, kOuter = 3.0;  // radii of the ring's walls; height [0, 1]

// Cube c of k covers the angles -[c, c + 1] 2π/k; parameters (a, b, h): a along the ring, b
// radial, h height. The polycube embedding and the physical map are the same bent ring.
inline Vec3 ring_point(int k, int c, const Vec3& abh) {
  const double t = -2 * kPi * (c + abh[0]) / k, r = kInner + (kOuter - kInner) * abh[1];  // clockwise: (a, b, h) right-handed
  return {r * std::cos(t), r * std::sin(t), abh[2]};
}

inline tmesh::PolycubeMaps ring(int k) {
  tmesh::PolycubeMaps m;
  m.boundary.assign(static_cast<std::size_t>(k), {0, 0, 1, 1, 1, 1});
  m.physical = [k](int c, const Vec3& x) { return ring_point(k, c, x); };
  m.polycube = [k](int c, const Vec3& x) { return ring_point(k, c, x); };
  return m;
}

// Distance to the ring's surface (two cylinders and two planes) of a point inside it.
inline double ring_distance(const Vec3& x) {
  const double r = std::hypot(x[0], x[1]);
  return std::min({std::abs(r - kInner), std::abs(r - kOuter), std::abs(x[2]), std::abs(x[2] - 1)});
}

// The ring with its true surface distance (adaptive levels, levels_test.cpp).
inline tmesh::PolycubeMaps measured_ring(int k) {
  tmesh::PolycubeMaps maps = ring(k);
  maps.diagonal = 2 * kOuter;
  maps.surface_distance = ring_distance;
  return maps;
}

// A ring whose surface, seen from cube 0's sector, lies 1e6 times as far as it does (a distance
// that still shrinks with every level, by the spline's h^4): adaptivity refines there first.
inline tmesh::PolycubeMaps ring_far_at_cube0(int k) {
  tmesh::PolycubeMaps maps = measured_ring(k);
  maps.surface_distance = [](const Vec3& x) {
    const double t = std::atan2(x[1], x[0]);
    return (t < -0.05 && t > -0.5 ? 1e6 : 1.0) * ring_distance(x);
  };
  return maps;
}

// Parameters under which ring_far_at_cube0 refines its cube 0 to level 4 (ε 0.01, no h-refinement).
inline tmesh::Params far_ring_params(int level, const std::string& refine) {
  tmesh::Params p;
  p.level = level;
  p.max_level = 4;
  p.epsilon_rel = 0.01;
  p.h_refine = 0;
  p.refine = refine;
  return p;
}

inline bezier::TensorBSplineVolume volume(const tmesh::TMesh& t) {
  bezier::TensorBSplineVolume v;
  v.degree = {t.degree, t.degree, t.degree};
  v.knots = t.knots;
  for (const auto& p : t.control_points) v.points.emplace_back(p[0], p[1], p[2]);
  return v;
}

// Block parameters of cube parameters x (Newton on the trilinear block map); false if x is not in the block.
inline bool block_params(const std::array<Vec3, 8>& corners, const Vec3& x, Vec3* uvw) {
  Eigen::Vector3d u(0.5, 0.5, 0.5);
  for (int it = 0; it < 50; ++it) {
    const Vec3 y = tmesh::block_point(corners, {u[0], u[1], u[2]});
    const Eigen::Vector3d r(y[0] - x[0], y[1] - x[1], y[2] - x[2]);
    if (r.norm() < 1e-15) break;
    Eigen::Matrix3d J;
    for (int d = 0; d < 3; ++d) {
      Eigen::Vector3d v = u;
      v[d] += 1e-7;
      const Vec3 z = tmesh::block_point(corners, {v[0], v[1], v[2]});
      J.col(d) = Eigen::Vector3d(z[0] - y[0], z[1] - y[1], z[2] - y[2]) / 1e-7;
    }
    u -= J.fullPivLu().solve(r);
  }
  for (int d = 0; d < 3; ++d)
    if (u[d] < -1e-10 || u[d] > 1 + 1e-10) return false;
  *uvw = {std::clamp(u[0], 0.0, 1.0), std::clamp(u[1], 0.0, 1.0), std::clamp(u[2], 0.0, 1.0)};
  return true;
}

// The spline of cube `cube` at cube parameters x (the first of its blocks that contains x).
inline Eigen::Vector3d spline_at(const std::vector<tmesh::TMesh>& ts, int cube, const Vec3& x) {
  for (const auto& t : ts) {
    Vec3 uvw;
    if (t.component == cube && block_params(t.corners, x, &uvw)) return bezier::evaluate(volume(t), Eigen::Vector3d(uvw[0], uvw[1], uvw[2]));
  }
  ADD_FAILURE() << "no block of cube " << cube << " holds " << x[0] << "," << x[1] << "," << x[2];
  return Eigen::Vector3d::Zero();
}

inline std::vector<bezier::BezierHex> hexes(const std::vector<tmesh::TMesh>& ts) {
  std::vector<bezier::BezierHex> h;
  for (const auto& t : ts) {
    const auto e = bezier::extract_bezier_hexes(volume(t));
    h.insert(h.end(), e.begin(), e.end());
  }
  return h;
}


// Optimizer settings under which the joint rounds run to their own bounds (a target out of
// reach) followed by one sweep.
inline tmesh::OptimizeParams running_rounds(int rounds, int evaluations) {
  tmesh::OptimizeParams op;
  op.target = 0.9;
  op.joint_rounds = rounds;
  op.joint_evaluations = evaluations;
  op.sweeps = 1;
  return op;
}

}  // namespace volts::test
