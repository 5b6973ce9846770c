// The tet route as a library call: surface → TetGen → Bézier tets (boundary curved onto the
// surface) → four hexes each, certified; and Bézier tets given directly.
#include <gtest/gtest.h>

#include "common/test_util.h"
#include "core/errors.h"
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

TEST(TetRoute, BadParametersAndInputAreRefused) {
  const surface::Mesh s = test::generated_model("tetrahedron", 4);
  Params p;
  p.degree = 5;
  EXPECT_THROW(run(s, p), core::ConfigError);
  p = {};
  p.boundary_samples = 1;
  EXPECT_THROW(run(s, p), core::ConfigError);
  EXPECT_THROW(run(std::vector<bezier::BezierTet>{}, Params{}), core::InvalidInputError);
}
