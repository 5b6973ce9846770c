#include "extract/extract.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bezier/bspline.h"
#include "bezier/bspline_volume.h"
#include "bezier/certify.h"
#include "bezier/vtk_bezier.h"
#include "core/errors.h"
#include "core/log.h"
#include "quality/quality.h"

namespace volts::extract {

using surface::Mesh;

Result extract(const std::vector<tmesh::TMesh>& ts, const Mesh& surface, const Params& params) {
  if (params.gauss_points < 0 || params.gauss_points > 10) throw core::ConfigError("extract.gauss_points must be in [0, 10]");
  if (params.boundary_samples < 2 || params.boundary_samples > 64) throw core::ConfigError("extract.boundary_samples must be in [2, 64]");
  if (ts.empty()) throw core::InvalidInputError("extract: no T-mesh");
  Result r;
  r.degree = ts[0].degree;
  std::vector<quality::BoundaryFace> boundary;
  {
    core::LogSection s("Bézier extraction");
    for (const auto& t : ts) {
      if (t.degree != r.degree) throw core::InvalidInputError("extract: the cubes' T-meshes have different degrees");
      bezier::TensorBSplineVolume vol;
      vol.degree = {t.degree, t.degree, t.degree};
      vol.knots = t.knots;
      for (const auto& p : t.control_points) vol.points.emplace_back(p[0], p[1], p[2]);
      const auto hexes = bezier::extract_bezier_hexes(vol);
      // Elements are ordered i fastest over the tensor grid of knot spans; boundary faces are those
      // on the first or last span in some direction, on a cube face that is on the surface.
      const int n[3] = {static_cast<int>(bezier::element_spans(t.knots[0], t.degree).size()),
                        static_cast<int>(bezier::element_spans(t.knots[1], t.degree).size()),
                        static_cast<int>(bezier::element_spans(t.knots[2], t.degree).size())};
      const int ne = static_cast<int>(hexes.size());
      if (n[0] * n[1] * n[2] != ne) throw core::NumericalError("extract: element count does not match the knot spans");
      const int offset = static_cast<int>(r.hexes.size());
      for (int e = 0; e < ne; ++e) {
        const int idx[3] = {e % n[0], (e / n[0]) % n[1], e / (n[0] * n[1])};
        for (int axis = 0; axis < 3; ++axis)
          for (int side = 0; side < 2; ++side)
            if (t.boundary[2 * axis + side] && idx[axis] == (side ? n[axis] - 1 : 0)) boundary.push_back({offset + e, axis, side});
      }
      r.hexes.insert(r.hexes.end(), hexes.begin(), hexes.end());
    }
  }
  const int gp = params.gauss_points > 0 ? params.gauss_points : r.degree + 1;
  {
    core::LogSection s("scaled Jacobian at corners and Gauss points");
    quality::ScaledJacobian sj = quality::scaled_jacobian(r.hexes, gp);
    r.min_scaled_jacobian = std::move(sj.min_per_element);
    r.max_scaled_jacobian = std::move(sj.max_per_element);
    r.min_scaled = sj.min, r.max_scaled = sj.max;
  }
  {
    // Certified sign of det J (Randrianarivony 2008 §4): the sampled figures above can miss a fold.
    core::LogSection s("certified Jacobian validity");
    r.certified_min_detj_rel = std::numeric_limits<double>::infinity();
    for (const auto& h : r.hexes) {
      const bezier::CertifyResult c = bezier::certify(h, params.certify);
      r.status.push_back(static_cast<int>(c.status));
      r.certified_min_detj.push_back(c.min_detj_lower);
      if (c.mean_detj != 0) r.certified_min_detj_rel = std::min(r.certified_min_detj_rel, c.min_detj_lower / std::abs(c.mean_detj));
    }
    if (r.hexes.empty()) r.certified_min_detj_rel = 0;
    const quality::ValidityCounts counts = quality::count_validity(r.status);
    r.certified_valid = counts.valid, r.certified_invalid = counts.invalid, r.undecided = counts.undecided;
  }
  {
    core::LogSection s("boundary deviation and volume");
    quality::BoundaryDeviation dev = quality::boundary_deviation(r.hexes, boundary, surface, params.boundary_samples);
    r.boundary_distance = std::move(dev.per_element);
    r.hausdorff_rel = dev.rel;
    const quality::Volume v = quality::volume(r.hexes, surface, std::max({r.degree, 1}) + 2);
    r.spline_volume = v.elements, r.surface_volume = v.surface, r.volume_rel_error = v.rel_error;
  }
  return r;
}

core::Json report_figures(const Result& r) {
  return core::Json{{"bezier_elements", r.hexes.size()},   {"degree", r.degree},
                    {"min_scaled_jacobian", r.min_scaled}, {"max_scaled_jacobian", r.max_scaled},
                    {"hausdorff_rel", r.hausdorff_rel},    {"volume_rel_error", r.volume_rel_error},
                    {"spline_volume", r.spline_volume},    {"surface_volume", r.surface_volume},
                    {"certified_valid", r.certified_valid}, {"certified_invalid", r.certified_invalid},
                    {"undecided", r.undecided},            {"certified_min_detj_rel", r.certified_min_detj_rel}};
}

void write_bezier_vtu(const std::string& path, const Result& r) {
  std::vector<bezier::CellArray> cells = {{"min_scaled_jacobian", 1, r.min_scaled_jacobian},
                                          {"max_scaled_jacobian", 1, r.max_scaled_jacobian},
                                          {"boundary_distance", 1, r.boundary_distance},
                                          {"status", 1, std::vector<double>(r.status.begin(), r.status.end())},
                                          {"certified_min_detj", 1, r.certified_min_detj}};
  bezier::write_bezier_vtu(path, r.hexes, cells);
}

}  // namespace volts::extract
