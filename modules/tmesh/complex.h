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
//
// Cubes of different sizes meeting in part (§4.3, Fig. 6(a): the rod's shank ending on a thinner
// eye, a ring on a plate) are given as boxes of one frame (BoxLayout); box_complex cuts them
// until every face is glued whole or not at all, and complex_blocks then pillows the sub-boxes
// with one pillow thickness in the frame (BoxComplex::pillow).
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

/// outer ∘ inner.
AxisMap compose(const AxisMap& outer, const AxisMap& inner);

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

/// Two surface planes through a corner of the complex perpendicular to one axis and facing
/// opposite ways: a non-manifold polycube (refuse), or, in a development (develop()), a ring's
/// convex turn at a cross section flattened next to a cube standing on part of the ring's face —
/// the rod's shoulder lens beside the next sector of its eye — where the two faces are not
/// coplanar in the solid (in_plane: the inner copy stays in their plane along that axis, inside
/// the frame's solid; the pillow blocks are flat at that corner in the frame, not in the solid).
/// The same holds for a crack: two occupied cubes side by side around the corner whose shared
/// face is glued from neither side (a ring leaving the face it stands on, next to the cell beside
/// its foot: a wedge of air in the solid, none in the complex). Its two faces are surface planes
/// facing each other; with in_plane the inner copy stays in their plane and moves, along each
/// other axis without a surface plane, toward the glued pair of cubes beside the crack (the foot).
enum class OppositePlanes { refuse, in_plane };

/// The pillowed blocks of every cube: its core (elements[0..2] per direction) and one slab of
/// `layers` elements per surface face, the pillow's thickness that of `layers` core elements
/// (p = layers / (elements + 2 layers) along each direction of a cube with two surface faces, as in
/// cube_blocks). Every block face is a surface face or the whole face of exactly one other block,
/// with the same element counts. Throws core::ConfigError for layers < 1 or elements < 1,
/// core::TopologyError naming the cube and corner where the solid is not a manifold polycube
/// there (two surface planes perpendicular to one axis facing opposite ways).
std::vector<std::vector<Block>> complex_blocks(const CubeComplex& k, int elements, int layers);

/// The same with element counts per cube and axis (`counts[c][d]` along axis d of cube c's core
/// and of its slabs across d; slabs have `layers` across their face) and the pillow's parametric
/// thickness per cube and axis, `p[c][d]` in (0, 0.5): the same thickness in a common frame for
/// cubes of different sizes (box_complex: P / the box's extent), so that the inner copies of
/// shared vertices coincide. The overload above is counts = `elements` and p = layers /
/// (elements + 2 layers) everywhere. Throws core::ConfigError for layers < 1, a count < 1, a p
/// outside (0, 0.5) or sizes not one per cube; core::TopologyError naming the cubes and the face
/// if two glued faces have different counts along their shared axes (element_counts makes them
/// agree), and as above; with OppositePlanes::in_plane such a corner's inner copy stays in the
/// two planes' plane along that axis.
std::vector<std::vector<Block>> complex_blocks(const CubeComplex& k, const std::vector<std::array<int, 3>>& counts, int layers,
                                               const std::vector<std::array<double, 3>>& p, OppositePlanes opposite = OppositePlanes::refuse);

/// Pillow thicknesses per cube and axis for complex_blocks that are one thickness in the solid:
/// the axes that gluings tie (through every gluing map, the faces' normal axes too, so that the
/// inner copies of shared vertices coincide) form classes, and a class whose mean physical
/// length is l gets p0 · l_min / l, p0 = layers / (elements + 2 layers) the uniform thickness,
/// l_min the shortest class's mean. One parametric thickness everywhere is physically ~4× thicker
/// along a long cube axis (the eight's ring cubes along the ring), which shears the slabs beside
/// a concave edge over their whole length (docs/status.md, session 25). `length[c][d]`: cube c's
/// physical length along axis d (> 0). Throws core::ConfigError for elements < 1, layers < 1 or
/// lengths not one positive triple per cube.
std::vector<std::array<double, 3>> physical_pillow(const CubeComplex& k, int elements, int layers, const std::vector<std::array<double, 3>>& length);

/// Element counts per cube and axis that agree across glued faces: axes that glued faces share
/// (their tangential axes, through the gluing maps) form classes, and every axis of a class gets
/// the largest count `wanted` asks for in it. An axis no gluing ties keeps its own wish (e.g. a
/// connector's length). Throws core::ConfigError if `wanted` is not one per cube or has a count < 1.
std::vector<std::array<int, 3>> element_counts(const CubeComplex& k, const std::vector<std::array<int, 3>>& wanted);

/// The cubes of a polycube as boxes of one frame (a development: structure.h's develop() puts
/// every cube of a connected polycube in one frame, cutting each torus open at one gluing), of any
/// sizes, meeting face to face in whole faces or in part (Liu et al. 2013 §4.3, Fig. 6(a)).
struct BoxLayout {
  std::vector<std::array<Vec3, 2>> boxes;  ///< lo, hi per box (lo < hi on every axis); interiors disjoint
  /// A torus cut open: face `fa` of box `a`, moved by `shift`, is face `fb` of box `b` (opposite
  /// sides of one axis; shift only along it).
  struct Closure {
    int a = 0, fa = 0, b = 0, fb = 0;
    Vec3 shift{0, 0, 0};
  };
  std::vector<Closure> closures;
};

/// A BoxLayout cut into sub-boxes that meet in whole faces: every box is cut by the planes where
/// a touching box's face ends on it, and by every cut of a touching box that crosses their
/// shared face, until none is left (cuts travel around rings through the closures). Each sub-box
/// is a cube of `complex` with unit parameters along the frame's axes; sub-boxes are glued where
/// their faces coincide (touching or across a closure), every other face is surface.
struct BoxComplex {
  CubeComplex complex;
  std::vector<int> box;                     ///< per cube: its box of the layout
  std::vector<std::array<Vec3, 2>> extent;  ///< per cube: lo, hi in the frame
  std::vector<BoxLayout::Closure> closures;  ///< the layout's
  std::vector<std::array<Vec3, 2>> boxes;    ///< the layout's boxes (lo, hi), by layout box
  double size = 1;                           ///< the frame's largest coordinate or extent (tolerances are relative to it)
  Vec3 to_frame(int cube, const Vec3& uvw) const;  ///< lo + uvw (hi - lo), also outside [0,1]^3
  /// The cube holding frame point x (within tol of its box, relative to the frame's size;
  /// `prefer` first, then in order) and x in its parameters (clamped to [0,1]^3); a point just past a
  /// closing face, within it, is carried across it (not a point in a gap of the layout). nullopt if
  /// no box holds it.
  std::optional<std::pair<int, Vec3>> locate(const Vec3& x, int prefer = -1, double tol = 1e-9) const;
  /// complex_blocks' per-cube thicknesses for a pillow `thickness` thick in the frame: thickness / extent.
  std::vector<std::array<double, 3>> pillow(double thickness) const;
};

/// Builds the BoxComplex of `layout`; `cuts[b][d]` (optional, frame coordinates strictly inside
/// box b along axis d) cut box b too (e.g. sharp lines), carried like the others. Throws
/// core::TopologyError naming the boxes if a box is empty or not finite, two boxes overlap, or a
/// closure's faces are not translates of each other by its shift; core::ConfigError for a cut
/// outside its box or cuts not one per box.
BoxComplex box_complex(const BoxLayout& layout, const std::vector<std::array<std::vector<double>, 3>>& cuts = {});

/// The complex laid out in one frame: per cube, the map from its parameters to the frame (cube 0's
/// parameters are the frame), found along the gluings; a gluing that closes a cycle with a
/// translation (a ring) becomes a closure. `layout` gets the cubes' boxes and the closures.
/// Throws core::TopologyError if the complex is not connected, a cycle closes with a turn (no
/// single frame holds it) or two cubes overlap in the frame.
std::vector<AxisMap> develop(const CubeComplex& k, BoxLayout& layout);

/// A cube's parameters to the frame and back when its box in the frame is `box` (develop's box,
/// or that box stretched along frame axes, e.g. a ring standing on part of a face): `frame`'s
/// signed permutation says which cube axis runs along which frame axis, the box its extent.
Vec3 cube_to_frame(const AxisMap& frame, const std::array<Vec3, 2>& box, const Vec3& x);
Vec3 frame_to_cube(const AxisMap& frame, const std::array<Vec3, 2>& box, const Vec3& y);

/// complex_blocks' blocks of a BoxComplex of develop()'s layout, given per cube of `k` (a layout
/// box) in that cube's own parameters and axes (`frame`: develop's maps, whose boxes the layout
/// may have stretched along frame axes before box_complex): corners through the frame and
/// frame_to_cube, renumbered so that block axis d is cube axis d, element counts and surface
/// flags permuted alike; per cube the cores of its sub-boxes first, then their slabs by face. With
/// one sub-box per cube this is complex_blocks(k, ...) itself, to rounding. Throws
/// core::ConfigError if `frame` is not one map per layout box.
std::vector<std::vector<Block>> blocks_in_cubes(const BoxComplex& bc, const std::vector<AxisMap>& frame,
                                                const std::vector<std::vector<Block>>& blocks);

/// The cube holding the point x given in cube c's parameters (it may lie outside [0,1]^3 by less
/// than one cube): the point is carried across glued faces until every coordinate is in [0,1]
/// (within `tol`, then clamped). nullopt if it leaves the solid through a surface face.
std::optional<std::pair<int, Vec3>> locate(const CubeComplex& k, int c, Vec3 x, double tol = 1e-9);

}  // namespace volts::tmesh
