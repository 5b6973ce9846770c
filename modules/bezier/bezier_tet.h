// volts::bezier — simplex Bézier patches of any degree n: triangles (d = 2) and tetrahedra
// (d = 3), polynomial or rational. Evaluation and partial derivatives by de Casteljau, blossoms by
// the pyramid algorithm, restriction to a sub-simplex by blossoming (Randrianarivony 2008 §3,
// (20)–(22)) and the 8-child split of a tetrahedron (§4, Fig. 5(c)). Hand-written: no Debian
// library offers Bézier simplices.
//
// Domain: the unit simplex {u_i >= 0, sum u_i <= 1} with barycentric coordinates
// λ = (1 - sum u, u_1, .., u_d). A control point's multi-index (a_1..a_d) holds the exponents of
// u_1..u_d (a_0 = n - sum a_i): the basis is n!/(a_0!..a_d!) λ_0^a_0 .. λ_d^a_d.
// Points are stored in simplex_index() order (a_1 fastest, then a_2, then a_3).
//
// Functions taking a BezierTriangle/BezierTet throw core::InvalidInputError if it is malformed.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

namespace volts::bezier {

/// Number of control points of a degree-n simplex patch in dimension d (2 or 3).
int simplex_size(int dim, int degree);

/// Position of multi-index (a1, a2[, a3]) (exponents of u, v[, w]; a1+a2+a3 <= n) in the
/// storage order; a3 = 0 for triangles.
int simplex_index(int dim, int degree, int a1, int a2, int a3 = 0);

/// All multi-indices of degree n in storage order, each as {a0, a1, a2, a3} (a3 = 0 for d = 2).
std::vector<std::array<int, 4>> simplex_multi_indices(int dim, int degree);

struct BezierTriangle {
  int degree = 1;
  std::vector<Eigen::Vector3d> points;  ///< Cartesian, simplex_index order
  std::vector<double> weights;          ///< empty = polynomial
  bool is_rational() const { return !weights.empty(); }
  double weight(int i) const { return weights.empty() ? 1.0 : weights[i]; }
};

struct BezierTet {
  int degree = 1;
  std::vector<Eigen::Vector3d> points;  ///< Cartesian, simplex_index order
  std::vector<double> weights;          ///< empty = polynomial
  bool is_rational() const { return !weights.empty(); }
  double weight(int i) const { return weights.empty() ? 1.0 : weights[i]; }
};

/// Throws core::InvalidInputError unless degree >= 1, the point count is simplex_size and the
/// weights are empty or finite positive, one per point.
void check(const BezierTriangle& tri);
void check(const BezierTet& tet);

/// F(s,t); if `jacobian` is given it receives the 3x2 matrix [dF/ds, dF/dt] (exact for rational).
Eigen::Vector3d evaluate(const BezierTriangle& tri, const Eigen::Vector2d& st,
                         Eigen::Matrix<double, 3, 2>* jacobian = nullptr);

/// X(u,v,w); if `jacobian` is given it receives dX/d(u,v,w) (columns; exact for rational).
Eigen::Vector3d evaluate(const BezierTet& tet, const Eigen::Vector3d& uvw, Eigen::Matrix3d* jacobian = nullptr);

/// The same patch in degree m >= degree (homogeneous, so exact for rational).
BezierTriangle elevate_degree(const BezierTriangle& tri, int m);
BezierTet elevate_degree(const BezierTet& tet, int m);

/// Blossom of a degree-n simplex net of homogeneous coefficients at n barycentric arguments
/// (pyramid algorithm, §3). Each argument has dim+1 barycentric coordinates (summing to 1, or
/// any weights: the blossom is multilinear). Throws InvalidInputError on a size mismatch.
Eigen::Vector4d blossom(int dim, int degree, const std::vector<Eigen::Vector4d>& net,
                        const std::vector<Eigen::Vector4d>& args);

/// Coefficients of the same polynomial on the sub-simplex whose vertices have barycentric
/// coordinates `vertices` (dim+1 of them, in the parent), by blossoming (§4, (22)):
/// c'_β = P(v_0^β0, .., v_d^βd). Works on any coefficient type T (double or Eigen::Vector4d).
std::vector<double> restrict_to_simplex(int dim, int degree, const std::vector<double>& coefs,
                                        const std::vector<Eigen::Vector4d>& vertices);
std::vector<Eigen::Vector4d> restrict_to_simplex(int dim, int degree, const std::vector<Eigen::Vector4d>& coefs,
                                                 const std::vector<Eigen::Vector4d>& vertices);

/// The 8 children of the regular split of a tetrahedron (§4, Fig. 5(c)): the 4 corner tets and
/// the octahedron cut along the diagonal m02–m13; each as its 4 vertices in barycentric
/// coordinates of the parent. The children have equal volume (1/8) and tile the parent.
std::array<std::array<Eigen::Vector4d, 4>, 8> tet_split_children();

/// The tet restricted to each child of tet_split_children() (the map X on the child, child
/// vertices as the new reference vertices; exact for rational).
std::array<BezierTet, 8> subdivide(const BezierTet& tet);

}  // namespace volts::bezier
