// Tests of bezier/bspline.h: basis functions, Greville abscissae, 1D Bézier extraction.
#include "bezier/bspline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bezier/bernstein.h"
#include "core/errors.h"
#include "test_util.h"

using namespace volts;
using namespace volts::bezier;
using volts::bezier::testing::random_knots;

namespace {

// Random parameters in the domain, plus every knot in it and both ends (the hard cases).
std::vector<double> sample_params(std::mt19937& rng, const std::vector<double>& knots, int p) {
  const int n = static_cast<int>(knots.size()) - p - 1;
  const double a = knots[p], b = knots[n];
  std::uniform_real_distribution<double> t(a, b);
  std::vector<double> ts;
  for (int i = 0; i < 30; ++i) ts.push_back(t(rng));
  for (double k : knots)
    if (k >= a && k <= b) ts.push_back(k);
  return ts;
}

}  // namespace

TEST(BSpline, PartitionOfUnityAndNonNegativity) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 200; ++trial) {
    const int p = trial % 5;
    const auto knots = random_knots(rng, p, trial % 2 == 0);
    for (double t : sample_params(rng, knots, p)) {
      const BasisValues b = basis_functions(knots, p, t, true);
      ASSERT_EQ(b.values.size(), p + 1);
      EXPECT_NEAR(b.values.sum(), 1.0, 1e-14) << "t=" << t << " p=" << p;
      EXPECT_GE(b.values.minCoeff(), 0.0);
      // Derivatives of a partition of unity sum to zero (scale: 1/shortest span).
      EXPECT_NEAR(b.derivatives.sum(), 0.0, 1e-9 * (1.0 + b.derivatives.cwiseAbs().maxCoeff()));
      // The span really contains t and is non-empty.
      EXPECT_LE(knots[b.span], t);
      EXPECT_LT(knots[b.span], knots[b.span + 1]);
      EXPECT_TRUE(t < knots[b.span + 1] || t == knots[knots.size() - p - 1]);
    }
  }
}

TEST(BSpline, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(2);
  for (int trial = 0; trial < 100; ++trial) {
    const int p = 1 + trial % 4;
    const auto knots = random_knots(rng, p, trial % 2 == 0);
    const int n = static_cast<int>(knots.size()) - p - 1;
    std::uniform_real_distribution<double> unif(knots[p], knots[n]);
    const double t = unif(rng);
    const BasisValues b = basis_functions(knots, p, t, true);
    const double h = 1e-7;
    // Stay inside the span so the functions are smooth on [t-h, t+h].
    if (t - h <= knots[b.span] || t + h >= knots[b.span + 1]) continue;
    const BasisValues bp = basis_functions(knots, p, t + h), bm = basis_functions(knots, p, t - h);
    ASSERT_EQ(bp.span, b.span);
    ASSERT_EQ(bm.span, b.span);
    const Eigen::VectorXd fd = (bp.values - bm.values) / (2 * h);
    EXPECT_LT((fd - b.derivatives).cwiseAbs().maxCoeff(), 1e-5 * (1.0 + b.derivatives.cwiseAbs().maxCoeff()));
  }
}

TEST(BSpline, GrevilleAbscissae) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 60; ++trial) {
    const int p = 1 + trial % 4;
    const auto knots = random_knots(rng, p, true);
    const auto g = greville_abscissae(knots, p);
    ASSERT_EQ(g.size(), knots.size() - p - 1);
    EXPECT_EQ(g.front(), 0.0);
    EXPECT_EQ(g.back(), 1.0);
    for (std::size_t i = 1; i < g.size(); ++i) EXPECT_LE(g[i - 1], g[i]);
    // Linear precision: sum_i g_i N_i(t) = t.
    for (double t : sample_params(rng, knots, p)) {
      const BasisValues b = basis_functions(knots, p, t);
      double x = 0.0;
      for (int k = 0; k <= p; ++k) x += g[b.span - p + k] * b.values[k];
      EXPECT_NEAR(x, t, 1e-14);
    }
  }
}

TEST(BSpline, OpenUniformKnots) {
  for (int p = 0; p <= 4; ++p)
    for (int e = 1; e <= 6; ++e) {
      const auto k = open_uniform_knots(e, p);
      ASSERT_EQ(k.size(), static_cast<std::size_t>(e + 2 * p + 1));
      EXPECT_EQ(k.front(), 0.0);
      EXPECT_EQ(k.back(), 1.0);
      EXPECT_NO_THROW(check_knot_vector(k, p));
      const auto iv = element_intervals(k, p);
      ASSERT_EQ(iv.size(), static_cast<std::size_t>(e));
      for (const auto& [a, b] : iv) EXPECT_NEAR(b - a, 1.0 / e, 1e-15);
    }
  EXPECT_THROW(open_uniform_knots(0, 2), core::InvalidInputError);
  EXPECT_THROW(open_uniform_knots(2, -1), core::InvalidInputError);
}

TEST(BSpline, ExtractionOperatorsReproduceBasis) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int p = 1 + trial % 4;
    const auto knots = random_knots(rng, p, trial % 3 != 0);  // unclamped every third
    const auto ops = extraction_operators(knots, p);
    const auto spans = element_spans(knots, p);
    const auto iv = element_intervals(knots, p);
    ASSERT_EQ(ops.size(), spans.size());
    ASSERT_EQ(ops.size(), iv.size());
    for (std::size_t e = 0; e < ops.size(); ++e) {
      ASSERT_EQ(ops[e].rows(), p + 1);
      ASSERT_EQ(ops[e].cols(), p + 1);
      // Columns sum to 1 (partition of unity in both bases).
      EXPECT_LT((ops[e].colwise().sum().array() - 1.0).abs().maxCoeff(), 1e-14);
      for (int s = 0; s < 10; ++s) {
        // Pick t in the element, then x from t (not the reverse: on a short element the rounding
        // of t would be amplified by 1/(b-a) in x). [a,b): b belongs to the next element.
        const double t = iv[e][0] + (s == 0 ? 0.0 : unit(rng)) * (iv[e][1] - iv[e][0]);
        const double x = (t - iv[e][0]) / (iv[e][1] - iv[e][0]);
        const Eigen::VectorXd via_extraction = ops[e] * bernstein_basis(p, x);
        const BasisValues b = basis_functions(knots, p, t);
        ASSERT_EQ(b.span, spans[e]);
        EXPECT_LT((via_extraction - b.values).cwiseAbs().maxCoeff(), 1e-13)
            << "p=" << p << " element " << e << " x=" << x;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 5000);
}

TEST(BSpline, ExtractionOfC0KnotsIsIdentityAtBoundaries) {
  // With every interior knot of multiplicity p the B-spline basis already is piecewise Bernstein:
  // every operator is the identity.
  for (int p = 1; p <= 4; ++p) {
    std::vector<double> knots(p + 1, 0.0);
    for (double x : {0.25, 0.5, 0.8}) knots.insert(knots.end(), p, x);
    knots.insert(knots.end(), p + 1, 1.0);
    for (const auto& C : extraction_operators(knots, p))
      EXPECT_LT((C - Eigen::MatrixXd::Identity(p + 1, p + 1)).cwiseAbs().maxCoeff(), 1e-15);
  }
}

// Knot refinement: the refined basis reproduces every coarse function, so a spline and its
// refined control points Rᵀ·P are one curve; clamped coarse bases keep their rows summing to one.
TEST(BSpline, RefinementMatrixReproducesTheCoarseBasis) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 100; ++trial) {
    const int p = 1 + trial % 4;
    const auto coarse = random_knots(rng, p, true);
    std::vector<double> fine = coarse;
    const int extra = 1 + trial % 5;
    for (int i = 0; i < extra; ++i) fine.push_back(unit(rng));
    if (trial % 3 == 0)  // an existing interior knot again (raised multiplicity)
      for (const double k : coarse)
        if (k > 0 && k < 1 && std::count(coarse.begin(), coarse.end(), k) < p) {
          fine.push_back(k);
          break;
        }
    std::sort(fine.begin(), fine.end());
    const Eigen::MatrixXd R = refinement_matrix(coarse, fine, p);
    const int nc = static_cast<int>(coarse.size()) - p - 1, nf = static_cast<int>(fine.size()) - p - 1;
    ASSERT_EQ(R.rows(), nc);
    ASSERT_EQ(R.cols(), nf);
    EXPECT_GE(R.minCoeff(), -1e-15);
    for (int j = 0; j < nf; ++j) EXPECT_NEAR(R.col(j).sum(), 1.0, 1e-13) << "fine function " << j;  // Rᵀ·1 = 1
    for (double t : sample_params(rng, fine, p)) {
      const BasisValues bc = basis_functions(coarse, p, t), bf = basis_functions(fine, p, t);
      for (int i = 0; i < nc; ++i) {
        const double want = (i >= bc.span - p && i <= bc.span) ? bc.values[i - (bc.span - p)] : 0.0;
        double got = 0;
        for (int k = 0; k <= p; ++k) got += R(i, bf.span - p + k) * bf.values[k];
        EXPECT_NEAR(got, want, 1e-13) << "t=" << t << " p=" << p << " coarse function " << i;
      }
    }
  }
  // Uniform doubling, the T-mesh's refinement of a cube: the fine control polygon of the line
  // x = t (Greville points) is the fine Greville points.
  const auto c4 = open_uniform_knots(4, 3), c8 = open_uniform_knots(8, 3);
  const Eigen::MatrixXd R = refinement_matrix(c4, c8, 3);
  const auto gc = greville_abscissae(c4, 3), gf = greville_abscissae(c8, 3);
  for (int j = 0; j < static_cast<int>(gf.size()); ++j) {
    double x = 0;
    for (int i = 0; i < static_cast<int>(gc.size()); ++i) x += R(i, j) * gc[static_cast<std::size_t>(i)];
    EXPECT_NEAR(x, gf[static_cast<std::size_t>(j)], 1e-15);
  }
  EXPECT_THROW(refinement_matrix(c8, c4, 3), core::InvalidInputError);  // coarsening
  EXPECT_THROW(refinement_matrix(open_uniform_knots(3, 3), c4, 3), core::InvalidInputError);  // 1/3 not in c4
}

TEST(BSpline, InvalidArgumentsThrow) {
  const std::vector<double> good{0, 0, 0, 0.5, 1, 1, 1};
  EXPECT_NO_THROW(find_span(good, 2, 0.3));
  EXPECT_THROW(find_span({0, 0, 0.6, 0.5, 1, 1}, 1, 0.3), core::InvalidInputError);  // decreasing
  EXPECT_THROW(find_span({0, 0, 1}, 1, 0.3), core::InvalidInputError);               // too few
  EXPECT_THROW(find_span(good, -1, 0.3), core::InvalidInputError);
  EXPECT_THROW(find_span(good, 2, 1.5), core::InvalidInputError);  // outside the domain
  EXPECT_THROW(find_span(good, 2, -0.1), core::InvalidInputError);
  EXPECT_THROW(find_span(good, 2, std::nan("")), core::InvalidInputError);
  EXPECT_THROW(extraction_operators({0, 0, 0, 0.5, 0.5, 0.5, 0.5, 1, 1, 1}, 2), core::InvalidInputError);
  EXPECT_THROW(greville_abscissae({0, 0, std::nan(""), 1, 1}, 1), core::InvalidInputError);
  EXPECT_THROW(basis_functions({0, 0.5, 0.5, 1}, 1, 0.5), core::InvalidInputError);  // empty domain
  EXPECT_EQ(find_span(good, 2, 1.0), 3);  // right end: last non-empty span
  EXPECT_EQ(find_span(good, 2, 0.5), 3);
}
