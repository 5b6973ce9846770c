// volts::bezier — Bernstein polynomials on [0,1] and degree elevation of Bézier coefficients
// (Farin, Curves and Surfaces for CAGD, ch. 5–6). The basis of every Bézier element in this module.
//
// Throws core::InvalidInputError for a negative degree or to < from.
#pragma once

#include <Eigen/Dense>

namespace volts::bezier {

/// B_i^p(x) = C(p,i) x^i (1-x)^(p-i), i = 0..p, by the de Casteljau triangle (sums to 1 exactly
/// up to rounding, non-negative on [0,1]). If `derivatives` is given it receives d/dx B_i^p(x).
Eigen::VectorXd bernstein_basis(int degree, double x, Eigen::VectorXd* derivatives = nullptr);

/// E ((to+1) x (from+1)) mapping Bézier coefficients of degree `from` to the coefficients of the
/// same polynomial in degree `to`: c_to = E · c_from. Rows sum to 1, so it is also right for
/// homogeneous (w·P, w) coefficients of rational Béziers.
Eigen::MatrixXd degree_elevation_matrix(int from, int to);

/// S ((p+1) x (p+1)) mapping Bézier coefficients on [0,1] to those of the same polynomial on
/// [a,b] reparametrised to [0,1] (de Casteljau / blossom: row i = P(a^(p-i), b^i)). Rows sum to 1.
/// [0,1/2] and [1/2,1] give the subdivision at 1/2. Any a, b (a == b, b < a and outside [0,1] too).
Eigen::MatrixXd subdivision_matrix(int degree, double a, double b);

}  // namespace volts::bezier
