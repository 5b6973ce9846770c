// write_surface: every format round-trips through read_surface (OFF, OBJ and PLY bit-exactly, STL
// as floats), writes atomically and leaves no temporary file behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "core/errors.h"
#include "surface/surface.h"
#include "surface_test_util.h"

namespace volts::surface::test {
namespace {

/// An octahedron whose coordinates need all 17 digits (thirds, pi, tiny offsets).
Mesh awkward_octahedron() {
  const double a = 1.0 / 3.0, b = M_PI, c = 1e-7 + 2.0 / 7.0;
  Mesh mesh;
  const auto v0 = mesh.add_vertex(Point(b, a, c));
  const auto v1 = mesh.add_vertex(Point(-b, a, -c));
  const auto v2 = mesh.add_vertex(Point(a, b + a, c));
  const auto v3 = mesh.add_vertex(Point(a, -b + a, -c));
  const auto v4 = mesh.add_vertex(Point(c, a, b + c));
  const auto v5 = mesh.add_vertex(Point(-c, a, -b + c));
  // One face per octant around the centre (0, a, 0), normals outward.
  for (const auto& [x, y, z] : {std::tuple{v0, v2, v4}, std::tuple{v0, v5, v2}, std::tuple{v0, v4, v3},
                                std::tuple{v0, v3, v5}, std::tuple{v1, v4, v2}, std::tuple{v1, v2, v5},
                                std::tuple{v1, v3, v4}, std::tuple{v1, v5, v3}})
    mesh.add_face(x, y, z);
  return mesh;
}

std::vector<Point> points_of(const Mesh& mesh) {
  std::vector<Point> points;
  for (const auto v : mesh.vertices()) points.push_back(mesh.point(v));
  return points;
}

std::set<std::string> files_in(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename().string());
  return names;
}

TEST(WriteSurface, FixtureIsAValidSolid) {
  const Mesh mesh = awkward_octahedron();
  EXPECT_TRUE(CGAL::is_closed(mesh));
  EXPECT_GT(signed_volume(mesh), 0.0);
}

TEST(WriteSurface, ExactRoundTripOffObjPly) {
  TempDir dir;
  const Mesh mesh = awkward_octahedron();
  const std::vector<Point> original = points_of(mesh);
  for (const std::string name : {"a.off", "a.obj", "a.ply"}) {
    SCOPED_TRACE(name);
    write_surface(dir.file(name), mesh);
    ReadInfo info;
    const Mesh back = read_surface(dir.file(name), &info);
    EXPECT_FALSE(info.flipped);
    EXPECT_EQ(back.number_of_faces(), mesh.number_of_faces());
    const std::vector<Point> read = points_of(back);
    ASSERT_EQ(read.size(), original.size());
    for (std::size_t i = 0; i < read.size(); ++i) {
      EXPECT_EQ(read[i].x(), original[i].x()) << "vertex " << i;  // bit-exact, not approximately
      EXPECT_EQ(read[i].y(), original[i].y()) << "vertex " << i;
      EXPECT_EQ(read[i].z(), original[i].z()) << "vertex " << i;
    }
    EXPECT_NEAR(signed_volume(back), signed_volume(mesh), 1e-12 * signed_volume(mesh));
  }
  EXPECT_EQ(files_in(dir.path()), (std::set<std::string>{"a.off", "a.obj", "a.ply"}));  // no temporaries left
}

TEST(WriteSurface, StlRoundTripStoresFloats) {
  TempDir dir;
  const Mesh mesh = awkward_octahedron();
  write_surface(dir.file("a.stl"), mesh);
  ReadInfo info;
  const Mesh back = read_surface(dir.file("a.stl"), &info);
  EXPECT_EQ(info.file_vertices, 3 * mesh.number_of_faces());
  EXPECT_EQ(back.number_of_vertices(), mesh.number_of_vertices());
  EXPECT_EQ(back.number_of_faces(), mesh.number_of_faces());
  // STL reorders vertices (first use by a triangle); compare as sets of float-rounded points.
  std::set<std::tuple<double, double, double>> expected, read;
  for (const Point& p : points_of(mesh))
    expected.emplace(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  for (const Point& p : points_of(back)) read.emplace(p.x(), p.y(), p.z());
  EXPECT_EQ(read, expected);
  EXPECT_GT(signed_volume(back), 0.0);
  EXPECT_EQ(files_in(dir.path()), std::set<std::string>{"a.stl"});
}

TEST(WriteSurface, ReplacesAnExistingFile) {
  TempDir dir;
  const std::string path = dir.write("a.off", "old content");
  write_surface(path, awkward_octahedron());
  EXPECT_EQ(read_surface(path).number_of_vertices(), 6u);
  EXPECT_EQ(files_in(dir.path()), std::set<std::string>{"a.off"});
}

TEST(WriteSurface, UnknownExtensionWritesNothing) {
  TempDir dir;
  const std::string path = dir.file("a.vtk");
  try {
    write_surface(path, awkward_octahedron());
    ADD_FAILURE() << "no exception";
  } catch (const core::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": unknown extension '.vtk'"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(files_in(dir.path()).empty());
}

TEST(WriteSurface, PolygonsGoToOffButNotToStl) {
  TempDir dir;
  Mesh quad_cube;
  std::vector<Mesh::Vertex_index> v;
  for (int i = 0; i < 8; ++i) v.push_back(quad_cube.add_vertex(Point(i & 1, (i >> 1) & 1, (i >> 2) & 1)));
  for (const auto& [a, b, c, d] : {std::tuple{0, 2, 3, 1}, std::tuple{4, 5, 7, 6}, std::tuple{0, 1, 5, 4},
                                   std::tuple{1, 3, 7, 5}, std::tuple{3, 2, 6, 7}, std::tuple{2, 0, 4, 6}})
    ASSERT_TRUE(quad_cube.add_face(v[a], v[b], v[c], v[d]).is_valid());
  EXPECT_THROW(write_surface(dir.file("cube.stl"), quad_cube), std::invalid_argument);
  write_surface(dir.file("cube.off"), quad_cube);
  ReadInfo info;
  const Mesh back = read_surface(dir.file("cube.off"), &info);
  EXPECT_EQ(info.triangulated_faces, 6u);
  EXPECT_NEAR(signed_volume(back), 1.0, 1e-12);
  EXPECT_EQ(files_in(dir.path()), std::set<std::string>{"cube.off"});
}

}  // namespace
}  // namespace volts::surface::test
