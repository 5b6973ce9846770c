// volts::bezier — tensor-product (rational) Bézier hexahedra of any degrees (p,q,r): evaluation
// with rational-correct Jacobians, sampled Jacobian quality, volume, degree elevation.
// The element of isogeometric analysis after Bézier extraction (Borden et al. 2011; Liu et al.
// 2013 §5.3). Parametric domain [0,1]^3 (as VTK's Bézier hexahedron).
//
// Every function taking a BezierHex throws core::InvalidInputError if it is malformed (see check()).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "bezier/quadrature.h"

namespace volts::bezier {

struct BezierHex {
  std::array<int, 3> degree{3, 3, 3};
  /// Cartesian control points (not premultiplied by the weights), index(i,j,k) = i + (p+1)(j + (q+1)k).
  std::vector<Eigen::Vector3d> points;
  /// Positive weights, one per point; empty = polynomial (all 1).
  std::vector<double> weights;

  int num_points() const { return (degree[0] + 1) * (degree[1] + 1) * (degree[2] + 1); }
  int index(int i, int j, int k) const { return i + (degree[0] + 1) * (j + (degree[1] + 1) * k); }
  std::array<int, 3> ijk(int index) const {
    const int a = degree[0] + 1, b = degree[1] + 1;
    return {index % a, (index / a) % b, index / (a * b)};
  }
  bool is_rational() const { return !weights.empty(); }
  double weight(int index) const { return weights.empty() ? 1.0 : weights[index]; }
};

/// Throws core::InvalidInputError unless every degree is >= 1, points.size() == num_points(),
/// and weights is empty or of the same size with finite positive entries.
void check(const BezierHex& hex);

/// The point x(u,v,w). If `jacobian` is given it receives dx/d(u,v,w): columns d/du, d/dv, d/dw
/// (quotient rule on the homogeneous map, so exact for rational hexes).
Eigen::Vector3d evaluate(const BezierHex& hex, const Eigen::Vector3d& uvw, Eigen::Matrix3d* jacobian = nullptr);

/// det(J) / (|J0| |J1| |J2|), in [-1,1]; 0 if a column vanishes (degenerate direction). Inline:
/// tmesh optimization evaluates it millions of times.
inline double scaled_jacobian(const Eigen::Matrix3d& J) {
  const double n0 = J.col(0).norm(), n1 = J.col(1).norm(), n2 = J.col(2).norm();
  if (n0 == 0.0 || n1 == 0.0 || n2 == 0.0) return 0.0;
  return std::clamp(J.determinant() / (n0 * n1 * n2), -1.0, 1.0);  // |det| <= product by Hadamard
}

struct JacobianSample {
  double min_scaled = 1.0;
  double max_scaled = -1.0;
  double min_det = std::numeric_limits<double>::infinity();
  double max_det = -std::numeric_limits<double>::infinity();
};

/// Jacobian at the 8 corners and at the n^3 Gauss–Legendre points (n = gauss_points per
/// direction, e.g. max degree + 1). A sample, not a certificate: det J may be negative elsewhere
/// (certification needs the Bernstein coefficients of det J). Throws InvalidInputError if n < 1.
/// grid_points > 2: the uniform grid of that many points per direction (faces, edges and corners;
/// coordinates k / (grid_points - 1)) instead of the corners alone. Throws InvalidInputError if
/// grid_points < 2.
JacobianSample sample_jacobian(const BezierHex& hex, int gauss_points, int grid_points = 2);

/// The Jacobian matrices sample_jacobian() looks at, in its order: the 8 corners, then the n^3
/// Gauss–Legendre points (u fastest). J is linear in the control points of a polynomial hex, so
/// callers moving one point can update these instead of re-evaluating (tmesh optimization).
/// With grid_points > 2 the first grid_points^3 samples are sample_jacobian()'s uniform grid.
std::vector<Eigen::Matrix3d> jacobian_samples(const BezierHex& hex, int gauss_points, int grid_points = 2);

/// The Jacobian on the uniform grid of n points per direction, the element's faces, edges and
/// corners included (coordinates k / (n - 1), u fastest): where sample_jacobian()'s interior Gauss
/// points and corners do not look (an optimizer that raises those samples can leave the field
/// low between them). Throws InvalidInputError if n < 2.
std::vector<Eigen::Matrix3d> jacobian_grid(const BezierHex& hex, int n);

/// The Jacobian at every point (t[a], t[b], t[c]) of the tensor grid of `t` (a fastest), by sum
/// factorization for polynomial hexes (jacobian_grid.h: (p+1)³ terms per grid line, not per point),
/// point by point with evaluate() for rational ones. What volume() and extract's Gauss-point
/// figures integrate.
std::vector<Eigen::Matrix3d> jacobian_tensor_grid(const BezierHex& hex, const std::vector<double>& t);

/// min/max scaled Jacobian and det J over matrices (what sample_jacobian() reports for them).
JacobianSample summarize_jacobians(const std::vector<Eigen::Matrix3d>& J);

/// ∫ det J over [0,1]^3 by n^3-point Gauss–Legendre (signed volume). Exact for polynomial hexes
/// when 2n-1 >= the degree of det J in each direction (3p-1 for degree p: n = 5 for cubics).
double volume(const BezierHex& hex, int gauss_points);

/// Applies a linear map of Bézier coefficients along each direction: M[d] is (m_d+1) x (degree[d]+1)
/// and the result has degrees m_d. Applied to homogeneous coordinates (w·P, w), so any map of
/// Bernstein coefficients (degree elevation, extraction Cᵀ, de Casteljau subdivision) is exact for
/// rational hexes. A polynomial hex stays polynomial; its maps must then have rows summing to 1.
/// Throws InvalidInputError on mismatched sizes, a polynomial hex with a non-affine map, or
/// non-positive resulting weights.
BezierHex map_coefficients(const BezierHex& hex, const std::array<Eigen::MatrixXd, 3>& M);

/// The same map in higher degrees (each new_degree[d] >= degree[d]); rational hexes are elevated
/// in homogeneous coordinates (w·P, w), so the geometry is unchanged.
BezierHex elevate_degree(const BezierHex& hex, const std::array<int, 3>& new_degree);

/// The hex restricted to the 8 octants of [0,1]^3 (split at 1/2 in each direction), each
/// reparametrised to [0,1]^3; child c covers u in [c&1 ? 1/2 : 0, ..], v by bit 1, w by bit 2.
/// Exact for rational hexes (homogeneous de Casteljau).
std::array<BezierHex, 8> subdivide(const BezierHex& hex);

}  // namespace volts::bezier
