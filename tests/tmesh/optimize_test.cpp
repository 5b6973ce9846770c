// Worst-Jacobian optimization (Liu et al. §5.2): it never lowers the worst scaled Jacobian, never
// makes a certified-valid element invalid, leaves surface control points where they are, and
// moves shared control points together.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <map>

#include "core/errors.h"

#include "bezier/bezier_hex.h"
#include "bezier/certify.h"
#include "ring_cubes.h"
#include "tmesh/optimize.h"
#include "tmesh/tmesh.h"
#include "unit_cube_blocks.h"

using namespace volts;
using tmesh::Vec3;

namespace {

// A cube whose cross sections are twisted about the axis b = c = 1/2, most in the middle of the
// cube and not at all on its surface: the interior elements start sheared, with room to improve
// by moving interior control points alone.
Vec3 twisted(const Vec3& abc, double twist = 1.2) {
  const double u = abc[1] - 0.5, v = abc[2] - 0.5;
  const double t = twist * 64 * abc[0] * (1 - abc[0]) * abc[1] * (1 - abc[1]) * abc[2] * (1 - abc[2]);
  return {abc[0], 0.5 + u * std::cos(t) - v * std::sin(t), 0.5 + v * std::cos(t) + u * std::sin(t)};
}

std::vector<tmesh::TMesh> blocks(int pillow, double twist = 1.2) {
  return tmesh::testing::unit_cube_blocks([twist](const Vec3& abc) { return twisted(abc, twist); }, pillow);
}

}  // namespace

TEST(Optimize, NeverLowersTheWorstJacobianAndKeepsSurfaceAndSharedPoints) {
  for (int pillow = 0; pillow <= 1; ++pillow) {
    std::vector<tmesh::TMesh> ts = blocks(pillow);
    const std::vector<tmesh::TMesh> start = ts;
    tmesh::OptimizeParams op;
    op.joint_rounds = 0;  // the per-node sweeps alone (joint rounds: their own test)
    op.sweeps = 1;
    op.target = 0.9;  // nearly every element is a candidate
    op.gauss_points = 2;
    // Measured at the check grid's tolerance of 0.05 (the default until session 43): at 0.01 the
    // one cycle's check finds dips it has no cycle left to raise, and stops on cycle_bound.
    op.check_tolerance = 0.05;
    const tmesh::OptimizeResult r = tmesh::optimize(ts, op);
    std::printf("pillow %d: worst %g -> %g, not certified valid %d -> %d, %d nodes moved\n", pillow, r.min_before, r.min_after,
                r.invalid_before, r.invalid_after, r.nodes_moved);
    EXPECT_GE(r.min_after, r.min_before);
    EXPECT_LE(r.invalid_after, r.invalid_before);
    EXPECT_GT(r.nodes_moved, 0);
    EXPECT_GT(r.min_after, r.min_before + 0.01);  // a real gain on this map
    // One sweep moved nodes, so the run stopped on its sweep bound and must say so.
    EXPECT_EQ(r.sweeps, 1);
    EXPECT_EQ(r.stop_reason, "sweep_bound");
    // Per-element figures (tmesh.vtu's bezier_scaled_jacobian_before/after): one per element,
    // their minima the worst figures, and no element below the start's worst afterwards.
    int elements = 0;
    for (const auto& t : ts) elements += t.elements();
    ASSERT_EQ(static_cast<int>(r.element_before.size()), elements);
    ASSERT_EQ(static_cast<int>(r.element_after.size()), elements);
    EXPECT_EQ(*std::min_element(r.element_before.begin(), r.element_before.end()), r.min_before);
    EXPECT_EQ(*std::min_element(r.element_after.begin(), r.element_after.end()), r.min_after);
    EXPECT_NE(r.element_before, r.element_after);
    std::map<int, Vec3> at;
    int moved = 0;
    for (std::size_t b = 0; b < ts.size(); ++b) {
      const auto& t = ts[b];
      for (std::size_t i = 0; i < t.control_points.size(); ++i) {
        const int idx[3] = {static_cast<int>(i) % t.size[0], (static_cast<int>(i) / t.size[0]) % t.size[1],
                            static_cast<int>(i) / (t.size[0] * t.size[1])};
        bool surface = false;
        for (int a = 0; a < 3; ++a)
          for (int s = 0; s < 2; ++s) surface |= t.boundary[2 * a + s] && idx[a] == (s ? t.size[a] - 1 : 0);
        if (surface) {
          EXPECT_EQ(t.control_points[i], start[b].control_points[i]) << "surface control point moved";
        }
        moved += t.control_points[i] != start[b].control_points[i];
        const auto [it, fresh] = at.emplace(t.function_ids[i], t.control_points[i]);
        if (!fresh) {
          EXPECT_EQ(it->second, t.control_points[i]) << "a shared control point moved in one block only";
        }
      }
    }
    EXPECT_GT(moved, 0);
  }
}

// The trilinear pass (Liu et al. eq. (1)–(2)): it raises the worst scaled Jacobian of the hexes of
// the elements' corner points, and keeps the Bézier pass's result (the worst sampled figure and
// every certified-valid element). Its figure is the T-mesh's trilinear figure.
TEST(Optimize, TrilinearPassRaisesTheCornerHexesAndKeepsTheBezierResult) {
  std::vector<tmesh::TMesh> ts = blocks(1);
  tmesh::OptimizeParams op;
  op.joint_rounds = 0;
  op.sweeps = 1;
  op.target = 0.9;
  op.gauss_points = 2;
  op.trilinear_target = 0.95;  // nearly every element is a candidate
  op.trilinear_sweeps = 2;
  const tmesh::OptimizeResult r = tmesh::optimize(ts, op);
  std::printf("trilinear %g -> %g, %d nodes moved; Bézier worst after its pass %g\n", r.trilinear_before, r.trilinear_after,
              r.trilinear_nodes_moved, r.min_after);
  EXPECT_GT(r.trilinear_nodes_moved, 0);
  EXPECT_GT(r.trilinear_after, r.trilinear_before + 1e-3);
  double t_mesh = 1;
  for (const auto& t : ts) t_mesh = std::min(t_mesh, tmesh::min_element_scaled_jacobian(t));
  EXPECT_NEAR(t_mesh, r.trilinear_after, 1e-9);
  // The Bézier figures of the final blocks, measured anew (no pass runs).
  tmesh::OptimizeParams measure = op;
  measure.sweeps = 0;
  measure.trilinear_sweeps = 0;
  const tmesh::OptimizeResult now = tmesh::optimize(ts, measure);
  // The result's figures are those of the final blocks (after both passes), and the trilinear
  // pass lowered neither of the Bézier pass's.
  EXPECT_EQ(now.min_before, r.min_after);
  EXPECT_EQ(now.invalid_before, r.invalid_after);
  tmesh::OptimizeParams bezier_only = op;
  bezier_only.trilinear_sweeps = 0;
  std::vector<tmesh::TMesh> ts2 = blocks(1);
  const tmesh::OptimizeResult rb = tmesh::optimize(ts2, bezier_only);
  EXPECT_GE(r.min_after, rb.min_after);
  EXPECT_LE(r.invalid_after, rb.invalid_after);
  op.trilinear_sweeps = -1;
  EXPECT_THROW(tmesh::optimize(ts, op), core::ConfigError);
}

TEST(Optimize, SaysWhyItStopped) {
  std::vector<tmesh::TMesh> ts = blocks(1);
  tmesh::OptimizeParams op;
  op.joint_rounds = 0;
  op.gauss_points = 2;
  op.sweeps = 0;
  EXPECT_EQ(tmesh::optimize(ts, op).stop_reason, "disabled");
  op.sweeps = 1;
  op.target = -1;  // no sampled scaled Jacobian is below -1
  const tmesh::OptimizeResult none = tmesh::optimize(ts, op);
  EXPECT_EQ(none.stop_reason, "no_element_below_target");
  EXPECT_EQ(none.sweeps, 0);
  op.target = 0.9;
  op.max_nodes_per_sweep = 3;  // far fewer than the candidates
  const tmesh::OptimizeResult cut = tmesh::optimize(ts, op);
  EXPECT_EQ(cut.sweeps_cut_at_node_bound, 1);
  EXPECT_LE(cut.nodes_moved, 3);
  // The only cycle's check grid finds dips that no cycle is left to raise.
  std::vector<tmesh::TMesh> dipping = blocks(1, 0.8);
  tmesh::OptimizeParams c;
  c.gauss_points = 2, c.grid_points = 2, c.check_points = 9, c.cycles = 1;
  c.target = 0.95, c.sweeps = 1, c.joint_evaluations = 100;
  const tmesh::OptimizeResult bound = tmesh::optimize(dipping, c);
  EXPECT_EQ(bound.stop_reason, "cycle_bound");
  EXPECT_GT(bound.elements_on_check_grid, 0);
  EXPECT_LT(bound.min_after_checked, bound.min_after);
}

TEST(Optimize, StopsWhenSweepsStall) {
  // A gain of 1 in the worst scaled Jacobian per sweep is impossible: with patience 1 the run stops
  // after the first sweep once every element is valid (a sweep that fixes the last invalid
  // elements counts as progress, hence at most 2), long before its bound of 40.
  std::vector<tmesh::TMesh> ts = blocks(1);
  tmesh::OptimizeParams op;
  op.joint_rounds = 0;
  op.gauss_points = 2;
  op.target = 0.9;
  op.sweeps = 40;
  op.check_tolerance = 0.05;  // the sweeps' own stop reasons (at 0.01 the one cycle's check ends on cycle_bound)
  op.min_gain = 1, op.patience = 1;
  const tmesh::OptimizeResult r = tmesh::optimize(ts, op);
  EXPECT_EQ(r.stop_reason, "stalled");
  EXPECT_LE(r.sweeps, 2);
  EXPECT_GT(r.nodes_moved, 0);
  // The default rule on the same map: it keeps going while sweeps gain, ends for a reason other
  // than the bound, and ends at least as well as one sweep.
  std::vector<tmesh::TMesh> one = blocks(1), many = blocks(1);
  op.min_gain = 1e-3, op.patience = 2;
  op.sweeps = 1;
  const tmesh::OptimizeResult r1 = tmesh::optimize(one, op);
  op.sweeps = 40;
  const tmesh::OptimizeResult rn = tmesh::optimize(many, op);
  std::printf("one sweep: worst %g; up to 40: worst %g after %d sweeps (%s)\n", r1.min_after, rn.min_after, rn.sweeps, rn.stop_reason.c_str());
  EXPECT_NE(rn.stop_reason, "sweep_bound");
  EXPECT_LT(rn.sweeps, 40);
  EXPECT_GE(rn.min_after, r1.min_after);
  EXPECT_LE(rn.invalid_after, r1.invalid_after);
}

// Surface control points stay, shared ones move together (ids give one position).
void expect_surface_kept_and_shared_together(const std::vector<tmesh::TMesh>& ts, const std::vector<tmesh::TMesh>& start) {
  std::map<int, Vec3> at;
  for (std::size_t b = 0; b < ts.size(); ++b) {
    const auto& t = ts[b];
    for (std::size_t i = 0; i < t.control_points.size(); ++i) {
      const int idx[3] = {static_cast<int>(i) % t.size[0], (static_cast<int>(i) / t.size[0]) % t.size[1],
                          static_cast<int>(i) / (t.size[0] * t.size[1])};
      bool surface = false;
      for (int a = 0; a < 3; ++a)
        for (int s = 0; s < 2; ++s) surface |= t.boundary[2 * a + s] && idx[a] == (s ? t.size[a] - 1 : 0);
      if (surface) {
        EXPECT_EQ(t.control_points[i], start[b].control_points[i]) << "surface control point moved";
      }
      const auto [it, fresh] = at.emplace(t.function_ids[i], t.control_points[i]);
      if (!fresh) {
        EXPECT_EQ(it->second, t.control_points[i]) << "a shared control point moved in one block only";
      }
    }
  }
}

// The joint-round tests' optimizer on the twisted blocks: the target out of reach, so every round
// and sweep runs to its own stopping rule; one sweep, no trilinear pass.
tmesh::OptimizeParams twist_family_params() {
  tmesh::OptimizeParams op;
  op.gauss_points = 2;
  op.target = 0.95;
  op.sweeps = 1;
  op.trilinear_sweeps = 0;
  op.joint_evaluations = 100;  // the family's figures were measured with 100 (the default since session 42)
  // Measured without the check grid; with its default (13^3, target 0.95) every cycle finds dips
  // and the family's tests take minutes. The check has its own test below.
  op.check_points = 0;
  return op;
}

// The twisted blocks the joint-round tests run over, from mild to folded, with and without a
// pillow layer: f(twist, pillow).
template <class F>
void for_each_twist(F f) {
  for (const double twist : {0.8, 1.2, 1.8, 2.6})
    for (int pillow = 0; pillow <= 1; ++pillow) f(twist, pillow);
}

// Joint rounds (L-BFGS on a soft minimum of all elements' sampled scaled Jacobians): over a family
// of twists, from mild to folded, they never lower the worst figure or the certified count, keep
// surface points, and end at least as well as the per-node sweeps given the same bound — the
// plateau of equally bad elements that a per-node search cannot raise is what they are for.
TEST(Optimize, JointRoundsRaiseTheWorstJacobianAtLeastAsFarAsPerNodeSweeps) {
  for_each_twist([](double twist, int pillow) {
    tmesh::OptimizeParams op = twist_family_params();
    std::vector<tmesh::TMesh> joint = blocks(pillow, twist), nodes = blocks(pillow, twist);
    const std::vector<tmesh::TMesh> start = joint;
    const tmesh::OptimizeResult rj = tmesh::optimize(joint, op);
    op.joint_rounds = 0;
    const tmesh::OptimizeResult rn = tmesh::optimize(nodes, op);
    std::printf("twist %.1f pillow %d: worst %.4f (%d not valid) -> joint %.4f (%d, %d rounds), per node %.4f (%d)\n", twist, pillow,
                rj.min_before, rj.invalid_before, rj.min_after, rj.invalid_after, rj.joint_rounds, rn.min_after, rn.invalid_after);
    EXPECT_GE(rj.joint_rounds, 1);
    EXPECT_GT(rj.min_after, rj.min_before + 0.01);
    EXPECT_EQ(rj.invalid_after, 0);  // the per-node sweeps alone leave up to 32 of 64
    EXPECT_LE(rj.invalid_after, rn.invalid_after);
    EXPECT_GE(rj.min_after, rn.min_after);
    expect_surface_kept_and_shared_together(joint, start);
  });
}

// The narrowed rounds (OptimizeParams::joint_window) only go on where the full rounds stop at a
// refused step: over the same twists they keep at least as many rounds, never lower the worst
// figure or lose a certificate, and end at least as high as rounds that stop at the refusal (the
// per-node sweep is left out, max_nodes_per_sweep 0: it starts from different points). At the
// corner + Gauss sample (grid_points 2), where steps fold elements between the samples and are
// refused; at 5^3 the full rounds reach ~0.577 on every twist without a refusal (since session 35).
// Measured (session 39): twist 1.8 pillowed 0.158 at the refusal, 0.577 narrowed.
TEST(Optimize, NarrowedJointRoundsGoOnWhereFullRoundsAreRefused) {
  int gained = 0;
  for_each_twist([&gained](double twist, int pillow) {
    tmesh::OptimizeParams op = twist_family_params();
    op.joint_rounds = 30;
    op.max_nodes_per_sweep = 0;
    op.grid_points = 2;
    // At 300 (the default before session 42): at the family's 100 the scaled full rounds (session
    // 39) are refused on the folded twists only where the narrowed ones gain nothing either.
    op.joint_evaluations = 300;
    std::vector<tmesh::TMesh> narrowed = blocks(pillow, twist), stopped = blocks(pillow, twist);
    const std::vector<tmesh::TMesh> start = narrowed;
    const tmesh::OptimizeResult rw = tmesh::optimize(narrowed, op);
    op.joint_window = 0;
    const tmesh::OptimizeResult r0 = tmesh::optimize(stopped, op);
    std::printf("twist %.1f pillow %d: worst %.4f -> narrowed %.4f (%d rounds), stopped at the refusal %.4f (%d rounds)\n", twist, pillow,
                rw.min_before, rw.min_after, rw.joint_rounds, r0.min_after, r0.joint_rounds);
    EXPECT_GE(rw.joint_rounds, r0.joint_rounds);
    EXPECT_GE(rw.min_after, rw.min_before);
    EXPECT_LE(rw.invalid_after, rw.invalid_before);
    EXPECT_GE(rw.min_after, r0.min_after - 1e-12);
    gained += rw.min_after > r0.min_after + 1e-6 ? 1 : 0;
    expect_surface_kept_and_shared_together(narrowed, start);
  });
  EXPECT_GE(gained, 1);  // the window is not a no-op on this family
}

// Cycles (OptimizeParams::cycles): the joint rounds run again after the sweeps, from where they
// left the nodes. The first cycle is the one-cycle run, every later one keeps only gains, so over
// the twists they end at least as high, never lose a certificate, keep surface points, run at
// most `cycles` cycles, and raise the worst figure somewhere.
TEST(Optimize, CyclesGoOnWhereOneCycleStops) {
  int gained = 0;
  for_each_twist([&gained](double twist, int pillow) {
    tmesh::OptimizeParams op = twist_family_params();
    std::vector<tmesh::TMesh> cycled = blocks(pillow, twist), once = blocks(pillow, twist);
    const std::vector<tmesh::TMesh> start = cycled;
    const tmesh::OptimizeResult r1 = tmesh::optimize(once, op);
    op.cycles = 4;
    const tmesh::OptimizeResult rc = tmesh::optimize(cycled, op);
    std::printf("twist %.1f pillow %d: worst %.4f -> one cycle %.4f, %d cycles %.4f (%d not valid)\n", twist, pillow, r1.min_before, r1.min_after,
                rc.cycles, rc.min_after, rc.invalid_after);
    EXPECT_EQ(r1.cycles, 1);
    EXPECT_GE(rc.cycles, 1);
    EXPECT_LE(rc.cycles, 4);
    EXPECT_GE(rc.min_after, r1.min_after - 1e-12);
    EXPECT_LE(rc.invalid_after, r1.invalid_after);
    gained += rc.min_after > r1.min_after + 1e-4 ? 1 : 0;
    expect_surface_kept_and_shared_together(cycled, start);
  });
  EXPECT_GE(gained, 1);  // cycles are not a no-op on this family
}

// OptimizeParams::stop_at: over a mild and a folded twist, a run told to stop halfway between the start and
// where the full run ends stops there, all valid and at least at stop_at, never above the full
// run and in no more rounds; 1 (off) is the full run exactly.
TEST(Optimize, StopAtEndsTheRunOnceTheWorstReachesIt) {
  int stopped = 0;
  for (const double twist : {0.8, 1.8})
    for (int pillow = 0; pillow <= 1; ++pillow) {
      tmesh::OptimizeParams op = twist_family_params();
      op.cycles = 4;
      std::vector<tmesh::TMesh> full = blocks(pillow, twist), off = blocks(pillow, twist), early = blocks(pillow, twist);
      const tmesh::OptimizeResult rf = tmesh::optimize(full, op);
      op.stop_at = 1.0;
      const tmesh::OptimizeResult ro = tmesh::optimize(off, op);
      EXPECT_EQ(ro.min_after, rf.min_after);
      EXPECT_EQ(ro.joint_rounds, rf.joint_rounds);
      if (rf.invalid_after > 0 || rf.min_after < std::max(rf.min_before, 0.0) + 0.05) continue;  // nothing to stop halfway
      op.stop_at = 0.5 * (std::max(rf.min_before, 0.0) + rf.min_after);
      const tmesh::OptimizeResult re = tmesh::optimize(early, op);
      std::printf("twist %.1f pillow %d: worst %.4f -> full %.4f in %d rounds; stop_at %.4f: %.4f in %d rounds (%s)\n", twist, pillow, rf.min_before,
                  rf.min_after, rf.joint_rounds, op.stop_at, re.min_after, re.joint_rounds, re.stop_reason.c_str());
      EXPECT_EQ(re.stop_reason, "reached_stop_at");
      EXPECT_EQ(re.invalid_after, 0);
      EXPECT_GE(re.min_after, op.stop_at);
      EXPECT_LE(re.min_after, rf.min_after + 1e-12);
      EXPECT_LE(re.joint_rounds, rf.joint_rounds);
      stopped += re.joint_rounds < rf.joint_rounds ? 1 : 0;
    }
  EXPECT_GE(stopped, 1);  // it ends some runs earlier
  std::vector<tmesh::TMesh> ts = blocks(0);
  for (const double bad : {-0.1, 1.5}) {
    tmesh::OptimizeParams p;
    p.stop_at = bad;
    EXPECT_THROW(tmesh::optimize(ts, p), core::ConfigError);
  }
}

// stop_at with dips found between the samples (session 47): a cycle whose check puts elements on
// the check grid still ends the run when none of them (and no other element) is below stop_at —
// their figures are then measured on the check grid. On the pillowed twist 1.2 at the corner +
// Gauss sample (grid_points 2, where the check finds dips: the test above), with stop_at at one
// cycle's worst on the check grid: the run stops with reached_stop_at after a cycle whose check
// found dips (more elements on the check grid than the run one cycle shorter), before its bound.
TEST(Optimize, StopAtCountsTheDipsFoundBetweenTheSamples) {
  tmesh::OptimizeParams op = twist_family_params();
  op.grid_points = 2;
  op.check_points = 9;
  op.cycles = 1;
  std::vector<tmesh::TMesh> one = blocks(1, 1.2);
  const tmesh::OptimizeResult r1 = tmesh::optimize(one, op);
  ASSERT_EQ(r1.invalid_after, 0);
  ASSERT_GT(r1.elements_on_check_grid, 0);
  op.stop_at = r1.min_after_checked;
  op.cycles = 4;
  std::vector<tmesh::TMesh> ts = blocks(1, 1.2);
  const tmesh::OptimizeResult r = tmesh::optimize(ts, op);
  ASSERT_GE(r.cycles, 2);
  op.cycles = r.cycles - 1;
  std::vector<tmesh::TMesh> shorter = blocks(1, 1.2);
  const tmesh::OptimizeResult rs = tmesh::optimize(shorter, op);
  std::printf("stop_at %.4f: %d cycles (%s), worst %.4f, %d elements on the check grid (%d one cycle before)\n", op.stop_at, r.cycles,
              r.stop_reason.c_str(), r.min_after_checked, r.elements_on_check_grid, rs.elements_on_check_grid);
  EXPECT_EQ(r.stop_reason, "reached_stop_at");
  EXPECT_LT(r.cycles, 4);
  EXPECT_GT(r.elements_on_check_grid, rs.elements_on_check_grid);  // its last check found dips
  EXPECT_GE(r.min_after_checked, op.stop_at);
  // Every element is certified valid and its field on the check grid at least stop_at, up to
  // check_tolerance for those not put on it (their dip was within the tolerance).
  for (const bezier::BezierHex& h : test::hexes(ts)) {
    EXPECT_EQ(bezier::certify(h).status, bezier::Validity::valid);
    EXPECT_GE(bezier::sample_jacobian(h, 2, 9).min_scaled, op.stop_at - op.check_tolerance - 1e-12);
  }
}

// The trilinear guard (OptimizeParams::trilinear_guard): over the twists, with the trilinear pass
// off, the Bézier passes never lower the Bézier worst figure nor lose a certificate, and where
// every element starts certified valid no corner hex ends below min(its worst at the start, 0)
// (no move folds one that is not folded); the guard is not a no-op on the family.
TEST(Optimize, TrilinearGuardKeepsCornerHexesFromFolding) {
  auto corner_worst = [](const std::vector<tmesh::TMesh>& ts) {
    double w = 1;
    for (const auto& t : ts) w = std::min(w, tmesh::min_element_scaled_jacobian(t));
    return w;
  };
  int changed = 0;
  for_each_twist([&](double twist, int pillow) {
    tmesh::OptimizeParams op = twist_family_params();
    op.cycles = 2;
    op.trilinear_guard = true;
    std::vector<tmesh::TMesh> guarded = blocks(pillow, twist), free = blocks(pillow, twist);
    const std::vector<tmesh::TMesh> start = guarded;
    const tmesh::OptimizeResult rg = tmesh::optimize(guarded, op);
    op.trilinear_guard = false;
    const tmesh::OptimizeResult rf = tmesh::optimize(free, op);
    const double t0 = corner_worst(start), tg = corner_worst(guarded), tf = corner_worst(free);
    std::printf("twist %.1f pillow %d: Bézier %.4f (%d not valid) -> guarded %.4f, free %.4f; corner hexes %.4f -> guarded %.4f, free %.4f\n",
                twist, pillow, rg.min_before, rg.invalid_before, rg.min_after, rf.min_after, t0, tg, tf);
    EXPECT_GE(rg.min_after, rg.min_before);
    EXPECT_LE(rg.invalid_after, rg.invalid_before);
    if (rg.invalid_before == 0) {
      EXPECT_GE(tg, std::min(t0, 0.0) - 1e-12);
    }
    changed += std::abs(tg - tf) > 1e-6 ? 1 : 0;
    expect_surface_kept_and_shared_together(guarded, start);
  });
  EXPECT_GE(changed, 1);
}

// The check grid (OptimizeParams::check_points): after the cycles, no certified-valid element's
// field dips between the samples by more than check_tolerance below min(target, the reported
// worst on the elements' own samples) — those that did are sampled on the check grid — the usual
// sample's worst never falls, and the check is not a no-op: on the pillowed twist 1.2 (grid_points 2,
// the paper's corner sample, leaves room for dips) it finds dips and ends with a higher
// check-grid figure than without it; on the unpillowed mild twist it finds none and changes nothing.
TEST(Optimize, ElementsWhoseFieldDipsBetweenTheSamplesAreSampledOnTheCheckGrid) {
  auto check_grid_worst = [](const std::vector<tmesh::TMesh>& ts, int points) {
    double w = 1;
    for (const bezier::BezierHex& h : test::hexes(ts))
      if (bezier::certify(h).status == bezier::Validity::valid) w = std::min(w, bezier::sample_jacobian(h, 2, points).min_scaled);
    return w;
  };
  for (const auto& [twist, pillow] : std::vector<std::pair<double, int>>{{0.8, 0}, {1.2, 1}}) {
    tmesh::OptimizeParams op = twist_family_params();
    op.grid_points = 2;
    op.cycles = 3;
    op.check_points = 9;
    std::vector<tmesh::TMesh> checked = blocks(pillow, twist), unchecked = blocks(pillow, twist);
    const std::vector<tmesh::TMesh> start = checked;
    const tmesh::OptimizeResult rc = tmesh::optimize(checked, op);
    op.check_points = 0;
    const tmesh::OptimizeResult ru = tmesh::optimize(unchecked, op);
    const double wc = check_grid_worst(checked, 9), wu = check_grid_worst(unchecked, 9);
    std::printf("twist %.1f pillow %d: worst %.4f -> checked %.4f (%.4f on own samples, %d elements on the check grid, %.4f on it), "
                "unchecked %.4f (%.4f on it)\n",
                twist, pillow, rc.min_before, rc.min_after, rc.min_after_checked, rc.elements_on_check_grid, wc, ru.min_after, wu);
    EXPECT_EQ(ru.elements_on_check_grid, 0);
    EXPECT_EQ(ru.min_after_checked, ru.min_after);
    EXPECT_GE(rc.min_after, rc.min_before);
    EXPECT_LE(rc.min_after_checked, rc.min_after);
    EXPECT_LE(rc.invalid_after, rc.invalid_before);
    EXPECT_GE(wc, std::min(op.target, rc.min_after_checked) - op.check_tolerance - 1e-12);
    if (pillow == 1) {
      EXPECT_GT(rc.elements_on_check_grid, 0);
      EXPECT_GT(wc, wu + 0.1);  // measured (session 39): 0.073 -> 0.392
    } else {
      EXPECT_EQ(rc.elements_on_check_grid, 0);
      EXPECT_EQ(rc.min_after, ru.min_after);
    }
    expect_surface_kept_and_shared_together(checked, start);
  }
}

// optimize_moved (volts-tmesh after the C2 projection): elements the move left as they were count
// as checked between their samples. On a net optimized without the check grid, whose field dips
// between its samples, with every element at the target (nothing to move): optimize finds the
// dips on the check grid, optimize_moved with the net itself as the settled one checks none. A
// settled net of another element count is refused.
TEST(Optimize, OptimizeMovedChecksOnlyTheElementsThatMoved) {
  tmesh::OptimizeParams op = twist_family_params();
  op.grid_points = 2;
  op.cycles = 1;
  std::vector<tmesh::TMesh> net = blocks(1, 1.2);
  const tmesh::OptimizeResult first = tmesh::optimize(net, op);
  op.target = first.min_after;  // every element at it: no round, only the check
  op.check_points = 9;
  std::vector<tmesh::TMesh> a = net, b = net;
  const tmesh::OptimizeResult ra = tmesh::optimize(a, op);
  const tmesh::OptimizeResult rb = tmesh::optimize_moved(b, net, op);
  std::printf("dips on the 9^3 grid: %d with optimize, %d with optimize_moved of an unmoved net\n", ra.elements_on_check_grid, rb.elements_on_check_grid);
  EXPECT_GT(ra.elements_on_check_grid, 0) << "no dip: the check proves nothing";
  EXPECT_EQ(rb.elements_on_check_grid, 0);
  EXPECT_EQ(b[0].control_points, net[0].control_points);
  std::vector<tmesh::TMesh> wrong = blocks(0, 1.2);
  EXPECT_THROW(tmesh::optimize_moved(b, wrong, op), core::InvalidInputError);
}

// The best cycle end is kept (OptimizeResult::cycle_kept): a cycle's moves can open dips between
// the samples that only the check after it finds, deeper than those it raised. Over the pillowed
// twists at the corner + Gauss sample (grid_points 2), three cycles never end with more elements
// not certified valid than one, nor lower on the check grid than one (by more than
// check_tolerance: an element put on the check grid after the kept end did not dip by more than
// that at it), with either joint method; and keeping an earlier end is not a no-op on the family
// with L-BFGS rounds (twist 0.8: cycle 1's end, 0.51 on the 9³ grid, where cycle 3's ended at
// 0.26; session 39). With CCSAQ rounds (the default since session 40) every later end there is
// higher (twist 0.8: 0.19 after one cycle, 0.58 after three), so none is kept.
TEST(Optimize, MoreCyclesNeverEndLowerOnTheCheckGrid) {
  using Method = tmesh::OptimizeParams::JointMethod;
  int kept = 0;
  for (const Method method : {Method::ccsaq, Method::lbfgs})
    for (const double twist : {0.8, 1.8}) {  // 1.2 and 2.6 keep the last end (measured)
      tmesh::OptimizeParams op = twist_family_params();
      op.joint_method = method;
      op.grid_points = 2;
      op.check_points = 9;
      // At the tolerance of 0.05 (the default until session 43) a last cycle can open dips that
      // leave it below an earlier end; at 0.01 three cycles ended higher on every twist here
      // (ccsaq 0.8: 0.19 -> 0.58), so no earlier end was kept and the keeping went unexercised.
      op.check_tolerance = 0.05;
      std::vector<tmesh::TMesh> one = blocks(1, twist), three = blocks(1, twist);
      const std::vector<tmesh::TMesh> start = three;
      const tmesh::OptimizeResult r1 = tmesh::optimize(one, op);
      op.cycles = 3;
      const tmesh::OptimizeResult r3 = tmesh::optimize(three, op);
      std::printf("%s, twist %.1f: one cycle %.4f (%d not valid), three %.4f (%d), cycle %d's end kept\n", method == Method::ccsaq ? "ccsaq" : "lbfgs", twist,
                  r1.min_after_checked, r1.invalid_after, r3.min_after_checked, r3.invalid_after, r3.cycle_kept);
      EXPECT_EQ(r1.cycle_kept, 0);
      EXPECT_LE(r3.invalid_after, r1.invalid_after);
      if (r3.invalid_after == r1.invalid_after) {
        EXPECT_GE(r3.min_after_checked, r1.min_after_checked - op.check_tolerance);
      }
      EXPECT_LT(r3.cycle_kept, r3.cycles);
      if (method == Method::lbfgs) kept += r3.cycle_kept > 0 ? 1 : 0;
      expect_surface_kept_and_shared_together(three, start);
    }
  EXPECT_GE(kept, 1);
}

// Folds between the samples (optimize.cpp's Folds): where the certifier finds an element folded
// while its samples are positive, the joint rounds sample around the fold from then on. Over the
// twists at the paper's corner + Gauss sample (grid_points 2, where folds hide between the
// points): they find such folds (the check is not vacuous), every fold is fixed, the worst figure
// never falls, and the folded pillowed twist ends far higher than the 0.07 measured before folds
// were sampled (0.32 since: its steps folded elements between the samples, were refused, and
// L-BFGS made the same folds again round after round).
TEST(Optimize, FoldsBetweenTheSamplesAreSampledAroundAndFixed) {
  int folds = 0;
  for_each_twist([&folds](double twist, int pillow) {
    tmesh::OptimizeParams op = twist_family_params();
    op.grid_points = 2;
    std::vector<tmesh::TMesh> ts = blocks(pillow, twist);
    const std::vector<tmesh::TMesh> start = ts;
    const tmesh::OptimizeResult r = tmesh::optimize(ts, op);
    std::printf("twist %.1f pillow %d: worst %.4f -> %.4f, not certified valid %d -> %d, %d folds between the samples\n", twist, pillow,
                r.min_before, r.min_after, r.invalid_before, r.invalid_after, r.folds_between_samples);
    folds += r.folds_between_samples;
    EXPECT_EQ(r.invalid_after, 0);
    EXPECT_GE(r.min_after, r.min_before);
    for (const bezier::BezierHex& h : test::hexes(ts)) EXPECT_EQ(bezier::certify(h).status, bezier::Validity::valid);
    if (twist == 2.6 && pillow == 1) {
      EXPECT_GT(r.min_after, 0.2);
    }
    expect_surface_kept_and_shared_together(ts, start);
  });
  EXPECT_GT(folds, 0);
}

// repair_folds (run by volts-tmesh on the refined net where optimize left folds): over the twist
// family it fixes folded elements without optimizing the rest first, never costs a certified
// element its certificate, never lowers one below the worst figure of the valid elements at the
// start, and keeps surface points and shared points together.
TEST(Optimize, RepairOfTheFoldsFixesThemAndKeepsTheValidElements) {
  int folded = 0, fixed = 0;
  for_each_twist([&](double twist, int pillow) {
    const tmesh::OptimizeParams op = twist_family_params();
    std::vector<tmesh::TMesh> ts = blocks(pillow, twist);
    const std::vector<tmesh::TMesh> start = ts;
    std::vector<bool> valid_before;
    for (const bezier::BezierHex& h : test::hexes(ts)) valid_before.push_back(bezier::certify(h).status == bezier::Validity::valid);
    const tmesh::OptimizeResult r = tmesh::repair_folds(ts, op);
    double floor = 1;
    for (std::size_t e = 0; e < valid_before.size(); ++e)
      if (valid_before[e]) floor = std::min(floor, r.element_before[e]);
    std::printf("twist %.1f pillow %d: not certified valid %d -> %d, worst %.4f -> %.4f, valid elements' floor %.4f, %s\n", twist, pillow,
                r.invalid_before, r.invalid_after, r.min_before, r.min_after, floor, r.stop_reason.c_str());
    folded += r.invalid_before, fixed += r.invalid_before - r.invalid_after;
    EXPECT_EQ(r.invalid_after, 0);  // measured: 16–32 folded per folded twist, all fixed
    EXPECT_EQ(r.stop_reason, "all_valid");
    EXPECT_GE(r.min_after, r.min_before);
    const std::vector<bezier::BezierHex> after = test::hexes(ts);
    for (std::size_t e = 0; e < after.size(); ++e) {
      if (!valid_before[e]) continue;
      EXPECT_EQ(bezier::certify(after[e]).status, bezier::Validity::valid) << "element " << e << " lost its certificate";
      EXPECT_GE(r.element_after[e], std::min(floor, r.element_before[e]) - 1e-12) << "element " << e;
    }
    expect_surface_kept_and_shared_together(ts, start);
  });
  std::printf("%d of %d folded elements fixed\n", fixed, folded);
  EXPECT_GT(folded, 0);  // the family has folds to repair
}

namespace {

// A run of the optimizer on a net with folds: the worst figures of the elements certified valid
// at the start (the rest) and of the others (the folds), before and after.
struct FoldRun {
  tmesh::OptimizeResult r;
  std::vector<bool> valid;  // per element, certified before
  double rest_before = 1, rest_after = 1, fold_before = 1, fold_after = 1;
};

FoldRun optimize_with_folds(std::vector<tmesh::TMesh>& ts) {
  FoldRun f;
  for (const bezier::BezierHex& h : test::hexes(ts)) f.valid.push_back(bezier::certify(h).status == bezier::Validity::valid);
  f.r = tmesh::optimize(ts, twist_family_params());
  for (std::size_t e = 0; e < f.valid.size(); ++e) {
    double& before = f.valid[e] ? f.rest_before : f.fold_before;
    double& after = f.valid[e] ? f.rest_after : f.fold_after;
    before = std::min(before, f.r.element_before[e]), after = std::min(after, f.r.element_after[e]);
  }
  std::printf("not certified valid %d -> %d; the certified elements' worst %.4f -> %.4f; the folded ones' %.4f -> %.4f\n", f.r.invalid_before,
              f.r.invalid_after, f.rest_before, f.rest_after, f.fold_before, f.fold_after);
  return f;
}

// Every element certified valid before the run still is.
void expect_certified_stay_certified(const std::vector<tmesh::TMesh>& ts, const FoldRun& f) {
  const std::vector<bezier::BezierHex> after = test::hexes(ts);
  for (std::size_t e = 0; e < after.size(); ++e)
    if (f.valid[e]) {
      EXPECT_EQ(bezier::certify(after[e]).status, bezier::Validity::valid) << "element " << e;
    }
}

}  // namespace

// A fold no move may fix (a surface control point, fixed, moved along its face past its
// neighbours: the surface folds over): the optimizer raises it as far as it goes, never lets a
// folded element fall below its start or a certified one lose its certificate, and stops. Known
// weakness, printed: the rounds that raise the fold may lower the certified elements to just
// above it (0.08 -> 0.004 here; a floor for them and a rest-only round, docs/status.md sessions
// 36–37, do not lift them).
TEST(Optimize, AFoldNoRoundFixesIsRaisedAndTheCertifiedStayCertified) {
  std::vector<tmesh::TMesh> ts = blocks(0, 1.2);
  tmesh::TMesh& t = ts[0];
  const int j = t.size[1] / 2, k = t.size[2] / 2;
  t.control_points[static_cast<std::size_t>(t.size[0] * (j + t.size[1] * k))][1] += 0.9;
  const std::vector<tmesh::TMesh> start = ts;
  const FoldRun f = optimize_with_folds(ts);
  ASSERT_GT(f.r.invalid_after, 0) << "the fold was fixed: the case does not test what it is for";
  EXPECT_LE(f.r.invalid_after, f.r.invalid_before);
  EXPECT_GT(f.fold_after, f.fold_before + 0.1);
  expect_certified_stay_certified(ts, f);
  expect_surface_kept_and_shared_together(ts, start);
}

// The rule that lets the rest rise past a stuck fold (a joint round with folded elements among its
// elements is kept when the certified elements' worst rises), alone: the cube's corner control
// point is reflected through the centroid of its three neighbours, which inverts its element's
// frame at the corner sample; that sample depends on those four points only, all on the surface
// (fixed: no sliding surface), so no move can raise the fold. The twisted interior can be raised.
// Such a fold also holds the soft minimum: the other samples weigh nothing (e^-43), the gradient
// is 0 and every round is refused; a refused round with folds is then run once without them in
// its objective (measured: the rest 0.081 -> 0.952; before that round 0.133, from the sweep alone).
TEST(Optimize, TheRestRisesPastAFoldNoMoveCanRaise) {
  std::vector<tmesh::TMesh> ts = blocks(0, 1.2);
  tmesh::TMesh& t = ts[0];
  const std::size_t nu = static_cast<std::size_t>(t.size[0]), nv = static_cast<std::size_t>(t.size[1]);
  Vec3& corner = t.control_points[0];
  const Vec3 &a = t.control_points[1], &b = t.control_points[nu], &c = t.control_points[nu * nv];
  for (int d = 0; d < 3; ++d) corner[static_cast<std::size_t>(d)] = 2 * (a[static_cast<std::size_t>(d)] + b[static_cast<std::size_t>(d)] + c[static_cast<std::size_t>(d)]) / 3 - corner[static_cast<std::size_t>(d)];
  const std::vector<tmesh::TMesh> start = ts;
  const FoldRun f = optimize_with_folds(ts);
  ASSERT_EQ(f.r.invalid_before, 1) << "the case is one folded corner element";
  EXPECT_EQ(f.r.invalid_after, 1);
  EXPECT_NEAR(f.fold_after, f.fold_before, 1e-12) << "the fold depends on fixed points only";
  EXPECT_GT(f.rest_after, 0.9) << "the rest did not rise past the stuck fold (the family's target is 0.95)";
  expect_certified_stay_certified(ts, f);
  expect_surface_kept_and_shared_together(ts, start);
}

TEST(Optimize, ParametersOutOfRangeAreRefused) {
  std::vector<tmesh::TMesh> ts = blocks(0);
  tmesh::OptimizeParams op;
  op.sweeps = -1;
  EXPECT_THROW(tmesh::optimize(ts, op), core::ConfigError);
  for (const double bad : {-0.1, 1.5}) {
    tmesh::OptimizeParams g;
    g.min_gain = bad;
    EXPECT_THROW(tmesh::optimize(ts, g), core::ConfigError);
    tmesh::OptimizeParams f;
    f.min_fixed_rel = bad;
    EXPECT_THROW(tmesh::optimize(ts, f), core::ConfigError);
  }
  tmesh::OptimizeParams p;
  p.patience = 0;
  EXPECT_THROW(tmesh::optimize(ts, p), core::ConfigError);
  tmesh::OptimizeParams j;
  j.joint_rounds = -1;
  EXPECT_THROW(tmesh::optimize(ts, j), core::ConfigError);
  j = {}, j.joint_sharpness = 0;
  EXPECT_THROW(tmesh::optimize(ts, j), core::ConfigError);
  j = {}, j.joint_window = 1.5;
  EXPECT_THROW(tmesh::optimize(ts, j), core::ConfigError);
  j = {}, j.joint_dense_points = 1;
  EXPECT_THROW(tmesh::optimize(ts, j), core::ConfigError);
  j = {}, j.joint_evaluations = 0;
  EXPECT_THROW(tmesh::optimize(ts, j), core::ConfigError);
  for (const int bad : {0, 101}) {
    j = {}, j.cycles = bad;
    EXPECT_THROW(tmesh::optimize(ts, j), core::ConfigError);
  }
  for (const double bad : {-1e-4, 1.5}) {
    j = {}, j.cycle_min_gain = bad;
    EXPECT_THROW(tmesh::optimize(ts, j), core::ConfigError);
    j = {}, j.check_tolerance = bad;
    EXPECT_THROW(tmesh::optimize(ts, j), core::ConfigError);
  }
  for (const int bad : {-1, 1, 33}) {
    j = {}, j.check_points = bad;
    EXPECT_THROW(tmesh::optimize(ts, j), core::ConfigError);
  }
}
