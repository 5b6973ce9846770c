#include "tmesh/slide_surface.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "core/errors.h"

namespace volts::tmesh {

namespace {
// Closest points decide no topology here (a move is checked by the certified Jacobian after it), so
// a double kernel is enough.
using K = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<K::Triangle_3>;
using Segments = std::vector<K::Segment_3>;
using TriangleTree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>>>;
using SegmentTree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_segment_primitive<K, Segments::const_iterator>>>;
}  // namespace

struct SlideSurface::Impl {
  Triangles triangles;
  Segments sharp;
  std::vector<K::Point_3> corners;  // few (tens on the parts here): searched one by one
  TriangleTree triangle_tree;
  SegmentTree sharp_tree;
};

SlideSurface::SlideSurface(const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& triangles, double sharp_angle_deg)
    : impl_(std::make_unique<Impl>()) {
  if (vertices.empty() || triangles.empty()) throw core::InvalidInputError("slide surface: the mesh is empty");
  auto point = [&](int i) {
    if (i < 0 || static_cast<std::size_t>(i) >= vertices.size())
      throw core::InvalidInputError("slide surface: vertex index " + std::to_string(i) + " out of range");
    const Vec3& v = vertices[static_cast<std::size_t>(i)];
    return K::Point_3(v[0], v[1], v[2]);
  };
  std::vector<K::Vector_3> normals;
  // Each undirected edge with the faces on it.
  std::map<std::pair<int, int>, std::vector<std::size_t>> faces_of;
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const auto& t = triangles[f];
    impl_->triangles.emplace_back(point(t[0]), point(t[1]), point(t[2]));
    K::Vector_3 n = CGAL::cross_product(point(t[1]) - point(t[0]), point(t[2]) - point(t[0]));
    const double l = std::sqrt(n.squared_length());
    normals.push_back(l > 0 ? n / l : n);
    for (int k = 0; k < 3; ++k) {
      const int a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
      faces_of[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  }
  const double cos_sharp = std::cos(sharp_angle_deg * M_PI / 180.0);
  std::map<int, std::vector<int>> sharp_at;  // per vertex, the other ends of its sharp edges
  for (const auto& [edge, fs] : faces_of) {
    // A boundary or non-manifold edge counts as sharp: nothing may slide across it.
    const bool sharp = fs.size() != 2 || normals[fs[0]] * normals[fs[1]] < cos_sharp;
    if (!sharp) continue;
    impl_->sharp.emplace_back(point(edge.first), point(edge.second));
    sharp_at[edge.first].push_back(edge.second), sharp_at[edge.second].push_back(edge.first);
  }
  for (const auto& [v, ends] : sharp_at) {
    bool corner = ends.size() != 2;
    if (!corner) {
      const K::Vector_3 a = point(v) - point(ends[0]), b = point(ends[1]) - point(v);
      const double la = std::sqrt(a.squared_length()), lb = std::sqrt(b.squared_length());
      corner = !(la > 0 && lb > 0) || (a * b) / (la * lb) < cos_sharp;
    }
    if (corner) impl_->corners.push_back(point(v));
  }
  impl_->triangle_tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->triangle_tree.accelerate_distance_queries();
  if (!impl_->sharp.empty()) {
    impl_->sharp_tree.insert(impl_->sharp.cbegin(), impl_->sharp.cend());
    impl_->sharp_tree.accelerate_distance_queries();
  }
}

SlideSurface::~SlideSurface() = default;
SlideSurface::SlideSurface(SlideSurface&&) noexcept = default;
SlideSurface& SlideSurface::operator=(SlideSurface&&) noexcept = default;

Vec3 SlideSurface::closest(const Vec3& p, Vec3* normal) const {
  const auto [q, it] = impl_->triangle_tree.closest_point_and_primitive(K::Point_3(p[0], p[1], p[2]));
  if (normal) {
    const K::Triangle_3& t = *it;
    K::Vector_3 n = CGAL::cross_product(t[1] - t[0], t[2] - t[0]);
    const double l = std::sqrt(n.squared_length());
    *normal = l > 0 ? Vec3{n.x() / l, n.y() / l, n.z() / l} : Vec3{0, 0, 0};
  }
  return {q.x(), q.y(), q.z()};
}

Vec3 SlideSurface::closest(const Vec3& p, const Vec3& hint) const {
  const K::Point_3 q = impl_->triangle_tree.closest_point(K::Point_3(p[0], p[1], p[2]), K::Point_3(hint[0], hint[1], hint[2]));
  return {q.x(), q.y(), q.z()};
}

double SlideSurface::sharp_distance(const Vec3& p) const {
  if (impl_->sharp.empty()) return std::numeric_limits<double>::infinity();
  return std::sqrt(impl_->sharp_tree.squared_distance(K::Point_3(p[0], p[1], p[2])));
}

int SlideSurface::sharp_edges() const { return static_cast<int>(impl_->sharp.size()); }

Vec3 SlideSurface::closest_sharp(const Vec3& p, Vec3* tangent) const {
  if (impl_->sharp.empty()) throw core::InvalidInputError("slide surface: closest_sharp on a surface without sharp edges");
  const auto [q, it] = impl_->sharp_tree.closest_point_and_primitive(K::Point_3(p[0], p[1], p[2]));
  if (tangent) {
    const K::Vector_3 d = it->to_vector();
    const double l = std::sqrt(d.squared_length());
    *tangent = l > 0 ? Vec3{d.x() / l, d.y() / l, d.z() / l} : Vec3{0, 0, 0};
  }
  return {q.x(), q.y(), q.z()};
}

double SlideSurface::sharp_corner_distance(const Vec3& p) const {
  double best = std::numeric_limits<double>::infinity();
  const K::Point_3 x(p[0], p[1], p[2]);
  for (const K::Point_3& c : impl_->corners) best = std::min(best, CGAL::squared_distance(x, c));
  return std::sqrt(best);
}

int SlideSurface::sharp_corners() const { return static_cast<int>(impl_->corners.size()); }

}  // namespace volts::tmesh
