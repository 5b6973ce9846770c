#include "bezier/quadrature.h"

#include <cmath>
#include <string>
#include <utility>

#include "core/errors.h"

namespace volts::bezier {

namespace {

// Points and weights on [0,1]; the roots of P_n on [-1,1] by Newton from Chebyshev-like guesses,
// mirrored so the rule is exactly symmetric.
std::pair<std::vector<double>, std::vector<double>> gauss_legendre(int n) {
  if (n < 1 || n > 1000)
    throw core::InvalidInputError("gauss_legendre: number of points " + std::to_string(n) + " not in [1, 1000]");
  const double pi = std::acos(-1.0);
  std::vector<double> t(n), w(n);
  // P_n(x) and P_n'(x) by the three-term recurrence; P_n' = n (x P_n - P_{n-1}) / (x^2 - 1).
  auto legendre = [n](double x, double& dp) {
    double p0 = 1.0, p1 = x;
    for (int k = 2; k <= n; ++k) {
      const double pk = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
      p0 = p1;
      p1 = pk;
    }
    dp = n * (x * p1 - p0) / (x * x - 1.0);
    return p1;
  };
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double x = std::cos(pi * (i + 0.75) / (n + 0.5));  // i-th largest root, approximately
    double dp = 0.0;
    if (2 * i + 1 == n) {
      x = 0.0;  // middle root of odd n, exactly
    } else {
      for (int iter = 0; iter < 100; ++iter) {
        const double dx = legendre(x, dp) / dp;
        x -= dx;
        if (std::abs(dx) <= 1e-15 * std::abs(x)) break;
      }
    }
    legendre(x, dp);
    const double weight = 1.0 / ((1.0 - x * x) * dp * dp);  // 2/((1-x^2)P'^2), halved for [0,1]
    t[i] = 0.5 * (1.0 - x);
    t[n - 1 - i] = 0.5 * (1.0 + x);
    w[i] = w[n - 1 - i] = weight;
  }
  return {t, w};
}

}  // namespace

std::vector<double> gauss_legendre_points(int n) { return gauss_legendre(n).first; }

std::vector<double> gauss_legendre_weights(int n) { return gauss_legendre(n).second; }

}  // namespace volts::bezier
