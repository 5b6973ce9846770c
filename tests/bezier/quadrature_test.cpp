// Tests of bezier/quadrature.h: Gauss–Legendre rules on [0,1].
#include "bezier/quadrature.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/errors.h"

using namespace volts;
using namespace volts::bezier;

TEST(Quadrature, GaussLegendreIsExactToDegree2nMinus1) {
  for (int n = 1; n <= 20; ++n) {
    const auto x = gauss_legendre_points(n);
    const auto w = gauss_legendre_weights(n);
    ASSERT_EQ(x.size(), static_cast<std::size_t>(n));
    ASSERT_EQ(w.size(), static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      EXPECT_GT(x[i], 0.0);
      EXPECT_LT(x[i], 1.0);
      EXPECT_GT(w[i], 0.0);
      if (i > 0) {
        EXPECT_LT(x[i - 1], x[i]);
      }
      EXPECT_NEAR(x[i] + x[n - 1 - i], 1.0, 1e-15);  // symmetric
    }
    // ∫_0^1 (x - 1/3)^k: shifted monomials so that odd powers do not vanish by symmetry.
    for (int k = 0; k <= 2 * n; ++k) {
      double q = 0.0;
      for (int i = 0; i < n; ++i) q += w[i] * std::pow(x[i] - 1.0 / 3.0, k);
      const double exact = (std::pow(2.0 / 3.0, k + 1) - std::pow(-1.0 / 3.0, k + 1)) / (k + 1);
      if (k <= 2 * n - 1) {
        EXPECT_NEAR(q, exact, 1e-14) << "n=" << n << " k=" << k;
      } else if (n <= 6) {
        // Degree 2n is not exact: the error is the Gauss remainder (n!)^4 / ((2n+1) ((2n)!)^2).
        double remainder = 1.0 / (2 * n + 1);
        for (int i = 1; i <= n; ++i) remainder *= static_cast<double>(i) / (n + i) * i / (n + i);
        EXPECT_NEAR(exact - q, remainder, 1e-12 * remainder + 1e-15) << "n=" << n;
      }
    }
  }
  EXPECT_THROW(gauss_legendre_points(0), core::InvalidInputError);
}
