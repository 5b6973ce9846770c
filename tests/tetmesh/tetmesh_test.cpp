// TetGen tetrahedralization of generated solids (volts::tetmesh).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "common/test_util.h"
#include "core/errors.h"
#include "tetmesh/tetmesh.h"

using namespace volts;
using namespace volts::tetmesh;

namespace {
double volume(const TetMesh& m) {
  double v = 0;
  for (const auto& t : m.tets) {
    const double d = (m.points[t[1]] - m.points[t[0]]).cross(m.points[t[2]] - m.points[t[0]]).dot(m.points[t[3]] - m.points[t[0]]) / 6;
    EXPECT_GT(d, 0);
    v += d;
  }
  return v;
}
}  // namespace

TEST(Tetrahedralize, FillsTheSolidExactlyWithPositiveTets) {
  for (const char* name : {"tetrahedron", "cone", "torus"}) {
    const surface::Mesh s = test::generated_model(name, 8);
    const TetMesh m = tetrahedralize(s, {});
    ASSERT_GT(m.tets.size(), 0u) << name;
    EXPECT_NEAR(volume(m), surface::signed_volume(s), 1e-10 * surface::signed_volume(s)) << name;
    // -Y: the boundary is the input triangulation, face for face.
    EXPECT_EQ(boundary_faces(m).size(), s.number_of_faces()) << name;
  }
}

TEST(Tetrahedralize, QualityAndVolumeBoundsRefine) {
  const surface::Mesh s = test::generated_model("cone", 8);
  TetgenParams coarse;
  coarse.max_radius_edge_ratio = 0;
  TetgenParams fine;
  fine.max_volume_rel = 0.002;
  fine.keep_boundary = false;  // with -Y TetGen may leave big tets whose refinement would split the surface
  const auto a = tetrahedralize(s, coarse), b = tetrahedralize(s, fine);
  EXPECT_GT(b.tets.size(), a.tets.size());
  double vmax = 0;
  for (const auto& t : b.tets)
    vmax = std::max(vmax, (b.points[t[1]] - b.points[t[0]]).cross(b.points[t[2]] - b.points[t[0]]).dot(b.points[t[3]] - b.points[t[0]]) / 6);
  EXPECT_LE(vmax, 0.002 * surface::signed_volume(s) * (1 + 1e-9));
}

TEST(Tetrahedralize, ParametersOutOfRangeAreConfigErrors) {
  const surface::Mesh s = test::generated_model("tetrahedron", 4);
  TetgenParams p;
  p.max_radius_edge_ratio = 0.5;
  EXPECT_THROW(tetrahedralize(s, p), core::ConfigError);
  p = {};
  p.min_dihedral_deg = 45;
  EXPECT_THROW(tetrahedralize(s, p), core::ConfigError);
  p = {};
  p.max_volume_rel = -1;
  EXPECT_THROW(tetrahedralize(s, p), core::ConfigError);
}

// Callers attach data per surface vertex: the surface vertices are the first points, bit for bit, and
// every boundary face is made of them.
TEST(Tetrahedralize, SurfaceVerticesComeFirstWithTheirIds) {
  for (const char* name : {"torus", "sphere", "cube-with-hole"}) {
    const surface::Mesh s = test::generated_model(name, 12);
    const TetMesh m = tetrahedralize(s, {});
    const int n = static_cast<int>(s.number_of_vertices());
    ASSERT_GE(static_cast<int>(m.points.size()), n) << name;
    for (auto v : s.vertices()) {
      const auto& p = s.point(v);
      const Eigen::Vector3d& q = m.points[static_cast<int>(v)];
      EXPECT_TRUE(q.x() == p.x() && q.y() == p.y() && q.z() == p.z()) << name << " vertex " << static_cast<int>(v);
    }
    for (const auto& bf : boundary_faces(m))
      for (int j : kOutwardFace[bf[1]]) EXPECT_LT(m.tets[bf[0]][j], n) << name;
  }
}

TEST(Tetrahedralize, SelfIntersectingSurfaceIsANumericalErrorNotACrash) {
  // Two closed tetrahedra that overlap (the second shifted by a tenth of its size): TetGen 1.5 can
  // crash on such input, so it is refused before TetGen runs.
  const surface::Mesh a = test::generated_model("tetrahedron", 4);
  surface::Mesh s = a;
  std::map<surface::Mesh::Vertex_index, surface::Mesh::Vertex_index> copy;
  for (auto v : a.vertices()) {
    const auto& p = a.point(v);
    copy[v] = s.add_vertex(surface::Point(p.x() + 0.1, p.y() + 0.05, p.z() + 0.02));
  }
  for (auto f : a.faces()) {
    std::vector<surface::Mesh::Vertex_index> vs;
    for (auto v : vertices_around_face(a.halfedge(f), a)) vs.push_back(copy[v]);
    ASSERT_NE(s.add_face(vs), surface::Mesh::null_face());
  }
  try {
    tetrahedralize(s, {});
    FAIL() << "no error";
  } catch (const core::NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("intersects itself"), std::string::npos) << e.what();
  }
}
