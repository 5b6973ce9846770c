// volts::split — the cases of split(), one per file (box in split.cpp, torus.cpp, difference.cpp).
#pragma once

#include <array>
#include <set>
#include <utility>
#include <vector>

#include "split/harmonic.h"
#include "split/layout.h"
#include "split/split.h"

namespace volts::split::detail {

/// Every sharp edge of a classification.
std::set<Edge> sharp_edges(const classify::Classification& c);

/// The vertex nearest to a point (smallest index on ties).
int nearest_vertex(const surface::Mesh& mesh, const std::array<double, 3>& p);

/// The first harmonic field of §4.1 (steps 1–2): 0 and 1 at the extreme points (params or the
/// principal axis), and its critical points. Throws core::TopologyError if both are one vertex.
std::vector<double> height_field(const surface::Mesh& mesh, const Params& params, CriticalPoints* cp);

/// (width, middle) of the gaps between consecutive saddle values, widest first.
std::vector<std::pair<double, double>> saddle_gaps(const std::vector<double>& f, const CriticalPoints& cp);

/// Genus of the faces labelled `which` (a region with one boundary loop: V - E + F = 1 - 2g).
int region_genus(const surface::Mesh& mesh, const std::vector<int>& label, int which);

/// Whether a vertex loop cuts the surface in two.
bool loop_separates(const surface::Mesh& mesh, const std::vector<int>& loop);

/// A level near c halfway between two vertex values of f (no vertex on the level set).
double level_between_vertices(double c, const std::vector<double>& f);

/// The disk where two tori meet, to be made one whole patch of each torus (Liu et al. §4.2, Fig.
/// 6(c): primitives united on whole faces): its rim is cut into two arcs on cross sections and two
/// on longitudinal lines, so the tori can share its control points.
struct DiskPatch {
  std::vector<int> rim;     ///< the loop where the disk meets the surface, in order (torus mesh ids)
  std::vector<int> inside;  ///< the disk's vertices off the rim
  /// Rim vertices where its arcs meet, in rim order; if -1, split_torus chooses them (the rim
  /// points furthest along the diagonals of the torus's ring and tube fields) and returns them.
  std::array<int, 4> corners{-1, -1, -1, -1};
};

/// A genus-1 surface without sharp corners as a ring of params.torus_cubes cube components.
/// `sharp` are the sharp edges of `mesh` to keep as cuts (closed curves around the ring). No cut
/// crosses a face all of whose vertices are in `protect` (the disk where two tori meet): the
/// cross sections and longitudinal lines are spread over the rest of the ring and the tube.
/// `first_cross_section`, if given, is a loop around the tube used instead of §4.1 steps 1–3.
/// With `disk`, the disk is one whole patch instead (its rim's arcs lie on two cross sections and
/// two longitudinal lines: the ring and tube fields are harmonic with those arcs as level sets),
/// `protect` is not used, and the corners chosen are written back; `sharp` is then used only if
/// it gives all four corner lines: each longitudinal rim arc closed around the ring by sharp
/// edges, and exactly two more closed sharp loops around the ring (a box-like eye: its outer
/// edges and its hole's rims); otherwise the tube field's levels are the lines, as without it.
Decomposition split_torus(const surface::Mesh& mesh, const std::set<Edge>& sharp, const Params& params,
                          const std::vector<int>& protect = {}, const std::vector<int>& first_cross_section = {},
                          DiskPatch* disk = nullptr);

/// A genus-2 surface as two tori that meet on a disk filling their separating loop.
Decomposition split_two_tori(const surface::Mesh& mesh, const Params& params, const classify::Classification* c = nullptr);

/// The difference curves of `c` chained into rim loops; `edges`, if given, receives their edges.
/// Throws core::TopologyError if they do not form loops.
std::vector<std::vector<int>> difference_rims(const classify::Classification& c, std::set<Edge>* edges = nullptr);

/// A surface of genus k >= 1 with sharp corners whose k through holes are each bounded by two
/// difference curves: a cube minus k virtual components (components 1..k, in the order of their
/// first rim), each with its two fills as contacts with the cube.
Decomposition split_difference(const surface::Mesh& mesh, const classify::Classification& c, const Params& params);

/// A torus standing on a cube minus k >= 0 through holes (genus k + 1; Liu et al. Fig. 1, the
/// assembly): the torus meets the cube along its foot, the one difference loop that alone cuts the
/// surface in two, filled in its plane. Components: the cube, its k virtual components (as
/// split_difference; the fill inside the cube's face), then the torus's cubes, the fill one whole
/// patch of one of them; contact (cube 0, that torus cube, "filled_patch", the fill's patch).
/// Throws core::TopologyError when the surface is not one (no or several separating rims, sharp
/// corners on both sides, a part on the foot of another genus).
Decomposition split_torus_on_cube(const surface::Mesh& mesh, const classify::Classification& c, const Params& params);

/// A genus-0 surface whose classify patches meet like the faces of a cube: one cube whose patches
/// are the classify patches, in their order.
Decomposition split_box(const surface::Mesh& mesh, const classify::Classification& c, ComponentType type);

}  // namespace volts::split::detail
