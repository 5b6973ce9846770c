// volts::bezier — certified sign of the Jacobian determinant of Bézier elements: algorithm Check
// of Randrianarivony 2008 §4 (Theorems 4.1, 4.2) on the Bernstein coefficients of det J
// (jacobian_bernstein.h).
//
// All coefficients positive → certified valid, with their minimum as a lower bound of min det J
// (convex hull property). A point value <= 0 (the corner coefficients of every (sub)element are
// exact values) → certified invalid with that witness point. Otherwise subdivide only the critical
// children (hexes at 1/2 in each direction, tets by the 8-child split of Fig. 5(c)) down to
// max_depth, then undecided with the interval [lower, upper] found for min det J.
//
// Degree reduction (§6) is not implemented: on the benchmark (bench/bench_certify) no element of
// the valid set needs subdivision, so reducing degrees after subdividing cannot speed it up, and
// bound (60) has an unstated constant (measurements in docs/certify.md).
//
// Floating point: a coefficient counts as positive only above rounding_rel · max|c|, so rounding
// in the products cannot certify a slightly negative element; point values are used as computed.
//
// Throws core::InvalidInputError for a malformed element or polynomial, max_depth outside [0, 20].
#pragma once

#include <Eigen/Dense>

#include "bezier/bernstein_poly.h"
#include "bezier/bezier_hex.h"
#include "bezier/bezier_tet.h"

namespace volts::bezier {

struct CertifyParams {
  int max_depth = 6;            ///< subdivision levels before "undecided" [0, 20]; each halves the element's size
  double rounding_rel = 1e-12;  ///< safety margin for positive coefficients, relative to max |coefficient| (unitless)
};

/// Values written as the `status` cell array: 1 valid, -1 invalid, 0 undecided.
enum class Validity : int { valid = 1, invalid = -1, undecided = 0 };

struct CertifyResult {
  Validity status = Validity::undecided;
  /// Certified bounds of min det J over the element: lower <= min det J <= upper (det J w.r.t. the
  /// reference element, [0,1]^3 or the unit tet; for a bare polynomial: its minimum).
  double min_detj_lower = 0;
  double min_detj_upper = 0;
  Eigen::Vector3d witness = Eigen::Vector3d::Zero();  ///< parametric point where det J = min_detj_upper
  /// Mean of det J over the reference element (= volume / reference volume): the element's size,
  /// to make the bounds relative. Exact for polynomial elements (the mean of the Bernstein
  /// coefficients); Gauss quadrature (degree 2·max degree + 2 per direction, Duffy-collapsed on
  /// tets) for rational ones.
  double mean_detj = 0;
  int depth = 0;         ///< deepest subdivision level visited
  int subdivisions = 0;  ///< number of (sub)elements split
};

CertifyResult certify(const BezierHex& hex, const CertifyParams& params = {});
CertifyResult certify(const BezierTet& tet, const CertifyParams& params = {});

/// The same on a bare polynomial (the sign of f on the unit cube / tetrahedron).
CertifyResult certify(const TensorBernstein& f, const CertifyParams& params = {});
CertifyResult certify(const SimplexBernstein& f, const CertifyParams& params = {});

const char* to_string(Validity v);  ///< "valid", "invalid", "undecided"

}  // namespace volts::bezier
