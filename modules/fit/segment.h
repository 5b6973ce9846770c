// volts::fit — automatic segmentation of a genus-0 surface into six patches meeting like the faces
// of a cube: the input of Lin, Huang & Hu's pillowed TBS construction ("a tet mesh with six
// surfaces segmented on its boundary mesh"), which the paper takes as given (issue 9 asks for it).
//
// Method: each triangle takes the axis direction (±x, ±y, ±z) nearest its normal; a few sweeps of
// iterated conditional modes trade normal deviation (1 − n·d) against boundary length (`smoothness`
// per differing neighbour); then every label keeps only its largest connected component, the
// others (smallest first) join the neighbouring patch whose direction best fits their area-weighted
// mean normal, never the opposite one unless it is the only neighbour. (Joining the neighbour with
// the longest shared boundary instead put the fandisk's slanted bottom face into +y, which then
// touched −y.) No rotation is applied: the model's axes are the cube's axes.
//
// Throws core::TopologyError if the surface is not genus 0, or if the result is not six disks
// meeting like cube faces (the message: the first problem and CubeLayout::summary()).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "surface/surface.h"

namespace volts::fit {

/// How far `label` (per face, 0..5) is from six disks meeting like cube faces.
struct CubeLayout {
  std::array<int, 6> components{};  ///< connected components per label (1 each)
  std::array<int, 6> loops{};       ///< boundary loops per label (1 each)
  std::array<int, 6> sides{};       ///< runs of one neighbour label along the boundary (4 each)
  std::array<long, 6> euler{};      ///< V − E + F per label (1 each: a disk)
  int corners = 0;            ///< vertices where three patches meet (8)
  int opposite_vertices = 0;  ///< vertices where opposite patches meet (0)
  int crowded_vertices = 0;   ///< vertices with more than three patches or a patch twice around (0)
  /// Vertex of each cube corner, −1 if none or not unique: corner c is on the + side of axis a iff
  /// bit a of c is set.
  std::array<int, 8> corner_vertex{-1, -1, -1, -1, -1, -1, -1, -1};
  std::string problem;  ///< the first problem found; empty iff cube-like
  bool ok() const { return problem.empty(); }
  std::string summary() const;  ///< the counts above in one line
};

/// Each label one connected patch with one boundary loop of four sides along the four
/// non-opposite labels and V − E + F = 1; eight corners where three mutually non-opposite patches
/// meet, one per cube corner; no vertex where opposite or more than three patches meet.
/// Throws core::InvalidInputError if label has the wrong size or a value outside 0..5.
CubeLayout cube_layout(const surface::Mesh& mesh, const std::vector<int>& label);

/// Patch labels: 0 +x, 1 −x, 2 +y, 3 −y, 4 +z, 5 −z (axis = label / 2, sign + when even).
struct SixPatches {
  std::vector<int> label;      ///< per face (Mesh face index)
  /// Vertex index of each cube corner: corner c lies on the + side of axis a iff bit a of c is set
  /// (c = 0 is where −x, −y, −z meet; c = 7 where +x, +y, +z meet).
  std::array<int, 8> corners{};
  CubeLayout layout;           ///< how cube-like the labels are (ok() unless require_cube_layout is off)
  int relabeled = 0;           ///< faces whose patch is not the direction nearest their normal
  double max_deviation_deg = 0;  ///< largest angle between a face normal and its patch's direction
};

struct SixPatchParams {
  double smoothness = 0.4;  ///< cost of one neighbour with another label, against 1 − n·d (unitless)
  int sweeps = 10;          ///< iterated-conditional-modes sweeps (stops early when nothing changes)
  /// Throw TopologyError unless the result is cube-like; off: return it with its layout (diagnosis).
  bool require_cube_layout = true;
};

SixPatches six_patches(const surface::Mesh& mesh, const SixPatchParams& params = {});

}  // namespace volts::fit
