// Connectivity repair of volume maps (volmap/repair.h): edge collapses and 2-3/3-2 flips on small
// hand-built meshes whose answers are known — flat or inverted tets in parameter space go, every
// tet stays positive in physical space, the volumes in both spaces do not change, and a flip that
// would fold the mesh is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tetmesh/tetmesh.h"
#include "volmap/repair.h"

using namespace volts;
using volmap::VolumeMap;

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

namespace {

// A bipyramid over a hexagon (surface: ring 0..5 at z = 0, apexes 6 = (0,0,1) and 7 = (0,0,-1))
// filled by the interior edge 8 = (0,0,0.3) - 9 = (0,0,-0.3): per hexagon side a tet from 6 to 8,
// one around the edge 8-9 and one from 9 to 7. Parameter positions equal the physical ones.
VolumeMap bipyramid() {
  VolumeMap m;
  m.surface_vertices = 8;
  for (int i = 0; i < 6; ++i) m.physical.emplace_back(std::cos(i * kPi / 3), std::sin(i * kPi / 3), 0.0);
  m.physical.emplace_back(0, 0, 1);
  m.physical.emplace_back(0, 0, -1);
  m.physical.emplace_back(0, 0, 0.3);
  m.physical.emplace_back(0, 0, -0.3);
  for (int i = 0; i < 6; ++i)
    for (const std::array<int, 2> e : {std::array<int, 2>{6, 8}, {8, 9}, {9, 7}}) {
      std::array<int, 4> t{e[0], e[1], i, (i + 1) % 6};
      const auto& p = m.physical;
      if (tetmesh::signed_volume6(p[t[0]], p[t[1]], p[t[2]], p[t[3]]) < 0) std::swap(t[2], t[3]);
      m.tets.push_back(t);
    }
  m.parameter = m.physical;
  return m;
}

double smallest_volume6(const std::vector<Eigen::Vector3d>& p, const VolumeMap& m) {
  double smallest = HUGE_VAL;
  for (const auto& t : m.tets) smallest = std::min(smallest, tetmesh::signed_volume6(p[t[0]], p[t[1]], p[t[2]], p[t[3]]));
  return smallest;
}

double total_volume6(const std::vector<Eigen::Vector3d>& p, const VolumeMap& m, double* smallest) {
  double sum = 0;
  *smallest = HUGE_VAL;
  for (const auto& t : m.tets) {
    const double v = tetmesh::signed_volume6(p[t[0]], p[t[1]], p[t[2]], p[t[3]]);
    sum += v;
    *smallest = std::min(*smallest, v);
  }
  return sum;
}

}  // namespace

// Untangling parked interior vertex 9 on 8 in parameter space: the six tets around the edge are
// flat there. Collapsing the edge removes them and leaves a tetrahedralization of the same solid,
// positive in both spaces.
TEST(CollapseFlatTetEdges, RemovesTheFlatTetsOfACoincidentInteriorEdge) {
  VolumeMap m = bipyramid();
  m.parameter[8] = m.parameter[9] = Eigen::Vector3d(0.1, 0.05, 0.0);
  double smallest = 0;
  const double phys = total_volume6(m.physical, m, &smallest), param = total_volume6(m.parameter, m, &smallest);
  ASSERT_EQ(smallest, 0.0);
  EXPECT_EQ(volmap::collapse_flat_tet_edges(m), 1);
  EXPECT_EQ(m.tets.size(), 12u);
  ASSERT_EQ(m.physical.size(), 9u);
  ASSERT_EQ(m.parameter.size(), 9u);
  for (const auto& t : m.tets)
    for (int v : t) ASSERT_LT(v, 9);
  EXPECT_NEAR(total_volume6(m.physical, m, &smallest), phys, 1e-12);
  EXPECT_GT(smallest, 0);
  EXPECT_NEAR(total_volume6(m.parameter, m, &smallest), param, 1e-12);
  EXPECT_GT(smallest, 0);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(m.physical[i], bipyramid().physical[i]) << "surface points keep their ids";
}

// An interior vertex parked on a surface vertex merges into it; the surface point does not move.
TEST(CollapseFlatTetEdges, KeepsTheSurfaceEnd) {
  VolumeMap m = bipyramid();
  m.parameter[8] = m.parameter[6];
  EXPECT_EQ(volmap::collapse_flat_tet_edges(m), 1);
  EXPECT_EQ(m.tets.size(), 12u);
  EXPECT_EQ(m.physical[6], Eigen::Vector3d(0, 0, 1));
  EXPECT_GT(smallest_volume6(m.physical, m), 0);
  EXPECT_GT(smallest_volume6(m.parameter, m), 0);
}

// Nothing flat: nothing changes. Ends 1e-6 apart with the edge's tets inverted: the edge goes too.
TEST(CollapseFlatTetEdges, CollapsesOnlyWhereTetsAreBad) {
  VolumeMap m = bipyramid();
  EXPECT_EQ(volmap::collapse_flat_tet_edges(m), 0);
  EXPECT_EQ(m.tets.size(), 18u);
  m.parameter[8] = Eigen::Vector3d(0.1, 0.05, 0.0);
  m.parameter[9] = Eigen::Vector3d(0.1, 0.05, 1e-6);  // above 8: the six tets around the edge are inverted
  ASSERT_LT(smallest_volume6(m.parameter, m), 0);
  EXPECT_EQ(volmap::collapse_flat_tet_edges(m), 1);
  EXPECT_EQ(m.tets.size(), 12u);
  EXPECT_GT(smallest_volume6(m.physical, m), 0);
  EXPECT_GT(smallest_volume6(m.parameter, m), 0);
}

namespace {

// Two tets on the triangle 0 1 2 (z = 0), apex 3 above and 4 below; the segment 3-4 crosses the
// triangle's interior. Points 3 and 4 are free.
VolumeMap two_tets() {
  VolumeMap m;
  m.surface_vertices = 3;
  m.physical = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.3, 0.3, 1}, {0.3, 0.3, -1}};
  m.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  m.parameter = m.physical;
  return m;
}

}  // namespace

// The apex lies in the triangle's plane in parameter space: the upper tet is flat, but the three
// tets around the edge 3-4 are positive in both spaces.
TEST(FlipFlatTets, TwoThreeFlipRemovesAFlatTet) {
  VolumeMap m = two_tets();
  m.parameter[3] = Eigen::Vector3d(0.3, 0.3, 0.0);
  double smallest = 0;
  const double phys = total_volume6(m.physical, m, &smallest), param = total_volume6(m.parameter, m, &smallest);
  ASSERT_EQ(smallest, 0.0);
  EXPECT_EQ(volmap::flip_flat_tets(m), 1);
  EXPECT_EQ(m.tets.size(), 3u);
  EXPECT_NEAR(total_volume6(m.physical, m, &smallest), phys, 1e-12);
  EXPECT_GT(smallest, 0);
  EXPECT_NEAR(total_volume6(m.parameter, m, &smallest), param, 1e-12);
  EXPECT_GT(smallest, 0);
}

// The segment 3-4 misses the triangle (it meets z = 0 at (1, 1)): the three tets around it would
// overlap their neighbours, so no flip, however bad the parameter tet is.
TEST(FlipFlatTets, NoTwoThreeFlipWhereTheNewEdgeMissesTheFace) {
  VolumeMap m = two_tets();
  m.physical[3] = Eigen::Vector3d(1, 1, 1);
  m.physical[4] = Eigen::Vector3d(1, 1, -1);
  m.parameter = m.physical;
  m.parameter[3] = Eigen::Vector3d(0.955, 1.366, -0.718);  // the upper tet inverted; the flip's tets would all be positive
  ASSERT_LT(smallest_volume6(m.parameter, m), 0);
  EXPECT_EQ(volmap::flip_flat_tets(m), 0);
  EXPECT_EQ(m.tets.size(), 2u);
}

// Three tets around the edge 3-4 whose parameter image passes through the triangle's edge 0-1:
// one of them is flat; the two tets on the triangle are positive.
TEST(FlipFlatTets, ThreeTwoFlipRemovesAFlatTet) {
  VolumeMap m = two_tets();
  ASSERT_EQ(volmap::flip_flat_tets(m), 0) << "nothing flat";
  m.tets = {{3, 4, 0, 1}, {3, 4, 1, 2}, {3, 4, 2, 0}};
  m.surface_vertices = 0;  // a triangle of three surface points would be an interior face on the surface: refused
  for (auto& t : m.tets)
    if (tetmesh::signed_volume6(m.physical[t[0]], m.physical[t[1]], m.physical[t[2]], m.physical[t[3]]) < 0) std::swap(t[2], t[3]);
  m.parameter[4] = Eigen::Vector3d(0.6, -0.3, -1);  // 3 -> 4 meets z = 0 at (0.45, 0, 0), on the edge 0-1
  ASSERT_NEAR(smallest_volume6(m.parameter, m), 0.0, 1e-15);
  EXPECT_EQ(volmap::flip_flat_tets(m), 1);
  EXPECT_EQ(m.tets.size(), 2u);
  EXPECT_GT(smallest_volume6(m.physical, m), 0);
  EXPECT_GT(smallest_volume6(m.parameter, m), 0);
}

