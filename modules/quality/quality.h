// volts::quality — quality figures of Bézier elements shared by every route (Liu et al. 2013 §6
// measures): sampled scaled Jacobian, certification counts, boundary deviation from the input
// surface and volume. extract (stage 5) and tet2hex (the tet route) report them with the same keys.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "bezier/bezier_hex.h"
#include "surface/surface.h"

namespace volts::quality {

struct ScaledJacobian {
  std::vector<double> min_per_element;  ///< per element, sampled
  std::vector<double> max_per_element;  ///< per element, sampled
  double min = 1, max = -1;             ///< over all elements (1 and -1 if there are none)
};

/// Scaled Jacobian of every hex sampled at its corners and gauss_points^3 Gauss points
/// (bezier::sample_jacobian). A sample, not a certificate.
ScaledJacobian scaled_jacobian(const std::vector<bezier::BezierHex>& hexes, int gauss_points);

/// Scaled Jacobian of every hex on the uniform grid of `points` per direction, faces, edges and
/// corners included (bezier::jacobian_grid): a denser sample than scaled_jacobian()'s, which sees
/// the field between its Gauss points and corners (still a sample, not a bound). Throws
/// core::InvalidInputError for points < 2.
ScaledJacobian scaled_jacobian_on_grid(const std::vector<bezier::BezierHex>& hexes, int points);

/// Fraction of the elements' volume where the scaled Jacobian exceeds `threshold`: Gauss–Legendre
/// quadrature of det J with gauss_points^3 points per element, each point counting when its scaled
/// Jacobian is above the threshold (Lin et al. 2018 quote "> 0.5 in over 80% region"). Sampled:
/// the boundary of the region is resolved to the Gauss spacing. Points with det J <= 0 count as
/// volume 0. Returns 0 for no volume.
double volume_fraction_scaled_jacobian_above(const std::vector<bezier::BezierHex>& hexes, int gauss_points, double threshold);

struct ValidityCounts {
  int valid = 0, invalid = 0, undecided = 0;
};

/// Counts of certification results given per element as bezier::Validity values (1, -1, 0).
ValidityCounts count_validity(const std::vector<int>& status);

/// Face of element `element` on the boundary: the face where parameter `axis` (0..2) is `side` (0 or 1).
struct BoundaryFace {
  int element = 0;
  int axis = 0;
  int side = 0;
};

struct BoundaryDeviation {
  std::vector<double> per_element;  ///< max sampled distance of the element's boundary faces to the surface (0 inside)
  double max = 0;                   ///< over all boundary faces
  double diagonal = 0;              ///< bounding-box diagonal of the surface
  double rel = 0;                   ///< max / diagonal (sampled Hausdorff distance boundary -> surface)
};

/// Samples each boundary face on a samples x samples grid of its parameter square and measures
/// the distance of the samples to `surface` (CGAL AABB tree). Throws core::InvalidInputError for
/// samples < 2 or a face naming no element, axis or side.
BoundaryDeviation boundary_deviation(const std::vector<bezier::BezierHex>& hexes, const std::vector<BoundaryFace>& faces,
                                     const surface::Mesh& surface, int samples);

/// Where an element's sampled scaled Jacobian is lowest, and what limits it there.
struct WorstSample {
  int element = 0;
  double scaled_jacobian = 0;          ///< the element's sampled minimum (its worst sample: within 1e-12)
  bool at_corner = false;              ///< at one of the 8 corners (else at a Gauss point, or a grid point)
  bool on_grid = false;                ///< a point of the uniform grid (worst_grid_samples)
  Eigen::Vector3d uvw{0, 0, 0};        ///< the sample in the element's parameters
  Eigen::Vector3d position{0, 0, 0};   ///< and in physical space
  int boundary_faces = 0;              ///< boundary faces of the element through the sample (0 inside)
  /// At a corner on exactly one boundary face: the sine of the angle between the two tangent
  /// derivatives there. The third column can at best be perpendicular to them, so the scaled
  /// Jacobian there cannot exceed this whatever the interior control points: the surface's
  /// parameterization is the limit when the two are close. 1 elsewhere (no such bound).
  double surface_bound = 1;
};

/// The `count` elements with the lowest sampled scaled Jacobian (`sj`: scaled_jacobian of
/// `hexes` with the same gauss_points), worst first (ties by element), with their worst samples;
/// `faces` are the boundary faces as for boundary_deviation. For reports: which elements to look
/// at in ParaView and whether the surface or the interior limits them. Throws
/// core::InvalidInputError for gauss_points < 1 or `sj` not of these hexes.
std::vector<WorstSample> worst_samples(const std::vector<bezier::BezierHex>& hexes, const ScaledJacobian& sj, const std::vector<BoundaryFace>& faces,
                                       int gauss_points, int count);

/// As worst_samples, on scaled_jacobian_on_grid's uniform grid of `points` per direction (`sj`
/// from it): the first grid point (i fastest) within roundoff of each element's minimum, on_grid
/// set, at_corner when it is one of the 8 corners. Throws InvalidInputError as worst_samples, or
/// if points < 2.
std::vector<WorstSample> worst_grid_samples(const std::vector<bezier::BezierHex>& hexes, const ScaledJacobian& sj,
                                            const std::vector<BoundaryFace>& faces, int points, int count);

struct Volume {
  double elements = 0;   ///< ∫ det J over all elements
  double surface = 0;    ///< volume enclosed by the surface
  double rel_error = 0;  ///< |elements - surface| / |surface|
};

/// Volume of the elements (bezier::volume with gauss_points per direction) against the volume
/// enclosed by the closed `surface`.
Volume volume(const std::vector<bezier::BezierHex>& hexes, const surface::Mesh& surface, int gauss_points);

}  // namespace volts::quality
