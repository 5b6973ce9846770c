// volts::tet2hex — tetrahedral meshes for the tet route: TetGen's constrained quality
// tetrahedralization of a closed surface (Si, TetGen 1.5, ACM TOMS 41(2), 2015) and .vtu input of
// linear or Bézier tetrahedra.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "bezier/bezier_tet.h"
#include "surface/surface.h"

namespace volts::tet2hex {

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
/// guarantee) with TetGen, quietly (-Q). Throws core::ConfigError for parameters out of range,
/// core::NumericalError naming TetGen's reason if it fails (self-intersecting surface, features
/// too small for its tolerance, out of memory) or returns no tet or a tet with volume <= 0.
TetMesh tetrahedralize(const surface::Mesh& surface, const TetgenParams& params);

/// Triangles on the boundary of the mesh: each as {tet, local vertex opposite the face}.
std::vector<std::array<int, 2>> boundary_faces(const TetMesh& mesh);

/// Reads a .vtu (VTK XML unstructured grid) of VTK_TETRA (10) or VTK_BEZIER_TETRAHEDRON (78;
/// degree from the point count, RationalWeights honoured) cells with bezier::read_bezier_vtu;
/// other cells are refused, naming the file and the cell. Tets are returned as Bézier tets (linear ones of degree 1), reoriented to
/// positive volume. Throws core::InvalidInputError naming the file for a missing or unreadable
/// file, no cells, another cell type, or mixed degrees.
std::vector<bezier::BezierTet> read_tet_vtu(const std::string& path);

/// The linear tets of `mesh` as Bézier tets of degree 1.
std::vector<bezier::BezierTet> linear_tets(const TetMesh& mesh);

}  // namespace volts::tet2hex
