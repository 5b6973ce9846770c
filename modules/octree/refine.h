#pragma once
// Refinement predicates for Octree::refine(): which cells a point, a plane or a sphere surface
// meets (tested on the cell's box in [0,1]^3), and a deterministic pseudo-random split decision.
// The refine_toward_* helpers split, to the tree's max level, every leaf the target meets (no
// balance). Shared by the octree / T-spline tests and bench_tspline, and the natural way to grade
// a T-mesh toward a feature.
#include <cstdint>

#include "octree/octree.h"

namespace volts::octree {

/// True iff the closed box [unit_lo, unit_hi] of `c` contains `q`.
bool contains_point(const Cell& c, const Vec3& q);

/// True iff the plane n·x = offset meets the closed box of `c` (n·x - offset takes both signs, or
/// zero, on its corners).
bool crosses_plane(const Cell& c, const Vec3& normal, double offset);

/// True iff the sphere surface |x - centre| = radius meets the closed box of `c` (the nearest point
/// of the box is within `radius` of the centre and the farthest corner is not).
bool crosses_sphere(const Cell& c, const Vec3& centre, double radius);

/// Deterministic pseudo-random split decision for `c`: true with probability `p` (splitmix64 of
/// `seed`, the level and the corner). Fixed seeds give reproducible random refinement families.
bool random_split(const Cell& c, std::uint64_t seed, double p);

/// Octree::refine(contains_point(·, q)); returns the number of splits.
int refine_toward_point(Octree& t, const Vec3& q);
/// Octree::refine(crosses_plane(·, normal, offset)); returns the number of splits.
int refine_toward_plane(Octree& t, const Vec3& normal, double offset);
/// Octree::refine(crosses_sphere(·, centre, radius)); returns the number of splits.
int refine_toward_sphere(Octree& t, const Vec3& centre, double radius);

}  // namespace volts::octree
