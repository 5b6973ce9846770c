// volts::bezier — tensor-product (rational) B-spline volumes: direct evaluation and Bézier
// extraction into one BezierHex per element (tensor product of the 1D operators of
// bezier/bspline.h, applied to homogeneous (w·P, w); Borden et al. 2011 §5).
//
// Functions throw core::InvalidInputError if a knot vector is invalid (see bspline.h), the point
// or weight count does not match, a weight is not positive, or a degree is < 1.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

#include "bezier/bezier_hex.h"

namespace volts::bezier {

struct TensorBSplineVolume {
  std::array<std::vector<double>, 3> knots;  ///< U, V, W; need not be clamped
  std::array<int, 3> degree{3, 3, 3};
  /// nu*nv*nw Cartesian control points, index i + nu*(j + nv*k), n_d = knots[d].size() - degree[d] - 1.
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;  ///< empty = polynomial

  std::array<int, 3> num_points() const {
    std::array<int, 3> n{};
    for (int d = 0; d < 3; ++d) n[d] = static_cast<int>(knots[d].size()) - degree[d] - 1;
    return n;
  }
};

/// Throws InvalidInputError unless the volume is well-formed (see above).
void check(const TensorBSplineVolume& volume);

/// x(u,v,w) by direct B-spline evaluation (the reference for extraction); (u,v,w) in the domain.
Eigen::Vector3d evaluate(const TensorBSplineVolume& volume, const Eigen::Vector3d& uvw);

/// One BezierHex per element (non-empty knot span triple), u-elements fastest, then v, then w,
/// in the order of element_intervals() per direction. Element (a,b,c) covers
/// element_intervals(U)[a] x element_intervals(V)[b] x element_intervals(W)[c]; its local
/// parameters are the affine images of these intervals on [0,1]. Rational iff the volume is.
std::vector<BezierHex> extract_bezier_hexes(const TensorBSplineVolume& volume);

}  // namespace volts::bezier
