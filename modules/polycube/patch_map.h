// volts::polycube — the surface map of every quad patch onto the unit square (Liu et al. 2013,
// §4.2–4.3: "the CAD surface is then mapped to the polycube surface").
//
// Corner k of a patch goes to (0,0), (1,0), (1,1), (0,1); each side onto its square edge by arc
// length, so the two patches along a side (or a patch and a cross section) parameterize it alike;
// the interior by Floater's mean-value weights (Floater 2003), which with a convex boundary gives a
// one-to-one map. Each patch's square is later placed on its polycube face.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "split/split.h"

namespace volts::polycube {

/// The map of one patch: (s, t) in [0,1]^2 for each of its vertices.
struct PatchMap {
  std::vector<int> vertices;                  ///< layout vertex ids of the patch, increasing
  std::vector<std::array<double, 2>> st;      ///< their images, same order
  int flipped_triangles = 0;                  ///< mapped triangles against the patch's orientation (CGAL exact orientation)
  double max_angle_distortion_deg = 0;        ///< max |angle in the square − angle on the surface| over triangle corners
};

/// Parameters of map_patches().
struct PatchMapParams {
  std::string weights = "mean-value";  ///< "mean-value" (Floater 2003) or "uniform" (Tutte 1963)
  /// Tori: sharp curves inside cube faces on straight lines, for C0 block faces there
  /// (TorusSurfaceMap::cuts); off: such faces are mapped as one patch (the spline is C2 across).
  bool sharp_lines = false;
  /// Tori whose cross section is rectilinear with concave sharp corners (the washer): "auto" maps
  /// them onto a ring of that profile (embed_profile_ring), "square" onto the square ring.
  std::string profile = "auto";
};

/// 2D positions of the vertices of `triangles` (layout ids): those in `fixed` where they are given,
/// every other one the weighted average of its neighbours (params.weights) — one sparse solve for
/// both coordinates. Returns every vertex of the triangles. Throws core::ConfigError for unknown
/// weights, core::NumericalError naming `what` if the system is singular (a free vertex not
/// connected to a fixed one).
std::map<int, std::array<double, 2>> harmonic_positions(const split::Layout& layout, const std::vector<int>& triangles,
                                                        const std::map<int, std::array<double, 2>>& fixed,
                                                        const PatchMapParams& params, const std::string& what);

/// Quality of a planar map of some triangles.
struct MapQuality {
  int flipped_triangles = 0;             ///< images turning against the majority, or degenerate (CGAL exact orientation)
  double max_angle_distortion_deg = 0;   ///< max |angle in the plane − angle on the surface| over triangle corners
};
/// The triangles (layout ids, oriented consistently first) at the 2D positions `at`.
MapQuality map_quality(const split::Layout& layout, const std::vector<int>& triangles, const std::map<int, std::array<double, 2>>& at);

/// Moves the free vertices (not in `fixed`) of the flipped triangles of a map (map_quality's) to
/// the mean of their neighbours' positions, sweep after sweep while that leaves fewer flipped
/// triangles (at most `sweeps`); returns the number left. A harmonic map of a face with holes is
/// not one-to-one where a rim the surface has smooth turns a corner in the plane (the assembly's
/// foot: 3 triangles outside its rectangle's corners).
int unfold_free_vertices(const split::Layout& layout, const std::vector<int>& triangles, const std::map<int, std::array<double, 2>>& fixed,
                         std::map<int, std::array<double, 2>>& at, int sweeps);

/// The map of a patch's `triangles` with the vertices of `fixed` there and the rest by
/// harmonic_positions, with its quality (map_quality); throws what harmonic_positions throws.
PatchMap solve_patch_map(const split::Layout& layout, const std::vector<int>& triangles, const std::map<int, std::array<double, 2>>& fixed,
                         const PatchMapParams& params, const std::string& what);

/// Maps every patch of a decomposition. Throws core::ConfigError for unknown weights,
/// core::NumericalError if a patch's linear system cannot be solved.
std::vector<PatchMap> map_patches(const split::Decomposition& d, const PatchMapParams& params);

/// Per triangle (layout ids), 1 if it must be reversed to turn like its neighbours across shared
/// edges, walking outwards from each connected piece's first triangle in the list (which keeps its
/// orientation). Fill triangles are stored once but bound two solids, the other way round in one.
std::vector<char> consistent_orientation(const split::Layout& layout, const std::vector<int>& triangles);

/// Which layout triangles layout_volume() counts.
enum class Fills { include, skip };

/// Volume enclosed by the layout's triangles (fill triangles too, or not) with vertex v at at[v]:
/// negative if they turn inward there (a map that mirrors the surface).
double layout_volume(const split::Layout& layout, const std::vector<std::array<double, 3>>& at, Fills fills);

/// Length of a vertex chain (the sum of its edges).
double chain_length(const split::Layout& layout, const std::vector<int>& chain);

/// Arc-length fraction of each vertex along a vertex chain (0 at the first, 1 at the last).
std::vector<double> arc_length_fractions(const split::Layout& layout, const std::vector<int>& chain);

}  // namespace volts::polycube
