// volts::tspline — octree refinement rules that make the polynomial T-spline basis of an octree
// T-mesh (tspline.h) a partition of unity, Σ_i N_i = 1, and with it linear reproduction: control
// points at the Greville points give the identity map (issue 8 groundwork, measured by
// bench/bench_tspline.cpp, docs/benchmarks.md "Adaptive T-spline (bench_tspline)").
//
// Why a rule is needed. With every T-mesh node an anchor and local knots by ray casting (Liu et al.
// 2013 §5.3), a 2:1 balanced adaptive octree is in general not analysis-suitable: Σ N ≠ 1 by up to
// 0.67 on the tested trees. Measured (tests/tspline/suitable_test.cpp, bench_tspline): one level of
// refinement of a box of coarse cells inside a uniform tree sums to one only when the box is a slab
// spanning the root in two directions; a cube, a bar (slab in one direction), an L-shaped prism all
// fail (0.018–0.2), because any edge of the refined region where two of its faces meet (a "corner
// line") makes T-junction extensions of two directions cross — the 3D form of the corner defect of
// quadtree-refined bicubic T-meshes (Li, Zheng, Sederberg, Hughes & Scott 2012: extensions of
// different directions must not intersect). Isotropic octree refinement always creates such corners
// unless the level of a leaf depends on one coordinate only. Measured by bench_tspline (families
// point / plane / sphere surface / random, max levels 3-5):
//   * stronger grading does not help: balancing across vertices, or within 2 leaf sides of every
//     leaf (balance_neighbourhood radius 1, 2), leaves Σ N error 0.04-0.61 on every tree;
//   * splitting the leaves whose Bézier elements have Σ N ≠ 1 (repair_partition_of_unity)
//     converges, but for max level >= 4 always at the uniform tree (1-6 rounds, 3-160x leaves);
//   * the slab rule (slab_closure) converges in one pass with no repair on every tree: each leaf is
//     refined to the deepest level found anywhere in its slab {x : x_axis in the leaf's range}
//     (then 2:1 balance), so the level is a function of x_axis alone and every T-junction
//     extension is perpendicular to that one axis. Σ N = 1 and the Greville identity (polynomial
//     and rational) then hold to 1e-15; cost 1.5-21x the balanced tree's leaves, 9-100 % of the
//     uniform tree's (point L5: 204 -> 2,976 of 32,768; sphere surface L5: 4,964 -> 21,120).
//   * without a rule, the rational basis is a partition of unity but does not reproduce linears:
//     Σ R_i g_i - u is 1e-3..2e-2 at random points.
//
// make_partition_of_unity applies the slab rule (on the axis giving fewest leaves) and then checks
// the result with TSpline::partition_of_unity_error(), repairing (and, as last resort, refining to
// the uniform tree, which is always a partition of unity) if the check ever fails, so its guarantee
// does not rest on the measurement: on return Σ N = 1 to the tolerance. It only splits (every new
// leaf lies inside an old one) and leaves the tree 2:1 balanced (octree::check ok).
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "octree/octree.h"
#include "tspline/tspline.h"

namespace volts::tspline {

/// Which refinement make_partition_of_unity applies before its check-and-repair loop.
enum class SuitableRule {
  slab,    ///< slab_closure on `axis` (or the best axis), then the check (the default)
  repair,  ///< only the check-and-repair loop (converges to the uniform tree in practice)
};

struct SuitableParams {
  SuitableRule rule = SuitableRule::slab;
  int axis = -1;             ///< slab axis 0..2; -1: the axis whose closure has fewest leaves
  double tolerance = 1e-12;  ///< on partition_of_unity_error()
  int max_iterations = 64;   ///< repair rounds before core::NumericalError
};

/// What make_partition_of_unity did.
struct SuitableReport {
  int splits = 0;            ///< leaves split in total (slab, balance and repair)
  int repair_iterations = 0; ///< rounds of the repair loop that split something
  int axis = -1;             ///< slab axis used (-1 for SuitableRule::repair)
  double pou_error = 0;      ///< partition_of_unity_error() of the final tree
};

/// Makes the polynomial T-spline basis of `tree` a partition of unity by refinement only (see the
/// file comment); returns the number of leaves split. The tree is 2:1 balanced first.
/// Throws core::InvalidInputError for an axis out of range or a non-positive tolerance, and
/// core::NumericalError if the repair loop has not converged after max_iterations rounds.
int make_partition_of_unity(octree::Octree& tree, const SuitableParams& params = {},
                            SuitableReport* report = nullptr);

/// The slab rule on one axis: splits leaves until each leaf is as deep as every leaf whose range
/// along `axis` overlaps its own, then 2:1 balances, repeating until both hold. Returns the splits.
int slab_closure(octree::Octree& tree, int axis);

/// Iterative repair: splits every leaf (not at max level) holding a Bézier element whose column
/// sums differ from 1 by more than `tolerance`, 2:1 balances, and repeats; if the only defective
/// leaves are at max level, splits every leaf above max level. Returns the splits; `iterations` gets
/// the rounds that split something. NumericalError after max_iterations rounds without convergence.
int repair_partition_of_unity(octree::Octree& tree, double tolerance, int max_iterations, int* iterations = nullptr);

/// Graded balance (candidate rule (b), measured, not sufficient): splits leaves until no leaf L has
/// a leaf more than one level deeper within `radius` times L's side of L (Chebyshev distance;
/// radius 1 = 2:1 balance across faces, edges and vertices), then 2:1 balances. radius >= 1
/// (InvalidInputError otherwise). Returns the splits.
int balance_neighbourhood(octree::Octree& tree, int radius);

/// Leaf ids holding at least one Bézier element of `spline` whose column sums (Σ_r op(r,b)) differ
/// from 1 by more than `tolerance`, ascending.
std::vector<int> non_unity_leaves(const TSpline& spline, double tolerance);

/// Greville points of the functions in [0,1]^3: per axis the mean of the 3 middle local knots / S.
std::vector<Eigen::Vector3d> greville_points(const TSpline& spline);

/// max over elements and Bernstein coefficients of |Σ_r op(r,b) g_r - identity_b|, g the Greville
/// points and identity_b the Bernstein coefficients of u on the element: 0 (up to rounding) iff the
/// polynomial map Σ N_i g_i is the identity everywhere.
double greville_identity_error(const TSpline& spline);

}  // namespace volts::tspline
