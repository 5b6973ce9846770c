// The tet route as a library call: surface → TetGen → Bézier tets (boundary curved onto the
// surface) → four hexes each, certified; and Bézier tets given directly.
#include <gtest/gtest.h>

#include "common/test_util.h"
#include "core/errors.h"
#include <array>
#include <iostream>
#include <set>

#include "extract/point_index.h"
#include "tet2hex/convert.h"
#include "tet2hex/tet2hex.h"
#include "test_util.h"

using namespace volts;
using namespace volts::tet2hex;

TEST(TetRoute, TetrahedronIsAllValidHexesWithTheExactVolume) {
  const surface::Mesh s = test::generated_model("tetrahedron", 4);
  Params p;
  p.degree = 2;
  const Result r = run(s, p);
  ASSERT_GT(r.tets.size(), 0u);
  EXPECT_EQ(r.hexes.size(), 4 * r.tets.size());
  EXPECT_EQ(r.certified_valid, static_cast<int>(r.hexes.size()));
  EXPECT_GT(r.min_scaled, 0);
  // Flat surface: the boundary is the input's, volume and boundary exact.
  EXPECT_LT(r.volume_rel_error, 1e-12);
  EXPECT_LT(r.hausdorff_rel, 1e-12);
}

// A coarse remesh of a sphere, curved back onto the fine input: closer to the surface than the
// flat tets, every element still certified valid, and every boundary face either curved or reverted.
TEST(TetRoute, CurvedBoundaryIsCloserToTheSurfaceAndCertified) {
  const surface::Mesh s = test::generated_model("sphere", 24);
  Params p;
  p.degree = 3;
  p.remesh_edge_rel = 0.1;
  p.curve_boundary = false;
  const Result flat = run(s, p);
  p.curve_boundary = true;
  const Result curved = run(s, p);
  EXPECT_EQ(flat.tets.size(), curved.tets.size());
  EXPECT_EQ(curved.boundary_faces_curved + curved.boundary_faces_reverted, curved.boundary_faces);
  EXPECT_GT(curved.boundary_faces_curved, 0);
  EXPECT_EQ(curved.certified_valid, static_cast<int>(curved.hexes.size()));
  EXPECT_LT(curved.hausdorff_rel, 0.5 * flat.hausdorff_rel);
  EXPECT_LT(curved.volume_rel_error, flat.volume_rel_error);
}

// Degree 1 has no boundary control points to move: curving is a no-op.
TEST(TetRoute, DegreeOneIsNotCurved) {
  Params p;
  p.degree = 1;
  p.remesh_edge_rel = 0.3;
  const Result r = run(test::generated_model("sphere", 16), p);
  EXPECT_EQ(r.boundary_faces_curved, 0);
  EXPECT_EQ(r.certified_valid, static_cast<int>(r.hexes.size()));
}

// Given Bézier tets: converted as they are (elevated to the asked degree), measured against the
// boundary of their corners.
TEST(TetRoute, GivenTetsAreConvertedAndElevated) {
  std::mt19937 rng(3);
  const std::vector<bezier::BezierTet> one = {test::random_tet(rng, 2, 0.0)};
  Params p;
  p.degree = 3;
  const Result r = run(one, p);
  EXPECT_EQ(r.degree, 3);
  EXPECT_EQ(r.hexes.size(), 4u);
  EXPECT_EQ(r.boundary_faces, 4);
  EXPECT_EQ(r.certified_valid, 4);
  EXPECT_LT(r.volume_rel_error, 1e-12);
}

// The optimizer's Jacobians are polynomial: rational hexes (weighted tets) are left as converted.
TEST(TetRouteOptimization, RationalHexesAreLeftAsConverted) {
  std::mt19937 rng(5);
  const std::vector<bezier::BezierTet> one = {test::random_tet(rng, 2, 0.05, true)};
  ASSERT_TRUE(one[0].is_rational());
  Params p;
  p.degree = 2;
  const Result exact = run(one, p);
  p.optimize_cycles = 1;
  const Result r = run(one, p);
  EXPECT_EQ(r.optimization_stop, "rational_hexes");
  ASSERT_EQ(r.hexes.size(), exact.hexes.size());
  for (std::size_t e = 0; e < r.hexes.size(); ++e) EXPECT_EQ(r.hexes[e].points, exact.hexes[e].points);
  EXPECT_EQ(r.certified_valid, exact.certified_valid);
}

TEST(TetRoute, BadParametersAndInputAreRefused) {
  const surface::Mesh s = test::generated_model("tetrahedron", 4);
  Params p;
  p.degree = 5;
  EXPECT_THROW(run(s, p), core::ConfigError);
  p = {};
  p.boundary_samples = 1;
  EXPECT_THROW(run(s, p), core::ConfigError);
  p = {};
  p.optimize_cycles = 101;
  EXPECT_THROW(run(s, p), core::ConfigError);
  p = {};
  p.optimize_target = 0;
  EXPECT_THROW(run(s, p), core::ConfigError);
  for (const int bad : {1, 9}) {
    p = {};
    p.optimize_grid_points = bad;
    EXPECT_THROW(run(s, p), core::ConfigError);
  }
  EXPECT_THROW(run(std::vector<bezier::BezierTet>{}, Params{}), core::InvalidInputError);
}

// Params::optimize_cycles: the tmesh optimizer on the hexes raises the worst one, keeps every
// certificate and every shared point shared, leaves the sharp corners where they are and the
// boundary on the surface (sliding nodes are projected back at their offset).
TEST(TetRouteOptimization, RaisesTheWorstHexAndKeepsCornersBoundaryAndConformity) {
  const surface::Mesh s = test::generated_model("box", 8);
  Params p;
  p.remesh_edge_rel = 0.25;
  const Result exact = run(s, p);
  p.optimize_cycles = 1;
  const Result opt = run(s, p);
  ASSERT_EQ(opt.hexes.size(), exact.hexes.size());
  EXPECT_EQ(exact.optimization_stop, "disabled");
  EXPECT_EQ(opt.certified_valid, static_cast<int>(opt.hexes.size()));
  EXPECT_NEAR(opt.min_scaled_before_optimization, exact.min_scaled, 1e-9);
  EXPECT_GT(opt.min_scaled, exact.min_scaled + 0.05) << "before " << exact.min_scaled;
  EXPECT_GT(opt.optimization_joint_rounds + opt.optimization_nodes_moved, 0);
  std::cout << "[ figures  ] box, tet route: " << opt.hexes.size() << " hexes, worst " << exact.min_scaled << " -> " << opt.min_scaled << ", hausdorff_rel "
            << exact.hausdorff_rel << " -> " << opt.hausdorff_rel << ", volume_rel_error " << exact.volume_rel_error << " -> "
            << opt.volume_rel_error << ", stop " << opt.optimization_stop << "\n";
  EXPECT_LT(opt.hausdorff_rel, 1.5 * exact.hausdorff_rel + 1e-4);
  EXPECT_LT(opt.volume_rel_error, exact.volume_rel_error + 1e-3);
  // The box's eight corners are sharp corners: control points there stay exactly.
  int corners = 0;
  for (const double x : {-1.0, 1.0})
    for (const double y : {-0.75, 0.75})
      for (const double z : {-0.5, 0.5}) {
        const Eigen::Vector3d c(x, y, z);
        bool before = false, after = false;
        for (std::size_t e = 0; e < opt.hexes.size(); ++e) {
          for (const auto& q : exact.hexes[e].points) before = before || q == c;
          for (const auto& q : opt.hexes[e].points) after = after || q == c;
        }
        corners += before;
        EXPECT_EQ(after, before) << c.transpose();
      }
  EXPECT_EQ(corners, 8);
  // Shared control points moved together: as many distinct points as the conversion had (it
  // computes a shared face's points in each tet, equal to roundoff), now equal bit for bit.
  extract::PointIndex index(Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-2), Eigen::Vector3d::Constant(2)), 1e-9);
  for (const auto& h : exact.hexes)
    for (const auto& q : h.points) index.find_or_add(q);
  std::set<std::array<double, 3>> points;
  for (const auto& h : opt.hexes)
    for (const auto& q : h.points) points.insert({q.x(), q.y(), q.z()});
  EXPECT_EQ(points.size(), index.points().size());
}
