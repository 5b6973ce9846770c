// Tests of bezier/bspline_volume.h: Bézier extraction of tensor-product (rational) B-spline volumes.
#include "bezier/bspline_volume.h"

#include <gtest/gtest.h>

#include <random>

#include "bezier/bspline.h"
#include "core/errors.h"
#include "test_util.h"

using namespace volts;
using namespace volts::bezier;
using Eigen::Vector3d;
using volts::bezier::testing::random_knots;

namespace {

TensorBSplineVolume random_volume(std::mt19937& rng, bool rational, bool clamped) {
  std::uniform_int_distribution<int> deg(1, 4);
  std::uniform_real_distribution<double> coord(-1.0, 1.0), weight(0.3, 3.0);
  TensorBSplineVolume v;
  for (int d = 0; d < 3; ++d) {
    v.degree[d] = deg(rng);
    v.knots[d] = random_knots(rng, v.degree[d], clamped);
  }
  const auto n = v.num_points();
  const int count = n[0] * n[1] * n[2];
  for (int i = 0; i < count; ++i) v.points.emplace_back(coord(rng), coord(rng), coord(rng));
  if (rational)
    for (int i = 0; i < count; ++i) v.weights.push_back(weight(rng));
  return v;
}

}  // namespace

TEST(BSplineVolume, ExtractedHexesAgreeWithDirectEvaluation) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const bool rational = trial % 2 == 1, clamped = trial % 4 < 2;
    const TensorBSplineVolume v = random_volume(rng, rational, clamped);
    const auto hexes = extract_bezier_hexes(v);
    std::array<std::vector<std::array<double, 2>>, 3> iv;
    for (int d = 0; d < 3; ++d) iv[d] = element_intervals(v.knots[d], v.degree[d]);
    ASSERT_EQ(hexes.size(), iv[0].size() * iv[1].size() * iv[2].size());
    std::size_t e = 0;
    for (std::size_t c = 0; c < iv[2].size(); ++c)
      for (std::size_t b = 0; b < iv[1].size(); ++b)
        for (std::size_t a = 0; a < iv[0].size(); ++a, ++e) {
          const BezierHex& h = hexes[e];
          ASSERT_EQ(h.degree, v.degree);
          ASSERT_EQ(h.is_rational(), rational);
          const std::array<const std::array<double, 2>*, 3> box{&iv[0][a], &iv[1][b], &iv[2][c]};
          for (int s = 0; s < 8; ++s) {
            // t first, then x from t, so that short elements do not amplify rounding (see bspline_test).
            Vector3d t, x;
            for (int d = 0; d < 3; ++d) {
              const double a0 = (*box[d])[0], a1 = (*box[d])[1];
              t[d] = a0 + (s == 0 ? 0.0 : unit(rng)) * (a1 - a0);
              x[d] = (t[d] - a0) / (a1 - a0);
            }
            EXPECT_LT((evaluate(h, x) - evaluate(v, t)).norm(), 1e-12)
                << "trial " << trial << " element " << e << " degrees " << v.degree[0] << v.degree[1] << v.degree[2];
            ++checked;
          }
        }
  }
  EXPECT_GT(checked, 1000);
}

TEST(BSplineVolume, ClampedCornersInterpolateControlPoints) {
  std::mt19937 rng(32);
  const TensorBSplineVolume v = random_volume(rng, true, true);
  const auto hexes = extract_bezier_hexes(v);
  const auto n = v.num_points();
  // First element's corner (0,0,0) is control point 0; last element's corner (p,q,r) the last one.
  EXPECT_LT((hexes.front().points.front() - v.points.front()).norm(), 1e-14);
  EXPECT_NEAR(hexes.front().weights.front(), v.weights.front(), 1e-14);
  EXPECT_LT((hexes.back().points.back() - v.points.back()).norm(), 1e-13);
  EXPECT_EQ(static_cast<int>(v.points.size()), n[0] * n[1] * n[2]);
}

TEST(BSplineVolume, MalformedVolumesThrow) {
  std::mt19937 rng(33);
  TensorBSplineVolume v = random_volume(rng, false, true);
  v.points.pop_back();
  EXPECT_THROW(extract_bezier_hexes(v), core::InvalidInputError);
  v = random_volume(rng, true, true);
  v.weights[0] = -1.0;
  EXPECT_THROW(extract_bezier_hexes(v), core::InvalidInputError);
  v = random_volume(rng, false, true);
  std::swap(v.knots[1].front(), v.knots[1].back());
  EXPECT_THROW(evaluate(v, Vector3d(0.5, 0.5, 0.5)), core::InvalidInputError);
}
