// volts::polycube — the polycube embedding of a torus decomposition (Liu et al. 2013, §4.2: "for a
// torus, we use four consecutive unit cubes ... the left face of the first cube connecting to the
// right face of the last"). The ring of n cubes is embedded as a round annulus (inner radius 1,
// outer 2, height 1): cube k is the sector between angles 2πk/n and 2π(k+1)/n, with local
// coordinates (a, b, c) ∈ [0,1]^3 — a along the ring, b across it (inner → outer), c through its
// height — in polar form. (A polygonal annulus, the polycube itself, has reentrant inner edges
// where the harmonic volume map degenerates: measured 164 of 2048 cubic elements invalid on the
// generated torus, against none with the round one.) Every surface vertex gets the
// point of its patch's square image on its cube face; this is the boundary condition of the volume
// map (volmap::harmonic_volume_map).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/stage_file.h"

#include "polycube/patch_map.h"
#include "split/split.h"
#include "viz/viz.h"

namespace volts::polycube {

/// The cross section of a ring whose sharp curves meet at right angles, convex and concave (the
/// washer's plus sign; Liu et al. §4.2, a union of torus primitives, Fig. 6(c)): a rectilinear
/// polygon in the sector's (b, c) square, cut by the lines through its sides into grid cells. Each
/// cell times each sector is one cube of the polycube, so every sharp curve lies on a cube edge:
/// convex ones at 90°, concave ones at 270°, none flattened inside a face. Empty: the square.
struct Profile {
  std::vector<double> b, c;               ///< grid lines, increasing, first 0 and last 1
  std::vector<std::array<int, 2>> cells;  ///< cells (i, j) = [b_i, b_i+1] x [c_j, c_j+1] inside the polygon
  std::vector<std::array<double, 2>> polygon;  ///< the polygon's corners (b, c), counter-clockwise
  int concave_corners = 0;
  bool empty() const { return cells.empty(); }
};

struct Embedding {
  int ring = 0;                                                 ///< cubes around the ring
  bool mirrored = false;                                        ///< height reversed (c -> 1 - c) to keep the surface's orientation
  std::vector<std::array<double, 3>> points;                    ///< per layout vertex (unused vertices: NaN)
  std::vector<std::array<std::array<double, 3>, 8>> cells;      ///< per component: its sector's corners, index a + 2b + 4c
  std::vector<std::array<int, 8>> corner_vertex;                ///< per component: layout vertex at each local corner
  double max_mismatch = 0;  ///< max distance between the points a vertex gets from its different patches (0 up to rounding)
  /// Max distance between the round annulus and the surface triangles drawn on it (the chords'
  /// sagitta, sampled at edge midpoints): point location must snap points up to this far.
  double boundary_gap = 0;
  Profile profile;  ///< the cross section (empty: the square [0,1]^2)
};

/// Embeds a decomposition of one torus whose cube faces are single patches or cross sections,
/// oriented like the surface (mirrored if needed, so the volume map keeps orientation). The cross
/// section's frame is turned so that its physically shortest side around the ring (the inner one)
/// lies on the annulus's inner circle (b = 0). Throws
/// core::TopologyError for other decompositions (several tori, virtual components, faces made of
/// several patches), naming what is not supported yet.
Embedding embed_torus(const split::Decomposition& d, const std::vector<PatchMap>& maps);

/// The embedding point of local coordinates abc in component k (polar in its sector).
std::array<double, 3> cell_point(const Embedding& e, int component, const std::array<double, 3>& abc);

/// A patch map placed on the ring: component (sector) and the sector coordinates of the patch's
/// corners 0..3 (its square's (0,0), (1,0), (1,1), (0,1)).
struct PlacedPatch {
  int component = 0;
  int patch = 0;
  std::array<std::array<double, 3>, 4> corners{};
};

/// e.points: every vertex of the patch maps at the embedding point of the bilinear image of its
/// (s, t) in its patch's corners (e.ring and e.mirrored set), e.max_mismatch the largest distance
/// between the points one vertex gets from different patches; then, if the embedded layout
/// triangles enclose a negative volume, e.mirrored = true and placed again (so the volume map
/// keeps the surface's orientation). Unused vertices: NaN.
void place_patches(Embedding& e, const split::Layout& layout, const std::vector<PlacedPatch>& placed, const std::vector<PatchMap>& maps);

/// Sector coordinates of local coordinates abc of profile cell `cell` (an index into
/// e.profile.cells; with an empty profile, abc itself).
std::array<double, 3> profile_to_sector(const Profile& p, int cell, const std::array<double, 3>& abc);

/// The decomposition with every cube face tiled by several patches (sharp curves inside a face,
/// e.g. the washer's chamfers) made one patch: the union of their triangles, its corners the
/// face's, its sides the boundary chains between them. The spline then smooths over those curves
/// (C2); keeping them needs repeated knots inside the face (issue 7). Throws core::TopologyError
/// if the patches of a face are not a disk with the face's corners on its boundary.
split::Decomposition merge_face_patches(const split::Decomposition& d);

/// The surface map of a torus decomposition (faces of several patches merged, see above): patch
/// maps placed on the ring embedding.
///
/// With params.sharp_lines, sharp curves inside faces (a face tiled by strips of patches along the
/// ring, e.g. the washer's) are laid on straight lines of the face: the patches become strips between the
/// lines, each line at one height `u` across the face in every cube of the ring (the mean of its
/// arc-length positions on the cross sections), so the T-mesh can put C0 block faces on them
/// (Liu et al. §5.2, sharp features by repeated knots). `cuts[axis]` lists those heights in local
/// coordinates (axis 1 = b for faces c = 0/1, axis 2 = c for faces b = 0/1; axis 0 stays empty).
/// Faces whose patches are not strips like this, or rings whose faces have different numbers of
/// lines, keep the merged map (and no cuts).
struct TorusSurfaceMap {
  Embedding embedding;  ///< with a profile if the ring's cross section is rectilinear with concave corners (params.profile)
  int flipped_surface_triangles = 0;
  double max_angle_distortion_deg = 0;
  std::array<std::vector<double>, 3> cuts;
};
TorusSurfaceMap map_torus_surface(const split::Decomposition& d, const PatchMapParams& params);

/// A rectilinear cross section (see Profile), if `d` is one torus whose cross sections' sharp
/// corners all turn by 90° (within 35°), at least one of them concave, and the same in every
/// cross section; nullopt otherwise, with the reason in `why`. The surface map puts every patch
/// (one side of the cross section times one sector) on its side of the polygon times the sector:
/// the sides by arc length, the side lengths those of the surface (mean over the cross sections),
/// lines closer than 5 % of the extent merged.
std::optional<Embedding> embed_profile_ring(const split::Decomposition& d, const std::vector<PatchMap>& maps, std::string& why);

/// Stage-file payload: {"kind": "torus", "ring", "mirrored", "cells", "corner_vertex", "points", "cuts",
/// "profile" (if any: {"b", "c", "cells", "polygon", "concave_corners"}), figures}.
core::Json to_json(const TorusSurfaceMap& m);

/// ParaView view: the segmented surface (fill triangles included) with the embedding point moved
/// by `offset` as point field `uvw` (`xyz`: the physical one, if mapped) and the cell fields
/// `component_id` and `filled`, drawn at its physical positions, or (mapped) at the moved embedding.
viz::PolyData torus_polydata(const split::Decomposition& d, const TorusSurfaceMap& m, bool mapped, const std::array<double, 3>& offset);

/// torus_polydata without offset, written to `path`. Throws core::IoError.
void write_torus_vtp(const std::string& path, const split::Decomposition& d, const TorusSurfaceMap& m, bool mapped);

}  // namespace volts::polycube
