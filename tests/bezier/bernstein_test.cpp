// Tests of bezier/bernstein.h: Bernstein basis and degree elevation.
#include "bezier/bernstein.h"

#include <gtest/gtest.h>

#include <random>

#include "core/errors.h"

using namespace volts;
using namespace volts::bezier;

namespace {
double eval(const Eigen::VectorXd& coeffs, double x) {
  return coeffs.dot(bernstein_basis(static_cast<int>(coeffs.size()) - 1, x));
}
}  // namespace

TEST(Bernstein, PartitionOfUnityNonNegativityAndDerivatives) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int p = 0; p <= 8; ++p)
    for (int s = 0; s < 50; ++s) {
      const double x = s == 0 ? 0.0 : s == 1 ? 1.0 : unit(rng);
      Eigen::VectorXd d;
      const Eigen::VectorXd B = bernstein_basis(p, x, &d);
      ASSERT_EQ(B.size(), p + 1);
      ASSERT_EQ(d.size(), p + 1);
      EXPECT_NEAR(B.sum(), 1.0, 1e-15);
      EXPECT_GE(B.minCoeff(), 0.0);
      EXPECT_NEAR(d.sum(), 0.0, 1e-12);
      // Linear precision: sum (i/p) B_i = x, so sum (i/p) B_i' = 1.
      if (p > 0) {
        const Eigen::VectorXd g = Eigen::VectorXd::LinSpaced(p + 1, 0.0, 1.0);
        EXPECT_NEAR(g.dot(B), x, 1e-15);
        EXPECT_NEAR(g.dot(d), 1.0, 1e-13);
      }
      const double h = 1e-6;
      if (x > h && x < 1 - h) {
        const Eigen::VectorXd fd = (bernstein_basis(p, x + h) - bernstein_basis(p, x - h)) / (2 * h);
        EXPECT_LT((fd - d).cwiseAbs().maxCoeff(), 1e-6 * (1 + d.cwiseAbs().maxCoeff()));
      }
    }
  // End-point interpolation: only B_0 at 0 and only B_p at 1.
  EXPECT_EQ(bernstein_basis(4, 0.0)[0], 1.0);
  EXPECT_EQ(bernstein_basis(4, 1.0)[4], 1.0);
  EXPECT_THROW(bernstein_basis(-1, 0.5), core::InvalidInputError);
}

TEST(Bernstein, DegreeElevationPreservesThePolynomial) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> unit(0.0, 1.0), coef(-2.0, 2.0);
  for (int from = 0; from <= 5; ++from)
    for (int to = from; to <= 8; ++to) {
      const Eigen::MatrixXd E = degree_elevation_matrix(from, to);
      ASSERT_EQ(E.rows(), to + 1);
      ASSERT_EQ(E.cols(), from + 1);
      EXPECT_LT((E.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-14);
      EXPECT_GE(E.minCoeff(), 0.0);
      Eigen::VectorXd c(from + 1);
      for (int i = 0; i <= from; ++i) c[i] = coef(rng);
      const Eigen::VectorXd ce = E * c;
      for (int s = 0; s < 10; ++s) {
        const double x = unit(rng);
        EXPECT_NEAR(eval(ce, x), eval(c, x), 1e-13);
      }
    }
  EXPECT_THROW(degree_elevation_matrix(3, 2), core::InvalidInputError);
}
