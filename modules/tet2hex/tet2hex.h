// volts::tet2hex — the tet route: any closed surface → TetGen tetrahedra → Bézier tets of degree n
// (optionally with the boundary curved onto the input surface) → four Bézier hexes per tet
// (Xu et al. 2018, Theorem 3; see tet2hex/convert.h) → optionally the tmesh stage's Jacobian
// optimizer on the hexes (Params::optimize_cycles; not in Xu et al.) → certified validity, quality
// figures, export.
// Reported with the same keys as extract (stage 5), so both routes compare line by line.
#pragma once

#include <string>
#include <vector>

#include "bezier/bezier_hex.h"
#include "bezier/bezier_tet.h"
#include "bezier/certify.h"
#include "core/stage_file.h"
#include "surface/surface.h"
#include "tet2hex/tet_mesh.h"

namespace volts::tet2hex {

/// Parameters of the tet route (config section `tet2hex`).
struct Params {
  tetmesh::TetgenParams tetgen;  ///< TetGen quality switches
  double remesh_edge_rel = 0.0;  ///< if > 0: remesh the surface isotropically first (CGAL) to this edge length / bbox diagonal [0, 0.5]; sharp edges kept
  int degree = 3;                ///< degree n of the tets and hexes [1, 4]
  bool curve_boundary = true;    ///< n >= 2: move boundary control points onto the input surface (interpolating it at the Lagrange nodes); reverted where not certified valid
  int gauss_points = 0;          ///< Gauss points per direction for the sampled scaled Jacobian; 0 = degree + 1 [0, 10]
  int boundary_samples = 8;      ///< samples per direction on each boundary hex face for hausdorff_rel [2, 64]
  bezier::CertifyParams certify; ///< certification of det J > 0 (bezier/certify.h)
  /// After the conversion, the hexes' worst scaled Jacobian is raised by the tmesh stage's
  /// optimizer (tmesh/optimize.h; not part of Xu et al.) on the hexes as one-span B-spline blocks
  /// sharing their control points: interior points move, boundary points slide along the surface
  /// where no sharp edge is near, sharp edges and corners stay; no hex loses its certificate. The
  /// domain stays, but the hexes no longer reproduce the tets. Cycles of joint rounds and per-node
  /// sweeps (tmesh::OptimizeParams::cycles) [0, 100]; 0 = off, the exact conversion.
  int optimize_cycles = 0;
  double optimize_target = 0.3;  ///< hexes below this sampled scaled Jacobian are improved (0, 1]
  /// The optimizer's uniform sample grid per hex besides its Gauss points
  /// (tmesh::OptimizeParams::grid_points; 2 = the corners alone, the tet route's sample until
  /// session 32) [2, 8]. The assembly (session 34): 0.200 in 177 s with 2, 0.200 in 409 s with 5.
  int optimize_grid_points = 2;
};

struct Result {
  std::vector<bezier::BezierTet> tets;      ///< the Bézier tets that were converted
  std::vector<bezier::BezierHex> hexes;     ///< 4 per tet, tet t's are 4t..4t+3
  std::vector<int> validity;                ///< per hex: bezier::Validity (1 valid, -1 invalid, 0 undecided)
  std::vector<double> min_scaled_jacobian;  ///< per hex, sampled at corners and Gauss points
  std::vector<double> max_scaled_jacobian;
  std::vector<double> boundary_distance;    ///< per hex: max sampled distance of its boundary faces to the surface (0 inside)
  int degree = 3;
  int certified_valid = 0, certified_invalid = 0, undecided = 0;
  int boundary_faces = 0;          ///< tet faces on the boundary
  int boundary_faces_curved = 0;   ///< of those, curved onto the surface and kept
  int boundary_faces_reverted = 0; ///< curved, then put back flat because a tet on them was not certified valid
  int surface_triangles = 0;       ///< triangles given to TetGen (after remeshing)
  double min_scaled = 0, max_scaled = 0;
  double hausdorff_rel = 0;        ///< max distance hex boundary → input surface / bbox diagonal (sampled)
  double spline_volume = 0, surface_volume = 0, volume_rel_error = 0;
  /// With Params::optimize_cycles > 0 (tmesh::OptimizeResult): the worst sampled scaled Jacobian
  /// before the optimization, the joint rounds kept, the nodes the per-node sweeps moved, the
  /// surface nodes slid and why it stopped ("disabled" when off, "rational_hexes" when the hexes
  /// are rational: the optimizer's Jacobians are polynomial, so they are left as they are).
  double min_scaled_before_optimization = 0;
  int optimization_joint_rounds = 0, optimization_nodes_moved = 0, optimization_surface_nodes_slid = 0;
  std::string optimization_stop = "disabled";
};

/// The Bézier tets of degree params.degree of `mesh`; with curve_boundary and degree >= 2, the
/// control points of boundary edges and faces interpolate `surface` at the Lagrange nodes (closest
/// points). Shared edges and faces get identical control points (conforming). Tets whose hexes
/// are not certified valid get their boundary entities flat again, until every tet is valid; the
/// counts go to `r` (boundary_faces*). Throws core::ConfigError for a degree out of range.
std::vector<bezier::BezierTet> bezier_tets(const tetmesh::TetMesh& mesh, const surface::Mesh& surface, const Params& params, Result& r);

/// Converts every tet into four hexes (Theorem 3), certifies them and measures them against
/// `surface` (hausdorff_rel, volume). `boundary` lists the boundary tet faces as {tet, opposite vertex}.
void convert_and_measure(Result& r, const surface::Mesh& surface, const std::vector<std::array<int, 2>>& boundary, const Params& params);

/// The whole route for a closed surface: remesh (optional), tetrahedralize, Bézier tets, convert,
/// certify, measure. Throws what tetrahedralize and bezier_tets throw.
Result run(const surface::Mesh& surface, const Params& params);

/// The route for given Bézier tets (a .vtu): convert, certify, measure against the boundary
/// triangles of the tets' corners (the only surface there is). Throws core::InvalidInputError for
/// no tets or tets whose corners do not form a closed boundary.
Result run(const std::vector<bezier::BezierTet>& tets, const Params& params);

/// Report keys: those of extract (bezier_elements, degree, min_scaled_jacobian, max_scaled_jacobian,
/// hausdorff_rel, volume_rel_error, spline_volume, surface_volume) + tets, certified_valid,
/// certified_invalid, undecided, boundary_faces, boundary_faces_curved, boundary_faces_reverted,
/// optimization {stop, min_scaled_jacobian_before, joint_rounds, nodes_moved, surface_nodes_slid}
/// (Params::optimize_cycles; stop "disabled" and the final figure as "before" when off).
core::Json report_figures(const Result& r);

/// bezier.vtu: VTK_BEZIER_HEXAHEDRON cells with per-cell min/max scaled Jacobian, boundary
/// distance, validity and the tet each came from.
void write_bezier_vtu(const std::string& path, const Result& r);

}  // namespace volts::tet2hex
