// volts::fit — sufficient validity conditions of Lin, Huang & Hu, "Trivariate B-spline solid
// construction by pillow operation and geometric iterative fitting" (Sci China Inf Sci 2018),
// section "Validity conditions", Propositions 1–4, as free functions any stage can call.
//
// All four work on unit difference vectors of the control net, T = (P_next − P)/|P_next − P|. A
// derivative of the spline on one knot span is a non-negative combination of the (unnormalised)
// differences of one sub-net of degree+1 points per direction, which is why the conditions are
// checked per sub-net. A difference shorter than tolerance·(largest difference of its sub-net)
// has no direction: the check fails with Condition::degenerate_difference (conservative: the spline
// may still be valid).
//
// Floating point: every "> 0" is tested as "> tolerance" on dot/triple products of unit vectors
// (rounding there is ~1e-16), so rounding cannot make an invalid net pass.
//
// The checks return a verdict, never throw for an invalid net; they throw core::InvalidInputError
// for a malformed net (see net.h) or a point index outside the net.
#pragma once

#include <array>
#include <string>

#include "fit/net.h"

namespace volts::fit {

enum class Condition {
  none,
  degenerate_difference,  ///< a difference vector of (near) zero length
  cone_aperture,          ///< minimum cone of a family of differences has aperture >= π (Prop. 1; Prop. 2: no axis U or V)
  surface_u,              ///< Prop. 2: some T^u of M_IJ violates T^u·U > T^u·V >= 0
  surface_v,              ///< Prop. 2: some T^v of M_IJ violates T^v·V > T^v·U >= 0
  solid_triple,           ///< Prop. 3: T^u·(T^v × T^w) <= 0 for a triple of G_IJK
  g1_shape,               ///< Prop. 4: boundary nets differ in size or degree
  g1_position,            ///< Prop. 4: P_{i,j,l_p} != Q_{i,j,0}
  g1_direction,           ///< Prop. 4: P_{i,j,l_p} − P_{i,j,l_p−1} != α (Q_{i,j,1} − Q_{i,j,0}), one α > 0
};
const char* to_string(Condition c);

/// One difference vector: from control point `start` (i, j, k; unused entries 0) along
/// direction 0 (u), 1 (v) or 2 (w).
struct Difference {
  int direction = -1;  ///< -1 = unused
  std::array<int, 3> start{0, 0, 0};
};

struct Validity {
  bool valid = true;
  /// Of the first failing sub-net in scan order (I fastest); Prop. 4: of the worst (i, j).
  Condition failed = Condition::none;
  std::array<int, 3> subnet{-1, -1, -1};   ///< its first index (I, J, K), unused entries 0; Prop. 4: (i, j, 0)
  std::array<Difference, 3> witness{};     ///< the difference vector(s) violating the condition
  /// The violated quantity: aperture in radians (cone_aperture), the failing side of the
  /// inequality (surface_*), the triple product (solid_triple), the residual / scale (g1_*; α
  /// itself when α <= 0).
  double value = 0;
  /// How far from failing, over the sub-nets checked: Prop. 1 min cos(half angle) of the minimum
  /// cones; Prop. 2 min of T^u·(U−V) and T^v·(V−U); Prop. 3 min T^u·(T^v × T^w) (exact minimum over
  /// all triples when positive); Prop. 4 tolerance_rel − max residual / scale. Positive when valid.
  double margin = 0;
  int checked = 0;   ///< sub-nets checked
  int failures = 0;  ///< sub-nets failing
  std::string describe() const;  ///< one line for a report or an error message
};

struct ValidityParams {
  double tolerance = 1e-12;  ///< positivity margin on products of unit vectors; relative zero length of differences
  /// Stop at the first failing sub-net (a fitting loop's rejected trial move); margin and
  /// failures then cover only the sub-nets checked.
  bool stop_at_first_failure = false;
  /// Prop. 3 only: test every triple (a family has d_u(d_v+1)(d_w+1) differences for u: 48³
  /// triples for tricubic) instead of the extreme directions of each family (same verdict; the
  /// reference the tests compare with).
  bool exhaustive = false;
};

/// Proposition 1: the curve is valid (C'(t) != 0) if, for every sub-polygon P_i..P_{i+d},
/// i = 0..m−d, the minimum circular cone enclosing T_i..T_{i+d−1} has aperture < π
/// (Cone::min_cos > tolerance).
Validity check_curve(const CurveNet& net, const ValidityParams& params = {});

/// Proposition 2: the surface is valid (S_u × S_v != 0) if on every sub-control-polygon M_IJ
/// (points I..I+d_u × J..J+d_v), with U, V the axes of the minimum cones of its T^u and T^v:
/// T^u·U > T^u·V >= 0 for every T^u and T^v·V > T^v·U >= 0 for every T^v of M_IJ.
/// Tested as T·U − T·V > tol, T·V >= −tol, and T·(U+V) > tol (implied by the exact condition and
/// what the proof needs: S_u, S_v non-parallel for any axes U, V, so approximate axes stay sound).
/// Only sufficient: a valid sheared grid whose u and v cone axes meet at more than 90° fails.
Validity check_surface(const SurfaceNet& net, const ValidityParams& params = {});

/// Proposition 3: the TBS is valid (det J > 0) if on every sub-grid G_IJK (points I..I+d_u ×
/// J..J+d_v × K..K+d_w), T^u·(T^v × T^w) > 0 for every T^u, T^v, T^w of G_IJK. det J is then a
/// positive combination of such products, so every Bernstein coefficient of det J of every
/// Bézier element is positive too (bezier::certify certifies it without subdivision).
/// By multilinearity only the extreme directions of each family (convex hull in the gnomonic
/// projection around its cone axis) are tested; a family outside every open hemisphere fails.
Validity check_solid(const SolidNet& net, const ValidityParams& params = {});

/// Propositions 1–3 on the sub-nets that contain control point i (resp. (i,j), (i,j,k)) only: the
/// cheap check after moving that one point in a fitting loop (at most (d+1)^dim sub-nets).
Validity check_curve_near(const CurveNet& net, int i, const ValidityParams& params = {});
Validity check_surface_near(const SurfaceNet& net, std::array<int, 2> ij, const ValidityParams& params = {});
Validity check_solid_near(const SolidNet& net, std::array<int, 3> ijk, const ValidityParams& params = {});

struct G1Params {
  double tolerance_rel = 1e-9;  ///< position and direction residuals relative to the bounding box diagonal of p ∪ q
};

/// Proposition 4: TBSs P (w = 1 face) and Q (ω = 0 face), both with uniform knots and Bézier end
/// conditions, are G1 along P(u,v,1) = Q(μ,ν,0) if P_{i,j,l_p} = Q_{i,j,0} and
/// P_{i,j,l_p} − P_{i,j,l_p−1} = α (Q_{i,j,1} − Q_{i,j,0}) for all i, j with one constant α > 0.
/// The boundary nets must have equal sizes and degrees in u and v. α is the least-squares ratio
/// over all (i, j); `alpha` receives it. Other face pairings: permute the nets' indices first.
Validity check_g1(const SolidNet& p, const SolidNet& q, const G1Params& params = {}, double* alpha = nullptr);

}  // namespace volts::fit
