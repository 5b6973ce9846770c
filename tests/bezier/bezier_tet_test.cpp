// Tests of bezier/bezier_tet.h: simplex indexing, evaluation against the explicit basis, exact
// derivatives, degree elevation, blossoms, restriction and the 8-child split of §4.
#include "bezier/bezier_tet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/errors.h"

using namespace volts;
using namespace volts::bezier;
using Eigen::Vector3d;
using Eigen::Vector4d;

namespace {

double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

BezierTet random_tet(std::mt19937& rng, int n, bool rational) {
  std::uniform_real_distribution<double> jitter(-0.1, 0.1), w(0.5, 2.0);
  BezierTet t;
  t.degree = n;
  for (const auto& a : simplex_multi_indices(3, n)) {
    t.points.push_back(Vector3d(a[1], a[2], a[3]) / n + Vector3d(jitter(rng), jitter(rng), jitter(rng)));
    if (rational) t.weights.push_back(w(rng));
  }
  return t;
}

Vector3d random_in_tet(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Vector3d x(unit(rng), unit(rng), unit(rng));
  while (x.sum() > 1) x = Vector3d(unit(rng), unit(rng), unit(rng));
  return x;
}

// Σ w_α b_α B_α / Σ w_α B_α with the multinomial basis written out.
Vector3d brute_force(const BezierTet& t, const Vector3d& x) {
  const double l[4] = {1 - x.sum(), x[0], x[1], x[2]};
  const auto idx = simplex_multi_indices(3, t.degree);
  Vector3d A = Vector3d::Zero();
  double W = 0;
  for (std::size_t i = 0; i < idx.size(); ++i) {
    double b = factorial(t.degree);
    for (int k = 0; k < 4; ++k) b *= std::pow(l[k], idx[i][k]) / factorial(idx[i][k]);
    A += t.weight(int(i)) * b * t.points[i];
    W += t.weight(int(i)) * b;
  }
  return A / W;
}

}  // namespace

TEST(BezierTet, IndexOrderMatchesMultiIndices) {
  for (int dim : {2, 3})
    for (int n = 0; n <= 6; ++n) {
      const auto idx = simplex_multi_indices(dim, n);
      ASSERT_EQ(int(idx.size()), simplex_size(dim, n));
      for (std::size_t i = 0; i < idx.size(); ++i) {
        EXPECT_EQ(idx[i][0] + idx[i][1] + idx[i][2] + idx[i][3], n);
        EXPECT_EQ(simplex_index(dim, n, idx[i][1], idx[i][2], idx[i][3]), int(i));
      }
    }
}

TEST(BezierTet, EvaluationMatchesExplicitBasisAndDerivativesMatchDifferences) {
  std::mt19937 rng(5);
  for (int n = 1; n <= 4; ++n)
    for (bool rational : {false, true}) {
      const BezierTet t = random_tet(rng, n, rational);
      for (int s = 0; s < 20; ++s) {
        const Vector3d x = random_in_tet(rng) * 0.9 + Vector3d::Constant(0.02);
        Eigen::Matrix3d J;
        const Vector3d y = evaluate(t, x, &J);
        EXPECT_LT((y - brute_force(t, x)).norm(), 1e-13);
        const double h = 1e-6;
        for (int d = 0; d < 3; ++d) {
          const Vector3d e = Vector3d::Unit(d) * h;
          const Vector3d fd = (brute_force(t, x + e) - brute_force(t, x - e)) / (2 * h);
          EXPECT_LT((J.col(d) - fd).norm(), 1e-7 * (1 + fd.norm())) << "n=" << n << " d=" << d;
        }
      }
    }
}

TEST(BezierTet, TriangleEvaluationIsTheTetOnItsFaceW0) {
  // A triangle with the tet's w = 0 face net evaluates like the tet at w = 0.
  std::mt19937 rng(6);
  const BezierTet t = random_tet(rng, 3, true);
  BezierTriangle tri;
  tri.degree = 3;
  for (const auto& a : simplex_multi_indices(2, 3)) {
    const int i = simplex_index(3, 3, a[1], a[2], 0);
    tri.points.push_back(t.points[i]);
    tri.weights.push_back(t.weights[i]);
  }
  for (int s = 0; s < 10; ++s) {
    Vector3d x = random_in_tet(rng);
    x[2] = 0;
    Eigen::Matrix<double, 3, 2> Jt;
    Eigen::Matrix3d J;
    EXPECT_LT((evaluate(tri, x.head<2>(), &Jt) - evaluate(t, x, &J)).norm(), 1e-14);
    EXPECT_LT((Jt - J.leftCols<2>()).norm(), 1e-12);
  }
}

TEST(BezierTet, ElevationKeepsTheMap) {
  std::mt19937 rng(7);
  for (bool rational : {false, true}) {
    const BezierTet t = random_tet(rng, 2, rational);
    const BezierTet e = elevate_degree(t, 5);
    EXPECT_EQ(e.degree, 5);
    for (int s = 0; s < 10; ++s) {
      const Vector3d x = random_in_tet(rng);
      EXPECT_LT((evaluate(t, x) - evaluate(e, x)).norm(), 1e-13);
    }
  }
  EXPECT_THROW(elevate_degree(random_tet(rng, 3, false), 2), core::InvalidInputError);
}

TEST(BezierTet, BlossomOnTheDiagonalIsTheValue) {
  std::mt19937 rng(8);
  const BezierTet t = random_tet(rng, 4, true);
  std::vector<Vector4d> net;
  for (std::size_t i = 0; i < t.points.size(); ++i) net.push_back((Vector4d() << t.weights[i] * t.points[i], t.weights[i]).finished());
  const Vector3d x = random_in_tet(rng);
  const Vector4d l(1 - x.sum(), x[0], x[1], x[2]);
  const Vector4d h = blossom(3, 4, net, std::vector<Vector4d>(4, l));
  EXPECT_LT((h.head<3>() / h[3] - evaluate(t, x)).norm(), 1e-13);
  EXPECT_THROW(blossom(3, 4, net, std::vector<Vector4d>(3, l)), core::InvalidInputError);
}

TEST(BezierTet, SplitChildrenTileTheTetAndCarryTheMap) {
  const auto children = tet_split_children();
  const auto to_uvw = [](const Vector4d& l) { return Vector3d(l[1], l[2], l[3]); };
  double total = 0;
  for (const auto& c : children) {
    Eigen::Matrix3d E;
    for (int k = 0; k < 3; ++k) E.col(k) = to_uvw(c[k + 1]) - to_uvw(c[0]);
    EXPECT_NEAR(std::abs(E.determinant()) / 6, 1.0 / 48, 1e-15);  // 1/8 of the unit tet
    total += std::abs(E.determinant()) / 6;
  }
  EXPECT_NEAR(total, 1.0 / 6, 1e-15);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> unit(0, 1);
  for (bool rational : {false, true}) {
    const BezierTet t = random_tet(rng, 3, rational);
    const auto kids = subdivide(t);
    for (int c = 0; c < 8; ++c)
      for (int s = 0; s < 5; ++s) {
        // A random point of child c, in the child's and the parent's coordinates.
        const Vector3d y = random_in_tet(rng);
        const Vector4d ly(1 - y.sum(), y[0], y[1], y[2]);
        Vector4d lp = Vector4d::Zero();
        for (int k = 0; k < 4; ++k) lp += ly[k] * children[c][k];
        EXPECT_LT((evaluate(kids[c], y) - evaluate(t, to_uvw(lp))).norm(), 1e-13);
      }
  }
  // Every point of the tet lies in some child (barycentric coordinates in it all >= 0).
  for (int s = 0; s < 200; ++s) {
    const Vector3d x = random_in_tet(rng);
    bool inside = false;
    for (const auto& c : children) {
      Eigen::Matrix4d B;
      for (int k = 0; k < 4; ++k) B.col(k) = c[k];
      const Vector4d l = B.colPivHouseholderQr().solve(Vector4d(1 - x.sum(), x[0], x[1], x[2]));
      inside = inside || l.minCoeff() >= -1e-12;
    }
    EXPECT_TRUE(inside);
  }
}

TEST(BezierTet, MalformedPatchesAreRejected) {
  BezierTet t;
  t.degree = 2;
  t.points.resize(9);
  EXPECT_THROW(check(t), core::InvalidInputError);
  t.points.resize(10);
  t.weights.assign(10, 1.0);
  t.weights[3] = -1;
  EXPECT_THROW(evaluate(t, Vector3d::Zero()), core::InvalidInputError);
  BezierTriangle tri;
  tri.degree = 0;
  tri.points.resize(1);
  EXPECT_THROW(check(tri), core::InvalidInputError);
}
