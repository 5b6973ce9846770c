// volts::tmesh — pillowing (Liu et al. 2013 §5.2, Fig. 9): one sheet of elements inserted under
// every face of a cube that lies on the surface. A cube edge on a smooth part of the surface is a
// 90° angle of the polycube flattened to 180° by the map, which leaves the elements along it with
// a near-zero Jacobian; the pillow splits that angle between two elements (45° each in the
// polycube, 90° each after the map) and leaves no element with two faces on the surface. For a
// torus cube (surface on four faces) this is the paper's circumferential pillow.
//
// A cube becomes blocks: a core box, and per boundary face a slab between the face and the core
// whose sides toward the neighbouring boundary faces are the diagonal planes through the cube
// edge. Every block is a trilinear image of the unit cube with its own element counts; blocks
// meeting on a face have the same bilinear face and the same element counts on it.
#pragma once

#include <array>
#include <vector>

#include "tmesh/tmesh.h"

namespace volts::tmesh {

/// The blocks of a cube with `elements` per direction and surface faces `boundary`: the cube
/// itself if layers == 0, else the core (the `elements` counts) and one slab of `layers` elements
/// per surface face. The pillow's parametric thickness is that of `layers` core elements, so the
/// parameter spacing stays uniform across the cube. Throws core::ConfigError if layers < 0 or an
/// element count < 1.
std::vector<Block> cube_blocks(const std::array<int, 6>& boundary, const std::array<int, 3>& elements, int layers);

/// Minimum distance between cuts, and from a cut to 0 and 1: closer ones are slivers, not features.
constexpr double kMinCutGap = 1e-6;

/// The same blocks cut along sharp curves inside cube faces (issue 7; the paper's repeated knots:
/// a crease on a block face is C0, inside a block the C2 spline would fold). cuts[d]: relative
/// positions u in (0,1), strictly increasing, along cube axis d. Every block that spans axis d
/// (all blocks except the slabs under the two faces perpendicular to d) is cut at its local
/// parameter u: the core (the cube if layers == 0) at x_d = lo_d + u (hi_d - lo_d), a slab along
/// the ruled plane from that line on its core face to x_d = u on its outer face. A slab's outer
/// face is the whole cube face, so on every surface face the cut line lies at x_d = u.
/// Elements along d are spread over the intervals by length (largest remainder, at least one
/// each; the total stays elements[d] unless there are more intervals); the slabs follow the
/// core's counts. Order: the core's pieces (index i + n0 (j + n1 k)), then each slab's pieces in
/// the uncut order of the slabs. A piece of a slab keeps the slab's outer-face flag; cut faces
/// are interior (0); with layers == 0 a piece is flagged on the parts of the cube's surface
/// faces it has. No cuts: exactly the blocks of the overload above. Throws core::ConfigError as
/// above, and for a cut outside (0,1), not strictly increasing, or closer than kMinCutGap to
/// another cut, 0 or 1.
std::vector<Block> cube_blocks(const std::array<int, 6>& boundary, const std::array<int, 3>& elements, int layers,
                               const std::array<std::vector<double>, 3>& cuts);

/// The blocks of a cube minus k >= 1 parallel through holes (Liu et al. 2013 §4.2 difference, Fig. 1:
/// a plate with bolt holes; §5.2 pillowing around "virtual cylinders"): the unit cube minus every
/// box holes[i] = {lo, hi}, each spanning the cube along `axis` (lo[axis] = 0, hi[axis] = 1).
/// The cross section (the two other axes) is cut into a grid by the lines of all hole walls; grid
/// cells inside a hole are skipped and every other cell is a column along `axis`. Holes with equal
/// lo (or hi) coordinates along a cross axis share a grid line; coordinates are compared exactly,
/// so the caller snaps nearly equal ones (else the grid gets a sliver column between them).
/// Without layers: the columns, cut along the planes of the walls. With layers: a pillow of
/// `layers` elements under every boundary face, outer and inner alike — a core (the solid shrunk
/// by the pillow's thickness: the columns between the grid lines moved by the thickness toward the
/// solid, i.e. the cube's sides inward and each hole's walls outward) and frusta between the core
/// and the faces: one per column under each holed face, one per grid interval under each side of
/// the cube and under each wall. No block has more than one face on the boundary. Every block face
/// is a boundary face or the whole face of exactly one other block, with the same element counts;
/// Block::boundary flags exactly the faces on the cube's sides and on the walls. `elements` is the
/// count along a cube edge: an interval of the grid (of the core's grid with layers) gets its
/// length in elements of 1 / (elements + 2 layers), rounded, at least one; the pillow's thickness
/// is that of `layers` elements. A block's parameter axes are the cube axes (axis + 1) % 3,
/// (axis + 2) % 3, axis (its elements and boundary flags in that order). Order: the columns (cross
/// axes' cells, first fastest), the frusta under the cube's sides, under the holed faces, under
/// each hole's walls (hole by hole).
/// Throws core::ConfigError for layers < 0 or elements < 1; core::TopologyError, naming the holes,
/// for an axis not in 0..2, no hole, a hole that is not a box through the cube along `axis` strictly
/// inside it across, holes that overlap or touch, a grid line that is a lo wall of one hole and a hi
/// wall of another (two holes meeting along a line), and holes that lie too close to each other or
/// to the cube's sides for the pillow (two grid lines whose core lines would cross: a hi wall or
/// the side 0, then a lo wall or the side 1, closer than twice the pillow's thickness — also when
/// the two holes are apart along the other cross axis, since every grid line crosses the section).
std::vector<Block> difference_blocks(int axis, const std::vector<std::array<Vec3, 2>>& holes, int elements, int layers);

/// The same with element counts per cube axis (`elements[a]` along cube axis a: a flat plate
/// needs fewer across its thickness than along its sides), the pillow `layers` elements of each
/// axis thick; the overload above is {elements, elements, elements}.
std::vector<Block> difference_blocks(int axis, const std::vector<std::array<Vec3, 2>>& holes, const std::array<int, 3>& elements, int layers);

/// The blocks of a cube minus one through hole [hole_lo, hole_hi]: difference_blocks(axis,
/// {{hole_lo, hole_hi}}, elements, layers) — eight columns; with layers the core's eight columns and
/// 32 frusta (three under each side of the cube, eight under each holed face, one under each wall).
std::vector<Block> difference_blocks(int axis, const Vec3& hole_lo, const Vec3& hole_hi, int elements, int layers);

/// The blocks of a ring (torus) whose cross section is a union of grid cells instead of a square
/// (e.g. a washer with a plus-shaped section): per cell (same order as `cells`), the blocks of its
/// cube in the cube's parameters (a, b, c), a along the ring (faces a = 0 and a = 1 are the same
/// cell of the neighbouring sectors, never surface), b along the grid's axis 0, c along its axis 1;
/// a b or c face is on the surface iff no cell lies across it. layers == 0: every cell is its
/// cube, which trivially conforms. With layers, two rules, the first that conforms:
/// 1. Per cell: a cell with a surface face is cube_blocks(its surface faces, {elements, elements,
///    elements}, layers). A cell without one (the plus's centre) gets no pillow of its own but is
///    cut (cube_blocks with cuts, no layers) where its neighbours' slabs end on its faces, with
///    the same element counts: the slabs of the cells around it continue through it, so the
///    pillow is one sheet under the whole surface that wraps around the concave edges of the
///    section instead of ending on them (Liu et al. 2013 §5.2, Fig. 9). Takes the plus, a row, a
///    full rectangle; not an L, T or U, whose cells with surface faces would need cuts.
/// 2. One sheet: every slab has the same thickness p = layers h, h = 1 / (elements + 2 layers),
///    the spacing along b and c in every cell (cube_blocks(surface faces, {elements, elements +
///    (2 - s_b) layers, elements + (2 - s_c) layers}, layers, cuts), s_d the cell's surface faces
///    along d). Along d, a cell is cut at x_d = p (1 - p) if its face (d, 0) ((d, 1)) is not on
///    the surface but a concave edge of the section runs along that side, where the cell keeps a
///    p x p column that the neighbours' slabs meet (the pillow wraps around the edge); a cut
///    crosses the whole cell, so the cells in a row along the other cross axis share their cuts.
///    Takes every edge-connected profile.
/// The result is checked: every face shared by two cells, and each cell's faces a = 0 and a = 1
/// (glued around the ring), carry the same block faces with the same element counts on both sides.
/// Throws core::ConfigError for elements < 1 or layers < 0; core::InvalidInputError if `cells` is
/// empty, has a cell twice or is not edge-connected; core::TopologyError, naming the cells, if the
/// check fails (not expected with rule 2).
std::vector<std::vector<Block>> profile_blocks(const std::vector<std::array<int, 2>>& cells, int elements, int layers);

/// The in-plane pillow of a pillow slab's surface face (Liu et al. 2013 §5.2, Fig. 9: the
/// circumferential pillow, here of one face): a ring of elements along the face's outline, so
/// that no element of the face has two edges on it. Where the outline is smooth at a corner of
/// the face (the rod's lensed connector end: the cube corner sits on the round section of the
/// shank, ~162 degrees between the face's edges) the corner element's surface face is flattened
/// and bounds its scaled Jacobian by the sine of that angle; the ring splits the angle between two
/// elements. It is a shrink-set pillow of the slab alone: cube_blocks of the slab's own
/// parameters with its five other faces as the pillowed ones (`layers` each), mapped through the
/// slab's corners. Each of those five faces stays the whole face of exactly one new block with
/// the same element counts, so the slab's neighbours conform unchanged; the surface face becomes
/// the core's face and four rim strips. Every new block is a pillow block; the ones reaching the
/// surface face carry its flag. Throws core::InvalidInputError if `slab` has not exactly one
/// surface face, core::ConfigError for layers < 1.
std::vector<Block> rim_pillow(const Block& slab, int layers);

/// Cube parameters of block parameters uvw (trilinear in the corners).
Vec3 block_point(const std::array<Vec3, 8>& corners, const Vec3& uvw);

}  // namespace volts::tmesh
