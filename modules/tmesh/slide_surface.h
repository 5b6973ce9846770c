// volts::tmesh — the input surface as the optimization's surface nodes see it (Liu et al. 2013
// §5.2, smoothing and optimization by node type: "surface nodes on the surface", sharp curves and
// corners kept). Closest points and the distance to the nearest sharp edge, both by CGAL AABB
// trees; a surface control point may slide where no sharp edge is within its reach.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "tmesh/tmesh.h"

namespace volts::tmesh {

class SlideSurface {
 public:
  /// A closed triangle mesh; an edge is sharp if its two faces' normals differ by more than
  /// `sharp_angle_deg` (classify's rule and default). Throws core::InvalidInputError for an empty
  /// mesh or a triangle index out of range.
  SlideSurface(const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& triangles, double sharp_angle_deg = 30.0);
  ~SlideSurface();
  SlideSurface(SlideSurface&&) noexcept;
  SlideSurface& operator=(SlideSurface&&) noexcept;

  /// The closest point of the surface to p and, if `normal` is given, the unit normal of its triangle.
  Vec3 closest(const Vec3& p, Vec3* normal = nullptr) const;
  /// The closest point of the surface to p, the search bounded from the start by the distance to
  /// `hint` (a point of the surface near the answer, e.g. a neighbouring sample's): the same
  /// point, found faster.
  Vec3 closest(const Vec3& p, const Vec3& hint) const;
  /// Distance from p to the nearest sharp edge; +infinity if the surface has none.
  double sharp_distance(const Vec3& p) const;
  /// The closest point of the sharp edges to p and, if `tangent` is given, the unit direction of
  /// its edge. Only for a surface with sharp edges (sharp_edges() > 0).
  Vec3 closest_sharp(const Vec3& p, Vec3* tangent = nullptr) const;
  /// Distance from p to the nearest sharp corner: a vertex where other than two sharp edges meet,
  /// or two that turn by more than the sharp angle (a curve's end, or a corner of the solid);
  /// +infinity if there is none (a closed smooth sharp loop, or no sharp edge).
  double sharp_corner_distance(const Vec3& p) const;
  int sharp_corners() const;
  int sharp_edges() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace volts::tmesh
