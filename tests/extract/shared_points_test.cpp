// Points merged within a tolerance (extract::PointIndex) and the connected bezier.vtu built on it
// (extract::shared_points, bezier::write_bezier_vtu's `shared`): against brute force on clusters
// of jittered copies, some straddling the index's cell sides; a rational cubic B-spline volume's
// elements sharing exactly their face points, read back through VTK.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <vector>

#include "bezier/element_factory.h"
#include "bezier/vtk_bezier.h"
#include "common/test_util.h"
#include "core/errors.h"
#include "extract/extract.h"
#include "extract/point_index.h"
#include "extract/two_blocks.h"

using namespace volts;
using Eigen::Vector3d;

namespace {

// The Bézier elements of a curved rational cubic volume of 2 x 2 x 1 elements.
std::vector<bezier::BezierHex> rational_hexes() {
  std::mt19937 rng(7);
  return bezier::extract_bezier_hexes(bezier::testing::curved_rational_volume(rng));
}

}  // namespace

TEST(PointIndex, MergesWithinTheToleranceLikeBruteForceAcrossCellSides) {
  // Clusters >= 100 tol apart; copies within 0.4 tol of their centre, so every copy is within
  // the tolerance of its cluster's first point and of no other cluster's.
  const Eigen::AlignedBox3d box(Vector3d::Zero(), Vector3d::Ones());
  const double tol = 1e-7;
  const double cell = std::max(1e-6 * box.diagonal().norm(), 1e3 * tol);  // the index's cell (point_index.cpp)
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0), small(-0.4 * tol / std::sqrt(3.0), 0.4 * tol / std::sqrt(3.0));
  std::vector<Vector3d> centres;
  while (centres.size() < 3000) {
    Vector3d c(unit(rng), unit(rng), unit(rng));
    // Every third centre on a cell side (along one to three axes): its copies fall in two cells.
    if (centres.size() % 3 == 0)
      for (int d = 0; d <= static_cast<int>(centres.size() / 3 % 3); ++d) c[d] = std::round(c[d] / cell) * cell;
    if (std::all_of(centres.begin(), centres.end(), [&](const Vector3d& o) { return (o - c).norm() > 100 * tol; })) centres.push_back(c);
  }
  std::vector<std::pair<Vector3d, int>> copies;  // point, cluster
  for (int c = 0; c < static_cast<int>(centres.size()); ++c)
    for (int r = 0; r < 1 + c % 4; ++r) copies.emplace_back(centres[static_cast<std::size_t>(c)] + Vector3d(small(rng), small(rng), small(rng)), c);
  std::shuffle(copies.begin(), copies.end(), rng);

  extract::PointIndex index(box, tol);  // no reserve: the table grows
  std::vector<int> first(centres.size(), -1);  // per cluster, its index
  for (const auto& [x, c] : copies) {
    const int i = index.find_or_add(x);
    if (first[static_cast<std::size_t>(c)] < 0) {
      EXPECT_EQ(i, static_cast<int>(index.points().size()) - 1) << "a new cluster gets the next index";
      first[static_cast<std::size_t>(c)] = i;
    }
    EXPECT_EQ(i, first[static_cast<std::size_t>(c)]);
    EXPECT_LE((index.points()[static_cast<std::size_t>(i)] - x).norm(), tol);
  }
  EXPECT_EQ(index.points().size(), centres.size());
  // find: any copy finds its cluster; a point 10 tol from every centre finds nothing.
  for (std::size_t c = 0; c < centres.size(); c += 7) EXPECT_EQ(index.find(centres[c]), first[c]);
  EXPECT_EQ(index.find(centres[1] + Vector3d(10 * tol, 0, 0)), -1);
  EXPECT_EQ(index.find(Vector3d(2, 2, 2)), -1);
}

TEST(SharedPoints, NeighbouringElementsShareTheirFacePointsAndTheFileReadsBack) {
  const std::vector<bezier::BezierHex> hexes = rational_hexes();
  ASSERT_EQ(hexes.size(), 4u);
  const std::vector<int> ids = extract::shared_points(hexes);
  ASSERT_EQ(ids.size(), 4u * 64u);
  // The Bézier points of a 2 x 2 x 1 cubic volume: (3·2 + 1)² (3·1 + 1).
  const int distinct = *std::max_element(ids.begin(), ids.end()) + 1;
  EXPECT_EQ(distinct, 7 * 7 * 4);
  // Numbered in order of first use; one id, one position and weight (to rounding).
  std::vector<Vector3d> at(static_cast<std::size_t>(distinct));
  std::vector<double> w(static_cast<std::size_t>(distinct));
  int next = 0;
  for (std::size_t h = 0, o = 0; h < hexes.size(); ++h)
    for (int n = 0; n < 64; ++n, ++o) {
      const int id = ids[o];
      ASSERT_LE(id, next);
      if (id == next) {
        at[static_cast<std::size_t>(id)] = hexes[h].points[static_cast<std::size_t>(n)], w[static_cast<std::size_t>(id)] = hexes[h].weight(n), ++next;
      } else {
        EXPECT_LT((at[static_cast<std::size_t>(id)] - hexes[h].points[static_cast<std::size_t>(n)]).norm(), 1e-12);
        EXPECT_NEAR(w[static_cast<std::size_t>(id)], hexes[h].weight(n), 1e-12);
      }
    }

  const std::filesystem::path dir = test::fresh_dir("extract", "shared_points");
  const std::string file = (dir / "shared.vtu").string();
  bezier::write_bezier_vtu(file, hexes, {}, ids);
  const bezier::VtuElements back = bezier::read_bezier_vtu(file);
  ASSERT_EQ(back.hexes.size(), hexes.size());
  for (std::size_t h = 0; h < hexes.size(); ++h)
    for (int n = 0; n < 64; ++n) {
      EXPECT_LT((back.hexes[h].points[static_cast<std::size_t>(n)] - hexes[h].points[static_cast<std::size_t>(n)]).norm(), 1e-12);
      EXPECT_NEAR(back.hexes[h].weight(n), hexes[h].weight(n), 1e-12);
    }
  // Smaller than one copy per cell.
  bezier::write_bezier_vtu((dir / "copies.vtu").string(), hexes);
  EXPECT_LT(std::filesystem::file_size(file), std::filesystem::file_size(dir / "copies.vtu"));

  // A shared face whose weights differ in one element: those points stay apart (16 more).
  std::vector<bezier::BezierHex> bent = hexes;
  for (int k = 0; k <= 3; ++k)
    for (int j = 0; j <= 3; ++j) bent[1].weights[static_cast<std::size_t>(0 + 4 * (j + 4 * k))] *= 1.5;  // i = 0: the face toward hex 0
  const std::vector<int> apart = extract::shared_points(bent);
  EXPECT_EQ(*std::max_element(apart.begin(), apart.end()) + 1, 7 * 7 * 4 + 16);

  // Malformed ids are refused, and no file is left.
  std::vector<int> short_ids(ids.begin(), ids.end() - 1), out_of_order = ids;
  out_of_order[0] = 5;
  EXPECT_THROW(bezier::write_bezier_vtu((dir / "a.vtu").string(), hexes, {}, short_ids), core::InvalidInputError);
  EXPECT_THROW(bezier::write_bezier_vtu((dir / "b.vtu").string(), hexes, {}, out_of_order), core::InvalidInputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "a.vtu"));
  EXPECT_FALSE(std::filesystem::exists(dir / "b.vtu"));
}

// The grids' structure (extract's blocks) gives the ids position alone gives, over one curved
// rational block, the same with a face's weights bent, and two blocks sharing a face; grids that
// do not cover the hexes are refused.
TEST(SharedPoints, ByTheGridsAsByPosition) {
  const std::vector<bezier::BezierHex> one = rational_hexes();  // 2 x 2 x 1 elements
  EXPECT_EQ(extract::shared_points(one, {{0, {2, 2, 1}}}), extract::shared_points(one));
  std::vector<bezier::BezierHex> bent = one;
  for (int k = 0; k <= 3; ++k)
    for (int j = 0; j <= 3; ++j) bent[1].weights[static_cast<std::size_t>(4 * (j + 4 * k))] *= 1.5;
  const std::vector<int> apart = extract::shared_points(bent, {{0, {2, 2, 1}}});
  EXPECT_EQ(apart, extract::shared_points(bent));
  EXPECT_EQ(*std::max_element(apart.begin(), apart.end()) + 1, 7 * 7 * 4 + 16);
  const std::vector<bezier::BezierHex> two = test::hexes_of(test::two_blocks());  // 2 x 2 x 2 each, one face shared
  const std::vector<int> ids = extract::shared_points(two, {{0, {2, 2, 2}}, {8, {2, 2, 2}}});
  EXPECT_EQ(ids, extract::shared_points(two));
  EXPECT_EQ(*std::max_element(ids.begin(), ids.end()) + 1, 2 * 7 * 7 * 7 - 7 * 7);
  EXPECT_THROW(extract::shared_points(two, {{0, {2, 2, 2}}}), core::InvalidInputError);
  EXPECT_THROW(extract::shared_points(two, {{0, {2, 2, 2}}, {9, {2, 2, 2}}}), core::InvalidInputError);
  EXPECT_THROW(extract::shared_points(two, {{0, {2, 2, 2}}, {8, {2, 2, 3}}}), core::InvalidInputError);
}
