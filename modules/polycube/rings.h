// volts::polycube — the polycube of two tori united on a disk (Liu et al. 2013, §4.2: union of
// primitives, Fig. 6(c)). split cuts a genus-2 solid into two tori of cubes that meet on a disk
// filling their separating loop; each torus with that disk is a closed surface of its own, mapped
// exactly like a single torus (patch maps on a round ring, harmonic volume map, untangling).
//
// The two rings parameterize the disk independently: a point of the disk gets one image on each
// ring, and nothing makes them agree (the interface is not conforming). The paper glues tori
// along whole cube faces; making the disk a whole cube face is split's job (a follow-up).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/stage_file.h"
#include "polycube/embedding.h"
#include "polycube/polycube.h"
#include "split/split.h"
#include "volmap/volmap.h"

namespace volts::polycube {

/// One torus (or a connector cube) of a decomposition as a one-torus (one-cube) decomposition of
/// its own closed surface, with its own ids: vertices in increasing layout order, then triangles — its surface triangles in layout
/// order followed by its fill triangles, each oriented outward from this torus (a fill triangle
/// stored the other way round in the layout is reversed) — patches and internal faces in layout
/// order, components in ring order (component k is the k-th of the torus).
struct Ring {
  split::Decomposition decomposition;  ///< one torus (tori[0] = components 0..n-1)
  std::vector<int> layout_vertex;      ///< ring vertex -> vertex of the whole layout
  std::vector<int> layout_triangle;    ///< ring triangle -> triangle of the whole layout
  std::vector<int> component;          ///< ring component -> component of the whole decomposition
};

/// The rings of a decomposition into exactly two tori of torus cubes that meet on one filled disk
/// (every fill triangle in exactly one patch of each torus), or that a connector cube joins
/// (split.genus2: connector; each torus closed by its own disk, a whole patch of the torus and an
/// end face of the connector). Throws core::TopologyError naming the components involved for any
/// other component graph: other than two tori, components in no torus (but one connector),
/// tori meeting other than on one filled disk or through one connector, a torus surface that is
/// not closed.
std::vector<Ring> rings(const split::Decomposition& d);

/// The connector cube of such a decomposition as a one-cube decomposition of its own closed
/// surface (its sides and both disks; Ring's ids, no torus), or nullopt if the tori meet on a
/// disk. Throws what rings() throws.
std::optional<Ring> connector(const split::Decomposition& d);

/// A torus standing on a cube minus through holes (split's union, the assembly: Liu et al. 2013
/// Fig. 1) as two pieces mapped on their own: the ring (the torus closed by its foot, a whole patch
/// of one of its cubes: mapped as a connector's rings are) and the base (the cube minus holes
/// closed by the foot; a difference whose foot is a rectangle of a holed face: FootRect).
struct TorusOnCube {
  Ring ring;  ///< the torus with its foot (Ring's ids)
  /// The cube and its virtual components (components in whole-decomposition order, `component`
  /// their ids there), their patches in layout order and the foot's last (in no component), the
  /// triangles in layout order as stored (the foot's not flagged: it closes the base's solid;
  /// the holes' fills flagged), vertices in increasing layout order (the solid's first).
  Ring base;
  int foot_patch = -1;      ///< the foot's patch in base.decomposition
  int foot_component = -1;  ///< the torus cube standing on it (whole-decomposition id)
};
/// The pieces of a decomposition into one torus of torus cubes and one cube with k >= 1 virtual
/// components, the torus meeting the cube on one filled patch (the foot: a whole patch of one
/// torus cube, its triangles inside a face of the cube). Throws core::TopologyError naming the
/// components for any other component graph, a foot that is not one whole patch of the ring, or a
/// piece whose surface is not closed.
TorusOnCube torus_on_cube(const split::Decomposition& d);

/// The volume map of a one-torus decomposition whose layout triangles (fills included) are the
/// torus's closed surface: TetGen tets of at most params.tet_max_volume_rel of its volume,
/// harmonic map onto the surface map's embedding, untangled. Throws what
/// volmap::harmonic_volume_map throws.
volmap::VolumeMap torus_volume_map(const split::Decomposition& d, const TorusSurfaceMap& m, const Params& params);

/// Stage-file entry of a ring: {"components" (whole-decomposition ids, ring order),
/// "layout_vertex", "layout_triangle", "polycube" (to_json(m), ring ids), "volume_map"
/// (volmap::to_json; its surface vertices are the ring's vertices)}.
core::Json to_json(const Ring& r, const TorusSurfaceMap& m, const volmap::VolumeMap& vm);

/// Offset of ring i in the ParaView views: ring i is drawn at x + kRingSpacing·i (the annuli have
/// radius 2, so they do not overlap).
constexpr double kRingSpacing = 5.0;

/// ParaView view of several rings: each ring's surface (fills included) with `uvw` (its embedding
/// point, moved by the ring's offset), cell fields `component_id` (whole-decomposition ids),
/// `filled` and `ring`; at the physical positions, or (mapped) at the offset embedding. The disk
/// appears once per ring. Throws core::IoError.
void write_rings_vtp(const std::string& path, const std::vector<Ring>& rings, const std::vector<TorusSurfaceMap>& maps, bool mapped);

}  // namespace volts::polycube
