// volts::polycube — stage 3: the polycube and the map of the surface and the volume onto it
// (Liu et al. 2013, §4.2–4.3).
//
// Implemented so far: one cube component (from split). Each quad patch is mapped onto its face of
// the unit cube [0,1]^3 by a bijective disk map: its curves onto the cube edges by arc length (so the
// two patches beside a curve agree on it), its interior by Floater's mean-value weights with that
// convex boundary, which gives a one-to-one map (Floater 2003). The interior of the solid is mapped
// by transfinite (Coons) interpolation of the six face maps. Tori: embedding.h; two tori united on
// a disk: rings.h; differences (virtual components) are not implemented yet (issue 6).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "classify/classify.h"
#include "core/stage_file.h"
#include "split/split.h"
#include "surface/surface.h"

namespace volts::polycube {

/// Parameters of map_surface().
struct Params {
  /// Interior weights of the disk map: "mean-value" (Floater 2003) or "uniform" (Tutte 1963).
  std::string weights = "mean-value";
  /// Volume map of tori (volmap): largest tet / volume of the solid. With TetGen's default sizes
  /// untangling left flipped tets at the ring's reentrant edges (docs/status.md) [1e-6, 1].
  double tet_max_volume_rel = 1e-3;
  /// Volume maps whose min volume ratio stays below `smooth_below_ratio` after untangling get this
  /// many sweeps of per-vertex smoothing (volmap::Params::smooth_sweeps); 0 = none [0, 10000].
  int smooth_sweeps = 300;
  double smooth_below_ratio = 1e-3;  ///< min volume ratio (smallest tet volume / mean, dimensionless) [0, 1]
  /// smooth_below_ratio for the maps of a connector split (split.genus2: connector): the rings
  /// whose disk is a whole cube face start at min volume ratios 0.006–0.008, and unsmoothed the
  /// eight kept 118 elements not certified valid after 9 minutes of tmesh (docs/status.md,
  /// session 17); smoothing costs the other models time (torus 0.86 -> 1.36 s), so it is per kind [0, 1].
  double connector_smooth_below_ratio = 0.9;
  /// Tori: sharp curves inside cube faces laid on straight lines and made C0 block faces by tmesh
  /// (PatchMapParams::sharp_lines). Off by default: on the washer it lowered the valid elements
  /// (docs/status.md, session 11).
  bool sharp_lines = false;
  /// Tori whose cross section is rectilinear with concave sharp corners (the washer's plus sign):
  /// "auto" maps them onto a ring of that profile, one cube per grid cell and sector
  /// (embed_profile_ring); "square" onto the square ring.
  std::string profile = "auto";
};

/// The polycube (so far one unit cube) and the surface map onto it.
struct Polycube {
  std::vector<std::array<int, 3>> corner_cube_coords;  ///< per classify corner: its cube corner (0/1 each)
  std::vector<int> patch_face;                         ///< per patch: cube face 2*axis + side (side 1 = coordinate 1)
  std::vector<std::array<double, 3>> vertex_uvw;       ///< per surface vertex: its image on the cube surface
  int flipped_surface_triangles = 0;                   ///< mapped triangles with non-positive orientation
  double max_angle_distortion_deg = 0;                 ///< max |angle on cube - angle on surface| over triangle corners
};

/// Maps the surface of a box-like decomposition onto the unit cube. Throws core::TopologyError if
/// the patch and corner structure is not that of a cube, core::NumericalError if a solve fails.
Polycube map_surface(const surface::Mesh& mesh, const classify::Classification& c, const split::Decomposition& d,
                     const Params& params);

/// The volume map: parameter point of the cube -> physical point, by transfinite interpolation of
/// the six face maps. Face maps are inverted by closest-point queries in an AABB tree of each
/// face's mapped triangles (CGAL), so points on cube edges and faces are handled exactly.
class VolumeMap {
 public:
  VolumeMap(const surface::Mesh& mesh, const classify::Classification& c, const Polycube& p);
  ~VolumeMap();
  VolumeMap(VolumeMap&&) noexcept;
  /// Physical position of the parameter point uvw in [0,1]^3.
  std::array<double, 3> operator()(const std::array<double, 3>& uvw) const;
  /// Physical position of a point on cube face `face` (2*axis+side) at in-face coordinates (s, t)
  /// = the coordinates of axes (axis+1)%3 and (axis+2)%3.
  std::array<double, 3> on_face(int face, double s, double t) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

core::Json to_json(const Polycube& p);
Polycube from_json(const core::Json& j, const std::string& file);
core::Json report_figures(const Polycube& p, const split::Decomposition& d);

/// ParaView views: the surface with its cube coordinates as a point field `uvw` and the face id, and
/// the same triangles drawn at their cube positions (the mapped surface).
void write_vtp(const std::string& path, const surface::Mesh& mesh, const classify::Classification& c, const Polycube& p);
void write_mapped_vtp(const std::string& path, const surface::Mesh& mesh, const classify::Classification& c, const Polycube& p);

}  // namespace volts::polycube
