// extract::global_basis on a hand-built two-block spline sharing a face: partition of unity,
// reproduction of the Bézier points, one id per shared function referenced from both sides, and
// the errors for inconsistent input.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/errors.h"
#include "extract/two_blocks.h"

using namespace volts;

namespace {

bool has(const std::vector<int>& v, int x) { return std::binary_search(v.begin(), v.end(), x); }

// The message of the E that global_basis throws on these blocks and hexes ("<no error>" if none).
template <class E>
std::string error_of(const std::vector<tmesh::TMesh>& ts, const std::vector<bezier::BezierHex>& hexes) {
  try {
    extract::global_basis(ts, hexes);
  } catch (const E& e) {
    return e.what();
  }
  return "<no error>";
}

}  // namespace

TEST(GlobalBasis, SharedFaceGivesOneIdPerFunction) {
  const auto ts = test::two_blocks();
  const auto hexes = test::hexes_of(ts);
  const extract::GlobalBasis g = extract::global_basis(ts, hexes);
  EXPECT_EQ(g.points.size(), 225u);  // 125 + 125 - 25 on the shared face
  ASSERT_EQ(g.weights.size(), 225u);
  for (const double w : g.weights) EXPECT_EQ(w, 1.0);
  ASSERT_EQ(g.elements.size(), 16u);
  for (const auto& el : g.elements) {
    EXPECT_EQ(el.functions.size(), 64u);
    EXPECT_TRUE(std::is_sorted(el.functions.begin(), el.functions.end()));
    EXPECT_EQ(el.op.cols(), 64);
  }
  // Element (1, j, k) of block 0 and element (0, j, k) of block 1 meet on x = 1; the function of
  // face control point (4, 4j', 4k') of block 0 (id 4 + 5(j' + 5k')) is in both.
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j) {
      const auto& left = g.elements[1 + 2 * (j + 2 * k)].functions;
      const auto& right = g.elements[8 + 0 + 2 * (j + 2 * k)].functions;
      const int shared = 4 + 5 * ((j ? 4 : 0) + 5 * (k ? 4 : 0));
      EXPECT_TRUE(has(left, shared) && has(right, shared)) << "element pair " << j << "," << k;
      std::vector<int> common;
      std::set_intersection(left.begin(), left.end(), right.begin(), right.end(), std::back_inserter(common));
      EXPECT_EQ(common.size(), 16u);  // the 4x4 face functions of the element's support
      for (const int id : common) EXPECT_EQ(id % 5, 4) << "only face functions (i = 4 of block 0) are shared";
    }
  EXPECT_DOUBLE_EQ(g.points[4].x(), test::bent(1, 0, 0)[0]);
}

TEST(GlobalBasis, PartitionOfUnityAndReproduction) {
  const auto ts = test::two_blocks();
  const auto hexes = test::hexes_of(ts);
  const extract::GlobalBasis g = extract::global_basis(ts, hexes);
  EXPECT_LT(g.partition_of_unity_error, 1e-14);
  double worst = 0;
  for (std::size_t e = 0; e < hexes.size(); ++e) {
    const Eigen::MatrixXd C(g.elements[e].op);
    Eigen::MatrixXd P(C.rows(), 3);
    for (int r = 0; r < C.rows(); ++r) P.row(r) = g.points[g.elements[e].functions[r]].transpose();
    const Eigen::MatrixXd bez = C.transpose() * P;
    const Eigen::RowVectorXd ones = Eigen::RowVectorXd::Ones(C.rows());
    EXPECT_LT(((ones * C).array() - 1).abs().maxCoeff(), 1e-12);
    for (int b = 0; b < 64; ++b) worst = std::max(worst, (bez.row(b).transpose() - hexes[e].points[b]).norm());
  }
  EXPECT_LT(worst, 1e-13);
  // Interior rows of uniform cubic extraction: the element's middle functions, e.g. the first row of
  // an element with a clamped start is the Bernstein B_0 alone (C(0, 0) = 1 in 1-D).
  EXPECT_DOUBLE_EQ(Eigen::MatrixXd(g.elements[0].op)(0, 0), 1.0);
}

TEST(GlobalBasis, WithoutIdsBlocksAreNumberedOneAfterTheOther) {
  const auto ts = test::two_blocks(false);
  const extract::GlobalBasis g = extract::global_basis(ts, test::hexes_of(ts));
  EXPECT_EQ(g.points.size(), 250u);
  EXPECT_EQ(g.elements[8].functions.front(), 125);
}

TEST(GlobalBasis, SharedIdWithTwoDifferentPointsIsRefused) {
  auto ts = test::two_blocks();
  ts[1].control_points[5 * 2][1] += 1e-3;  // (0, 2, 0) of block 1: a shared face point
  const std::string m = error_of<core::InvalidInputError>(ts, test::hexes_of(ts));
  EXPECT_NE(m.find("blocks 0 and 1"), std::string::npos) << m;
}

TEST(GlobalBasis, UnusedIdIsRefused) {
  auto ts = test::two_blocks();
  for (int& id : ts[1].function_ids)
    if (id >= 125) id += 1;  // leaves 125 unused
  EXPECT_THROW(extract::global_basis(ts, test::hexes_of(ts)), core::InvalidInputError);
}

TEST(GlobalBasis, IdBeyondTheControlPointsIsRefusedBeforeAllocating) {
  auto ts = test::two_blocks();
  ts[0].function_ids[3] = 2000000000;
  const std::string m = error_of<core::InvalidInputError>(ts, test::hexes_of(ts));
  EXPECT_NE(m.find("function id 2000000000, outside [0, 250)"), std::string::npos) << m;
}

TEST(GlobalBasis, HexThatDoesNotReproduceIsANumericalErrorNamingTheElement) {
  const auto ts = test::two_blocks();
  auto hexes = test::hexes_of(ts);
  hexes[5].points[21] += Eigen::Vector3d(0, 0, 1e-6);
  const std::string m = error_of<core::NumericalError>(ts, hexes);
  EXPECT_NE(m.find("element 5 "), std::string::npos) << m;
}

// Without the operators kept (exports without bext and json), every element is still checked.
TEST(GlobalBasis, WithoutOperatorsKeptEveryElementIsStillChecked) {
  const auto ts = test::two_blocks();
  auto hexes = test::hexes_of(ts);
  const extract::GlobalBasis all = extract::global_basis(ts, hexes);
  const extract::GlobalBasis g = extract::global_basis(ts, hexes, false);
  EXPECT_TRUE(g.elements.empty());
  EXPECT_EQ(g.points, all.points);
  EXPECT_EQ(g.partition_of_unity_error, all.partition_of_unity_error);
  hexes[5].points[21] += Eigen::Vector3d(0, 0, 1e-6);
  try {
    extract::global_basis(ts, hexes, false);
    ADD_FAILURE() << "a hex that does not reproduce passed";
  } catch (const core::NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("element 5 "), std::string::npos) << e.what();
  }
}

// CAD parts sit far from the origin: the checks must not flag rounding at the size of the coordinates.
TEST(GlobalBasis, FarFromTheOriginStillPassesItsChecks) {
  auto ts = test::two_blocks();
  for (auto& t : ts)
    for (auto& p : t.control_points) p = {p[0] + 1e5, p[1] - 2e5, p[2] + 5e4};
  const auto hexes = test::hexes_of(ts);
  extract::GlobalBasis g;
  EXPECT_NO_THROW(g = extract::global_basis(ts, hexes));
  EXPECT_LT(g.partition_of_unity_error, 1e-14);
}
