// volts::bezier — scalar polynomials in Bernstein form on the unit cube (tensor product, degrees
// (p,q,r)) and on the unit tetrahedron (total degree n): evaluation, exact products, subdivision.
// The representation in which the sign of det J is decided (Randrianarivony 2008 §4–5).
//
// Products are exact (Prop. 5.2, here in coefficient form): with scaled coefficients
// ĉ_i = c_i·C(n,i) (resp. multinomials), the product is a plain convolution of the scaled arrays.
// Hand-written: no Debian library offers Bernstein-form products or subdivision.
//
// Throws core::InvalidInputError on a negative degree or a coefficient count that does not match.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

namespace volts::bezier {

/// Σ c_ijk B_i^p(u) B_j^q(v) B_k^r(w) on [0,1]^3; coefs index i + (p+1)(j + (q+1)k).
struct TensorBernstein {
  std::array<int, 3> degree{0, 0, 0};
  std::vector<double> coefs;
};

/// Σ c_α n!/α! λ^α on the unit tetrahedron, λ = (1-u-v-w, u, v, w); coefs in simplex_index order.
struct SimplexBernstein {
  int degree = 0;
  std::vector<double> coefs;
};

double evaluate(const TensorBernstein& f, const Eigen::Vector3d& uvw);
double evaluate(const SimplexBernstein& f, const Eigen::Vector3d& uvw);

/// The exact product (degrees add).
TensorBernstein multiply(const TensorBernstein& a, const TensorBernstein& b);
SimplexBernstein multiply(const SimplexBernstein& a, const SimplexBernstein& b);

/// The 8 octant restrictions (child c: u half c&1, v half bit 1, w half bit 2), as bezier_hex's subdivide.
std::array<TensorBernstein, 8> subdivide(const TensorBernstein& f);

/// The 8 children of tet_split_children() (bezier_tet.h).
std::array<SimplexBernstein, 8> subdivide(const SimplexBernstein& f);

/// C(n, k) as a double (exact up to n = 60).
double binomial(int n, int k);

}  // namespace volts::bezier
