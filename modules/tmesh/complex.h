// volts::tmesh — pillowing of a complex of glued cubes (Liu et al. 2013 §5.2, Fig. 9) where the
// per-cube rule of pillow.h cannot conform: a cube united with a torus on a whole face (§4.2,
// Fig. 6(c)) leaves a concave edge that ends on a convex one at each corner of the shared face,
// a surface vertex where five faces of the polycube meet.
//
// The pillow here is the sheet insertion of the coarse hex mesh (one hex per cube): every surface
// vertex v of the polycube gets an inner copy v + p·s, s_d = ±1 toward the solid across each
// surface plane through v perpendicular to axis d (0 if none), p the pillow's thickness; each cube
// becomes its core (its corners replaced by their inner copies) and each surface face a pillow
// hex between the face and the inner copies of its corners. Where no vertex of a cube lies on a
// concave edge this is exactly cube_blocks. Blocks may reach into neighbouring cubes (a concave
// edge's inner copy lies in the cube across the edge's bisector): their corners are given in the
// owning cube's parameters, possibly outside [0,1]^3, and locate() takes such a point to the cube
// that holds it.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "tmesh/tmesh.h"

namespace volts::tmesh {

/// An affine map between two cubes' parameters that takes axes to axes: y = P x + t, P a signed
/// permutation matrix (entries -1, 0, 1).
struct AxisMap {
  std::array<std::array<int, 3>, 3> P{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  Vec3 t{0, 0, 0};
  Vec3 operator()(const Vec3& x) const;
  Vec3 linear(const Vec3& x) const;  ///< P x
  AxisMap inverse() const;
};

/// Cubes glued face to face. glue[c][f] (face f = 2·axis + side of cube c): the neighbouring cube,
/// its face, and the map from c's parameters to the neighbour's (it takes face f onto that face and
/// c's outward normal there to the neighbour's inward one); none: f lies on the surface.
struct CubeComplex {
  struct Glue {
    int cube = -1;
    int face = -1;
    AxisMap map;
  };
  std::vector<std::array<std::optional<Glue>, 6>> glue;
};

/// Glues face fa of cube a to face fb of cube b (both directions) with the map `a_to_b`. Throws
/// core::TopologyError if a face is glued twice or the map does not take face fa onto fb.
void glue_faces(CubeComplex& k, int a, int fa, int b, int fb, const AxisMap& a_to_b);

/// The pillowed blocks of every cube: its core (elements[0..2] per direction) and one slab of
/// `layers` elements per surface face, the pillow's thickness that of `layers` core elements
/// (p = layers / (elements + 2 layers) along each direction of a cube with two surface faces, as in
/// cube_blocks). Every block face is a surface face or the whole face of exactly one other block,
/// with the same element counts. Throws core::ConfigError for layers < 1 or elements < 1,
/// core::TopologyError naming the cube and corner where the solid is not a manifold polycube
/// there (two surface planes perpendicular to one axis facing opposite ways).
std::vector<std::vector<Block>> complex_blocks(const CubeComplex& k, int elements, int layers);

/// The cube holding the point x given in cube c's parameters (it may lie outside [0,1]^3 by less
/// than one cube): the point is carried across glued faces until every coordinate is in [0,1]
/// (within `tol`, then clamped). nullopt if it leaves the solid through a surface face.
std::optional<std::pair<int, Vec3>> locate(const CubeComplex& k, int c, Vec3 x, double tol = 1e-9);

}  // namespace volts::tmesh
