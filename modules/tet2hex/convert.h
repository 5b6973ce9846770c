// volts::tet2hex — exact conversion of Bézier tetrahedra into Bézier hexahedra of the same degree,
// after Xu, Jin, Xiao, Wu, Mourrain & Rabczuk, "Exact conversion from Bézier tetrahedra to Bézier
// hexahedra", CAGD 62 (2018):
//   Theorem 1  one degenerate n×n×n hex through the map ψ of eq. (9)/(11) (face r = 1 collapses to
//              a point, face s = 1 to an edge) with the degree-elevation matrices A of eq. (7);
//   Theorem 3  four non-degenerate n×n×n hexes over the sub-domains D1..D4 of Fig. 4 (corner, three
//              edge midpoints, three face centroids, centroid), control points by eq. (12)–(13):
//              hypergeometric convex combinations of blossom values at the sub-domain's corners,
//              each blossom a chain of de Casteljau convex combinations (the stable evaluation the
//              paper recommends after eq. (17)).
// Both are exact (up to rounding) for polynomial and rational tets: rational ones are converted in
// homogeneous coordinates (w·P, w). The tet's parameter domain and control point order are those
// of bezier/bezier_tet.h (u, v, w with λ0 = 1-u-v-w; the paper's T_{i,j,k,l} is a = (i,j,k), l = λ0's).
//
// Every function throws core::InvalidInputError for a malformed tet (bezier::check).
#pragma once

#include <Eigen/Dense>
#include <array>

#include "bezier/bezier_hex.h"
#include "bezier/bezier_tet.h"

namespace volts::tet2hex {

/// Theorem 1: the degenerate hex H with H(r,s,t) = T(ψ⁻¹(r,s,t)), ψ⁻¹: u = r, v = (1-r)s,
/// w = (1-r)(1-s)t (eq. (11)). det J of H vanishes on the collapsed faces r = 1 and s = 1.
bezier::BezierHex degenerate_hex(const bezier::BezierTet& tet);

/// The eight corners of the sub-domain D_c (c = 0..3, the sub-domain at tet vertex c) in barycentric
/// coordinates (λ0..λ3), indexed by hex corner r + 2s + 4t: (0,0,0) the tet vertex, the r, s, t
/// directions towards three edge midpoints ordered so that the trilinear map has det > 0
/// (Proposition 4), faces' centroids at two set bits, the tet centroid at (1,1,1).
std::array<Eigen::Vector4d, 8> subdomain_corners(int c);

/// The hex H(r,s,t) = T(φ(r,s,t)) for the trilinear map φ interpolating `corners` (barycentric
/// coordinates of the tet domain, indexed r + 2s + 4t) — eq. (12)–(13) of Theorem 3 for any
/// hexahedral sub-domain with corners in the tet domain (then every step is a convex combination).
bezier::BezierHex compose_trilinear(const bezier::BezierTet& tet, const std::array<Eigen::Vector4d, 8>& corners);

/// Theorem 3: the four hexes over D_0..D_3 (subdomain_corners). Together they cover the tet exactly
/// once; each is as regular as the tet (Proposition 4): det J > 0 on the tet ⇒ det J > 0 on each hex.
std::array<bezier::BezierHex, 4> four_hexes(const bezier::BezierTet& tet);

}  // namespace volts::tet2hex
