#include "quality/quality.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Polygon_mesh_processing/measure.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "bezier/certify.h"
#include "bezier/hex_point.h"
#include "bezier/quadrature.h"
#include "core/errors.h"
#include "core/parallel.h"

namespace volts::quality {

using surface::Mesh;
// The deviation is a measurement: no decision of topology rests on it, so the tree runs on plain
// doubles (Epick's filtered predicates in its traversal cost a third of the phase).
using DK = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<DK::Triangle_3>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<DK, CGAL::AABB_triangle_primitive<DK, Triangles::const_iterator>>>;

ScaledJacobian scaled_jacobian(const std::vector<bezier::BezierHex>& hexes, int gauss_points) {
  ScaledJacobian r;
  r.min_per_element.resize(hexes.size());
  r.max_per_element.resize(hexes.size());
  core::parallel_for(hexes.size(), [&](std::size_t e) {
    const auto js = bezier::sample_jacobian(hexes[e], gauss_points);
    r.min_per_element[e] = js.min_scaled, r.max_per_element[e] = js.max_scaled;
  });
  for (std::size_t e = 0; e < hexes.size(); ++e) r.min = std::min(r.min, r.min_per_element[e]), r.max = std::max(r.max, r.max_per_element[e]);
  return r;
}

ScaledJacobian scaled_jacobian_on_grid(const std::vector<bezier::BezierHex>& hexes, int points) {
  if (points < 2) throw core::InvalidInputError("scaled_jacobian_on_grid: at least 2 points per direction, got " + std::to_string(points));
  ScaledJacobian r;
  r.min_per_element.resize(hexes.size());
  r.max_per_element.resize(hexes.size());
  core::parallel_for(hexes.size(), [&](std::size_t e) {
    const bezier::JacobianSample js = bezier::summarize_jacobians(bezier::jacobian_grid(hexes[e], points));
    r.min_per_element[e] = js.min_scaled, r.max_per_element[e] = js.max_scaled;
  });
  for (std::size_t e = 0; e < hexes.size(); ++e) r.min = std::min(r.min, r.min_per_element[e]), r.max = std::max(r.max, r.max_per_element[e]);
  return r;
}

double volume_fraction_scaled_jacobian_above(const std::vector<bezier::BezierHex>& hexes, int gauss_points, double threshold) {
  const std::vector<double> g = bezier::gauss_legendre_points(gauss_points), w = bezier::gauss_legendre_weights(gauss_points);
  // Volume of every point (negative: its scaled Jacobian is not above the threshold), in
  // parallel; summed in order afterwards, so the sum does not depend on the threads.
  const std::size_t n = g.size(), per = n * n * n;
  std::vector<double> dvs(hexes.size() * per);
  core::parallel_for(hexes.size(), [&](std::size_t e) {
    double* out = dvs.data() + e * per;
    const std::vector<Eigen::Matrix3d> Js = bezier::jacobian_tensor_grid(hexes[e], g);
    for (std::size_t k = 0; k < n; ++k)
      for (std::size_t j = 0; j < n; ++j)
        for (std::size_t i = 0; i < n; ++i) {
          const Eigen::Matrix3d& J = Js[i + n * (j + n * k)];
          const double dv = std::max(J.determinant(), 0.0) * w[i] * w[j] * w[k];
          *out++ = bezier::scaled_jacobian(J) > threshold ? dv : -dv;
        }
  });
  double all = 0, above = 0;
  for (const double dv : dvs) {
    all += std::abs(dv);
    if (dv > 0) above += dv;
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
  Triangles triangles;
  triangles.reserve(surface.number_of_faces());
  for (const auto f : surface.faces()) {
    std::array<DK::Point_3, 3> v;
    int k = 0;
    for (const auto x : CGAL::vertices_around_face(surface.halfedge(f), surface)) {
      if (k == 3) throw core::InvalidInputError("boundary_deviation: the surface has a face that is no triangle");
      const auto& p = surface.point(x);
      v[static_cast<std::size_t>(k++)] = DK::Point_3(p.x(), p.y(), p.z());
    }
    if (k != 3) throw core::InvalidInputError("boundary_deviation: the surface has a face that is no triangle");
    triangles.emplace_back(v[0], v[1], v[2]);
  }
  Tree tree(triangles.cbegin(), triangles.cend());
  tree.build();  // now, not lazily in the first (parallel) query
  tree.accelerate_distance_queries();
  const CGAL::Bbox_3 bb = tree.bbox();
  r.diagonal = std::sqrt(CGAL::square(bb.xmax() - bb.xmin()) + CGAL::square(bb.ymax() - bb.ymin()) + CGAL::square(bb.zmax() - bb.zmin()));
  r.per_element.assign(hexes.size(), 0.0);
  for (const BoundaryFace& f : faces)
    if (f.element < 0 || f.element >= static_cast<int>(hexes.size()) || f.axis < 0 || f.axis > 2 || (f.side != 0 && f.side != 1))
      throw core::InvalidInputError("boundary_deviation: boundary face names no element face");
  const int m = samples;
  auto grid_point = [m](int axis, int side, int a, int b) {
    Eigen::Vector3d uvw;
    uvw[axis] = side;
    uvw[(axis + 1) % 3] = double(a) / (m - 1);
    uvw[(axis + 2) % 3] = double(b) / (m - 1);
    return uvw;
  };
  // Bases of the sample grid of each of the 6 faces (axis, side), for the first hex's degrees.
  std::vector<bezier::HexPoints> grids;
  if (!hexes.empty() && hexes[0].degree[0] >= 1 && hexes[0].degree[1] >= 1 && hexes[0].degree[2] >= 1)
    for (int f = 0; f < 6; ++f) {
      std::vector<Eigen::Vector3d> uvw;
      for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b) uvw.push_back(grid_point(f / 2, f % 2, a, b));
      grids.emplace_back(hexes[0].degree, uvw);
    }
  // Distance of every face in parallel (the tree and its KD-tree are built above, queries only
  // read them), then the maxima in face order.
  std::vector<double> face_dist(faces.size(), 0.0);
  core::parallel_for(faces.size(), [&](std::size_t i) {
    const BoundaryFace& f = faces[i];
    const bezier::BezierHex& hex = hexes[f.element];
    std::vector<Eigen::Vector3d> xs;
    const bool same = !grids.empty() && grids[0].has_degree(hex.degree);
    if (same) grids[static_cast<std::size_t>(2 * f.axis + f.side)].evaluate(hex, &xs, nullptr);
    double dist = 0;
    // Each sample's search starts from its neighbour's closest point: a tight first bound, the
    // exact closest point still (the eight: this phase 0.110 -> 0.081 s, the same figures).
    std::optional<DK::Point_3> hint;
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b) {
        const Eigen::Vector3d x = same ? xs[static_cast<std::size_t>(a * m + b)] : bezier::evaluate(hex, grid_point(f.axis, f.side, a, b));
        const DK::Point_3 q(x[0], x[1], x[2]);
        hint = hint ? tree.closest_point(q, *hint) : tree.closest_point(q);
        dist = std::max(dist, std::sqrt(CGAL::squared_distance(q, *hint)));
      }
    face_dist[i] = dist;
  }, 4);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    double& dist = r.per_element[faces[i].element];
    dist = std::max(dist, face_dist[i]);
    r.max = std::max(r.max, dist);
  }
  r.rel = r.max / r.diagonal;
  return r;
}

Volume volume(const std::vector<bezier::BezierHex>& hexes, const Mesh& surface, int gauss_points) {
  Volume v;
  std::vector<double> per(hexes.size());
  core::parallel_for(hexes.size(), [&](std::size_t e) { per[e] = bezier::volume(hexes[e], gauss_points); });
  for (const double x : per) v.elements += x;  // in element order: independent of the threads
  v.surface = CGAL::Polygon_mesh_processing::volume(surface);
  v.rel_error = std::abs(v.elements - v.surface) / std::abs(v.surface);
  return v;
}

namespace {

// The `count` lowest elements of sj in order, each at its first sample within roundoff of its
// minimum. samples(hex) gives the element's Jacobians, uvw_of(j) sample j's parameters.
template <class Samples, class Uvw>
std::vector<WorstSample> lowest_elements(const std::vector<bezier::BezierHex>& hexes, const ScaledJacobian& sj, const std::vector<BoundaryFace>& faces,
                                         int count, bool on_grid, Samples samples, Uvw uvw_of) {
  if (sj.min_per_element.size() != hexes.size()) throw core::InvalidInputError("worst_samples: one scaled Jacobian per element is needed");
  const std::vector<double>& worst = sj.min_per_element;
  std::vector<int> order(hexes.size());
  for (std::size_t e = 0; e < order.size(); ++e) order[e] = static_cast<int>(e);
  const std::size_t k = std::min(order.size(), static_cast<std::size_t>(std::max(count, 0)));
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
                    [&](int a, int b) { return worst[static_cast<std::size_t>(a)] < worst[static_cast<std::size_t>(b)] || (worst[static_cast<std::size_t>(a)] == worst[static_cast<std::size_t>(b)] && a < b); });
  std::vector<WorstSample> out;
  for (std::size_t i = 0; i < k; ++i) {
    const int e = order[i];
    const bezier::BezierHex& hex = hexes[static_cast<std::size_t>(e)];
    const std::vector<Eigen::Matrix3d> J = samples(hex);
    // The first sample within roundoff of the minimum: equal samples of an affine element name
    // its first one, not whichever roundoff favours.
    std::size_t at = 0;
    for (std::size_t j = 1; j < J.size(); ++j)
      if (bezier::scaled_jacobian(J[j]) < bezier::scaled_jacobian(J[at]) - 1e-12) at = j;
    WorstSample w;
    w.element = e;
    w.scaled_jacobian = worst[static_cast<std::size_t>(e)];
    w.on_grid = on_grid;
    w.uvw = uvw_of(at);
    w.at_corner = (w.uvw.array() == 0.0 || w.uvw.array() == 1.0).all();
    w.position = bezier::evaluate(hex, w.uvw);
    int axis = -1;
    for (const BoundaryFace& f : faces)
      if (f.element == e && w.uvw[f.axis] == static_cast<double>(f.side)) ++w.boundary_faces, axis = f.axis;
    if (w.at_corner && w.boundary_faces == 1) {
      const Eigen::Vector3d a = J[at].col((axis + 1) % 3), b = J[at].col((axis + 2) % 3);
      const double l = a.norm() * b.norm();
      w.surface_bound = l > 0 ? a.cross(b).norm() / l : 0.0;
    }
    out.push_back(w);
  }
  return out;
}

}  // namespace

std::vector<WorstSample> worst_samples(const std::vector<bezier::BezierHex>& hexes, const ScaledJacobian& sj, const std::vector<BoundaryFace>& faces,
                                       int gauss_points, int count) {
  if (gauss_points < 1) throw core::InvalidInputError("worst_samples: gauss_points must be >= 1");
  const std::vector<double> g = bezier::gauss_legendre_points(gauss_points);
  const std::size_t n = g.size();
  // jacobian_samples: the 8 corners (bit d of the index: coordinate d), then the Gauss points.
  return lowest_elements(hexes, sj, faces, count, false, [&](const bezier::BezierHex& h) { return bezier::jacobian_samples(h, gauss_points); },
                         [&](std::size_t at) {
                           if (at < 8) return Eigen::Vector3d(static_cast<double>(at & 1), static_cast<double>((at >> 1) & 1), static_cast<double>((at >> 2) & 1));
                           const std::size_t q = at - 8;
                           return Eigen::Vector3d(g[q % n], g[(q / n) % n], g[q / (n * n)]);
                         });
}

std::vector<WorstSample> worst_grid_samples(const std::vector<bezier::BezierHex>& hexes, const ScaledJacobian& sj,
                                            const std::vector<BoundaryFace>& faces, int points, int count) {
  if (points < 2) throw core::InvalidInputError("worst_grid_samples: at least 2 points per direction, got " + std::to_string(points));
  const std::size_t n = static_cast<std::size_t>(points);
  return lowest_elements(hexes, sj, faces, count, true, [&](const bezier::BezierHex& x) { return bezier::jacobian_grid(x, points); },
                         [&](std::size_t at) {
                           const std::size_t i = at % n, j = (at / n) % n, k = at / (n * n);
                           // As jacobian_grid's abscissae: a / (n - 1), exact at the ends.
                           auto t = [&](std::size_t a) { return static_cast<double>(a) / (points - 1.0); };
                           return Eigen::Vector3d(t(i), t(j), t(k));
                         });
}

}  // namespace volts::quality
