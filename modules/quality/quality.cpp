#include "quality/quality.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/measure.h>

#include <algorithm>
#include <cmath>

#include "bezier/certify.h"
#include "bezier/quadrature.h"
#include "core/errors.h"

namespace volts::quality {

using surface::Mesh;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<surface::Kernel, Primitive>>;

ScaledJacobian scaled_jacobian(const std::vector<bezier::BezierHex>& hexes, int gauss_points) {
  ScaledJacobian r;
  r.min_per_element.reserve(hexes.size());
  r.max_per_element.reserve(hexes.size());
  for (const auto& h : hexes) {
    const auto js = bezier::sample_jacobian(h, gauss_points);
    r.min_per_element.push_back(js.min_scaled);
    r.max_per_element.push_back(js.max_scaled);
    r.min = std::min(r.min, js.min_scaled);
    r.max = std::max(r.max, js.max_scaled);
  }
  return r;
}

double volume_fraction_scaled_jacobian_above(const std::vector<bezier::BezierHex>& hexes, int gauss_points, double threshold) {
  const std::vector<double> g = bezier::gauss_legendre_points(gauss_points), w = bezier::gauss_legendre_weights(gauss_points);
  double all = 0, above = 0;
  for (const auto& h : hexes)
    for (std::size_t k = 0; k < g.size(); ++k)
      for (std::size_t j = 0; j < g.size(); ++j)
        for (std::size_t i = 0; i < g.size(); ++i) {
          Eigen::Matrix3d J;
          bezier::evaluate(h, Eigen::Vector3d(g[i], g[j], g[k]), &J);
          const double dv = std::max(J.determinant(), 0.0) * w[i] * w[j] * w[k];
          all += dv;
          if (bezier::scaled_jacobian(J) > threshold) above += dv;
        }
  return all > 0 ? above / all : 0;
}

ValidityCounts count_validity(const std::vector<int>& status) {
  ValidityCounts c;
  for (int v : status)
    (v == static_cast<int>(bezier::Validity::valid) ? c.valid : v == static_cast<int>(bezier::Validity::invalid) ? c.invalid : c.undecided)++;
  return c;
}

BoundaryDeviation boundary_deviation(const std::vector<bezier::BezierHex>& hexes, const std::vector<BoundaryFace>& faces,
                                     const Mesh& surface, int samples) {
  if (samples < 2) throw core::InvalidInputError("boundary_deviation: samples must be >= 2");
  BoundaryDeviation r;
  Tree tree(CGAL::faces(surface).first, CGAL::faces(surface).second, surface);
  tree.accelerate_distance_queries();
  const CGAL::Bbox_3 bb = tree.bbox();
  r.diagonal = std::sqrt(CGAL::square(bb.xmax() - bb.xmin()) + CGAL::square(bb.ymax() - bb.ymin()) + CGAL::square(bb.zmax() - bb.zmin()));
  r.per_element.assign(hexes.size(), 0.0);
  const int m = samples;
  for (const BoundaryFace& f : faces) {
    if (f.element < 0 || f.element >= static_cast<int>(hexes.size()) || f.axis < 0 || f.axis > 2 || (f.side != 0 && f.side != 1))
      throw core::InvalidInputError("boundary_deviation: boundary face names no element face");
    double& dist = r.per_element[f.element];
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b) {
        Eigen::Vector3d uvw;
        uvw[f.axis] = f.side;
        uvw[(f.axis + 1) % 3] = double(a) / (m - 1);
        uvw[(f.axis + 2) % 3] = double(b) / (m - 1);
        const Eigen::Vector3d x = bezier::evaluate(hexes[f.element], uvw);
        dist = std::max(dist, std::sqrt(tree.squared_distance(surface::Point(x[0], x[1], x[2]))));
      }
    r.max = std::max(r.max, dist);
  }
  r.rel = r.max / r.diagonal;
  return r;
}

Volume volume(const std::vector<bezier::BezierHex>& hexes, const Mesh& surface, int gauss_points) {
  Volume v;
  for (const auto& h : hexes) v.elements += bezier::volume(h, gauss_points);
  v.surface = CGAL::Polygon_mesh_processing::volume(surface);
  v.rel_error = std::abs(v.elements - v.surface) / std::abs(v.surface);
  return v;
}

}  // namespace volts::quality
