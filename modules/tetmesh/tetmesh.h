// volts::tetmesh — TetGen's constrained quality tetrahedralization of a closed surface (Si, TetGen
// 1.5, ACM TOMS 41(2), 2015), shared by the tet route (tet2hex) and the volume map (volmap).
#pragma once

#include <array>
#include <vector>

#include <Eigen/Dense>

#include "surface/surface.h"

namespace volts::tetmesh {

/// Quality switches of TetGen (`-pq<ratio>/<angle>a<volume>Y`). Defaults: TetGen's own quality bound.
struct TetgenParams {
  double max_radius_edge_ratio = 2.0;  ///< -q: max circumradius / shortest edge of a tet [1.1, 10]; 0 = no quality refinement
  double min_dihedral_deg = 0.0;       ///< -q: min dihedral angle TetGen aims for [degrees, 0..30]; 0 = TetGen's default
  double max_volume_rel = 0.0;         ///< -a: max tet volume / volume enclosed by the surface [0, 1]; 0 = no limit
  bool keep_boundary = true;           ///< -Y: no Steiner points on the surface (boundary faces = input triangles)
};

/// Linear tetrahedra; every tet positively oriented (det(p1-p0, p2-p0, p3-p0) > 0).
struct TetMesh {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 4>> tets;
};

/// Tetrahedralizes the solid bounded by `surface` (closed, outward oriented: read_surface's
/// guarantee) with TetGen, quietly (-Q). The first surface.number_of_vertices() points are the
/// surface vertices in the order of surface.vertices() (= vertex index when the mesh has no
/// garbage), bit for bit; TetGen's Steiner points follow. Throws core::ConfigError for parameters
/// out of range, core::NumericalError naming TetGen's reason if it fails (self-intersecting
/// surface, features too small for its tolerance, out of memory), returns no tet or a tet with
/// volume <= 0, or does not keep the surface vertices first.
TetMesh tetrahedralize(const surface::Mesh& surface, const TetgenParams& params);

/// Triangles on the boundary of the mesh: each as {tet, local vertex opposite the face}.
std::vector<std::array<int, 2>> boundary_faces(const TetMesh& mesh);

/// Local vertices of the face opposite local vertex x, ordered so that its normal points out of a
/// positively oriented tet.
inline constexpr int kOutwardFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

/// 6 × the signed volume of the tet (a, b, c, d).
inline double signed_volume6(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                             const Eigen::Vector3d& d) {
  return (b - a).cross(c - a).dot(d - a);
}

}  // namespace volts::tetmesh
