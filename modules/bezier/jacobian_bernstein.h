// volts::bezier — the Jacobian determinant of a Bézier element in Bernstein form, exactly (products
// of the derivative nets, Randrianarivony 2008 §5: "since the determinant function is multiaffine,
// J can be written in B-patch form by the same idea"), not by fitting samples.
//
//  * polynomial hex of degree (p,q,r): det J, degree (3p-1, 3q-1, 3r-1);
//  * polynomial tet of degree n: det J, degree 3(n-1);
//  * rational elements: D = det[H, H_u, H_v, H_w] with H = (w, w·x) the homogeneous map, of degree
//    (4p-1, 4q-1, 4r-1) resp. 4n-3. det J = D / W^4 with W > 0, so D has the sign of det J.
//
// Throws core::InvalidInputError for a malformed element (see check()).
#pragma once

#include "bezier/bernstein_poly.h"
#include "bezier/bezier_hex.h"
#include "bezier/bezier_tet.h"

namespace volts::bezier {

/// The polynomial above for a hex (det J itself if polynomial, D if rational).
TensorBernstein jacobian_determinant(const BezierHex& hex);

/// The same into `out`, reusing its storage: no allocation once `out` and the per-thread
/// workspace have the size of this degree (the hot loop of certification). Degree (3,3,3) is
/// compiled with constant sizes.
void jacobian_determinant(const BezierHex& hex, TensorBernstein& out);

/// The polynomial above for a tet.
SimplexBernstein jacobian_determinant(const BezierTet& tet);

}  // namespace volts::bezier
