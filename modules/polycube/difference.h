// volts::polycube — the polycube of a difference (Liu et al. 2013, §4.2 "difference" and Fig. 6,
// §4.3): a cube minus a virtual component that runs through it (a through hole). The polycube is
// the unit cube minus a box [hole_lo, hole_hi] that spans the cube along `axis`; the solid (the
// input surface, not the fills split added over the hole's rims) is mapped onto it:
// * the cube's faces without the hole and the hole's four walls: patch maps (patch_map.h) placed on
//   their face of the cube or of the hole's box;
// * the two holed faces: the annulus between the face's sides and the rim, by a harmonic map with
//   both boundaries fixed (the rim where the walls put it);
// * the volume: TetGen tets of the solid, harmonic map with that boundary condition, untangled
//   (volmap).
// The hole's box sits where the rims lie in their faces (bilinear coordinates of the rim vertices
// in the face's corner quad), 0.25 from the cube's sides at least; its mean width is the ratio of
// the rims' perimeter to the holed faces' perimeter, its aspect the rims' (a sizing choice, not a
// constraint: any box gives a bijective map, the proportions only lower its distortion).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/stage_file.h"
#include "polycube/patch_map.h"
#include "polycube/polycube.h"
#include "split/split.h"
#include "viz/viz.h"
#include "volmap/volmap.h"

namespace volts::polycube {

/// The surface map of a difference.
struct DifferenceMap {
  int cube = 0;               ///< the cube component
  int virtual_component = 1;  ///< the virtual component (the hole)
  int axis = 2;               ///< the hole runs along this cube axis
  std::array<double, 3> hole_lo{0, 0, 0}, hole_hi{1, 1, 1};  ///< the hole's box in cube parameters (0 and 1 along axis)
  bool mirrored = false;      ///< two cube axes swapped so that the map keeps the surface's orientation
  int solid_vertices = 0;     ///< layout vertices [0, solid_vertices) are the solid's surface; the others lie only on fills
  std::vector<std::array<double, 3>> points;  ///< per solid vertex: its point on the polycube's boundary
  int flipped_surface_triangles = 0;
  double max_angle_distortion_deg = 0;
  double max_mismatch = 0;    ///< max distance between the points a vertex gets from different patches (0 up to rounding)
};

/// Maps the surface of a decomposition into one cube and one virtual component that meet on two
/// filled patches (split's difference case). Throws core::TopologyError naming the components for
/// any other component graph, or when the hole's walls do not join the rims' corners straight
/// through; what map_patches throws.
DifferenceMap map_difference_surface(const split::Decomposition& d, const PatchMapParams& params);

/// The solid's surface: layout vertices [0, solid_vertices) and the triangles that are not fills.
surface::Mesh difference_solid(const split::Decomposition& d, const DifferenceMap& m);

/// The volume map of the solid onto the polycube: TetGen tets of at most
/// params.tet_max_volume_rel of its volume, harmonic map, untangling (volmap::harmonic_volume_map).
volmap::VolumeMap difference_volume_map(const split::Decomposition& d, const DifferenceMap& m, const Params& params);

/// Stage-file payload: {"kind": "difference", "cube", "virtual_component", "axis", "hole_lo",
/// "hole_hi", "mirrored", "solid_vertices", "points", figures}; from_json checks sizes and ranges and
/// throws core::InvalidInputError naming `file`.
core::Json to_json(const DifferenceMap& m);
DifferenceMap difference_from_json(const core::Json& j, const std::string& file);

/// ParaView view of the solid's surface at its physical points with `uvw` (the polycube point), or
/// (mapped) at its polycube points with `xyz`; cell field `component_id` (the cube or the virtual
/// component whose patch holds the triangle). Throws core::IoError.
void write_difference_vtp(const std::string& path, const split::Decomposition& d, const DifferenceMap& m, bool mapped);

}  // namespace volts::polycube
