// Theorem 1 (Xu et al. 2018): the degenerate hex of a Bézier tet is the same map: H(r,s,t) =
// T(ψ⁻¹(r,s,t)) at 1,000 random points, for random polynomial and rational tets of degree 1–4.
#include <gtest/gtest.h>

#include "core/errors.h"
#include "tet2hex/convert.h"
#include "test_util.h"

using namespace volts;
using namespace volts::tet2hex;

namespace {
Eigen::Vector3d psi_inverse(const Eigen::Vector3d& rst) {  // eq. (11)
  const double r = rst[0], s = rst[1], t = rst[2];
  return {r, (1 - r) * s, (1 - r) * (1 - s) * t};
}
}  // namespace

class DegenerateHex : public ::testing::TestWithParam<std::tuple<int, bool>> {};

TEST_P(DegenerateHex, AgreesWithTheTetAtRandomPoints) {
  const auto [n, rational] = GetParam();
  std::mt19937 rng(100 + n + 10 * rational);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    const bezier::BezierTet tet = test::random_tet(rng, n, 0.1, rational);
    const bezier::BezierHex hex = degenerate_hex(tet);
    ASSERT_EQ(hex.degree, (std::array<int, 3>{n, n, n}));
    EXPECT_EQ(hex.is_rational(), rational);
    double worst = 0;
    for (int i = 0; i < 1000; ++i) {
      const Eigen::Vector3d rst(u(rng), u(rng), u(rng));
      worst = std::max(worst, (bezier::evaluate(hex, rst) - bezier::evaluate(tet, psi_inverse(rst))).norm());
    }
    EXPECT_LE(worst, 1e-12 * test::size(tet)) << "degree " << n << " trial " << trial;
  }
}

// The face r = 1 collapses onto the tet's corner u = 1 (Theorem 2's degeneracy), s = 1 onto an edge.
TEST_P(DegenerateHex, CollapsedFaces) {
  const auto [n, rational] = GetParam();
  std::mt19937 rng(7 + n);
  const bezier::BezierTet tet = test::random_tet(rng, n, 0.1, rational);
  const bezier::BezierHex hex = degenerate_hex(tet);
  const Eigen::Vector3d apex = tet.points[bezier::simplex_index(3, n, n, 0, 0)];
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j) EXPECT_LE((hex.points[hex.index(n, j, k)] - apex).norm(), 1e-13 * test::size(tet));
}

// Theorem 1 by degree elevation (eq. (5)–(7)) equals the general blossom composition (eq. (12)) with
// ψ⁻¹'s corners: two independent computations of the same control points.
TEST_P(DegenerateHex, MatchesTheBlossomComposition) {
  const auto [n, rational] = GetParam();
  std::mt19937 rng(31 + n);
  const bezier::BezierTet tet = test::random_tet(rng, n, 0.1, rational);
  std::array<Eigen::Vector4d, 8> corners;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d uvw = psi_inverse(Eigen::Vector3d(c & 1, (c >> 1) & 1, (c >> 2) & 1));
    corners[c] << 1 - uvw.sum(), uvw;
  }
  const bezier::BezierHex a = degenerate_hex(tet), b = compose_trilinear(tet, corners);
  for (int i = 0; i < a.num_points(); ++i) {
    EXPECT_LE((a.points[i] - b.points[i]).norm(), 1e-13 * test::size(tet));
    EXPECT_NEAR(a.weight(i), b.weight(i), 1e-13);
  }
}

INSTANTIATE_TEST_SUITE_P(Degrees, DegenerateHex,
                         ::testing::Combine(::testing::Values(1, 2, 3, 4), ::testing::Bool()));

TEST(DegenerateHexErrors, MalformedTetIsRefused) {
  bezier::BezierTet t;
  t.degree = 2;
  t.points.resize(5);
  EXPECT_THROW(degenerate_hex(t), core::InvalidInputError);
  EXPECT_THROW(four_hexes(t), core::InvalidInputError);
  EXPECT_THROW(subdomain_corners(4), core::InvalidInputError);
}
