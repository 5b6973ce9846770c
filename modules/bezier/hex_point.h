// volts::bezier — one parameter point at which many Bézier hexahedra of the same degrees are
// evaluated (quality sampling: Gauss points, grids on boundary faces, volume quadrature). The
// Bernstein products of the point are computed once; the sums are evaluate()'s, term by term in
// the same order, so the results are bit-identical to evaluate(), which rebuilds the bases at
// every call (half of extract's time went there).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

#include "bezier/bezier_hex.h"

namespace volts::bezier {

class HexPoint {
 public:
  /// The point uvw of [0,1]^3 for hexes of `degree` (each >= 1, else core::InvalidInputError).
  HexPoint(const std::array<int, 3>& degree, const Eigen::Vector3d& uvw);

  /// evaluate(hex, uvw, jacobian), bit for bit. Throws core::InvalidInputError if the hex is
  /// malformed or of other degrees. Rational hexes are passed on to evaluate().
  Eigen::Vector3d evaluate(const BezierHex& hex, Eigen::Matrix3d* jacobian = nullptr) const;

  const Eigen::Vector3d& uvw() const { return uvw_; }
  bool has_degree(const std::array<int, 3>& degree) const { return degree == degree_; }

 private:
  std::array<int, 3> degree_;
  Eigen::Vector3d uvw_;
  std::vector<double> b_;               // B_i(u) B_j(v) B_k(w) per control point, in index order
  std::vector<Eigen::RowVector3d> db_;  // its partial derivatives d/du, d/dv, d/dw
};

}  // namespace volts::bezier
