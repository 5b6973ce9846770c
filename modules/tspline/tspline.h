// volts::tspline — cubic (rational) T-spline blending functions of one adaptive octree T-mesh and
// their Bézier extraction (Liu et al. 2013, §5.3 "Volumetric T-spline construction", with the
// local knot vectors of §3's T-mesh by ray casting; issue 8 items 1–2, groundwork: not yet used by
// the pipeline).
//
// Hand-written because no Debian library builds T-spline bases (the packaged spline libraries,
// e.g. OpenCASCADE, handle tensor-product B-splines/NURBS only; the papers' T-spline codes are not
// packaged). The 1D kernels are not re-written: 1D B-spline values come from
// bezier::basis_functions, 1D Bézier extraction (knot insertion of an interval's ends to
// multiplicity 3) from bezier::extraction_operators, restriction to a sub-interval from
// bezier::subdivision_matrix, and the elements are bezier::BezierHex.
//
// Index space is the octree's: the root is [0, S]^3, S = Octree::root_side(). The parameter of
// evaluation is u in [0,1]^3 = index / S (exact: S is a power of two).
//
// Blending functions (one per anchor). Every T-mesh node (Octree::nodes()) is an anchor. Along each
// axis a, rays from the anchor in +a and -a stop at the first two positions where the ray meets a
// T-mesh face perpendicular to a (q is on such a face iff q lies on the closed face x_a = lo_a or
// x_a = hi_a of some leaf whose closed box contains q); positions the ray does not find before the
// root's boundary repeat the boundary value. The 5 knots per axis are (m2, m1, anchor, p1, p2) and
// N_i is the product of the three cubic B-splines on them.
// At the root's boundary the repeated boundary value alone gives 3 equal knots (C^0, value 0 on
// the boundary), which neither sums to one nor interpolates. A clamped cubic needs the boundary
// knot 4 times, i.e. one more anchor: a node on the root face x_a = 0 (resp. S) also anchors a
// second function per such axis, on the repeated boundary knot plane (a zero-parametric-length
// layer, the paper's §5.3 "zero parametric length edges"), with knots (0,0,0,0,p1) (resp.
// (m1,S,S,S,S)); `layer` tells which. On a uniform tree this gives exactly the tensor-product
// clamped cubic B-splines on [0,1]^3 ((n+3)^3 functions for n^3 leaves) and Σ N_i = 1.
//
// Rational basis R_i = w_i N_i / Σ_j w_j N_j (weights default 1): partition of unity by
// construction, also where the polynomial basis does not sum to one (T-meshes that are not
// analysis-suitable: see partition_of_unity_error()).
//
// Bézier elements. A T-spline function is polynomial on a box only if none of its knots lies
// strictly inside the box along an axis; near T-junctions the knots of the hanging nodes' functions
// cut the coarse neighbouring leaves (the "face extensions" of T-spline theory). So each leaf is
// split along every knot plane of the functions supported on it that crosses its interior (the
// Bézier mesh; on a uniform tree the leaves themselves, on a 2:1 balanced tree at most halves per
// axis) and every piece is one Bézier element with its functions and their Bernstein coefficients.
//
// Errors: core::InvalidInputError for arguments out of range (function or element id, u outside
// [0,1]^3 or not finite, point or weight count, non-positive or non-finite weights);
// core::NumericalError when Σ_j w_j N_j is not positive where a rational value is asked for
// (evaluation or a Bézier weight of element_hex).
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <array>
#include <utility>
#include <vector>

#include "bezier/bezier_hex.h"
#include "octree/octree.h"

namespace volts::tspline {

/// Polynomial degree per direction (cubic).
constexpr int kDegree = 3;
/// Bernstein functions of one element: (kDegree+1)^3, numbered as BezierHex::index(i,j,k).
constexpr int kBernstein = (kDegree + 1) * (kDegree + 1) * (kDegree + 1);

/// Local knot vector of one direction, in index space, non-decreasing.
using LocalKnots = std::array<int, 5>;

/// One blending function N_i.
struct BlendingFunction {
  octree::Index3 anchor{0, 0, 0};  ///< its T-mesh node
  int node = -1;                   ///< index of the anchor in Octree::nodes()
  /// Per axis: 0 = anchored on the node; -1 / +1 = the extra anchor of a node on the low / high root
  /// face, on the repeated boundary knot plane (knots (0,0,0,0,p1) / (m1,S,S,S,S)).
  std::array<int, 3> layer{0, 0, 0};
  std::array<LocalKnots, 3> knots{};  ///< local knot vector per axis (index space)

  /// Closed support [knots[a][0], knots[a][4]] per axis (index space).
  octree::Index3 support_lo() const { return {knots[0][0], knots[1][0], knots[2][0]}; }
  octree::Index3 support_hi() const { return {knots[0][4], knots[1][4], knots[2][4]}; }
};

/// One Bézier element: a box of one leaf on which every blending function is polynomial.
struct BezierElement {
  int leaf = -1;               ///< the octree leaf containing it
  octree::Index3 lo{0, 0, 0};  ///< index box [lo, hi] (= the leaf's unless knot planes cut the leaf)
  octree::Index3 hi{0, 0, 0};
  /// Global ids of the functions not identically zero on the element (those whose open support
  /// meets the open box), ascending.
  std::vector<int> functions;
  /// Extraction operator, functions.size() x kBernstein, as extract::ExtractionElement::op:
  /// N_{functions[r]}(u) = Σ_b op(r,b) B_b(ξ), B_b the tensor Bernstein polynomials of degree 3 in
  /// BezierHex::index order and ξ in [0,1]^3 the element's local coordinate
  /// (u = (lo + ξ (hi - lo)) / S). Bézier points are opᵀ·P in homogeneous form. Exact zeros are
  /// not stored.
  Eigen::SparseMatrix<double, Eigen::RowMajor> op;
};

/// The cubic T-spline basis of one octree T-mesh (Liu et al. 2013 §5.3), with settable weights.
class TSpline {
 public:
  /// Builds the functions and the Bézier elements of the tree's leaves. Any tiling tree works; 2:1
  /// balance (Octree::balance) is what the pipeline will use.
  explicit TSpline(const octree::Octree& tree);

  int root_side() const { return root_side_; }
  const std::vector<octree::Index3>& nodes() const { return nodes_; }
  const std::vector<BlendingFunction>& functions() const { return functions_; }
  int num_functions() const { return static_cast<int>(functions_.size()); }
  const std::vector<BezierElement>& elements() const { return elements_; }
  /// Leaves cut by some knot plane into several Bézier elements.
  int split_leaves() const { return split_leaves_; }

  const std::vector<double>& weights() const { return weights_; }
  /// One finite positive weight per function (InvalidInputError otherwise).
  void set_weights(std::vector<double> weights);

  /// max over elements and Bernstein functions b of |Σ_r op(r,b) - 1|: 0 (up to rounding) iff the
  /// polynomial basis sums to one everywhere (the Bernstein basis is linearly independent).
  double partition_of_unity_error() const;

  /// N_i(u) by direct evaluation (1D B-splines on the local knot vectors); u in [0,1]^3. At the
  /// root's boundary the values are the limits from inside (clamped ends).
  double basis(int i, const Eigen::Vector3d& u) const;
  /// (i, N_i(u)) of every function whose closed support contains u, ids ascending (values may be 0
  /// on the support's boundary).
  std::vector<std::pair<int, double>> basis(const Eigen::Vector3d& u) const;
  /// (i, R_i(u)) for the same functions, R_i = w_i N_i / Σ_j w_j N_j.
  std::vector<std::pair<int, double>> rational_basis(const Eigen::Vector3d& u) const;
  /// Σ_i R_i(u) P_i for control points P (one per function).
  Eigen::Vector3d evaluate(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& u) const;

  /// Bernstein coefficients of Σ_j w_j N_j on element e (the rational denominator; the Bézier
  /// weights of element_hex).
  Eigen::VectorXd denominator_coefficients(int e) const;
  /// The rational Bézier hex of element e for control points P: weight_b = Σ_r w_r op(r,b),
  /// point_b = Σ_r w_r op(r,b) P_r / weight_b; its parameter ξ is the element's local coordinate.
  bezier::BezierHex element_hex(int e, const std::vector<Eigen::Vector3d>& points) const;
  /// u in [0,1]^3 of the element-local coordinate ξ of element e.
  Eigen::Vector3d element_point(int e, const Eigen::Vector3d& xi) const;

 private:
  void build_functions(const octree::Octree& tree);
  void build_elements(const octree::Octree& tree);
  void check_point(const Eigen::Vector3d& u, const char* what) const;
  double basis_index(int i, const Eigen::Vector3d& x) const;  // x in index space
  std::vector<int> candidates(const Eigen::Vector3d& x) const;

  int root_side_ = 1;
  std::vector<octree::Index3> nodes_;
  std::vector<BlendingFunction> functions_;
  std::vector<double> weights_;
  std::vector<BezierElement> elements_;
  int split_leaves_ = 0;
  // Uniform bucket grid over index space: functions whose open support meets each bucket.
  int bucket_side_ = 1, buckets_ = 1;
  std::vector<std::vector<int>> bucket_functions_;
};

}  // namespace volts::tspline
