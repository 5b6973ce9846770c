// volts::extract — stage 5: the spline from the T-mesh, its Bézier elements by extraction, quality
// figures and export (Liu et al. 2013, §5.3 and §6).
//
// Implemented so far: the tensor-product B-spline of a uniform T-mesh, Bézier extraction by knot
// insertion (bezier::extraction_operators), scaled Jacobian sampled at corners and Gauss points,
// boundary deviation from the input surface and volume error, and bezier.vtu for ParaView.
// T-spline templates at irregular nodes and the solver exports (.bext, .json, .msh) are issue 8.
#pragma once

#include <string>
#include <vector>

#include "bezier/bezier_hex.h"
#include "bezier/certify.h"
#include "core/stage_file.h"
#include "surface/surface.h"
#include "tmesh/tmesh.h"

namespace volts::extract {

/// Parameters of extract().
struct Params {
  int gauss_points = 0;       ///< Gauss points per direction for the Jacobian sample; 0 = degree + 1
  int boundary_samples = 8;   ///< samples per direction on each boundary element face (Hausdorff) [2, 64]
  bezier::CertifyParams certify;  ///< certification of det J > 0 per element (max_depth: subdivision levels)
};

struct Result {
  std::vector<bezier::BezierHex> hexes;
  std::vector<double> min_scaled_jacobian;  ///< per element, sampled
  std::vector<double> max_scaled_jacobian;  ///< per element, sampled
  std::vector<double> boundary_distance;    ///< per element: max sampled distance of its boundary faces to the surface (0 inside)
  std::vector<int> status;                  ///< per element: bezier::Validity (1 valid, -1 invalid, 0 undecided)
  std::vector<double> certified_min_detj;   ///< per element: certified lower bound of min det J (bezier::certify)
  int certified_valid = 0, certified_invalid = 0, undecided = 0;
  double certified_min_detj_rel = 0;  ///< min over elements of (lower bound of min det J) / (element's mean det J)
  int degree = 3;
  double min_scaled = 0, max_scaled = 0;
  double hausdorff_rel = 0;     ///< max distance spline boundary -> input surface / bbox diagonal (sampled)
  double spline_volume = 0;     ///< ∫ det J over all elements
  double surface_volume = 0;    ///< volume enclosed by the input surface
  double volume_rel_error = 0;  ///< |spline_volume - surface_volume| / surface_volume
};

/// Extracts the Bézier elements of the splines of the cubes `t` (all of one degree) and measures them
/// against the input `surface`; boundary deviation is sampled on the cube faces marked boundary.
Result extract(const std::vector<tmesh::TMesh>& t, const surface::Mesh& surface, const Params& params);

/// Report keys: bezier_elements, degree, min_scaled_jacobian, max_scaled_jacobian, hausdorff_rel,
/// volume_rel_error (+ spline_volume, surface_volume), certified_valid, certified_invalid,
/// undecided, certified_min_detj_rel.
core::Json report_figures(const Result& r);

/// bezier.vtu: VTK_BEZIER_HEXAHEDRON cells with per-cell min/max scaled Jacobian, boundary distance,
/// certification status and certified_min_detj.
void write_bezier_vtu(const std::string& path, const Result& r);

}  // namespace volts::extract
