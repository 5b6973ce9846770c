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
  friend class HexPoints;
  std::array<int, 3> degree_;
  Eigen::Vector3d uvw_;
  std::vector<double> b_;               // B_i(u) B_j(v) B_k(w) per control point, in index order
  std::vector<Eigen::RowVector3d> db_;  // its partial derivatives d/du, d/dv, d/dw
};

/// Several parameter points at once: the same sums as HexPoint (so evaluate()'s, bit for bit),
/// each point's in its own order, all points in one pass over the control points so that the
/// compiler vectorizes across points (extract's volume and Gauss-point figures).
class HexPoints {
 public:
  /// Each degree >= 1, else core::InvalidInputError.
  HexPoints(const std::array<int, 3>& degree, const std::vector<Eigen::Vector3d>& uvw);

  /// x (if given) and the Jacobians (if given) at every point, in the order of the constructor's
  /// uvw. Throws core::InvalidInputError for a malformed hex or other degrees. Rational hexes are
  /// passed on to evaluate().
  void evaluate(const BezierHex& hex, std::vector<Eigen::Vector3d>* x, std::vector<Eigen::Matrix3d>* jacobians) const;

  bool has_degree(const std::array<int, 3>& degree) const { return degree == degree_; }
  std::size_t size() const { return uvw_.size(); }

 private:
  std::array<int, 3> degree_;
  std::vector<Eigen::Vector3d> uvw_;
  std::vector<double> b_;                 // b_[idx * size() + point]: HexPoint's products
  std::array<std::vector<double>, 3> db_;  // their derivatives, same layout
  std::vector<double> w_;                  // W = sum of b_ per point (a polynomial hex's)
  std::array<std::vector<double>, 3> dw_;  // dW per point
};

}  // namespace volts::bezier
