// volts::split — the cases of split(), one per file (box in split.cpp, torus.cpp, difference.cpp).
#pragma once

#include <array>
#include <set>
#include <vector>

#include "split/layout.h"
#include "split/split.h"

namespace volts::split::detail {

/// Every sharp edge of a classification.
std::set<Edge> sharp_edges(const classify::Classification& c);

/// The vertex nearest to a point (smallest index on ties).
int nearest_vertex(const surface::Mesh& mesh, const std::array<double, 3>& p);

/// A genus-1 surface without sharp corners as a ring of params.torus_cubes cube components.
/// `sharp` are the sharp edges of `mesh` to keep as cuts (closed curves around the ring).
Decomposition split_torus(const surface::Mesh& mesh, const std::set<Edge>& sharp, const Params& params);

/// A genus-1 surface with sharp corners whose through hole is bounded by difference curves: a
/// cube minus a virtual component.
Decomposition split_difference(const surface::Mesh& mesh, const classify::Classification& c, const Params& params);

/// A genus-0 surface whose classify patches meet like the faces of a cube: one cube whose patches
/// are the classify patches, in their order.
Decomposition split_box(const surface::Mesh& mesh, const classify::Classification& c, ComponentType type);

}  // namespace volts::split::detail
