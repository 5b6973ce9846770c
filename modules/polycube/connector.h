// volts::polycube — the connector cube of two tori (Liu et al. 2013 §4.2 union of primitives,
// Fig. 6(c); §6: "some red curves in the middle region between the two tori are obtained by
// finding the shortest distance on the surface"). split (split.genus2: connector) cuts a genus-2
// solid into torus + neck + torus; each torus is closed by its own disk, a whole patch of the torus
// (so a whole face of one of its cubes), and the neck is one cube whose two ends are those disks.
// Here the neck's closed surface is mapped onto the unit cube — a along the neck, a = 0 on the
// disk of ring 0 — patch by patch (patch_map.h), and its volume by TetGen tets and a harmonic map
// (volmap), as a torus's is. Each end's patch map is the one the ring computes for the same disk
// (the same triangles, corners and arc-length sides), so the neck and the ring parameterize their
// shared face alike; tmesh glues them there. An end on a shoulder (Fig. 13, the rod's small eye)
// is the disk between the shoulder's two faces, mapped as three strips across the eye.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/stage_file.h"
#include "polycube/patch_map.h"
#include "polycube/polycube.h"
#include "polycube/rings.h"
#include "volmap/volmap.h"

namespace volts::polycube {

/// The surface map of a connector (its Ring piece: its own vertex and triangle ids).
struct ConnectorMap {
  std::array<int, 8> corner_vertex{};            ///< piece vertex at cube corner a + 2b + 4c
  std::vector<std::array<double, 3>> points;     ///< per piece vertex: its point on the unit cube's surface
  bool mirrored = false;                         ///< b and c swapped so that the map keeps the surface's orientation
  int flipped_surface_triangles = 0;
  double max_angle_distortion_deg = 0;
  double max_mismatch = 0;                       ///< max distance between a vertex's points from different patches
  /// A lensed end (split.connector_end: shoulder): its face a = strip_end is three strips across
  /// cube axis strip_axis (1 = b, 2 = c; 0: no lensed end), lens [0, lo], disk [lo, hi], lens [hi, 1].
  int strip_end = -1;
  int strip_axis = 0;
  std::array<double, 2> strip{0, 1};
  /// The disk's corners (the lenses' tips, piece vertices) at (other axis, strip axis) =
  /// (i & 1, lo if i < 2 else hi).
  std::array<int, 4> strip_vertex{-1, -1, -1, -1};
};

/// Maps the connector `piece` onto the unit cube: its face holding a fill triangle of `ring0` (the
/// first torus's piece) at a = 0, the other disk at a = 1; corner k of the a = 0 face's patch at
/// (b, c) = (0,0), (1,0), (1,1), (0,1) (or b and c swapped: `mirrored`), the other ends of the side
/// curves at a = 1. An end face of three patches (a disk between a shoulder's two lenses,
/// split.connector_end: shoulder) is mapped as three strips (`strip`): each of its patches onto
/// its rectangle, the face's two sides through the lenses' tips piecewise by arc length between
/// the tips, so the disk's strip is the disk's own patch map scaled. Throws core::TopologyError if
/// the piece is not a cube with one disk per ring (a side patch not joining the two disks, a face
/// of three patches that is not a disk between two lenses), what map_patches throws.
ConnectorMap map_connector(const Ring& piece, const Ring& ring0, const PatchMapParams& params);

/// The volume map of the connector: TetGen tets of at most params.tet_max_volume_rel of its volume,
/// harmonic map onto the unit cube with the surface map as boundary condition, untangled.
volmap::VolumeMap connector_volume_map(const Ring& piece, const ConnectorMap& m, const Params& params);

/// Stage-file entry: {"component" (whole-decomposition id), "layout_vertex", "layout_triangle",
/// "corner_vertex", "mirrored", "points", figures, "volume_map"}, and for a lensed end
/// "end_strip" {"end", "axis", "lo", "hi", "corner_vertex" (strip_vertex)}. connector_corners reads the
/// corners back as layout vertex ids (index a + 2b + 4c) and checks them, throwing
/// core::InvalidInputError naming `file`.
core::Json to_json(const Ring& piece, const ConnectorMap& m, const volmap::VolumeMap& vm);
std::array<int, 8> connector_corners(const core::Json& j, const std::string& file);

}  // namespace volts::polycube
