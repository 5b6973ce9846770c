// volts::fit — the solid onto the unit cube, its six boundary patches onto the six faces: the step
// of Lin, Huang & Hu 2018 ("Partition of the tet mesh model by pillow operation", Fig. 1(a)–(b))
// that parameterizes the tet mesh into Ω = [0,1]^3. Done with the polycube stage's kernels: the
// six patches as a box-like classification, split's box case, polycube::map_surface (arc-length
// sides, mean-value disk maps), then TetGen and volmap's harmonic volume map with untangling.
//
// The six patches come from classify when the surface has them (six quad patches, twelve curves,
// eight corners: a box-like part) and otherwise from six_patches() (segment.h).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "classify/classify.h"
#include "fit/segment.h"
#include "polycube/polycube.h"
#include "surface/surface.h"
#include "volmap/volmap.h"

namespace volts::fit {

/// True if `c` is six quad patches bounded by twelve open curves meeting at eight corners on a
/// genus-0 surface (what split's box case accepts).
bool box_like(const classify::Classification& c);

/// The six patches of `s` (segment.h; s.layout.ok()) as a classification: patch = label, the
/// twelve boundaries between labels as curves from corner to corner, their edges as sharp edges.
/// Throws core::TopologyError if the labels are not cube-like (the layout's problem).
classify::Classification classification_of(const surface::Mesh& mesh, const SixPatches& s);

struct CubeMapParams {
  SixPatchParams segmentation;          ///< used when classify's patches are not box-like
  /// Disk-map weights of the patches (polycube::Params::weights); if they flip triangles the
  /// patches are mapped again with "uniform" (Tutte: positive weights, so one-to-one).
  std::string weights = "mean-value";
  double tet_max_volume_rel = 1e-3;     ///< largest tet / the solid's volume [1e-6, 1]
  /// Sweeps of smoothing of a nearly degenerate volume map (volmap::Params::smooth_sweeps) [0, 10000].
  /// Off by default on this route: its figures (docs/status.md) were measured without it.
  int smooth_sweeps = 0;
};

struct CubeMap {
  /// The input surface with the chords of every patch (interior edges joining two of its boundary
  /// vertices) split at their midpoints and triangles with three boundary vertices at their
  /// centroids, so that no triangle is flat on the cube; the input's vertex ids are kept.
  surface::Mesh mesh;
  int splits = 0;                       ///< edges and triangles split so
  std::string patch_source;             ///< "classify" or "segmentation"
  classify::Classification patches;     ///< the six patches (box-like), faces of `mesh`
  SixPatches segmentation;              ///< if patch_source == "segmentation"
  polycube::Polycube surface;           ///< per surface vertex its point on the cube's surface
  std::string weights;                  ///< disk-map weights used (uniform if the requested ones flipped triangles)
  volmap::VolumeMap volume;             ///< tets of the solid bounded by `mesh`, physical and in [0,1]^3
  bool mirrored = false;                ///< the patch maps were left-handed; u and v were swapped
};

/// Maps the closed genus-0 surface `mesh` (classified as `c`) and its solid onto [0,1]^3.
/// Throws core::TopologyError if neither classify nor the segmentation gives six cube-like
/// patches (the message says which and why), core::NumericalError if the volume map keeps
/// flipped tets (the surface map's distortion is in the message), what tetmesh throws.
CubeMap map_to_cube(const surface::Mesh& mesh, const classify::Classification& c, const CubeMapParams& params);

}  // namespace volts::fit
