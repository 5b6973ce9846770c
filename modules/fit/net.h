// volts::fit — control nets of B-spline curves, surfaces and trivariate B-spline solids (TBSs) as
// the validity conditions of Lin, Huang & Hu, "Trivariate B-spline solid construction by pillow
// operation and geometric iterative fitting" (Sci China Inf Sci, doi 10.1007/s11432-017-9376-8,
// section "Validity conditions") see them: points and degrees only. Knots do not enter
// Propositions 1–3 (they hold for any knot vectors of a polynomial B-spline); the paper's TBSs have
// uniform knots with Bézier end conditions, which to_volume() builds.
//
// check() and to_volume() throw core::InvalidInputError for a degree < 1, fewer than degree+1
// points in a direction, a point count that does not match the sizes, or a non-finite coordinate.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

#include "bezier/bspline_volume.h"

namespace volts::fit {

/// Control polygon P_0..P_m of a B-spline curve of degree d.
struct CurveNet {
  int degree = 3;
  std::vector<Eigen::Vector3d> points;
};

/// Control net S_ij, i < size[0], j < size[1], of a B-spline surface; index i + size[0]·j.
struct SurfaceNet {
  std::array<int, 2> size{0, 0};
  std::array<int, 2> degree{3, 3};
  std::vector<Eigen::Vector3d> points;
  int index(int i, int j) const { return i + size[0] * j; }
};

/// Control grid H_ijk of a TBS; index i + size[0]·(j + size[1]·k), as bezier::TensorBSplineVolume.
struct SolidNet {
  std::array<int, 3> size{0, 0, 0};
  std::array<int, 3> degree{3, 3, 3};
  std::vector<Eigen::Vector3d> points;
  int index(int i, int j, int k) const { return i + size[0] * (j + size[1] * k); }
  const Eigen::Vector3d& at(int i, int j, int k) const { return points[index(i, j, k)]; }
  Eigen::Vector3d& at(int i, int j, int k) { return points[index(i, j, k)]; }
};

void check(const CurveNet& net);
void check(const SurfaceNet& net);
void check(const SolidNet& net);

/// The TBS of the paper: open uniform knots on [0,1] (Bézier end conditions), size−degree spans.
bezier::TensorBSplineVolume to_volume(const SolidNet& net);

/// The net of a polynomial tensor B-spline volume (its knots are dropped); throws
/// InvalidInputError if the volume is rational or malformed.
SolidNet solid_net(const bezier::TensorBSplineVolume& volume);

}  // namespace volts::fit
