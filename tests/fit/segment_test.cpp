// Tests of fit/segment.h: six patches meeting like cube faces on generated genus-0 solids and on
// the fandisk.
#include "fit/segment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "common/test_util.h"
#include "core/errors.h"

using namespace volts;
using namespace volts::fit;

namespace {

Eigen::Vector3d point(const surface::Mesh& m, int v) {
  const auto& p = m.point(surface::Mesh::Vertex_index(v));
  return {p.x(), p.y(), p.z()};
}

// Each corner c lies on the sides of the axes its bits say.
void expect_corner_signs(const surface::Mesh& m, const SixPatches& s) {
  for (int c = 0; c < 8; ++c) {
    ASSERT_GE(s.corners[c], 0) << c;
    const Eigen::Vector3d x = point(m, s.corners[c]);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(x[a] > 0, ((c >> a) & 1) == 1) << "corner " << c << " axis " << a;
  }
}

}  // namespace

TEST(SixPatches, SphereSplitsIntoItsSixCubeFaces) {
  const surface::Mesh m = test::generated_model("sphere", 16);
  const SixPatches s = six_patches(m);
  EXPECT_TRUE(cube_layout(m, s.label).ok()) << cube_layout(m, s.label).summary();
  std::array<int, 6> count{};
  for (int l : s.label) ++count[l];
  for (int l = 0; l < 6; ++l) EXPECT_EQ(count[l], static_cast<int>(m.number_of_faces()) / 6) << l;  // symmetric
  expect_corner_signs(m, s);
  for (int c = 0; c < 8; ++c) {  // the cube's corners projected onto the sphere
    const Eigen::Vector3d x = point(m, s.corners[c]);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(std::abs(x[a]), 1 / std::sqrt(3.0), 1e-9);
  }
  EXPECT_EQ(s.relabeled, 0);
  EXPECT_LT(s.max_deviation_deg, 55.0);
}

TEST(SixPatches, BulgedBoxSplitsAtItsSharpEdges) {
  for (const char* name : {"box", "bulged-box"}) {
    const surface::Mesh m = test::generated_model(name, 16);
    const SixPatches s = six_patches(m);
    expect_corner_signs(m, s);
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d x = point(m, s.corners[c]);
      EXPECT_NEAR(std::abs(x.x()), 1.0, 1e-12) << name;
      EXPECT_NEAR(std::abs(x.y()), 0.75, 1e-12) << name;
      EXPECT_NEAR(std::abs(x.z()), 0.5, 1e-12) << name;
    }
    EXPECT_EQ(s.relabeled, 0) << name;
    EXPECT_LT(s.max_deviation_deg, 30.0) << name;
  }
}

TEST(SixPatches, BrokenLayoutsAreNamed) {
  const surface::Mesh m = test::generated_model("sphere", 16);
  const SixPatches s = six_patches(m);
  std::vector<int> island = s.label;
  // A face in the middle of +z (the face whose centroid is highest) labelled -x: a second -x component.
  int top = 0;
  double best = -1;
  for (auto f : m.faces()) {
    double z = 0;
    for (auto v : m.vertices_around_face(m.halfedge(f))) z += m.point(v).z();
    if (z > best) best = z, top = static_cast<int>(f.idx());
  }
  island[top] = 1;
  const CubeLayout li = cube_layout(m, island);
  EXPECT_EQ(li.components[1], 2);
  EXPECT_EQ(li.loops[4], 2);  // +z now has a hole
  EXPECT_EQ(li.opposite_vertices, 0);
  EXPECT_EQ(li.corners, 8);
  EXPECT_FALSE(li.ok());
  std::vector<int> five = s.label;
  for (int& l : five)
    if (l == 5) l = 3;
  const CubeLayout l5 = cube_layout(m, five);  // -z merged into -y
  EXPECT_EQ(l5.components[5], 0);
  EXPECT_EQ(l5.opposite_vertices, 5);  // the old -z/+y edge (4 segments) now joins -y and +y
  EXPECT_EQ(l5.corners, 4);
  EXPECT_EQ(l5.sides[3], 4);  // +z, +x, +y, -x around the merged patch
  EXPECT_FALSE(l5.ok());
  EXPECT_THROW(six_patches(test::generated_model("torus", 16)), core::TopologyError);
}

// The fandisk (CAD part, 12,946 triangles, in its own axes). Measured: six disks with four sides
// each, 8 corners, no opposite patches touching; 4,008 faces (31 %) end in a patch other than their
// nearest axis direction (up to 92.7° off): the slanted bottom faces and the fan's sides join the
// patches next to them. Before merging by mean normal (by shared boundary length instead) the
// bottom face joined +y, which then touched -y along 33 vertices.
TEST(SixPatches, FandiskIsCubeLike) {
  const surface::Mesh m = surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/c3d_fandisk.obj");
  const SixPatches s = six_patches(m);
  const CubeLayout& l = s.layout;
  std::printf("fandisk: %s; %d faces relabeled, max deviation %.1f deg\n", l.summary().c_str(), s.relabeled,
              s.max_deviation_deg);
  ASSERT_TRUE(l.ok()) << l.problem;
  for (int p = 0; p < 6; ++p) {
    EXPECT_EQ(l.components[p], 1) << p;
    EXPECT_EQ(l.loops[p], 1) << p;
    EXPECT_EQ(l.euler[p], 1) << p;
    EXPECT_EQ(l.sides[p], 4) << p;
  }
  EXPECT_EQ(l.corners, 8);
  EXPECT_EQ(l.opposite_vertices, 0);
  std::set<int> distinct(s.corners.begin(), s.corners.end());
  EXPECT_EQ(distinct.size(), 8u);
  EXPECT_EQ(distinct.count(-1), 0u);
  EXPECT_LT(s.relabeled, static_cast<int>(m.number_of_faces()) / 3);
  EXPECT_LT(s.max_deviation_deg, 95.0);  // merges never go into the opposite direction
}
