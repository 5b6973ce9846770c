// Tests of bezier/bernstein_poly.h (exact products, subdivision) and of the subdivision of
// Bézier hexes and 1D subdivision matrices.
#include "bezier/bernstein_poly.h"

#include <gtest/gtest.h>

#include <random>

#include "bezier/bernstein.h"
#include "bezier/bezier_hex.h"
#include "bezier/bezier_tet.h"
#include "core/errors.h"

using namespace volts;
using namespace volts::bezier;
using Eigen::Vector3d;

namespace {

TensorBernstein random_tensor(std::mt19937& rng, std::array<int, 3> d) {
  std::uniform_real_distribution<double> c(-1, 1);
  TensorBernstein f;
  f.degree = d;
  for (int i = 0; i < (d[0] + 1) * (d[1] + 1) * (d[2] + 1); ++i) f.coefs.push_back(c(rng));
  return f;
}

SimplexBernstein random_simplex(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> c(-1, 1);
  SimplexBernstein f;
  f.degree = n;
  for (int i = 0; i < simplex_size(3, n); ++i) f.coefs.push_back(c(rng));
  return f;
}

Vector3d random_in_tet(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Vector3d x(unit(rng), unit(rng), unit(rng));
  while (x.sum() > 1) x = Vector3d(unit(rng), unit(rng), unit(rng));
  return x;
}

}  // namespace

TEST(BernsteinPoly, TensorProductIsExact) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int trial = 0; trial < 5; ++trial) {
    const TensorBernstein a = random_tensor(rng, {trial % 3, 2, 1 + trial % 2}), b = random_tensor(rng, {3, trial, 2});
    const TensorBernstein c = multiply(a, b);
    EXPECT_EQ(c.degree[0], a.degree[0] + b.degree[0]);
    for (int s = 0; s < 10; ++s) {
      const Vector3d x(unit(rng), unit(rng), unit(rng));
      EXPECT_NEAR(evaluate(c, x), evaluate(a, x) * evaluate(b, x), 1e-13);
    }
  }
}

TEST(BernsteinPoly, SimplexProductIsExact) {
  std::mt19937 rng(2);
  for (int n = 0; n <= 3; ++n)
    for (int m = 1; m <= 3; ++m) {
      const SimplexBernstein a = random_simplex(rng, n), b = random_simplex(rng, m);
      const SimplexBernstein c = multiply(a, b);
      EXPECT_EQ(c.degree, n + m);
      for (int s = 0; s < 10; ++s) {
        const Vector3d x = random_in_tet(rng);
        EXPECT_NEAR(evaluate(c, x), evaluate(a, x) * evaluate(b, x), 1e-13);
      }
    }
}

TEST(BernsteinPoly, SubdivisionMatrixRestrictsToTheInterval) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int p = 0; p <= 5; ++p) {
    const Eigen::VectorXd c = Eigen::VectorXd::Random(p + 1);
    const double a = unit(rng) - 0.5, b = unit(rng) + 0.5;
    const Eigen::MatrixXd S = subdivision_matrix(p, a, b);
    EXPECT_LT((S.rowwise().sum() - Eigen::VectorXd::Ones(p + 1)).norm(), 1e-13);
    for (int s = 0; s < 5; ++s) {
      const double t = unit(rng);
      EXPECT_NEAR(bernstein_basis(p, t).dot(S * c), bernstein_basis(p, a + t * (b - a)).dot(c), 1e-12);
    }
  }
}

TEST(BernsteinPoly, OctantsCarryThePolynomialAndTheHex) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> unit(0, 1), w(0.5, 2);
  const TensorBernstein f = random_tensor(rng, {4, 2, 3});
  const auto kids = subdivide(f);
  BezierHex h;
  h.degree = {2, 3, 1};
  for (int n = 0; n < h.num_points(); ++n) {
    h.points.push_back(Vector3d(unit(rng), unit(rng), unit(rng)));
    h.weights.push_back(w(rng));
  }
  const auto hk = subdivide(h);
  for (int c = 0; c < 8; ++c)
    for (int s = 0; s < 5; ++s) {
      const Vector3d y(unit(rng), unit(rng), unit(rng));
      const Vector3d x = 0.5 * (y + Vector3d(c & 1, (c >> 1) & 1, (c >> 2) & 1));
      EXPECT_NEAR(evaluate(kids[c], y), evaluate(f, x), 1e-13);
      EXPECT_LT((evaluate(hk[c], y) - evaluate(h, x)).norm(), 1e-13);
    }
}

TEST(BernsteinPoly, SimplexSubdivisionCarriesThePolynomial) {
  std::mt19937 rng(5);
  const SimplexBernstein f = random_simplex(rng, 5);
  const auto kids = subdivide(f);
  const auto ch = tet_split_children();
  for (int c = 0; c < 8; ++c) {
    const Vector3d y = random_in_tet(rng);
    const Eigen::Vector4d ly(1 - y.sum(), y[0], y[1], y[2]);
    Eigen::Vector4d lp = Eigen::Vector4d::Zero();
    for (int k = 0; k < 4; ++k) lp += ly[k] * ch[c][k];
    EXPECT_NEAR(evaluate(kids[c], y), evaluate(f, lp.tail<3>()), 1e-13);
  }
}

TEST(BernsteinPoly, MismatchedSizesAreRejected) {
  TensorBernstein f;
  f.degree = {1, 1, 1};
  f.coefs.resize(7);
  EXPECT_THROW(evaluate(f, Vector3d::Zero()), core::InvalidInputError);
  SimplexBernstein g;
  g.degree = 2;
  g.coefs.resize(4);
  EXPECT_THROW(multiply(g, g), core::InvalidInputError);
}
