// volts::polycube — the polycube of a difference (Liu et al. 2013, §4.2 "difference" and Fig. 6,
// §4.3): a cube minus k >= 1 virtual components that run through it (through holes, all along the
// same cube axis: the plate's four bolt holes, Fig. 1(d)). The polycube is the unit cube minus one
// box per hole, [lo, hi], spanning the cube along `axis`; the solid (the input surface, not the
// fills split added over the holes' rims) is mapped onto it:
// * the cube's faces without holes and the holes' walls: patch maps (patch_map.h) placed on their
//   face of the cube or of their hole's box;
// * the two holed faces (each one patch with k rims): the face minus its fills, by a harmonic map
//   with the outer boundary and every rim fixed (the rims where the walls put them), its flipped
//   triangles (beside the boxes' or the foot's corners) unfolded (unfold_free_vertices);
// * the volume: TetGen tets of the solid, harmonic map with that boundary condition, untangled
//   (volmap).
// Each hole's box sits where its rims lie in their faces (bilinear coordinates of the rim vertices
// in the face's corner quad, Gauss-Newton; exact for a planar face, affine there). One hole: the
// box keeps 0.25 from the cube's sides at least; its mean width is the ratio of the rims' perimeter
// to the holed faces' perimeter, its aspect the rims' (a sizing choice, not a constraint: any box
// gives a bijective map, the proportions only lower its distortion). Several holes: each box is the
// rims' bilinear extent (min/max over the rim vertices, averaged over the two holed faces), no
// width rule and no margin; across each cross axis, box coordinates within 1e-6 of each other are
// made equal (their mean) so that aligned holes share the T-mesh's grid lines, and points of a
// patch on a plane of the cube or of a box lie on it exactly (one hole keeps the plain bilinear
// sum, which can miss by an ulp, so that its maps stay bitwise what they were).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/stage_file.h"
#include "polycube/patch_map.h"
#include "polycube/polycube.h"
#include "split/split.h"
#include "viz/viz.h"
#include "volmap/volmap.h"

namespace volts::polycube {

/// One through hole of a difference: its virtual component and its box in cube parameters (0 and 1
/// along the difference's axis, strictly inside the unit cube across it).
struct HoleBox {
  int virtual_component = 1;
  std::array<double, 3> lo{0, 0, 0}, hi{1, 1, 1};
};

/// A rectangle of a holed face that another component stands on, glued there whole (the foot of
/// the assembly's ring): its patch lies in the face's patch (not a fill: it closes the solid) and
/// is placed on [lo, hi] (lo[axis] = hi[axis] = the face's plane) bilinearly.
struct FootRect {
  int patch = -1;  ///< the foot's patch in the decomposition mapped (in no component)
  std::array<double, 3> lo{0, 0, 0}, hi{1, 1, 1};
};

/// The surface map of a difference.
struct DifferenceMap {
  int cube = 0;                ///< the cube component
  std::vector<HoleBox> holes;  ///< one per virtual component, in component order; boxes interior-disjoint, not touching
  int axis = 2;                ///< every hole runs along this cube axis
  bool mirrored = false;       ///< two cube axes swapped (in the boxes too) so that the map keeps the surface's orientation
  int solid_vertices = 0;      ///< layout vertices [0, solid_vertices) are the solid's surface; the others lie only on fills
  std::vector<std::array<double, 3>> points;  ///< per solid vertex: its point on the polycube's boundary
  int flipped_surface_triangles = 0;
  double max_angle_distortion_deg = 0;
  double max_mismatch = 0;     ///< max distance between the points a vertex gets from different patches (0 up to rounding)
  std::optional<FootRect> foot;  ///< the rectangle a torus stands on (torus_on_cube), if any
};

/// Maps the surface of a decomposition into one cube and k >= 1 virtual components, each meeting
/// the cube on two filled patches on opposite faces, all on the same two faces (split's difference
/// case). Throws core::TopologyError naming the components for any other component graph (a blind
/// hole, holes along different axes), when a hole's walls do not join its rims' corners straight
/// through, or (several holes) when two boxes overlap or touch or a box comes within 1e-3 of the
/// cube's sides, naming the holes; what map_patches throws.
/// With `foot_patch` >= 0 (a patch in no component whose triangles lie in one of the two holed
/// faces), that patch becomes a FootRect: the rim's bilinear extent in its face shrunk to the rim's
/// length as a hole's box is, its corners matched to the face's by the nearest cyclic
/// correspondence (either way round: the foot may turn like the component standing on it);
/// TopologyError when it lies in no holed face or its rectangle touches a hole's box or comes
/// within 1e-3 of the cube's sides.
DifferenceMap map_difference_surface(const split::Decomposition& d, const PatchMapParams& params, int foot_patch = -1);

/// The solid's surface: layout vertices [0, solid_vertices) and the triangles that are not fills.
surface::Mesh difference_solid(const split::Decomposition& d, const DifferenceMap& m);

/// The volume map of the solid onto the polycube: TetGen tets of at most
/// params.tet_max_volume_rel of its volume, harmonic map, untangling (volmap::harmonic_volume_map).
volmap::VolumeMap difference_volume_map(const split::Decomposition& d, const DifferenceMap& m, const Params& params);

/// Stage-file payload: {"kind": "difference", "cube", "axis", "mirrored", "solid_vertices",
/// "points", figures} and the holes: one hole as "virtual_component", "hole_lo", "hole_hi" (the
/// one-hole format, unchanged), several as "holes": [{"virtual_component", "hole_lo", "hole_hi"}];
/// a foot as "foot": {"patch", "lo", "hi"} (checked: on a holed face, inside it, apart from the boxes).
/// from_json reads either form, checks sizes and ranges (every box through the unit cube along
/// axis, strictly inside across it; the boxes of distinct virtual components, neither overlapping
/// nor touching) and throws core::InvalidInputError naming `file`.
core::Json to_json(const DifferenceMap& m);
DifferenceMap difference_from_json(const core::Json& j, const std::string& file);

/// ParaView view of the solid's surface at its physical points with `uvw` (the polycube point), or
/// (mapped) at its polycube points with `xyz`; cell field `component_id` (the cube or the virtual
/// component, i.e. the hole, whose patch holds the triangle). Throws core::IoError.
void write_difference_vtp(const std::string& path, const split::Decomposition& d, const DifferenceMap& m, bool mapped);

}  // namespace volts::polycube
