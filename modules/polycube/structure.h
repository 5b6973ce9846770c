// volts::polycube — the polycube structure: cube and torus primitives, their union along shared
// faces and their difference with virtual components (Liu et al. 2013, §4.2 "Two Primitives", §4.3
// "Two Boolean Operations" and Fig. 6).
//
// Each cube has its own parameter box; a gluing says which rectangle of one cube's face is the same
// as a rectangle of another's, through an axis-aligned affine map (signed axis permutation, scale,
// offset), so faces of cubes of different sizes may meet partially (Fig. 6(a)). A torus is n >= 4
// cubes in a row (four in the paper; split makes 4..16), the last one's right face glued to the
// first one's left face by a translation (Fig. 5(b)): no single axis-aligned embedding holds it,
// hence maps rather than one frame. A virtual component (Fig. 6(b)/(d), Fig. 7) is a region of one
// cube (boxes in its frame) whose elements the T-mesh stage removes. A contact records two cube
// faces that touch where no gluing can say how (split's two tori meet on a filled disk inside a
// face of each ring, not on a rectangle of both): it joins the solid but relates no frames.
//
// Coordinates are compared exactly: they are lattice values (dyadic fractions, as the octree's), so
// maps with power-of-two scales compose without rounding. Two coordinates that differ by less than
// StructureParams::near_rel of the structure's size but are not equal are a TopologyError, never
// rounded to equal. Coordinates that no map moves (a virtual box in its own cube's frame, e.g. the
// hole box polycube/difference.h sizes) may be any doubles: they are only compared, never
// computed. Faces are 2*axis + side (side 1 = the hi side); a face's coordinates (s, t) are those
// of axes (axis+1)%3 and (axis+2)%3, as in polycube.h.
//
// Limits: a virtual component lies in one cube (a hole through two glued cubes is one per cube);
// the development cuts a torus at its closing gluing, so a cube glued across that cut is not
// represented (glue it to the representative cube, as the paper does).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/stage_file.h"

namespace volts::polycube {

using Point = std::array<double, 3>;

/// Parameters of the structure's checks.
struct StructureParams {
  /// Coordinates closer than near_rel * (the structure's largest coordinate or extent) but not
  /// equal are an error: an "almost" shared face or flush edge is a bug upstream, not a contact.
  double near_rel = 1e-9;
};

/// An axis-aligned box [lo, hi] (lo < hi on every axis).
struct Box {
  Point lo{0, 0, 0}, hi{1, 1, 1};
};

/// A rectangle [lo, hi] in a face's (s, t) coordinates.
struct Rect {
  std::array<double, 2> lo{0, 0}, hi{1, 1};
};

/// x -> y with y[k] = scale[k] * x[axis[k]] + offset[k]: a signed axis permutation (negative
/// scale: a flip), a scale and an offset per axis. Maps points of one cube's frame to another's.
struct AxisMap {
  std::array<int, 3> axis{0, 1, 2};
  Point scale{1, 1, 1};
  Point offset{0, 0, 0};
};

/// A cube; its id is its index in Structure::cubes.
struct Cube {
  std::string label;  ///< the split component it comes from (messages name it)
  Box box;            ///< its parameter box
  int primitive = 0;  ///< the primitive it belongs to
};

/// A cube primitive (one cube) or a torus primitive (n >= 4 cubes in a ring, the first the
/// representative of Fig. 6(c)/(d)).
struct Primitive {
  std::string label;
  bool torus = false;
  std::vector<int> cubes;
};

/// Rectangle `rect_a` of face `fa` of cube `a` is glued to face `fb` of cube `b`; `map` takes a's
/// frame to b's (its image of rect_a is b's glued rectangle).
struct Gluing {
  int a = 0, fa = 0, b = 0, fb = 0;
  Rect rect_a;
  AxisMap map;
  int closes_torus = -1;  ///< the torus whose ring this gluing closes (its period), -1 if none
};

/// A region of one cube to be removed after the T-mesh is built (a difference, Fig. 6(b)/(d)):
/// interior-disjoint boxes in the cube's frame, clipped to it.
struct VirtualComponent {
  std::string label;
  int cube = 0;
  std::vector<Box> boxes;
  bool torus = false;  ///< a square ring of four boxes (a cube minus a torus)
};

/// A non-conforming contact: face `fa` of cube `a` and face `fb` of cube `b` touch on a region
/// (named by `label`, e.g. a filled disk) that is not a rectangle of both faces, so no gluing (no
/// map) relates them. It makes the solid connected but not one polycube: the cubes on either side
/// stay in frames of their own (separate parts of the development), and the T-mesh does not match
/// across it. Both faces must hold boundary (neither glued nor opened all over), and the cubes must
/// not be joined by gluings (cubes in one frame that touch need a gluing).
struct Contact {
  std::string label;
  int a = 0, fa = 0, b = 0, fb = 0;
};

struct Structure {
  std::vector<Cube> cubes;
  std::vector<Primitive> primitives;
  std::vector<Gluing> gluings;
  std::vector<VirtualComponent> virtual_components;
  std::vector<Contact> contacts;
};

Point apply(const AxisMap& m, const Point& x);
/// The image of a box (its corners sorted back into lo <= hi).
Box apply(const AxisMap& m, const Box& b);
/// outer ∘ inner.
AxisMap compose(const AxisMap& outer, const AxisMap& inner);
AxisMap inverse(const AxisMap& m);
/// The rectangle of face `face` of box `b` in that face's (s, t).
Rect face_rect(const Box& b, int face);

/// Adds a cube primitive; returns its primitive id (its cube is the last of Structure::cubes).
/// Throws core::TopologyError naming `label` if the box is empty or not finite.
int add_cube(Structure& s, const std::string& label, const Box& box);

/// Adds a torus primitive: `cubes` (>= 4) copies of `first` in a row along `ring_axis` (cube i
/// shifted by i box widths), consecutive cubes glued face to face, the last's hi face glued to the
/// first's lo face by a translation of minus `cubes` widths. Cubes are labelled label/0 ..
/// label/(cubes-1). Returns the primitive id. Throws core::TopologyError as add_cube, or if
/// ring_axis is not 0, 1 or 2, or cubes < 4.
int add_torus(Structure& s, const std::string& label, const Box& first, int ring_axis, int cubes = 4);

/// Union (Fig. 6(a)/(c)): primitives p and q, their boxes given in one frame, are glued on every
/// face rectangle of positive area where a cube of p touches a cube of q (identity maps). Returns
/// the new gluings. Throws core::TopologyError naming both primitives if they share no face
/// rectangle, if two of their cubes overlap, or if a coordinate of one almost equals one of the
/// other (StructureParams::near_rel).
std::vector<int> unite(Structure& s, int p, int q, const StructureParams& params = {});

/// Glues rect_a of face fa of cube a to face fb of cube b through `map`; returns the gluing id.
/// Throws core::TopologyError naming both cubes if the map does not take a's face plane onto b's,
/// puts the cubes on the same side, mirrors (det < 0), or a rectangle is not inside its face.
int glue(Structure& s, int a, int fa, int b, int fb, const Rect& rect_a, const AxisMap& map, const StructureParams& params = {});

/// Difference (Fig. 6(b)): a virtual component of cube `cube`: `boxes` (its frame) clipped to the
/// cube — a through or blind hole, a notch at an edge, a box inside. Returns its id. Throws
/// core::TopologyError naming the component and the cube if a box misses the cube, boxes overlap
/// (also another virtual component's), a coordinate almost equals another, or what is left of the
/// cube is empty or in pieces.
int subtract(Structure& s, int cube, const std::string& label, const std::vector<Box>& boxes, const StructureParams& params = {});

/// Difference with a torus (Fig. 6(d)): the square ring between `outer` and `inner` (equal along
/// `axis`, inner strictly inside outer across it) as four interior-disjoint boxes (a pinwheel),
/// subtracted from `cube` as one virtual component with torus = true. Throws as subtract.
int subtract_ring(Structure& s, int cube, const std::string& label, const Box& outer, const Box& inner, int axis,
                  const StructureParams& params = {});

/// Records a non-conforming contact (see Contact) of face fa of cube a with face fb of cube b;
/// returns its id. Throws core::TopologyError naming the contact and the cubes if an index or face
/// is out of range, a == b, or a face holds no boundary. That no gluings join a and b is check()'s
/// (gluings may come later).
int add_contact(Structure& s, const std::string& label, int a, int fa, int b, int fb);

/// Re-expresses cube `cube` in a new frame: its box becomes m(box), and its gluings (faces,
/// rectangles, maps) and virtual boxes follow, so the structure is the same polycube (e.g. every
/// cube on [0,1]^3, as the paper maps them). Throws core::TopologyError naming the cube if m is not
/// a signed axis permutation with nonzero scales or mirrors (det < 0).
void reframe(Structure& s, int cube, const AxisMap& m);

/// The face of m(box) that face `face` of box becomes.
int map_face(const AxisMap& m, int face);

/// Per cube: its map into the frame of its connected part (that part's first cube's frame),
/// composed along a spanning tree of the gluings that never uses a torus's closing gluing (the
/// development cuts each torus open there). Cubes glued with identity maps keep their boxes.
/// Contacts join no frames: cubes joined only through contacts are in different parts.
std::vector<AxisMap> develop(const Structure& s);

enum class RegionKind { boundary, glued, virtual_opening };

/// A rectangle of a cube face: glued to a neighbour, on the solid's boundary, or the opening of a
/// virtual component (removed later; if also glued, gluing and neighbor say to whom).
struct FaceRegion {
  int face = 0;
  Rect rect;  ///< in the face's (s, t) of the cube's own box
  RegionKind kind = RegionKind::boundary;
  int gluing = -1, neighbor = -1, virtual_component = -1;
};

/// The six faces of `cube` cut into maximal rectangles of one kind (they tile each face): what
/// the T-mesh stage needs for boundary flags. Throws core::TopologyError naming the cubes if a
/// face rectangle is glued twice or opened by two virtual components.
std::vector<FaceRegion> boundary_regions(const Structure& s, int cube);

/// A rectangle of face `face` of box `box` of a virtual component inside its cube: boundary of
/// the solid once the component's elements are removed.
struct Wall {
  int box = 0, face = 0;
  Rect rect;
};
std::vector<Wall> virtual_walls(const Structure& s, int virtual_component);

/// Throws core::TopologyError, naming the components involved, unless the structure is a polycube:
/// every gluing valid (as glue checks), connected, no face rectangle glued twice, the gluing maps
/// compose to the identity around every cycle (a torus's ring: to a translation), developed cubes
/// neither overlap nor touch on a face without a gluing there, no coordinates almost equal, each
/// torus a ring of n >= 4 cubes glued on whole faces, virtual components as subtract checks.
/// With contacts: parts of the development joined by gluings or contacts must be connected, each
/// contact joins two different parts on faces that hold boundary (as add_contact checks), and
/// overlap and crack checks run per part (parts have no common frame). Without contacts every cube
/// must be in one part, as before: a contact is the only way a structure may have several.
void check(const Structure& s, const StructureParams& params = {});

/// {"cubes": [{label, lo, hi, primitive}], "primitives": [{label, torus, cubes}], "gluings": [{a,
/// fa, b, fb, rect_lo, rect_hi, axis, scale, offset, closes_torus}], "virtual_components": [{label,
/// cube, torus, boxes: [{lo, hi}]}], "contacts": [{label, a, fa, b, fb, conforming: false}]}.
/// structure_from_json checks types, sizes, ranges and references and throws
/// core::InvalidInputError naming `file` and the member (`contacts` may be absent: none; a contact
/// with conforming true is refused: that is a gluing); realizability is check()'s.
core::Json to_json(const Structure& s);
Structure structure_from_json(const core::Json& j, const std::string& file);

/// {"cubes", "tori", "virtual_components", "gluings", "contacts"}: counts.
core::Json report_figures(const Structure& s);

/// ParaView: cubes at their developed position and virtual boxes as hexahedra, cell fields
/// cube_id, primitive_id, torus (0/1), virtual (0/1), virtual_component (-1 for cubes), part (of
/// the development). Parts after the first (joined only by contacts) are drawn moved along x, each
/// half its width clear of the one before, so they do not overlap. Throws core::IoError.
void write_structure_vtu(const std::string& path, const Structure& s);

}  // namespace volts::polycube
