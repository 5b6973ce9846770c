// bezier::HexPoint: bit-identical to evaluate() (quality figures must not depend on which is used).
#include <gtest/gtest.h>

#include <random>

#include "bezier/hex_point.h"
#include "core/errors.h"

namespace volts::bezier {
namespace {

BezierHex random_hex(std::mt19937_64& rng, const std::array<int, 3>& degree, bool rational) {
  std::uniform_real_distribution<double> u(-1, 1);
  BezierHex h;
  h.degree = degree;
  for (int n = 0; n < h.num_points(); ++n) {
    const auto [i, j, k] = h.ijk(n);
    h.points.emplace_back(i + 0.3 * u(rng), j + 0.3 * u(rng), k + 0.3 * u(rng));
    if (rational) h.weights.push_back(1.5 + u(rng));
  }
  return h;
}

TEST(HexPoint, EqualsEvaluateBitForBit) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> t(0, 1);
  for (const std::array<int, 3>& degree : {std::array<int, 3>{3, 3, 3}, {1, 2, 4}}) {
    for (const bool rational : {false, true}) {
      for (int trial = 0; trial < 20; ++trial) {
        const Eigen::Vector3d uvw(trial == 0 ? 0.0 : t(rng), trial == 1 ? 1.0 : t(rng), t(rng));
        const HexPoint point(degree, uvw);
        const BezierHex h = random_hex(rng, degree, rational);
        Eigen::Matrix3d J, Jp;
        const Eigen::Vector3d x = evaluate(h, uvw, &J);
        EXPECT_EQ(point.evaluate(h, &Jp), x);
        EXPECT_EQ(Jp, J);
        EXPECT_EQ(point.evaluate(h), evaluate(h, uvw));
      }
    }
  }
}

TEST(HexPoints, EqualEvaluateBitForBit) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> t(0, 1);
  for (const std::array<int, 3>& degree : {std::array<int, 3>{3, 3, 3}, {2, 1, 3}}) {
    std::vector<Eigen::Vector3d> uvw = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()};
    for (int i = 0; i < 23; ++i) uvw.emplace_back(t(rng), t(rng), t(rng));
    const HexPoints points(degree, uvw);
    for (const bool rational : {false, true}) {
      const BezierHex h = random_hex(rng, degree, rational);
      std::vector<Eigen::Vector3d> xs, only;
      std::vector<Eigen::Matrix3d> Js;
      points.evaluate(h, &xs, &Js);
      points.evaluate(h, &only, nullptr);
      ASSERT_EQ(xs.size(), uvw.size());
      for (std::size_t p = 0; p < uvw.size(); ++p) {
        Eigen::Matrix3d J;
        EXPECT_EQ(xs[p], evaluate(h, uvw[p], &J));
        EXPECT_EQ(Js[p], J);
        EXPECT_EQ(only[p], xs[p]);
      }
    }
  }
}

TEST(HexPoint, RejectsOtherDegrees) {
  std::mt19937_64 rng(1);
  const HexPoint point({3, 3, 3}, Eigen::Vector3d(0.5, 0.5, 0.5));
  EXPECT_THROW(point.evaluate(random_hex(rng, {2, 3, 3}, false)), core::InvalidInputError);
  EXPECT_THROW(HexPoint({0, 3, 3}, Eigen::Vector3d::Zero()), core::InvalidInputError);
  const HexPoints points({3, 3, 3}, {Eigen::Vector3d(0.5, 0.5, 0.5)});
  std::vector<Eigen::Vector3d> xs;
  EXPECT_THROW(points.evaluate(random_hex(rng, {3, 3, 2}, false), &xs, nullptr), core::InvalidInputError);
}

}  // namespace
}  // namespace volts::bezier
