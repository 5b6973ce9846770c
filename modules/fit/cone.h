// volts::fit — the minimum circular cone enclosing a set of directions (Lin, Huang & Hu, §"Validity
// conditions", used by Propositions 1 and 2), i.e. the smallest spherical cap holding the unit
// vectors.
//
// Method: Welzl's move-to-front algorithm on the sphere (Welzl 1991), with caps through one point,
// two points (axis along a+b) and three points (axis normal to their plane), over a fixed
// pseudo-random order. When the directions lie in an open hemisphere this is an LP-type problem
// (the cap's axis is the direction of the point of the convex hull of the vectors nearest to the
// origin, and cos(half angle) is that distance), and the result is the minimum cone up to rounding:
// a direction counts as inside a candidate cap if axis·v >= cos − 1e-14. When they do not (the
// hull holds the origin: aperture >= π), the algorithm meets a cap of half angle >= π/2 and stops;
// no axis is returned then. The verdict does not rest on Welzl's optimality: min_cos is recomputed
// over all vectors with the returned axis, and min_cos > 0 proves the open hemisphere.
//
// Throws core::InvalidInputError for an empty set, a zero or non-finite vector.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

namespace volts::fit {

struct Cone {
  bool in_open_hemisphere = false;  ///< aperture < π
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();  ///< unit axis; zero if !in_open_hemisphere
  double min_cos = 0;      ///< min_i axis·v_i over the normalised vectors (0 if !in_open_hemisphere)
  double half_angle = 0;   ///< acos(min_cos), radians; π/2 if !in_open_hemisphere
  std::array<int, 3> support{-1, -1, -1};  ///< indices of the vectors defining the cap (-1 unused)
  double aperture() const { return 2 * half_angle; }
};

/// The minimum enclosing cone of the directions of `vectors` (each normalised first).
Cone enclosing_cone(const std::vector<Eigen::Vector3d>& vectors);

}  // namespace volts::fit
