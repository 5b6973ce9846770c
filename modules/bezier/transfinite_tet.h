// volts::bezier — tetrahedral transfinite interpolation of four triangular Bézier faces
// (Randrianarivony 2008 §2 and §5), as one Bézier tet whose regularity certify() decides.
//
// Boundary conditions (3), u = (u,v,w) on the unit tet:
//   X(u,v,0) = F1(v,u),  X(u,0,w) = F2(u,w),  X(0,v,w) = F4(w,v),  X = F3(v,w) on u+v+w = 1.
// Construction, of form (6) with polynomial blending functions p1 = u, p2 = v, p3 = w,
// p4 = 1-u-v-w (conditions (C1)–(C4) and (4)): X = Σ_i p_i T_i, where T_i is the Boolean sum of
// the three affine projections, along the edges at the vertex of p_i, onto the three faces through
// that vertex (face terms − edge terms + vertex term; each F_s∘ψ with ψ affine). T_i reproduces the
// faces through its vertex and p_i vanishes on the opposite face, so X satisfies (3); the
// expansion is the same family as the paper's explicit formula after (6). Each F∘ψ is a Bézier tet
// by blossoming (§3, (20)), multiplied by the linear p_i exactly (§5): X has degree n + 1.
//
// Faces must be polynomial (a sum of rational terms with different denominators is not one
// rational Bézier tet); faces of different degrees are elevated to the highest.
#pragma once

#include <array>

#include "bezier/bezier_tet.h"

namespace volts::bezier {

struct TransfiniteParams {
  double tolerance_rel = 1e-9;  ///< corner/edge compatibility tolerance, relative to the faces' bounding-box diagonal
};

/// Throws core::InvalidInputError naming the first corner or edge compatibility condition of §2
/// that fails (e.g. "edge (0,0,0)-(1,0,0): F1(0,μ) = F2(μ,0) fails at μ = 0.5 by 0.12"), or for
/// a malformed or rational face.
void check_compatibility(const std::array<BezierTriangle, 4>& faces, const TransfiniteParams& params = {});

/// X as a Bézier tet of degree max(face degrees) + 1; faces[0] is F1, .., faces[3] is F4.
/// Throws as check_compatibility().
BezierTet transfinite_tet(const std::array<BezierTriangle, 4>& faces, const TransfiniteParams& params = {});

}  // namespace volts::bezier
