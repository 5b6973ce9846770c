// Tests of bezier/certify.h (algorithm Check, §4): folded elements are certified invalid with a
// witness where det J < 0 (checked by direct evaluation), a nearly degenerate valid element is
// certified only after subdivision, and the bounds enclose det J sampled densely.
#include "bezier/certify.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/errors.h"
#include "element_factory.h"

using namespace volts;
using namespace volts::bezier;
using namespace volts::bezier::testing;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

double det_at(const BezierHex& h, const Vector3d& x) {
  Matrix3d J;
  evaluate(h, x, &J);
  return J.determinant();
}

double det_at(const BezierTet& t, const Vector3d& x) {
  Matrix3d J;
  evaluate(t, x, &J);
  return J.determinant();
}

// The trilinear hex with corners c (VTK-free order: bit0 u, bit1 v, bit2 w), elevated to cubic.
BezierHex cubic_from_corners(const std::array<Vector3d, 8>& c) {
  BezierHex lin;
  lin.degree = {1, 1, 1};
  lin.points.assign(c.begin(), c.end());
  return elevate_degree(lin, {3, 3, 3});
}

double min_sampled(const BezierHex& h, int n) {
  double m = INFINITY;
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) m = std::min(m, det_at(h, Vector3d(i, j, k) / n));
  return m;
}

}  // namespace

TEST(Certify, RandomValidHexesAreValidAndBoundsEncloseSamples) {
  std::mt19937 rng(21);
  for (int t = 0; t < 20; ++t) {
    const bool rational = t % 2;
    const BezierHex h = perturbed_hex(rng, {3, 3, 3}, 0.05, rational);
    const CertifyResult r = certify(h);
    ASSERT_EQ(r.status, Validity::valid);
    const double sampled = min_sampled(h, 12);
    EXPECT_LE(r.min_detj_lower, sampled * (1 + 1e-12));
    EXPECT_GT(r.min_detj_lower, 0);
    EXPECT_NEAR(r.min_detj_upper, det_at(h, r.witness), 1e-12 * std::abs(r.min_detj_upper));
    EXPECT_LE(r.min_detj_lower, r.min_detj_upper);
    // The mean is the volume (reference volume 1); Gauss with 6 points is exact for polynomial det J.
    EXPECT_NEAR(r.mean_detj, volume(h, 6), (rational ? 1e-6 : 1e-12) * r.mean_detj);
  }
}

TEST(Certify, TwistedHexIsInvalidWithAWitness) {
  // Top face twisted: its corners over (1,0) and (1,1) swapped, so the element folds near them.
  std::array<Vector3d, 8> c;
  for (int m = 0; m < 8; ++m) c[m] = Vector3d(m & 1, (m >> 1) & 1, (m >> 2) & 1);
  std::swap(c[5], c[7]);
  const BezierHex h = cubic_from_corners(c);
  const CertifyResult r = certify(h);
  ASSERT_EQ(r.status, Validity::invalid);
  EXPECT_LT(det_at(h, r.witness), 0.0);
  EXPECT_NEAR(det_at(h, r.witness), r.min_detj_upper, 1e-12);
  EXPECT_LE(r.min_detj_lower, r.min_detj_upper);
}

TEST(Certify, InteriorFoldIsFoundBySubdivision) {
  // A fold strictly inside (no corner sees it): a valid cubic hex with one interior control point
  // pushed far along -u, which makes x_u negative around it.
  std::mt19937 rng(22);
  BezierHex h = perturbed_hex(rng, {3, 3, 3}, 0.0, false);
  h.points[h.index(2, 1, 1)] += Vector3d(-8.0, 0, 0);  // x_u ~ 1 - 8 (4/9)^2 < 0 near (1/3, 1/3, 1/3)
  const CertifyResult r = certify(h);
  ASSERT_EQ(r.status, Validity::invalid);
  EXPECT_LT(det_at(h, r.witness), 0.0);
  EXPECT_GT(r.subdivisions, 0);
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(r.witness[k] > 0 && r.witness[k] < 1);
}

TEST(Certify, TetWithInvertedCornerIsInvalidWithAWitness) {
  std::mt19937 rng(23);
  BezierTet t = perturbed_tet(rng, 2, 0.0, false);
  t.points[simplex_index(3, 2, 1, 0, 0)] = Vector3d(-0.6, 0, 0);  // x_u < 0 at vertex (0,0,0)
  const CertifyResult r = certify(t);
  ASSERT_EQ(r.status, Validity::invalid);
  EXPECT_LT(det_at(t, r.witness), 0.0);
  EXPECT_NEAR(det_at(t, r.witness), r.min_detj_upper, 1e-12);
  // The same tet unperturbed, and random valid ones (also rational), are valid.
  for (int n = 1; n <= 4; ++n) {
    const BezierTet v = perturbed_tet(rng, n, 0.03, n % 2 == 0);
    const CertifyResult rv = certify(v);
    EXPECT_EQ(rv.status, Validity::valid) << n;
    for (int s = 0; s < 50; ++s) EXPECT_LE(rv.min_detj_lower, det_at(v, random_in_tet(rng)) * (1 + 1e-12));
  }
}

TEST(Certify, NearlyDegenerateValidHexNeedsSubdivision) {
  // x = R s (f(u), v, w) with f(u) = (u - 1/2)^3 + εu: det J = s^3 (3(u - 1/2)^2 + ε), whose minimum
  // s^3 ε is 1e-6 of its mean s^3 (1/4 + ε). Cubic Bernstein coefficients of f, rotated and scaled.
  const double eps = 0.25e-6 / (1 - 0.25e-6) * 1.0, s = 2.5;
  const double fc[4] = {-0.125, 0.125 + eps / 3, -0.125 + 2 * eps / 3, 0.125 + eps};
  const Matrix3d R = Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  BezierHex h;
  h.degree = {3, 3, 3};
  for (int n = 0; n < 64; ++n) {
    const auto [i, j, k] = h.ijk(n);
    h.points.push_back(s * R * Vector3d(fc[i], j / 3.0, k / 3.0) + Vector3d(1, -2, 0.5));
  }
  const double min_true = s * s * s * eps, mean = s * s * s * (0.25 + eps);
  EXPECT_NEAR(min_true / mean, 1e-6, 1e-9);
  EXPECT_NEAR(det_at(h, Vector3d(0.5, 0.3, 0.9)), min_true, 1e-12);

  CertifyParams no_subdivision;
  no_subdivision.max_depth = 0;
  const CertifyResult r0 = certify(h, no_subdivision);
  EXPECT_EQ(r0.status, Validity::undecided);
  EXPECT_LT(r0.min_detj_lower, 0.0);  // some coefficient is negative: not decidable unsubdivided
  EXPECT_GT(r0.min_detj_upper, 0.0);

  const CertifyResult r = certify(h);
  ASSERT_EQ(r.status, Validity::valid);
  EXPECT_GE(r.depth, 1);
  EXPECT_GT(r.subdivisions, 0);
  EXPECT_GT(r.min_detj_lower, 0.0);
  EXPECT_LE(r.min_detj_lower, min_true * (1 + 1e-6));
  EXPECT_GE(r.min_detj_upper, min_true * (1 - 1e-6));
}

TEST(Certify, BarePolynomialsAndParameters) {
  // f = (u - 1/2)^2 - 1e-4 on the cube is negative near u = 1/2: invalid within a few levels.
  TensorBernstein f;
  f.degree = {2, 0, 0};
  f.coefs = {0.25 - 1e-4, -0.25 - 1e-4, 0.25 - 1e-4};
  const CertifyResult r = certify(f);
  EXPECT_EQ(r.status, Validity::invalid);
  EXPECT_LE(std::pow(r.witness[0] - 0.5, 2) - 1e-4, 0.0);
  SimplexBernstein g{0, {2.0}};
  const CertifyResult rg = certify(g);
  EXPECT_EQ(rg.status, Validity::valid);
  EXPECT_EQ(rg.min_detj_lower, 2.0);
  CertifyParams bad;
  bad.max_depth = 21;
  EXPECT_THROW(certify(g, bad), core::InvalidInputError);
  EXPECT_STREQ(to_string(Validity::undecided), "undecided");
}
