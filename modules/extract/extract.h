// volts::extract — stage 5: the spline from the T-mesh, its Bézier elements by extraction, quality
// figures and export (Liu et al. 2013, §5.3 and §6).
//
// Implemented so far: the tensor-product B-spline blocks of a uniform T-mesh, Bézier extraction by
// knot insertion (bezier::extraction_operators), the global basis shared across blocks with every
// element's sparse extraction operator C (Borden, Scott, Evans & Hughes 2011, §5: Bézier points =
// Cᵀ·P), checked for partition of unity and reproduction; scaled Jacobian sampled at corners and
// Gauss points, boundary deviation from the input surface and volume error, and bezier.vtu for
// ParaView. Solver exports (.bext, .json, .msh, histogram): extract/export.h. T-spline templates
// at irregular nodes are issue 8 item 1.
#pragma once

#include <Eigen/Geometry>
#include <Eigen/Sparse>
#include <string>
#include <vector>

#include "bezier/bezier_hex.h"
#include "bezier/certify.h"
#include "core/stage_file.h"
#include "surface/surface.h"
#include "quality/quality.h"
#include "tmesh/tmesh.h"

namespace volts::extract {

/// Files volts-extract can write (extract.exports): bezier.vtu, bezier.bext with its keyword deck
/// bezier.k, bezier.json, bezier.msh, scaled_jacobian_histogram.png (extract/export.h).
inline const std::vector<std::string>& export_names() {
  static const std::vector<std::string> names = {"vtu", "bext", "json", "msh", "png"};
  return names;
}

/// Parameters of extract().
struct Params {
  int gauss_points = 0;       ///< Gauss points per direction for the Jacobian sample; 0 = degree + 1
  int boundary_samples = 8;   ///< samples per direction on each boundary element face (Hausdorff) [2, 64]
  /// Points per direction of the uniform grid (faces, edges, corners included) of the second,
  /// denser scaled-Jacobian sample (quality::scaled_jacobian_on_grid); 0 = none [0 or 2, 16]
  int dense_points = 7;
  bezier::CertifyParams certify;  ///< certification of det J > 0 per element (max_depth: subdivision levels)
  std::vector<std::string> exports = export_names();  ///< files volts-extract writes (names of export_names())
  /// How bezier.json stores the extraction operators: "triplets" (version 1: every nonzero as
  /// [row, column, value]) or "kronecker" (version 2: an element whose operator is a Kronecker
  /// product of three 1-D operators — no T-junction or smooth row among its functions — as those
  /// three (p+1)x(p+1) matrices, the others as triplets; write_bezier_json).
  std::string json_operators = "triplets";
};

/// One Bézier element in the global basis.
struct ExtractionElement {
  std::vector<int> functions;  ///< global function ids of the element, ascending
  /// Extraction operator C: row r = global function functions[r], column b = Bernstein function b
  /// in BezierHex::index order; N_functions[r] = sum_b C(r,b) B_b, so the Bézier points are Cᵀ·P.
  Eigen::SparseMatrix<double, Eigen::RowMajor> op;
};

/// The spline in its global basis: what IGA solvers assemble on.
struct GlobalBasis {
  std::vector<Eigen::Vector3d> points;      ///< control point of each global function
  std::vector<double> weights;              ///< weight of each global function (1 today: rational with unit weights)
  std::vector<ExtractionElement> elements;  ///< same order as the Bézier hexes; empty unless kept (global_basis)
  double partition_of_unity_error = 0;      ///< max over columns of C of |column sum - 1|
  /// The smallest entry of the extraction operators: >= 0 where the global functions are
  /// B-splines (c0, T-junctions); below 0 with tmesh.continuity c2's smooth rows, whose functions
  /// are not (docs/formats.md). Solvers lumping the mass matrix by row sums want >= 0.
  double min_coefficient = 0;
};

/// Elements laid out as a tensor grid (a block's, as extract() orders them): `first` in the hexes
/// list, then n[0] × n[1] × n[2] elements, u fastest.
struct ElementGrid {
  int first = 0;
  std::array<int, 3> n{};
};

struct Result {
  std::vector<bezier::BezierHex> hexes;
  GlobalBasis basis;
  std::vector<double> min_scaled_jacobian;  ///< per element, sampled
  std::vector<double> max_scaled_jacobian;  ///< per element, sampled
  std::vector<double> min_scaled_jacobian_dense;  ///< per element, on the uniform grid (Params::dense_points; empty if 0)
  std::vector<double> boundary_distance;    ///< per element: max sampled distance of its boundary faces to the surface (0 inside)
  std::vector<int> status;                  ///< per element: bezier::Validity (1 valid, -1 invalid, 0 undecided)
  std::vector<double> certified_min_detj;   ///< per element: certified lower bound of min det J (bezier::certify)
  int certified_valid = 0, certified_invalid = 0, undecided = 0;
  double certified_min_detj_rel = 0;  ///< min over elements of (lower bound of min det J) / (element's mean det J)
  int degree = 3;
  double min_scaled = 0, max_scaled = 0;
  double min_scaled_dense = 0;  ///< min of min_scaled_jacobian_dense (0 without it)
  /// Fraction of the volume (det J-weighted Gauss points) whose scaled Jacobian is > 0.5
  double volume_frac_scaled_jacobian_above_0_5 = 0;
  double hausdorff_rel = 0;     ///< max distance spline boundary -> input surface / bbox diagonal (sampled)
  double spline_volume = 0;     ///< ∫ det J over all elements
  double surface_volume = 0;    ///< volume enclosed by the input surface
  double volume_rel_error = 0;  ///< |spline_volume - surface_volume| / surface_volume
  /// The 10 worst elements, where their worst samples lie (quality::worst_samples) and the
  /// T-mesh block (index in the input, its cube and kind) each belongs to.
  struct Worst {
    quality::WorstSample sample;
    int block = 0, component = 0;
    std::string block_kind;
  };
  std::vector<Worst> worst;
  /// The same on the uniform grid of Params::dense_points (quality::worst_grid_samples; empty
  /// without it): where the field between the samples above is lowest.
  std::vector<Worst> worst_dense;
  /// Each block's elements in `hexes` (shared_points' grids).
  std::vector<ElementGrid> grids;
};

/// Distance under which two points of a model in `box` count as equal: rel × its diagonal, plus
/// 64 ulps of its largest coordinate (a part far from the origin cannot be resolved finer).
double point_tolerance(const Eigen::AlignedBox3d& box, double rel);

/// The global basis of the blocks `t` and the extraction operator of each of their elements, in
/// the order of `hexes` (block after block, u fastest, then v, then w; = extract_bezier_hexes per
/// block). Function ids are TMesh::function_ids, or numbered block after block where empty.
/// 1-D operators equal within 1e-14 are made identical (uniform knots: bit-identical rows, so
/// exporters can share coefficient vectors). Checks every element: each column of C sums to 1
/// within 1e-12, and Cᵀ·P equals the hex's Bézier points within point_tolerance(bbox, 1e-12).
/// Throws core::InvalidInputError for ids that do not match the control points (wrong count, an
/// unused id, one id with two different points), core::NumericalError naming the element if a
/// check fails. With keep_operators false every element is still built and checked, but
/// `elements` is left empty: the operators (~12 KB per cubic element, 37 MB on the torus) are only
/// read by the bext and json exports, and allocating them was a third of extract's time.
GlobalBasis global_basis(const std::vector<tmesh::TMesh>& t, const std::vector<bezier::BezierHex>& hexes, bool keep_operators = true);

/// The global basis of Bézier elements that meet face to face with equal control points there
/// (the tet route's hexes; any C0 mesh of Bézier hexes): one function per distinct control point
/// (points closer than point_tolerance(bbox, 1e-12) are one), each element's extraction operator
/// the identity on its Bernstein functions, so the partition of unity holds exactly and Cᵀ·P is
/// the hex's points to the tolerance. Functions are numbered in order of first appearance. Throws
/// core::InvalidInputError naming the element if two of its own control points are one function
/// (a degenerate element) or a shared point has two different weights (not C0 there). With
/// keep_operators false `elements` is left empty, as in global_basis.
GlobalBasis bezier_basis(const std::vector<bezier::BezierHex>& hexes, bool keep_operators = true);

/// The points of a connected .vtu of the hexes (bezier::write_bezier_vtu's `shared`): control
/// points closer than point_tolerance(bbox, 1e-12) with weights equal to 1e-12 relative are one point, so
/// neighbouring elements share their face points (the spline is C0 there: its Bézier points
/// coincide up to rounding); points with other weights stay apart.
std::vector<int> shared_points(const std::vector<bezier::BezierHex>& hexes);

/// shared_points on hexes that are grids of elements: the same ids, found by the grids' structure
/// where it tells (a point of the net of Bézier points inside a grid is its elements' own, merged
/// by index if within the tolerance and of equal weight) and by position only on the grids' sides.
/// Only a net with two of its own points within the tolerance of each other (degenerate) numbers
/// differently: those points stay apart here. The grids must cover the hexes in order, each of
/// elements of one degree; throws core::InvalidInputError otherwise.
std::vector<int> shared_points(const std::vector<bezier::BezierHex>& hexes, const std::vector<ElementGrid>& grids);

/// Extracts the Bézier elements of the splines of the cubes `t` (all of one degree) and measures them
/// against the input `surface`; boundary deviation is sampled on the cube faces marked boundary.
/// The extraction operators are kept (Result::basis.elements) only if params.exports has bext or json.
Result extract(const std::vector<tmesh::TMesh>& t, const surface::Mesh& surface, const Params& params);

/// Report keys: bezier_elements, degree, min_scaled_jacobian, max_scaled_jacobian, hausdorff_rel,
/// volume_rel_error (+ spline_volume, surface_volume), certified_valid, certified_invalid,
/// undecided, certified_min_detj_rel, global_functions, partition_of_unity_error,
/// frac_scaled_jacobian_above_0_5 (elements whose sampled min scaled Jacobian is > 0.5),
/// volume_frac_scaled_jacobian_above_0_5 (the volume where it is, quality.h), worst_elements
/// (Result::worst).
core::Json report_figures(const Result& r);

/// bezier.vtu: VTK_BEZIER_HEXAHEDRON cells with per-cell min/max scaled Jacobian, boundary distance,
/// certification status and certified_min_detj.
void write_bezier_vtu(const std::string& path, const Result& r);

}  // namespace volts::extract
