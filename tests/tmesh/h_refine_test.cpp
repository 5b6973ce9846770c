// Tests of h-refinement by knot insertion (tmesh.h h_refine): the refined T-mesh is the same
// spline — every block evaluates alike, every fine element is a piece of its parent with the same
// scaled Jacobian — on eight times the elements, its T-junctions still on their rows and its basis
// a partition of unity. The family: rings of 3–5 cubes of mixed levels, before and after the
// optimizer has moved their nodes.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "bezier/bezier_hex.h"
#include "core/errors.h"
#include "extract/extract.h"
#include "ring_cubes.h"
#include "tmesh/optimize.h"
#include "tmesh/tmesh.h"

using namespace volts;
using namespace volts::test;

namespace {

// A ring whose inside is pushed along it (a map no spline reproduces, elements sheared), so the
// refined nets are not the coarse ones' linear interpolation.
tmesh::PolycubeMaps sheared_ring(int k) {
  tmesh::PolycubeMaps maps = ring(k);
  maps.physical = [k](int c, const Vec3& abh) {
    const double t = -2 * kPi * (c + abh[0]) / k, r = kInner + (kOuter - kInner) * abh[1];
    const double shift = 0.4 * 16 * abh[1] * (1 - abh[1]) * abh[2] * (1 - abh[2]) * std::sin(2 * t) / r;
    return Vec3{r * std::cos(t + shift), r * std::sin(t + shift), abh[2]};
  };
  return maps;
}

// Checks that `fine` is `coarse` h-refined `times` times (parent: fine element -> coarse one);
// every `stride`-th fine element is compared with its parent point by point.
void expect_same_spline(const std::vector<tmesh::TMesh>& coarse, const std::vector<tmesh::TMesh>& fine, int times, const std::vector<int>& parent,
                        std::size_t stride = 1) {
  ASSERT_EQ(fine.size(), coarse.size());
  const int split = 1 << times;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  double gap = 0, scale = 0;
  for (std::size_t b = 0; b < coarse.size(); ++b) {
    EXPECT_EQ(fine[b].level, coarse[b].level + times);
    EXPECT_EQ(fine[b].elements(), coarse[b].elements() * split * split * split);
    for (int s = 0; s < 40; ++s) {
      const Eigen::Vector3d x(u(rng), u(rng), u(rng));
      const Eigen::Vector3d a = bezier::evaluate(volume(coarse[b]), x), c = bezier::evaluate(volume(fine[b]), x);
      gap = std::max(gap, (a - c).norm()), scale = std::max(scale, a.norm());
    }
  }
  EXPECT_LE(gap, 1e-12 * scale) << "the refined blocks are another spline";
  // Every fine element is a piece of its parent: each of its corners is a point of the parent's
  // grid of local parameters k / split, where both have the same scaled Jacobian (it does not see
  // the parameters' scale).
  const auto hc = hexes(coarse), hf = hexes(fine);
  ASSERT_EQ(parent.size(), hf.size());
  std::vector<int> children(hc.size(), 0);
  double sj_gap = 0;
  for (std::size_t e = 0; e < hf.size(); ++e) {
    const int p = parent[e];
    ASSERT_GE(p, 0);
    ASSERT_LT(static_cast<std::size_t>(p), hc.size());
    ++children[static_cast<std::size_t>(p)];
    if (e % stride) continue;
    for (int corner = 0; corner < 8; ++corner) {
      Eigen::Matrix3d Jf;
      const Eigen::Vector3d y = bezier::evaluate(hf[e], Eigen::Vector3d(corner & 1, (corner >> 1) & 1, corner >> 2), &Jf);
      double best = std::numeric_limits<double>::infinity(), best_sj = 0;
      for (int i = 0; i <= split; ++i)
        for (int j = 0; j <= split; ++j)
          for (int k = 0; k <= split; ++k) {
            Eigen::Matrix3d Jc;
            const Eigen::Vector3d z = bezier::evaluate(hc[static_cast<std::size_t>(p)], Eigen::Vector3d(i, j, k) / split, &Jc);
            if ((z - y).norm() < best) best = (z - y).norm(), best_sj = bezier::scaled_jacobian(Jc);
          }
      EXPECT_LE(best, 1e-12 * scale) << "fine element " << e << " is not in its parent " << p;
      sj_gap = std::max(sj_gap, std::abs(best_sj - bezier::scaled_jacobian(Jf)));
    }
  }
  EXPECT_LE(sj_gap, 1e-9);
  for (const int n : children) EXPECT_EQ(n, split * split * split);
  // T-junctions on their rows (global_basis checks each, 1e-12) and a partition of unity.
  const extract::GlobalBasis g = extract::global_basis(fine, hf);
  EXPECT_LE(g.partition_of_unity_error, 1e-12);
}

}  // namespace

TEST(HRefine, TheRefinedTMeshIsTheSameSplineOnEightTimesTheElements) {
  for (int k = 3; k <= 5; ++k) {
    SCOPED_TRACE("ring of " + std::to_string(k) + " cubes");
    const tmesh::PolycubeMaps maps = sheared_ring(k);
    tmesh::Params p;
    p.level = 1;
    std::vector<int> levels;
    for (int c = 0; c < k; ++c) levels.push_back(1 + c % 2);  // T-junctions between cubes and between slabs and cores
    const auto coarse = tmesh::build(maps, p, levels);
    std::vector<int> parent;
    const auto fine = tmesh::h_refine(maps, p, coarse, 1, &parent);
    expect_same_spline(coarse, fine, 1, parent);
    const tmesh::NodeCounts nc = tmesh::count_nodes(coarse), nf = tmesh::count_nodes(fine);
    EXPECT_GT(nf.t_junctions, nc.t_junctions);
    EXPECT_GT(nf.nodes - nf.t_junctions, nc.nodes - nc.t_junctions) << "refinement adds functions";
  }
}

// After the optimizer moved nodes (and T-junctions with them), twice refined.
TEST(HRefine, RefinesTheOptimizedSplineTwice) {
  const tmesh::PolycubeMaps maps = sheared_ring(4);
  tmesh::Params p;
  p.level = 1;
  auto ts = tmesh::build(maps, p, {1, 2, 1, 2});
  const auto start = ts;
  const tmesh::OptimizeResult r = tmesh::optimize(ts, test::running_rounds(1, 30));
  ASSERT_GT(r.nodes_moved + r.joint_rounds, 0);
  double moved = 0;
  for (std::size_t b = 0; b < ts.size(); ++b)
    for (std::size_t i = 0; i < ts[b].control_points.size(); ++i)
      for (int d = 0; d < 3; ++d) moved = std::max(moved, std::abs(ts[b].control_points[i][static_cast<std::size_t>(d)] - start[b].control_points[i][static_cast<std::size_t>(d)]));
  ASSERT_GT(moved, 1e-6) << "the optimizer moved nothing: the test would not see moved nodes";
  std::vector<int> parent;
  const auto fine = tmesh::h_refine(maps, p, ts, 2, &parent);
  expect_same_spline(ts, fine, 2, parent, 13);
  // Stage-file round trip of the refined T-mesh (its rows are checked on reading).
  for (const auto& t : fine) EXPECT_NO_THROW(tmesh::from_json(tmesh::to_json(t), "refined"));
}

// The stage's "before" figure: each element split in 2^h per direction on the unrefined blocks
// gives the refined net's worst trilinear hex (the same spline at the same corners) without
// building it; rings of 3-5 sheared cubes of mixed levels, once and twice refined.
TEST(HRefine, SplitElementsGiveTheRefinedNetsTrilinearFigure) {
  for (int k = 3; k <= 5; ++k)
    for (int times = 1; times <= 2; ++times) {
      SCOPED_TRACE("ring of " + std::to_string(k) + " cubes, h_refine " + std::to_string(times));
      const tmesh::PolycubeMaps maps = sheared_ring(k);
      tmesh::Params p;
      p.level = 1;
      std::vector<int> levels;
      for (int c = 0; c < k; ++c) levels.push_back(1 + c % 2);
      const auto coarse = tmesh::build(maps, p, levels);
      const auto fine = tmesh::h_refine(maps, p, coarse, times);
      double split = std::numeric_limits<double>::infinity(), refined = split, unsplit = split;
      for (const auto& t : coarse) split = std::min(split, tmesh::min_element_scaled_jacobian(t, times)), unsplit = std::min(unsplit, tmesh::min_element_scaled_jacobian(t));
      for (const auto& t : fine) refined = std::min(refined, tmesh::min_element_scaled_jacobian(t));
      EXPECT_NEAR(split, refined, 1e-12);
      EXPECT_NE(split, unsplit) << "the split changes nothing on this family: the test would not see a missing split";
    }
  tmesh::Params p;
  p.level = 1;
  const auto ts = tmesh::build(sheared_ring(3), p, {1, 1, 1});
  EXPECT_THROW(tmesh::min_element_scaled_jacobian(ts.front(), 4), core::ConfigError);
  EXPECT_THROW(tmesh::min_element_scaled_jacobian(ts.front(), -1), core::ConfigError);
}

TEST(HRefine, RefusesWhatIsNotTheRefinementOfItsPolycube) {
  const tmesh::PolycubeMaps maps = sheared_ring(4);
  tmesh::Params p;
  p.level = 2;
  const auto ts = tmesh::build(maps, p, {2, 3, 2, 3});
  std::vector<int> parent;
  const auto same = tmesh::h_refine(maps, p, ts, 0, &parent);
  ASSERT_EQ(same.size(), ts.size());
  for (std::size_t b = 0; b < ts.size(); ++b) EXPECT_EQ(same[b].control_points, ts[b].control_points);
  EXPECT_EQ(static_cast<int>(parent.size()), [&] {
    int n = 0;
    for (const auto& t : ts) n += t.elements();
    return n;
  }());
  EXPECT_THROW(tmesh::h_refine(maps, p, ts, 4), core::ConfigError);
  EXPECT_THROW(tmesh::h_refine(maps, p, ts, -1), core::ConfigError);
  auto fewer = ts;
  fewer.pop_back();
  EXPECT_THROW(tmesh::h_refine(maps, p, fewer, 1), core::InvalidInputError);
  auto other_cube = ts;
  other_cube[0].corners[7] = {0.5, 0.5, 0.5};
  EXPECT_THROW(tmesh::h_refine(maps, p, other_cube, 1), core::InvalidInputError);
  // A node moved in one block only: the blocks part (not C0), which refinement must not hide.
  auto cracked = ts;
  for (std::size_t i = 0; i < cracked[0].control_points.size(); ++i) {
    const int id = cracked[0].function_ids[i];
    bool shared = false;
    for (std::size_t b = 1; b < cracked.size(); ++b)
      for (const int other : cracked[b].function_ids) shared = shared || other == id;
    if (!shared) continue;
    cracked[0].control_points[i][2] += 1e-3;
    break;
  }
  EXPECT_THROW(tmesh::h_refine(maps, p, cracked, 1), core::NumericalError);
}
