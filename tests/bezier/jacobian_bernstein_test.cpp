// Tests of bezier/jacobian_bernstein.h: the Bernstein coefficients of det J reproduce direct
// evaluation (de Casteljau Jacobians) at random points, for hexes of degree 1–4 (isotropic,
// anisotropic, rational) and tets of degree 1–4 (polynomial, rational).
#include "bezier/jacobian_bernstein.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "element_factory.h"

using namespace volts::bezier;
using namespace volts::bezier::testing;
using Eigen::Vector3d;

namespace {

// Rational elements: the polynomial is W^4 det J.
template <class E>
double weight_at(const E& e, const Vector3d& x);

template <>
double weight_at(const BezierHex& h, const Vector3d& x) {
  if (!h.is_rational()) return 1;
  TensorBernstein W{h.degree, h.weights};
  return evaluate(W, x);
}

template <>
double weight_at(const BezierTet& t, const Vector3d& x) {
  if (!t.is_rational()) return 1;
  SimplexBernstein W{t.degree, t.weights};
  return evaluate(W, x);
}

}  // namespace

TEST(JacobianBernstein, HexCoefficientsReproduceDirectEvaluation) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0, 1);
  const std::array<int, 3> degrees[] = {{1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {4, 4, 4}, {1, 2, 3}, {4, 1, 2}, {3, 4, 1}};
  for (const auto& d : degrees)
    for (bool rational : {false, true}) {
      const BezierHex h = perturbed_hex(rng, d, 0.08, rational);
      const TensorBernstein J = jacobian_determinant(h);
      const int extra = rational ? 1 : 0;  // D has degree 4p-1, det J 3p-1
      for (int k = 0; k < 3; ++k) EXPECT_EQ(J.degree[k], (3 + extra) * d[k] - 1);
      for (int s = 0; s < 20; ++s) {
        const Vector3d x(unit(rng), unit(rng), unit(rng));
        Eigen::Matrix3d Jm;
        evaluate(h, x, &Jm);
        const double direct = Jm.determinant(), W = weight_at(h, x);
        const double from_bernstein = evaluate(J, x) / std::pow(W, 4);
        EXPECT_NEAR(from_bernstein, direct, 1e-12 * std::abs(direct))
            << "degree " << d[0] << d[1] << d[2] << (rational ? " rational" : "");
      }
    }
}

TEST(JacobianBernstein, AllocationFreeVariantMatches) {
  std::mt19937 rng(12);
  TensorBernstein out;
  for (int t = 0; t < 3; ++t) {
    const BezierHex h = perturbed_hex(rng, {3, 3, 3}, 0.1, false);
    jacobian_determinant(h, out);
    const TensorBernstein ref = jacobian_determinant(h);
    ASSERT_EQ(out.coefs.size(), ref.coefs.size());
    for (std::size_t i = 0; i < out.coefs.size(); ++i) EXPECT_EQ(out.coefs[i], ref.coefs[i]);
  }
}

TEST(JacobianBernstein, TetCoefficientsReproduceDirectEvaluation) {
  std::mt19937 rng(13);
  for (int n = 1; n <= 4; ++n)
    for (bool rational : {false, true}) {
      const BezierTet t = perturbed_tet(rng, n, 0.06, rational);
      const SimplexBernstein J = jacobian_determinant(t);
      EXPECT_EQ(J.degree, rational ? 4 * n - 3 : 3 * (n - 1));
      for (int s = 0; s < 20; ++s) {
        const Vector3d x = random_in_tet(rng);
        Eigen::Matrix3d Jm;
        evaluate(t, x, &Jm);
        const double direct = Jm.determinant();
        EXPECT_NEAR(evaluate(J, x) / std::pow(weight_at(t, x), 4), direct, 1e-12 * std::abs(direct))
            << "degree " << n << (rational ? " rational" : "");
      }
    }
}
