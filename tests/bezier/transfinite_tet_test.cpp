// Tests of bezier/transfinite_tet.h (§2, §5): X reproduces its four faces exactly (conditions
// (3)), is certified regular for curved valid faces and irregular for a folded face, and
// incompatible faces are refused naming the failing condition.
#include "bezier/transfinite_tet.h"

#include <gtest/gtest.h>

#include <random>

#include "bezier/certify.h"
#include "core/errors.h"
#include "element_factory.h"

using namespace volts;
using namespace volts::bezier;
using namespace volts::bezier::testing;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

// The four boundary triangles of a Bézier tet G in the parametrisations of (3):
// F1(s,t) = G(t,s,0), F2(s,t) = G(s,0,t), F3(s,t) = G(1-s-t,s,t), F4(s,t) = G(0,t,s).
// Face f sets λ_zero = 0, s = λ_s, t = λ_t; a triangle multi-index (a0,a1,a2) becomes the tet
// multi-index with a1 at s, a2 at t and a0 at the remaining barycentric slot.
std::array<BezierTriangle, 4> faces_of(const BezierTet& G) {
  const int map[4][3] = {{3, 2, 1}, {2, 1, 3}, {0, 2, 3}, {1, 3, 2}};
  std::array<BezierTriangle, 4> F;
  for (int f = 0; f < 4; ++f) {
    F[f].degree = G.degree;
    int rest = 0;
    while (rest == map[f][0] || rest == map[f][1] || rest == map[f][2]) ++rest;
    for (const auto& a : simplex_multi_indices(2, G.degree)) {
      int b[4] = {0, 0, 0, 0};
      b[map[f][1]] = a[1];
      b[map[f][2]] = a[2];
      b[rest] = a[0];
      F[f].points.push_back(G.points[simplex_index(3, G.degree, b[1], b[2], b[3])]);
    }
  }
  return F;
}

// The tet points of (3) for face f at (s,t).
Vector3d on_face(int f, double s, double t) {
  switch (f) {
    case 0: return {t, s, 0};
    case 1: return {s, 0, t};
    case 2: return {1 - s - t, s, t};
    default: return {0, t, s};
  }
}

}  // namespace

TEST(TransfiniteTet, ReproducesItsFacesExactly) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int n = 1; n <= 4; ++n) {
    const auto F = faces_of(perturbed_tet(rng, n, 0.08, false));
    const BezierTet X = transfinite_tet(F);
    EXPECT_EQ(X.degree, n + 1);
    for (int f = 0; f < 4; ++f)
      for (int k = 0; k < 20; ++k) {
        double s = unit(rng), t = unit(rng);
        if (s + t > 1) s = 1 - s, t = 1 - t;
        EXPECT_LT((evaluate(X, on_face(f, s, t)) - evaluate(F[f], Vector2d(s, t))).norm(), 1e-13)
            << "F" << f + 1 << " degree " << n;
      }
  }
}

TEST(TransfiniteTet, AffineFacesGiveTheAffineMap) {
  std::mt19937 rng(32);
  const auto F = faces_of(perturbed_tet(rng, 2, 0.0, false));  // the identity, as quadratic faces
  const BezierTet X = transfinite_tet(F);
  for (int k = 0; k < 20; ++k) {
    const Vector3d x = random_in_tet(rng);
    EXPECT_LT((evaluate(X, x) - x).norm(), 1e-14);
  }
}

TEST(TransfiniteTet, CurvedValidFacesAreRegularAndAFoldedFaceIsNot) {
  std::mt19937 rng(33);
  const auto curved = faces_of(perturbed_tet(rng, 3, 0.05, false));
  const CertifyResult r = certify(transfinite_tet(curved));
  EXPECT_EQ(r.status, Validity::valid);
  EXPECT_GT(r.min_detj_lower, 0.0);

  // F1 (the face w = 0) bulged through the opposite vertex: its interior control point far above it.
  auto folded = curved;
  folded[0].points[simplex_index(2, 3, 1, 1)] += Vector3d(0, 0, 2.5);
  const BezierTet X = transfinite_tet(folded);
  const CertifyResult rf = certify(X);
  ASSERT_EQ(rf.status, Validity::invalid);
  Eigen::Matrix3d J;
  evaluate(X, rf.witness, &J);
  EXPECT_LT(J.determinant(), 0.0);
}

TEST(TransfiniteTet, IncompatibleFacesNameTheCondition) {
  std::mt19937 rng(34);
  const auto good = faces_of(perturbed_tet(rng, 2, 0.05, false));
  auto corner = good;
  corner[1].points[0] += Vector3d(0.1, 0, 0);  // F2(0,0)
  try {
    transfinite_tet(corner);
    FAIL() << "no error";
  } catch (const core::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("corner (0,0,0): F1(0,0) = F2(0,0) = F4(0,0)"), std::string::npos) << e.what();
  }
  auto edge = good;
  edge[1].points[simplex_index(2, 2, 1, 0)] += Vector3d(0, 0.1, 0);  // F2(μ,0): the edge along u
  try {
    transfinite_tet(edge);
    FAIL() << "no error";
  } catch (const core::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("edge (0,0,0)-(1,0,0): F1(0,μ) = F2(μ,0)"), std::string::npos) << e.what();
  }
  auto rational = good;
  rational[2].weights.assign(6, 1.0);
  EXPECT_THROW(transfinite_tet(rational), core::InvalidInputError);
}
