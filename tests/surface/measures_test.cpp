// bbox_diagonal, signed_volume and genus on meshes whose values are known in closed form.
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "surface/surface.h"

namespace volts::surface {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

Mesh mesh_of(const std::vector<Point>& points, const std::vector<std::vector<std::size_t>>& faces) {
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, faces, mesh);
  return mesh;
}

/// Box [0,a]x[0,b]x[0,c] as 12 outward triangles (the last `missing` ones left out).
Mesh box(double a, double b, double c, std::size_t missing = 0) {
  std::vector<Point> p;
  for (int i = 0; i < 8; ++i) p.emplace_back(a * (i & 1), b * ((i >> 1) & 1), c * ((i >> 2) & 1));
  std::vector<std::vector<std::size_t>> faces;
  for (const auto& q : std::vector<std::vector<std::size_t>>{{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {1, 3, 7, 5}, {3, 2, 6, 7}, {2, 0, 4, 6}}) {
    faces.push_back({q[0], q[1], q[2]});
    faces.push_back({q[0], q[2], q[3]});
  }
  faces.resize(faces.size() - missing);
  return mesh_of(p, faces);
}

/// Torus sampled on an n x m grid (major radius R, minor r), two triangles per cell, outward.
Mesh torus(std::size_t n, std::size_t m, double R, double r) {
  std::vector<Point> p;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < m; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / m;
      p.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
    }
  std::vector<std::vector<std::size_t>> faces;
  const auto id = [&](std::size_t i, std::size_t j) { return (i % n) * m + j % m; };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < m; ++j) {
      faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return mesh_of(p, faces);
}

TEST(SurfaceMeasures, BoxVolumeDiagonalGenus) {
  Mesh mesh = box(1, 2, 3);
  EXPECT_NEAR(bbox_diagonal(mesh), std::sqrt(14.0), 1e-12);
  EXPECT_NEAR(signed_volume(mesh), 6.0, 1e-12);
  EXPECT_EQ(genus(mesh), 0);
  PMP::reverse_face_orientations(mesh);
  EXPECT_NEAR(signed_volume(mesh), -6.0, 1e-12);
}

TEST(SurfaceMeasures, VolumeDoesNotDependOnPosition) {
  Mesh mesh = box(1, 1, 1);
  for (const auto v : mesh.vertices()) mesh.point(v) = mesh.point(v) + Kernel::Vector_3(100, -50, 7);
  EXPECT_NEAR(signed_volume(mesh), 1.0, 1e-9);
}

TEST(SurfaceMeasures, TorusHasGenusOne) {
  const Mesh mesh = torus(24, 12, 3.0, 1.0);
  EXPECT_EQ(genus(mesh), 1);
  // A polyhedral torus is inscribed in the smooth one: slightly less than 2 pi^2 R r^2, and positive.
  const double smooth = 2 * M_PI * M_PI * 3.0 * 1.0;
  EXPECT_GT(signed_volume(mesh), 0.9 * smooth);
  EXPECT_LT(signed_volume(mesh), smooth);
}

TEST(SurfaceMeasures, EmptyAndOpenMeshes) {
  EXPECT_EQ(bbox_diagonal(Mesh()), 0.0);
  const Mesh open = box(1, 1, 1, 1);
  EXPECT_FALSE(CGAL::is_closed(open));
  EXPECT_THROW(signed_volume(open), std::invalid_argument);
}

}  // namespace
}  // namespace volts::surface
