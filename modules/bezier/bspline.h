// volts::bezier — univariate B-spline tools: knot spans and basis functions (Piegl & Tiller,
// The NURBS Book, A2.1–A2.3), Greville abscissae, and 1D Bézier extraction operators by knot
// insertion (Borden, Scott, Evans & Hughes 2011, §4; as used in Liu et al. 2013 §5.3).
// Hand-written and small on purpose: no external spline library.
//
// Knot vectors need not be clamped (T-spline local knot vectors are not): with n = knots.size()-p-1
// functions, the parametric domain is [knots[p], knots[n]] and its elements are the non-empty
// spans [knots[s], knots[s+1]], p <= s < n. Interior knots may repeat up to p+1 times.
//
// Every function throws core::InvalidInputError if degree < 0, if knots has fewer than 2(p+1)
// entries, is not non-decreasing (or has NaN), has an empty domain, or a knot repeated more than
// p+1 times; and, where a parameter t is given, if t lies outside the domain.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

namespace volts::bezier {

/// Span s with knots[s] <= t < knots[s+1] and knots[s] < knots[s+1], p <= s < n. At the right end
/// of the domain (t == knots[n]) the last non-empty span is returned, so the domain is closed.
int find_span(const std::vector<double>& knots, int degree, double t);

/// The p+1 B-spline functions that may be non-zero at t: values[k] is N_{span-p+k}(t).
struct BasisValues {
  int span = 0;
  Eigen::VectorXd values;
  Eigen::VectorXd derivatives;  ///< d/dt of values; empty unless requested
};
BasisValues basis_functions(const std::vector<double>& knots, int degree, double t,
                            bool with_derivatives = false);

/// Greville abscissae (knots[i+1] + ... + knots[i+p]) / p, one per function (for p = 0 the span
/// midpoints). Clamped knot vectors give first = knots[0] and last = knots.back().
std::vector<double> greville_abscissae(const std::vector<double>& knots, int degree);

/// Clamped (open) uniform knot vector on [0,1] with `elements` >= 1 spans: p+1 zeros, the interior
/// knots i/elements, p+1 ones.
std::vector<double> open_uniform_knots(int elements, int degree);

/// Parametric interval [a, b] of every element (non-empty span), in increasing order.
std::vector<std::array<double, 2>> element_intervals(const std::vector<double>& knots, int degree);

/// Span index s of every element, same order as element_intervals(); the functions supported on
/// element e are N_{s-p}, ..., N_s.
std::vector<int> element_spans(const std::vector<double>& knots, int degree);

/// Bézier extraction operator C^e of every element (same order as element_intervals()):
/// a (p+1)x(p+1) matrix with N_{s-p+a}(t) = sum_b C^e(a,b) B_b^p(x), x = (t-a_e)/(b_e-a_e) the
/// element-local coordinate in [0,1] and B_b^p the Bernstein polynomials. Rows = the functions
/// supported on e in order, columns = Bernstein polynomials. Bézier control points of the element
/// are C^eᵀ·P (P = rows of the p+1 control points), applied to (w·P, w) when rational.
/// Computed per element by inserting its two end knots up to multiplicity p in the element's
/// local knot vector (Boehm insertion, same result as Borden et al.'s global Algorithm 1 but also
/// valid for unclamped knot vectors).
std::vector<Eigen::MatrixXd> extraction_operators(const std::vector<double>& knots, int degree);

/// Knot refinement (Boehm insertion of every knot of `fine` not in `coarse`): the matrix R, one
/// row per coarse function and one column per fine function, with N_i(coarse) = sum_j R(i,j)
/// N_j(fine); the same spline's fine control points are Rᵀ·P. Rows sum to one where the coarse
/// basis does. Knots are matched within 1e-12. Throws core::InvalidInputError if `fine` does not
/// contain every knot of `coarse` (with its multiplicity) or the two do not span the same interval.
Eigen::MatrixXd refinement_matrix(const std::vector<double>& coarse, const std::vector<double>& fine, int degree);

/// Throws core::InvalidInputError (message prefixed by `what`) unless knots/degree are valid as above.
void check_knot_vector(const std::vector<double>& knots, int degree, const char* what = "knot vector");

}  // namespace volts::bezier
