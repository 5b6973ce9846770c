// classify (Liu et al. §3) over a family of meshes: generated box-like models at several
// resolutions and orientations, a cube minus a cylinder, a torus, and a real polyhedral ring.
// Besides the counts the issue fixes, it checks the structural invariants of any classification.
#include <gtest/gtest.h>

#include <CGAL/Aff_transformation_3.h>

#include <cmath>
#include <set>

#include "classify/classify.h"
#include "common/test_util.h"

using namespace volts;

namespace {


// Invariants: curves partition the sharp edges; curve ends are corners and interior curve
// vertices are not; faces across a non-sharp edge share a patch; patches beside a curve differ.
// Real models may have sharp curves that end inside a patch (both sides the same patch); generated
// models must not.
void check_invariants(const surface::Mesh& mesh, const classify::Classification& c, bool curves_separate_patches = true) {
  std::set<std::pair<int, int>> sharp;
  for (std::size_t i = 0; i < c.sharp_edge_vertices.size(); i += 2) sharp.insert({c.sharp_edge_vertices[i], c.sharp_edge_vertices[i + 1]});
  const std::set<int> corners(c.corners.begin(), c.corners.end());
  std::set<std::pair<int, int>> covered;
  for (const auto& k : c.curves) {
    ASSERT_GE(k.vertices.size(), 2u);
    if (k.closed) {
      for (int v : k.vertices) EXPECT_FALSE(corners.count(v)) << "closed curve through a corner";
    } else {
      EXPECT_TRUE(corners.count(k.vertices.front()));
      EXPECT_TRUE(corners.count(k.vertices.back()));
      for (std::size_t i = 1; i + 1 < k.vertices.size(); ++i) EXPECT_FALSE(corners.count(k.vertices[i]));
    }
    const std::size_t n = k.vertices.size();
    for (std::size_t i = 0; i + (k.closed ? 0 : 1) < n; ++i) {
      const int a = k.vertices[i], b = k.vertices[(i + 1) % n];
      const auto e = std::make_pair(std::min(a, b), std::max(a, b));
      EXPECT_TRUE(sharp.count(e)) << "curve edge is not sharp";
      EXPECT_TRUE(covered.insert(e).second) << "sharp edge in two curves";
    }
    if (curves_separate_patches) {
      EXPECT_NE(k.patch_left, k.patch_right);
    }
  }
  EXPECT_EQ(covered.size(), sharp.size()) << "sharp edges not covered by curves";
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge(e);
    const int a = static_cast<int>(mesh.source(h)), b = static_cast<int>(mesh.target(h));
    if (!sharp.count({std::min(a, b), std::max(a, b)})) {
      EXPECT_EQ(c.face_patch[mesh.face(h)], c.face_patch[mesh.face(mesh.opposite(h))]);
    }
  }
  EXPECT_EQ(c.face_patch.size(), mesh.number_of_faces());
  const std::set<int> ids(c.face_patch.begin(), c.face_patch.end());
  EXPECT_EQ(static_cast<int>(ids.size()), c.patches);
}

}  // namespace

TEST(Classify, BoxLikeModelsHaveTheCubeStructureAtEveryResolution) {
  for (const std::string name : {"box", "bulged-box"})
    for (int res : {4, 8, 16, 24}) {
      SCOPED_TRACE(name + " resolution " + std::to_string(res));
      const auto mesh = test::generated_model(name, res);
      const auto c = classify::classify(mesh, {});
      EXPECT_EQ(c.corners.size(), 8u);
      EXPECT_EQ(c.curves.size(), 12u);
      EXPECT_EQ(c.feature_curves(), 12);
      EXPECT_EQ(c.patches, 6);
      EXPECT_EQ(c.genus, 0);
      check_invariants(mesh, c);
      // Every sharp edge lies on the box's edges: each curve's length is one of the box sides.
      for (const auto& k : c.curves) {
        double len = 0;
        for (std::size_t i = 1; i < k.vertices.size(); ++i)
          len += std::sqrt(CGAL::squared_distance(mesh.point(surface::Mesh::Vertex_index(k.vertices[i - 1])),
                                                  mesh.point(surface::Mesh::Vertex_index(k.vertices[i]))));
        EXPECT_TRUE(std::abs(len - 2.0) < 1e-9 || std::abs(len - 1.5) < 1e-9 || std::abs(len - 1.0) < 1e-9) << len;
      }
    }
}

TEST(Classify, ResultDoesNotDependOnOrientationInSpace) {
  auto mesh = test::generated_model("bulged-box", 12);
  const auto before = classify::classify(mesh, {});
  // A rotation about an oblique axis.
  const double a = 0.7, s = std::sin(a), co = std::cos(a);
  const CGAL::Aff_transformation_3<surface::Kernel> rot(co, -s, 0, s * 0.6, s * co, co * 0.8 - 0.1, 0.3, -0.2, 0.9);
  for (auto v : mesh.vertices()) mesh.point(v) = rot.transform(mesh.point(v));
  const auto after = classify::classify(mesh, {});
  EXPECT_EQ(after.corners, before.corners);
  EXPECT_EQ(after.face_patch, before.face_patch);
  EXPECT_EQ(after.curves.size(), before.curves.size());
}

TEST(Classify, CubeWithHoleHasTwoDifferenceCurves) {
  for (int res : {16, 32}) {
    SCOPED_TRACE(res);
    const auto mesh = test::generated_model("cube-with-hole", res);
    const auto c = classify::classify(mesh, {});
    EXPECT_EQ(c.corners.size(), 8u);
    EXPECT_EQ(c.curves.size(), 14u);
    EXPECT_EQ(c.feature_curves(), 12);
    EXPECT_EQ(c.difference_curves(), 2);
    EXPECT_EQ(c.patches, 7);
    EXPECT_EQ(c.genus, 1);
    for (const auto& k : c.curves) EXPECT_EQ(k.kind == classify::CurveKind::difference, k.closed);
    check_invariants(mesh, c);
  }
}

TEST(Classify, SmoothTorusHasNoCurves) {
  const auto mesh = test::generated_model("torus", 24);
  const auto c = classify::classify(mesh, {});
  EXPECT_EQ(c.corners.size(), 0u);
  EXPECT_EQ(c.curves.size(), 0u);
  EXPECT_EQ(c.patches, 1);
  EXPECT_EQ(c.genus, 1);
}

TEST(Classify, RealSquareRing) {
  const auto mesh = surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/vhacd_tube1.off");
  const auto c = classify::classify(mesh, {});
  EXPECT_EQ(c.corners.size(), 16u);
  EXPECT_EQ(c.curves.size(), 24u);
  EXPECT_EQ(c.patches, 10);
  EXPECT_EQ(c.genus, 1);
  check_invariants(mesh, c);
}

TEST(Classify, RealModelsSatisfyInvariants) {
  for (const std::string f : {"cinolib_torus.obj", "cfwen_eight.off", "loopycuts_rod_rem.obj", "loopycuts_mechanical08_rem.obj", "c3d_fandisk.obj"}) {
    SCOPED_TRACE(f);
    const auto mesh = surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/" + f);
    const auto c = classify::classify(mesh, {});
    check_invariants(mesh, c, false);
  }
}

TEST(Classify, HigherThresholdNeverFindsMoreSharpEdges) {
  const auto mesh = surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/c3d_fandisk.obj");
  std::size_t prev = SIZE_MAX;
  for (double t : {10.0, 20.0, 30.0, 45.0, 60.0, 90.0}) {
    classify::Params p;
    p.sharp_angle_deg = t;
    const auto n = classify::classify(mesh, p).sharp_edge_vertices.size();
    EXPECT_LE(n, prev);
    prev = n;
  }
}

TEST(Classify, StageFilePayloadRoundTrips) {
  const auto mesh = test::generated_model("cube-with-hole", 16);
  const auto c = classify::classify(mesh, {});
  const auto d = classify::from_json(classify::to_json(c), "mem");
  EXPECT_EQ(d.corners, c.corners);
  EXPECT_EQ(d.face_patch, c.face_patch);
  ASSERT_EQ(d.curves.size(), c.curves.size());
  for (std::size_t i = 0; i < c.curves.size(); ++i) {
    EXPECT_EQ(d.curves[i].vertices, c.curves[i].vertices);
    EXPECT_EQ(d.curves[i].kind, c.curves[i].kind);
  }
  EXPECT_EQ(classify::report_figures(d), classify::report_figures(c));
}
