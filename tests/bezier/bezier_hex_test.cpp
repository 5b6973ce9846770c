// Tests of bezier/bezier_hex.h: evaluation, Jacobians, scaled Jacobian, volume, elevation.
#include "bezier/bezier_hex.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bezier/quadrature.h"
#include "core/errors.h"

using namespace volts;
using namespace volts::bezier;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

// Degree-(p,q,r) hex whose control points sample the map f at the Greville points (i/p, j/q, k/r):
// exact for maps that are affine in each variable separately (Bernstein linear precision).
template <class F>
BezierHex hex_from_multilinear(const std::array<int, 3>& degree, F f) {
  BezierHex h;
  h.degree = degree;
  h.points.resize(h.num_points());
  for (int n = 0; n < h.num_points(); ++n) {
    const auto [i, j, k] = h.ijk(n);
    h.points[n] = f(Vector3d(double(i) / degree[0], double(j) / degree[1], double(k) / degree[2]));
  }
  return h;
}

Vector3d random_uvw(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  return {unit(rng), unit(rng), unit(rng)};
}

}  // namespace

TEST(BezierHex, IndexHelpersRoundTrip) {
  BezierHex h;
  h.degree = {2, 3, 4};
  for (int n = 0; n < h.num_points(); ++n) {
    const auto [i, j, k] = h.ijk(n);
    EXPECT_EQ(h.index(i, j, k), n);
  }
  EXPECT_EQ(h.num_points(), 3 * 4 * 5);
}

TEST(BezierHex, ElevatedTrilinearMapAndItsJacobianAreReproduced) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  for (int trial = 0; trial < 10; ++trial) {
    // Random trilinear map: corners of the unit cube, jittered.
    std::array<Vector3d, 8> c;
    for (int m = 0; m < 8; ++m)
      c[m] = Vector3d(m & 1, (m >> 1) & 1, (m >> 2) & 1) + Vector3d(jitter(rng), jitter(rng), jitter(rng));
    auto map = [&](const Vector3d& x, Matrix3d* J) {
      Vector3d out = Vector3d::Zero();
      if (J) J->setZero();
      for (int m = 0; m < 8; ++m) {
        const int a = m & 1, b = (m >> 1) & 1, d = (m >> 2) & 1;
        const double fu = a ? x[0] : 1 - x[0], fv = b ? x[1] : 1 - x[1], fw = d ? x[2] : 1 - x[2];
        const double su = a ? 1 : -1, sv = b ? 1 : -1, sw = d ? 1 : -1;
        out += fu * fv * fw * c[m];
        if (J) {
          J->col(0) += su * fv * fw * c[m];
          J->col(1) += fu * sv * fw * c[m];
          J->col(2) += fu * fv * sw * c[m];
        }
      }
      return out;
    };
    BezierHex lin = hex_from_multilinear({1, 1, 1}, [&](const Vector3d& x) { return map(x, nullptr); });
    for (const std::array<int, 3>& deg : {std::array<int, 3>{3, 3, 3}, std::array<int, 3>{2, 3, 4}}) {
      const BezierHex h = elevate_degree(lin, deg);
      ASSERT_EQ(h.degree, deg);
      ASSERT_FALSE(h.is_rational());
      for (int s = 0; s < 20; ++s) {
        const Vector3d uvw = random_uvw(rng);
        Matrix3d J, Jexact;
        const Vector3d x = evaluate(h, uvw, &J);
        EXPECT_LT((x - map(uvw, &Jexact)).norm(), 1e-14);
        EXPECT_LT((J - Jexact).cwiseAbs().maxCoeff(), 1e-13);
      }
    }
  }
}

TEST(BezierHex, ScaledJacobianOfBoxAndShearedHex) {
  const BezierHex box = hex_from_multilinear({3, 3, 3}, [](const Vector3d& x) {
    return Vector3d(2.0 * x[0] + 1.0, 0.5 * x[1], 3.0 * x[2]);
  });
  const JacobianSample sb = sample_jacobian(box, 4);
  EXPECT_NEAR(sb.min_scaled, 1.0, 1e-14);
  EXPECT_NEAR(sb.max_scaled, 1.0, 1e-14);
  EXPECT_NEAR(sb.min_det, 3.0, 1e-13);
  EXPECT_NEAR(sb.max_det, 3.0, 1e-13);

  // Affine shear x = A uvw: scaled Jacobian = det A / (|a0||a1||a2|) everywhere.
  Matrix3d A;
  A << 1.0, 0.7, 0.2,  //
      0.0, 1.0, -0.4,  //
      0.1, 0.0, 2.0;
  const BezierHex sheared = hex_from_multilinear({3, 2, 3}, [&](const Vector3d& x) { return Vector3d(A * x); });
  const double expected = A.determinant() / (A.col(0).norm() * A.col(1).norm() * A.col(2).norm());
  const JacobianSample ss = sample_jacobian(sheared, 3);
  EXPECT_NEAR(ss.min_scaled, expected, 1e-14);
  EXPECT_NEAR(ss.max_scaled, expected, 1e-14);
  EXPECT_LT(expected, 0.95);  // a real shear

  // Mirrored hex: negative everywhere.
  const BezierHex mirrored = hex_from_multilinear({2, 2, 2}, [](const Vector3d& x) { return Vector3d(-x[0], x[1], x[2]); });
  const JacobianSample sm = sample_jacobian(mirrored, 3);
  EXPECT_NEAR(sm.max_scaled, -1.0, 1e-14);
  EXPECT_LT(sm.max_det, 0.0);

  Matrix3d degenerate = Matrix3d::Identity();
  degenerate.col(1).setZero();
  EXPECT_EQ(scaled_jacobian(degenerate), 0.0);
  EXPECT_THROW(sample_jacobian(box, 0), core::InvalidInputError);
}

TEST(BezierHex, RationalQuarterCylinderShellIsExact) {
  // Quadratic rational arc in u (weights 1, √2/2, 1), linear in v (radius R1 -> R2), linear in w.
  // The arc runs clockwise so that (u, v, w) is right-handed.
  const double R1 = 1.5, R2 = 2.5, H = 0.75;
  BezierHex h;
  h.degree = {2, 1, 1};
  h.points.resize(h.num_points());
  h.weights.resize(h.num_points());
  const std::array<Eigen::Vector2d, 3> arc{Eigen::Vector2d(0, 1), Eigen::Vector2d(1, 1), Eigen::Vector2d(1, 0)};
  const std::array<double, 3> aw{1.0, std::sqrt(0.5), 1.0};
  for (int n = 0; n < h.num_points(); ++n) {
    const auto [i, j, k] = h.ijk(n);
    const double R = j ? R2 : R1;
    h.points[n] = Vector3d(R * arc[i][0], R * arc[i][1], k * H);
    h.weights[n] = aw[i];
  }
  std::mt19937 rng(22);
  const BezierHex elevated = elevate_degree(h, {3, 3, 3});
  ASSERT_TRUE(elevated.is_rational());
  for (const BezierHex* hex : std::array<const BezierHex*, 2>{&h, &elevated}) {
    for (int s = 0; s < 50; ++s) {
      const Vector3d uvw = random_uvw(rng);
      Matrix3d J;
      const Vector3d x = evaluate(*hex, uvw, &J);
      const double R = R1 + uvw[1] * (R2 - R1);
      EXPECT_NEAR(std::hypot(x[0], x[1]), R, 1e-14);
      EXPECT_NEAR(x[2], uvw[2] * H, 1e-15);
      EXPECT_GE(x[0], -1e-15);
      EXPECT_GE(x[1], -1e-15);
      // Exact derivatives: d/dv radial with length R2-R1, d/dw = (0,0,H), d/du tangential.
      const Vector3d radial(x[0] / std::hypot(x[0], x[1]), x[1] / std::hypot(x[0], x[1]), 0.0);
      EXPECT_LT((J.col(1) - (R2 - R1) * radial).norm(), 1e-13);
      EXPECT_LT((J.col(2) - Vector3d(0, 0, H)).norm(), 1e-13);
      EXPECT_NEAR(J.col(0).dot(radial), 0.0, 1e-13);
      // And against central differences of the map (checks the quotient rule numerically).
      const double hstep = 1e-6;
      const Vector3d du(hstep, 0, 0);
      const Vector3d fd = (evaluate(*hex, uvw + du) - evaluate(*hex, uvw - du)) / (2 * hstep);
      EXPECT_LT((fd - J.col(0)).norm(), 1e-7);
    }
    EXPECT_GT(sample_jacobian(*hex, 4).min_scaled, 0.99);  // the tangent, radial, axial frame
    // Volume of the shell: (π/4)(R2²-R1²)H; the integrand is rational, so Gauss is only accurate.
    EXPECT_NEAR(volume(*hex, 10), std::acos(-1.0) / 4 * (R2 * R2 - R1 * R1) * H, 1e-8);
  }
}

TEST(BezierHex, VolumeIsExactForPolynomialMaps) {
  const BezierHex cube = elevate_degree(hex_from_multilinear({1, 1, 1}, [](const Vector3d& x) { return x; }), {3, 3, 3});
  EXPECT_NEAR(volume(cube, 5), 1.0, 1e-14);
  // x = (u, v(1+αu), w(1+βv+γuv)): det J = (1+αu)(1+βv+γuv).
  const double a = 0.5, b = -0.3, g = 0.8;
  const BezierHex h = hex_from_multilinear({3, 3, 3}, [&](const Vector3d& x) {
    return Vector3d(x[0], x[1] * (1 + a * x[0]), x[2] * (1 + b * x[1] + g * x[0] * x[1]));
  });
  const double exact = (1 + b / 2) + a / 2 * (1 + b / 2) + g / 4 + a * g / 6;
  EXPECT_NEAR(volume(h, 5), exact, 1e-14);
  EXPECT_NEAR(volume(h, 3), exact, 1e-14);  // det J here is only degree 2 per direction
  std::mt19937 rng(23);
  for (int s = 0; s < 20; ++s) {
    Matrix3d J;
    const Vector3d uvw = random_uvw(rng);
    evaluate(h, uvw, &J);
    EXPECT_NEAR(J.determinant(), (1 + a * uvw[0]) * (1 + b * uvw[1] + g * uvw[0] * uvw[1]), 1e-14);
  }
}

TEST(BezierHex, MalformedHexesThrow) {
  BezierHex h;
  h.degree = {2, 2, 2};
  h.points.assign(26, Vector3d::Zero());
  EXPECT_THROW(evaluate(h, Vector3d(0.5, 0.5, 0.5)), core::InvalidInputError);
  h.points.assign(27, Vector3d::Zero());
  EXPECT_NO_THROW(evaluate(h, Vector3d(0.5, 0.5, 0.5)));
  h.weights.assign(27, 1.0);
  h.weights[5] = 0.0;
  EXPECT_THROW(volume(h, 2), core::InvalidInputError);
  h.weights.assign(3, 1.0);
  EXPECT_THROW(check(h), core::InvalidInputError);
  h.weights.clear();
  h.degree = {0, 2, 2};
  EXPECT_THROW(check(h), core::InvalidInputError);
  h.degree = {2, 2, 2};
  EXPECT_THROW(elevate_degree(h, {1, 2, 2}), core::InvalidInputError);
}

// jacobian_samples forms the Gauss grid's partial sums once per shared point: its matrices must be
// those of evaluate() at the corners and at the Gauss points (u fastest), for unequal degrees too.
TEST(BezierHex, JacobianSamplesAreTheJacobiansAtCornersAndGaussPoints) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  for (const std::array<int, 3> degree : {std::array<int, 3>{3, 3, 3}, std::array<int, 3>{2, 3, 1}}) {
    BezierHex h = hex_from_multilinear(degree, [](const Vector3d& u) { return Vector3d(u[0] + 0.2 * u[1] * u[2], u[1], u[2] + 0.1 * u[0]); });
    for (auto& p : h.points) p += Vector3d(jitter(rng), jitter(rng), jitter(rng));
    for (const int n : {1, 3, 4}) {
      const std::vector<Matrix3d> js = jacobian_samples(h, n);
      std::vector<Vector3d> at;
      for (int c = 0; c < 8; ++c) at.emplace_back(c & 1, (c >> 1) & 1, (c >> 2) & 1);
      const std::vector<double> g = gauss_legendre_points(n);
      for (const double w : g)
        for (const double v : g)
          for (const double u : g) at.emplace_back(u, v, w);
      ASSERT_EQ(js.size(), at.size());
      for (std::size_t s = 0; s < at.size(); ++s) {
        Matrix3d J;
        evaluate(h, at[s], &J);
        EXPECT_LT((js[s] - J).norm(), 1e-13 * J.norm()) << "degree " << degree[0] << degree[1] << degree[2] << ", n " << n << ", sample " << s;
      }
    }
  }
}

// With a uniform grid instead of the corners (grid_points > 2), and jacobian_grid: the Jacobians
// of evaluate() at k / (n - 1) (u fastest), then the Gauss points; polynomial and rational hexes.
TEST(BezierHex, GridSamplesAreTheJacobiansOnTheUniformGrid) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1), weight(0.5, 2.0);
  for (const bool rational : {false, true})
    for (const std::array<int, 3> degree : {std::array<int, 3>{3, 3, 3}, std::array<int, 3>{2, 3, 1}}) {
      BezierHex h = hex_from_multilinear(degree, [](const Vector3d& u) { return Vector3d(u[0] + 0.2 * u[1] * u[2], u[1], u[2] + 0.1 * u[0]); });
      for (auto& p : h.points) p += Vector3d(jitter(rng), jitter(rng), jitter(rng));
      if (rational)
        for (int i = 0; i < h.num_points(); ++i) h.weights.push_back(weight(rng));
      for (const int m : {2, 3, 5}) {
        std::vector<Vector3d> at;
        for (int k = 0; k < m; ++k)
          for (int j = 0; j < m; ++j)
            for (int i = 0; i < m; ++i) at.emplace_back(i / (m - 1.0), j / (m - 1.0), k / (m - 1.0));
        const std::vector<Matrix3d> grid = jacobian_grid(h, m);
        const std::size_t n_grid = at.size();
        const std::vector<double> g = gauss_legendre_points(3);
        for (const double w : g)
          for (const double v : g)
            for (const double u : g) at.emplace_back(u, v, w);
        const std::vector<Matrix3d> js = jacobian_samples(h, 3, m);
        ASSERT_EQ(js.size(), at.size());
        ASSERT_EQ(grid.size(), n_grid);
        double worst = 1;
        for (std::size_t s = 0; s < at.size(); ++s) {
          Matrix3d J;
          evaluate(h, at[s], &J);
          EXPECT_LT((js[s] - J).norm(), 1e-13 * J.norm()) << "rational " << rational << ", grid " << m << ", sample " << s;
          if (s < n_grid) {
            EXPECT_LT((grid[s] - J).norm(), 1e-13 * J.norm());
          }
          worst = std::min(worst, scaled_jacobian(J));
        }
        EXPECT_NEAR(sample_jacobian(h, 3, m).min_scaled, worst, 1e-12);
      }
      EXPECT_THROW(jacobian_grid(h, 1), core::InvalidInputError);
      EXPECT_THROW(jacobian_samples(h, 3, 1), core::InvalidInputError);
    }
}

// jacobian_tensor_grid at points that are not uniform (Gauss points, an uneven set), for two
// degrees in turn (its bases are cached per thread): evaluate()'s Jacobians, a fastest.
TEST(BezierHex, TensorGridJacobiansAreEvaluatesAtEveryPoint) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1), weight(0.5, 2.0);
  const std::vector<std::vector<double>> point_sets{gauss_legendre_points(5), {0.0, 0.13, 0.5, 0.91}};
  for (int pass = 0; pass < 2; ++pass)
    for (const bool rational : {false, true})
      for (const std::array<int, 3> degree : {std::array<int, 3>{3, 3, 3}, std::array<int, 3>{1, 2, 3}})
        for (const std::vector<double>& t : point_sets) {
          BezierHex h = hex_from_multilinear(degree, [](const Vector3d& u) { return Vector3d(u[0] + 0.3 * u[1] * u[2], u[1] - 0.1 * u[0], u[2]); });
          for (auto& p : h.points) p += Vector3d(jitter(rng), jitter(rng), jitter(rng));
          if (rational)
            for (int i = 0; i < h.num_points(); ++i) h.weights.push_back(weight(rng));
          const std::vector<Matrix3d> js = jacobian_tensor_grid(h, t);
          ASSERT_EQ(js.size(), t.size() * t.size() * t.size());
          std::size_t s = 0;
          for (const double w : t)
            for (const double v : t)
              for (const double u : t) {
                Matrix3d J;
                evaluate(h, Vector3d(u, v, w), &J);
                EXPECT_LT((js[s++] - J).norm(), 1e-13 * J.norm()) << "rational " << rational << ", at " << u << " " << v << " " << w;
              }
        }
}
