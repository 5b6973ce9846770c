// C2 across block faces (continuity.h, Liu et al. §5.3): over a family of block complexes — a
// pillowed cube under smooth maps (core-slab faces), rings of cubes with and without a pillow
// (cube-cube faces) — the spline is C2 across every face it merged (first and second derivatives
// across the face centre agree, where before they did not), the rows sum to one and name free
// nodes only, extract's global basis stays a partition of unity with one function fewer per
// row, a net that is C2 already gets the same rows without moving, and the optimizer keeps every
// constrained point on its row.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <functional>
#include <set>

#include "bezier/bspline_volume.h"
#include "core/errors.h"
#include "extract/extract.h"
#include "ring_cubes.h"
#include "tmesh/continuity.h"
#include "tmesh/optimize.h"
#include "tmesh/tmesh.h"

using namespace volts;
using tmesh::Vec3;

namespace {

std::vector<tmesh::TMesh> cube_blocks(const std::function<Vec3(const Vec3&)>& map, int level, int pillow) {
  tmesh::PolycubeMaps m;
  m.boundary = {{1, 1, 1, 1, 1, 1}};
  m.physical = [map](int, const Vec3& abc) { return map(abc); };
  m.polycube = [](int, const Vec3& abc) { return abc; };
  tmesh::Params p;
  p.level = level;
  p.pillow_layers = pillow;
  return tmesh::build(m, p);
}

std::vector<tmesh::TMesh> ring_blocks(int cubes, int level, int pillow) {
  tmesh::Params p;
  p.level = level;
  p.pillow_layers = pillow;
  return tmesh::build(test::ring(cubes), p);
}

Vec3 bulged(const Vec3& x) {
  const double s = std::sin(3.14159265358979 * x[0]) * std::sin(3.14159265358979 * x[1]) * std::sin(3.14159265358979 * x[2]);
  return {x[0] + 0.15 * s, x[1] + 0.1 * s * x[0], x[2] + 0.2 * x[0] * x[1]};
}

Vec3 twisted(const Vec3& abc) {
  const double u = abc[1] - 0.5, v = abc[2] - 0.5;
  const double t = 0.8 * 64 * abc[0] * (1 - abc[0]) * abc[1] * (1 - abc[1]) * abc[2] * (1 - abc[2]);
  return {abc[0], 0.5 + u * std::cos(t) - v * std::sin(t), 0.5 + v * std::cos(t) + u * std::sin(t)};
}

struct Case {
  const char* name;
  std::function<std::vector<tmesh::TMesh>()> make;
};

std::vector<Case> family() {
  return {{"cube bulged, pillow 1", [] { return cube_blocks(bulged, 3, 1); }},
          {"cube twisted, pillow 1", [] { return cube_blocks(twisted, 3, 1); }},
          {"cube twisted, pillow 2", [] { return cube_blocks(twisted, 3, 2); }},
          {"ring of 4, pillow 0", [] { return ring_blocks(4, 3, 0); }},
          {"ring of 3, pillow 1", [] { return ring_blocks(3, 3, 1); }}};
}

// The first and second derivatives, in index units (one element = 1; or the block's parameter
// `length` units along `a` when given, its elements alike), of block t's spline along its axis `a`
// at the face `side` of the face centre, toward the face (exact: four points in the element next
// to the face, where the spline is a cubic polynomial).
std::pair<Eigen::Vector3d, Eigen::Vector3d> face_derivatives(const tmesh::TMesh& t, int a, int side, double length = 0,
                                                             const Eigen::Vector3d& at_face = Eigen::Vector3d(0.5, 0.5, 0.5)) {
  const bezier::TensorBSplineVolume vol = test::volume(t);
  const int n = t.size[a] - t.degree;
  const double units = length > 0 ? length : n;
  // Four points in the last element (its own length: spans halved by refine "spans" differ).
  const std::vector<double>& k = t.knots[static_cast<std::size_t>(a)];
  const double last = side ? 1.0 - k[static_cast<std::size_t>(t.size[a] - 1)] : k[static_cast<std::size_t>(t.degree + 1)];
  const double h = 0.25 * units * last;
  Eigen::Vector3d f[4];
  for (int k = 0; k < 4; ++k) {
    Eigen::Vector3d uvw = at_face;
    uvw[a] = side ? 1.0 - k * h / units : k * h / units;
    f[k] = bezier::evaluate(vol, uvw);
  }
  // Along s toward the face, s = 0 on it and -k h at point k.
  const Eigen::Vector3d d1 = (11 * f[0] - 18 * f[1] + 9 * f[2] - 2 * f[3]) / (6 * h);
  const Eigen::Vector3d d2 = (2 * f[0] - 5 * f[1] + 4 * f[2] - f[3]) / (h * h);
  return {d1, d2};
}

// The inner faces (two blocks sharing the 4 corner ids of a face) that `raised` made C2 at their
// centre: the points next to the face at the centre and around it carry smooth rows.
struct Face {
  int ba = 0, fa = 0, bb = 0, fb = 0;
};

std::size_t at(const tmesh::TMesh& t, const std::array<int, 3>& idx) {
  return static_cast<std::size_t>(idx[0] + t.size[0] * (idx[1] + t.size[1] * idx[2]));
}

std::vector<Face> merged_faces(const std::vector<tmesh::TMesh>& raised) {
  std::vector<Face> out;
  for (const tmesh::SharedFace& sf : tmesh::shared_faces(raised)) {
    const int ba = sf.a, fa = sf.fa;
    const tmesh::TMesh& t = raised[static_cast<std::size_t>(ba)];
    const int a = fa / 2, u = (a + 1) % 3, w = (a + 2) % 3;
    if (t.size[u] % 2 == 0 || t.size[w] % 2 == 0) continue;  // no line through the centre
    // The centre is a knot (an even count of elements): the three lines whose functions are
    // nonzero there, in both directions, must all be C2.
    bool all = true;
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        std::array<int, 3> idx{};
        idx[static_cast<std::size_t>(a)] = fa % 2 ? t.size[a] - 2 : 1;
        idx[static_cast<std::size_t>(u)] = t.size[u] / 2 + di, idx[static_cast<std::size_t>(w)] = t.size[w] / 2 + dj;
        const int point = static_cast<int>(at(t, idx));
        all = all && std::any_of(t.constraints.begin(), t.constraints.end(), [&](const tmesh::TMesh::Constraint& k) { return k.point == point && k.smooth; });
      }
    if (all) out.push_back({ba, fa, sf.b, sf.fb});
  }
  return out;
}

// The jumps of the first and second derivatives across a face's centre (one block's toward the
// face against the other's away from it), and the size of the first block's derivatives.
struct Jump {
  double d1 = 0, d2 = 0, scale = 0;
};

Jump jump(const std::vector<tmesh::TMesh>& ts, const Face& f, const std::vector<std::array<double, 3>>* lengths = nullptr) {
  auto length = [&](int b, int face) { return lengths ? (*lengths)[static_cast<std::size_t>(b)][static_cast<std::size_t>(face / 2)] : 0.0; };
  const auto [a1, a2] = face_derivatives(ts[static_cast<std::size_t>(f.ba)], f.fa / 2, f.fa % 2, length(f.ba, f.fa));
  const auto [b1, b2] = face_derivatives(ts[static_cast<std::size_t>(f.bb)], f.fb / 2, f.fb % 2, length(f.bb, f.fb));
  // B's "toward its face" is A's "away": the first derivatives are opposite, the second equal.
  return {(a1 + b1).norm(), (a2 - b2).norm(), a1.norm() + a2.norm()};
}

// Every node's point by id.
std::map<int, Eigen::Vector3d> points_by_id(const std::vector<tmesh::TMesh>& ts) {
  std::map<int, Eigen::Vector3d> p;
  for (const auto& t : ts)
    for (std::size_t i = 0; i < t.function_ids.size(); ++i)
      p[t.function_ids[i]] = Eigen::Vector3d(t.control_points[i][0], t.control_points[i][1], t.control_points[i][2]);
  return p;
}

// The largest distance of a constrained point from its row's combination.
double off_rows(const std::vector<tmesh::TMesh>& ts) {
  const auto p = points_by_id(ts);
  double off = 0;
  for (const auto& t : ts)
    for (const auto& k : t.constraints) {
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (std::size_t m = 0; m < k.ids.size(); ++m) x += k.weights[m] * p.at(k.ids[m]);
      off = std::max(off, (x - p.at(t.function_ids[static_cast<std::size_t>(k.point)])).norm());
    }
  return off;
}

// The net `start` raised with `params`, and what raise_continuity did.
std::pair<std::vector<tmesh::TMesh>, tmesh::ContinuityResult> raised(const std::vector<tmesh::TMesh>& start, const tmesh::ContinuityParams& params = {}) {
  std::vector<tmesh::TMesh> ts = start;
  const tmesh::ContinuityResult r = tmesh::raise_continuity(ts, params);
  return {std::move(ts), r};
}

// Extract's global basis of a net (its blocks' Bézier elements).
extract::GlobalBasis global_basis_of(const std::vector<tmesh::TMesh>& net) {
  std::vector<bezier::BezierHex> hexes;
  for (const auto& t : net) {
    const auto e = bezier::extract_bezier_hexes(test::volume(t));
    hexes.insert(hexes.end(), e.begin(), e.end());
  }
  return extract::global_basis(net, hexes, false);
}

// The grid index of block t's control point i.
std::array<int, 3> grid_of(const tmesh::TMesh& t, std::size_t i) {
  const int k = static_cast<int>(i);
  return {k % t.size[0], (k / t.size[0]) % t.size[1], k / (t.size[0] * t.size[1])};
}

}  // namespace

TEST(Continuity, MergedFacesAreC2AcrossTheirCentre) {
  for (const Case& c : family()) {
    std::vector<tmesh::TMesh> ts = c.make();
    const std::vector<tmesh::TMesh> start = ts;
    const tmesh::ContinuityResult r = tmesh::raise_continuity(ts);
    const std::vector<Face> faces = merged_faces(ts);
    std::printf("%s: %d faces made C2 (%d lines, %d rows), %d kept C0; %zu through their centre\n", c.name, r.faces, r.lines, r.constrained,
                r.faces_kept, faces.size());
    EXPECT_GT(r.faces, 0);
    EXPECT_GT(faces.size(), 0u);
    EXPECT_EQ(r.constrained, 2 * r.lines);
    double worst_before = 0, worst_after = 0;
    for (const Face& f : faces) {
      const Jump j0 = jump(start, f), j = jump(ts, f);
      EXPECT_LT(j.d1, 1e-9 * j.scale) << c.name << ": not C1 at the face of blocks " << f.ba << ", " << f.bb;
      worst_before = std::max(worst_before, j0.d2 / j0.scale);
      worst_after = std::max(worst_after, j.d2 / j.scale);
    }
    std::printf("  second-derivative jump at the face centres (relative): %.3g before, %.3g after\n", worst_before, worst_after);
    EXPECT_LT(worst_after, 1e-8);
    EXPECT_GT(worst_before, 1e-6) << c.name << ": C2 before, the check proves nothing";
  }
}

TEST(Continuity, RowsSumToOneNameFreeNodesAndKeepAPartitionOfUnity) {
  for (const Case& c : family()) {
    std::vector<tmesh::TMesh> ts = c.make();
    const std::vector<bezier::BezierHex> hexes0 = [&] {
      std::vector<bezier::BezierHex> h;
      for (const auto& t : ts) {
        const auto e = bezier::extract_bezier_hexes(test::volume(t));
        h.insert(h.end(), e.begin(), e.end());
      }
      return h;
    }();
    const extract::GlobalBasis g0 = extract::global_basis(ts, hexes0, false);
    const tmesh::ContinuityResult r = tmesh::raise_continuity(ts);
    std::set<int> constrained;
    for (const auto& t : ts)
      for (const auto& k : t.constraints) {
        EXPECT_TRUE(k.smooth);
        constrained.insert(t.function_ids[static_cast<std::size_t>(k.point)]);
        double sum = 0;
        for (const double w : k.weights) sum += w;
        EXPECT_NEAR(sum, 1.0, 1e-12);
      }
    for (const auto& t : ts)
      for (const auto& k : t.constraints)
        for (const int m : k.ids) EXPECT_EQ(constrained.count(m), 0u) << c.name << ": a row names a constrained point";
    EXPECT_EQ(static_cast<int>(constrained.size()), r.constrained);
    EXPECT_LT(off_rows(ts), 1e-12);
    std::vector<bezier::BezierHex> hexes;
    for (const auto& t : ts) {
      const auto e = bezier::extract_bezier_hexes(test::volume(t));
      hexes.insert(hexes.end(), e.begin(), e.end());
    }
    const extract::GlobalBasis g = extract::global_basis(ts, hexes, false);
    std::printf("%s: %zu -> %zu global functions, partition of unity within %.1e\n", c.name, g0.points.size(), g.points.size(), g.partition_of_unity_error);
    EXPECT_EQ(g.points.size() + static_cast<std::size_t>(r.constrained), g0.points.size());
    EXPECT_LT(g.partition_of_unity_error, 1e-12);
    // The clamped blocks' functions are B-splines; the smooth rows' are not (negative weights).
    EXPECT_GE(g0.min_coefficient, 0.0) << c.name;
    EXPECT_LT(g.min_coefficient, 0.0) << c.name;
  }
}

TEST(Continuity, ANetThatIsC2AlreadyGetsTheSameRowsWithoutMoving) {
  for (const Case& c : family()) {
    std::vector<tmesh::TMesh> ts = c.make();
    const tmesh::ContinuityResult r = tmesh::raise_continuity(ts);
    std::vector<tmesh::TMesh> again = ts;
    for (auto& t : again) t.constraints.clear();
    tmesh::ContinuityParams keep;
    keep.project = false;
    const tmesh::ContinuityResult r2 = tmesh::raise_continuity(again, keep);
    EXPECT_EQ(r2.lines, r.lines) << c.name;
    for (std::size_t b = 0; b < ts.size(); ++b) {
      EXPECT_EQ(again[b].control_points, ts[b].control_points) << c.name << ": a point moved";
      ASSERT_EQ(again[b].constraints.size(), ts[b].constraints.size());
      for (std::size_t k = 0; k < ts[b].constraints.size(); ++k) {
        EXPECT_EQ(again[b].constraints[k].point, ts[b].constraints[k].point);
        EXPECT_EQ(again[b].constraints[k].ids, ts[b].constraints[k].ids);
      }
    }
    // The interpolating net of a curved map is not C2 across the faces: without projecting,
    // fewer lines qualify.
    std::vector<tmesh::TMesh> fresh = c.make();
    const tmesh::ContinuityResult r0 = tmesh::raise_continuity(fresh, keep);
    EXPECT_LT(r0.lines, r.lines) << c.name;
  }
}

// The pillow layer split across the surface (tmesh.pillow_splits) leaves the spline C2 where it
// was, with the slabs' knot intervals across the core's faces a fraction of the core's: given the
// blocks' lengths in the uniform refinement's units the rows find every line the unsplit
// refinement has (and more across the faces between slabs, whose points the split multiplies);
// without them, unit intervals are assumed and those faces are lost.
TEST(Continuity, PillowSplitsKeepTheirC2FacesGivenTheBlocksLengths) {
  tmesh::PolycubeMaps m;
  m.boundary = {{1, 1, 1, 1, 1, 1}};
  m.physical = [](int, const Vec3& abc) { return twisted(abc); };
  m.polycube = [](int, const Vec3& abc) { return abc; };
  tmesh::Params p;
  p.level = 2;
  p.pillow_layers = 1;
  std::vector<tmesh::TMesh> ts = tmesh::build(m, p);
  ASSERT_GT(tmesh::raise_continuity(ts).lines, 0);
  int unsplit = -1;
  for (const int s : {1, 2, 3}) {
    SCOPED_TRACE("pillow_splits " + std::to_string(s));
    tmesh::Params q = p;
    q.pillow_splits = s;
    const auto splits = tmesh::refinement_splits(m, q, ts, 1);
    std::vector<tmesh::TMesh> fine = tmesh::h_refine(m, q, ts, 1);
    std::vector<tmesh::TMesh> blind = fine;
    tmesh::ContinuityParams keep;
    keep.project = false;
    const tmesh::ContinuityResult without = tmesh::raise_continuity(blind, keep);
    for (const auto& sp : splits) keep.lengths.push_back({2.0 * sp[0].size(), 2.0 * sp[1].size(), 2.0 * sp[2].size()});
    const tmesh::ContinuityResult with = tmesh::raise_continuity(fine, keep);
    if (s == 1) {
      unsplit = with.lines;
      EXPECT_EQ(without.lines, with.lines) << "unit intervals either way";
    } else {
      EXPECT_GE(with.lines, unsplit);
      EXPECT_LT(without.lines, unsplit) << "the split slabs' faces were found without their lengths";
    }
    EXPECT_LT(off_rows(fine), 1e-9);
    // C2 across every merged face's centre, in the units of the lengths.
    const std::vector<Face> merged = merged_faces(fine);
    EXPECT_FALSE(merged.empty());
    for (const Face& f : merged) {
      const Jump j = jump(fine, f, &keep.lengths);
      EXPECT_LT(j.d1, 1e-8 * j.scale);
      EXPECT_LT(j.d2, 1e-6 * j.scale);
    }
  }
  EXPECT_GT(unsplit, 0);
  tmesh::ContinuityParams bad;
  bad.lengths = {{1.0, 1.0, 1.0}};
  EXPECT_THROW(tmesh::raise_continuity(ts, bad), core::InvalidInputError);
  bad.lengths.assign(ts.size(), {1.0, 0.0, 1.0});
  EXPECT_THROW(tmesh::raise_continuity(ts, bad), core::InvalidInputError);
}

// Adaptive spans (tmesh.refine spans) leave knot intervals of half an element next to some faces
// (a ring whose cube 0 deviates near its face with cube 3): given the blocks' units
// (Levels::span_units) every merged face is C2 in them; taken as unit intervals the rows
// are wrong there.
TEST(Continuity, AdaptiveSpansAreC2GivenTheirUnits) {
  const tmesh::PolycubeMaps maps = test::ring_far_at_cube0(4);
  const tmesh::Params p = test::far_ring_params(2, "spans");
  tmesh::Levels lv;
  const std::vector<tmesh::TMesh> ts = tmesh::build(maps, p, &lv);
  ASSERT_GT(lv.knots_inserted, 0);
  ASSERT_EQ(lv.span_units.size(), ts.size());
  for (std::size_t b = 0; b < ts.size(); ++b)
    for (int a = 0; a < 3; ++a) {
      // A block's units are its elements as laid out: the same on every block along the ring's height.
      if (a == 2) {
        EXPECT_EQ(lv.span_units[b][2], static_cast<double>(ts[b].size[2] - 3));
      }
      EXPECT_LE(lv.span_units[b][static_cast<std::size_t>(a)], static_cast<double>(ts[b].size[a] - 3));
    }
  std::vector<tmesh::TMesh> with = ts, blind = ts;
  tmesh::ContinuityParams cp;
  cp.lengths = lv.span_units;
  EXPECT_GT(tmesh::raise_continuity(with, cp).lines, 0);
  tmesh::raise_continuity(blind);
  EXPECT_LT(off_rows(with), 1e-9);
  double worst_with = 0, worst_blind = 0;
  for (const Face& f : merged_faces(with)) {
    const Jump j = jump(with, f, &cp.lengths);
    EXPECT_LT(j.d1, 1e-8 * j.scale);
    EXPECT_LT(j.d2, 1e-6 * j.scale);
    worst_with = std::max(worst_with, j.d2 / j.scale);
  }
  for (const Face& f : merged_faces(blind)) {
    const Jump j = jump(blind, f, &cp.lengths);
    worst_blind = std::max(worst_blind, std::max(j.d1, j.d2) / j.scale);
  }
  EXPECT_GT(worst_blind, 1e-3) << "unit intervals gave C2 rows across the halved spans too";
  EXPECT_LE(extract::global_basis(with, test::hexes(with)).partition_of_unity_error, 1e-12);
}

TEST(Continuity, TheOptimizerKeepsEveryConstrainedPointOnItsRow) {
  std::vector<tmesh::TMesh> ts = cube_blocks(twisted, 3, 1);
  tmesh::raise_continuity(ts);
  const std::vector<tmesh::TMesh> start = ts;
  tmesh::OptimizeParams op;
  op.target = 0.95;
  op.sweeps = 1;
  op.joint_rounds = 2;
  op.joint_evaluations = 30;
  op.gauss_points = 2;
  op.check_points = 0;
  const tmesh::OptimizeResult r = tmesh::optimize(ts, op);
  std::printf("twisted cube, pillow 1: worst %.4f -> %.4f, %d nodes moved, %d joint rounds\n", r.min_before, r.min_after, r.nodes_moved, r.joint_rounds);
  EXPECT_GE(r.min_after, r.min_before);
  EXPECT_GT(r.min_after, r.min_before + 1e-3);  // moves happened
  EXPECT_LT(off_rows(ts), 1e-12);
  for (const Face& f : merged_faces(ts)) EXPECT_LT(jump(ts, f).d2, 1e-8 * jump(ts, f).scale);
}

TEST(Continuity, BadInputIsRefused) {
  std::vector<tmesh::TMesh> ts = cube_blocks(twisted, 3, 1);
  tmesh::ContinuityParams p;
  p.margin = 1;
  EXPECT_THROW(tmesh::raise_continuity(ts, p), core::ConfigError);
  for (const double bad : {-0.1, std::nan("")}) {
    tmesh::ContinuityParams m;
    m.max_move_rel = bad;
    EXPECT_THROW(tmesh::raise_continuity(ts, m), core::ConfigError);
    tmesh::ContinuityParams s;
    s.surface_move_max = bad;
    EXPECT_THROW(tmesh::raise_continuity(ts, s), core::ConfigError);
  }
  std::vector<tmesh::TMesh> no_ids = ts;
  no_ids[0].function_ids.clear();
  EXPECT_THROW(tmesh::raise_continuity(no_ids), core::InvalidInputError);
  tmesh::PolycubeMaps m;
  m.boundary = {{1, 1, 1, 1, 1, 1}};
  m.physical = [](int, const Vec3& abc) { return abc; };
  m.polycube = [](int, const Vec3& abc) { return abc; };
  tmesh::Params quad;
  quad.level = 3, quad.pillow_layers = 1, quad.degree = 2;
  std::vector<tmesh::TMesh> q = tmesh::build(m, quad);
  EXPECT_THROW(tmesh::raise_continuity(q), core::ConfigError);
}

// Any positive ratio of the knot intervals on a face's two sides is a C2 spline (the blocks'
// parameters are glued by an affine map per face). A net made C2 with block lengths that are not
// its element counts (ratios 2.5 and 0.4 across the faces) is moved by the rows of index space's
// ratio 1; with the ratio fitted per face it is moved by almost nothing, and it is C2 in the
// lengths it was made with.
TEST(Continuity, AFittedRatioFindsTheKnotIntervalsANetIsC2In) {
  for (const Case& c : family()) {
    std::vector<tmesh::TMesh> net = c.make();
    tmesh::ContinuityParams made;
    for (std::size_t b = 0; b < net.size(); ++b) {
      const double s = b % 2 ? 2.5 : 1.0;
      made.lengths.push_back({s * (net[b].size[0] - 3), s * (net[b].size[1] - 3), s * (net[b].size[2] - 3)});
    }
    const tmesh::ContinuityResult r0 = tmesh::raise_continuity(net, made);
    ASSERT_GT(r0.lines, 0) << c.name;
    for (auto& t : net) t.constraints.clear();
    std::vector<tmesh::TMesh> unit = net, fitted = net;
    const tmesh::ContinuityResult ru = tmesh::raise_continuity(unit);
    tmesh::ContinuityParams fit;
    fit.fit_ratio = true;
    const tmesh::ContinuityResult rf = tmesh::raise_continuity(fitted, fit);
    std::printf("%s: %d lines; moved up to %.3g with ratio 1, %.3g with the ratio fitted\n", c.name, rf.lines, ru.moved_max, rf.moved_max);
    EXPECT_EQ(rf.lines, ru.lines) << c.name;
    EXPECT_GT(ru.moved_max, 1e-3) << c.name << ": index space's ratio fits too, the check proves nothing";
    EXPECT_LT(rf.moved_max, 1e-3 * ru.moved_max) << c.name;
    double worst = 0;
    for (const Face& f : merged_faces(fitted)) {
      const Jump j = jump(fitted, f, &made.lengths);
      worst = std::max({worst, j.d1 / j.scale, j.d2 / j.scale});
    }
    EXPECT_LT(worst, 1e-3) << c.name << ": not C2 in the lengths the net was made with";
  }
}

// ContinuityParams::max_move_rel: a line whose extra would move farther than that fraction of
// the distance to its nearest neighbour keeps C0; the rest are the lines of the unbounded run.
TEST(Continuity, LinesThatWouldMoveTooFarKeepC0) {
  constexpr double kBound = 0.02;
  int bounded_cases = 0;  // where the bound keeps some line C0 (the ring of 4 is nearly C2 already)
  for (const Case& c : family()) {
    const std::vector<tmesh::TMesh> start = c.make();
    tmesh::ContinuityParams p;
    p.max_move_rel = kBound;
    const auto [all, ra] = raised(start);
    const auto [bounded, rb] = raised(start, p);
    std::printf("%s: %d of %d lines moved by at most %g of their nearest neighbour's distance\n", c.name, rb.lines, ra.lines, kBound);
    EXPECT_EQ(rb.lines + rb.lines_kept, ra.lines) << c.name;
    bounded_cases += rb.lines_kept > 0 ? 1 : 0;
    EXPECT_LE(rb.moved_max, ra.moved_max);
    double worst = 0;  // a moved point's move over kBound of its nearest neighbour's distance
    for (std::size_t b = 0; b < start.size(); ++b) {
      const tmesh::TMesh& t = start[b];
      for (std::size_t i = 0; i < t.control_points.size(); ++i) {
        const Eigen::Vector3d x0(t.control_points[i][0], t.control_points[i][1], t.control_points[i][2]);
        const Eigen::Vector3d x(bounded[b].control_points[i][0], bounded[b].control_points[i][1], bounded[b].control_points[i][2]);
        if ((x - x0).norm() == 0) continue;
        const std::array<int, 3> g = grid_of(t, i);
        double reach = std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a)
          for (const int step : {-1, 1}) {
            std::array<int, 3> n = g;
            n[static_cast<std::size_t>(a)] += step;
            if (n[static_cast<std::size_t>(a)] < 0 || n[static_cast<std::size_t>(a)] >= t.size[a]) continue;
            const auto& y = t.control_points[at(t, n)];
            reach = std::min(reach, (x0 - Eigen::Vector3d(y[0], y[1], y[2])).norm());
          }
        worst = std::max(worst, (x - x0).norm() / (kBound * reach));
      }
    }
    EXPECT_LE(worst, 1.0 + 1e-9) << c.name;
  }
  EXPECT_GE(bounded_cases, 3) << "no line moves that far: the check proves nothing";
}

// ContinuityParams::surface_layer: the rims of a face on the surface keep no margin, so the
// spline is C2 across the face up to the surface and on it (the pillowed cubes' faces between
// slabs, the ring's between cubes): at the middle of every such rim whose lines got rows, the
// derivatives across agree where before they did not; there are more lines than without it; and
// with surface_move_max no surface point moves farther than it.
TEST(Continuity, TheSurfaceLayerIsC2AcrossFacesUpToTheSurface) {
  for (const Case& c : family()) {
    const std::vector<tmesh::TMesh> start = c.make();
    tmesh::ContinuityParams p;
    p.surface_layer = true;
    const auto [inner, ri] = raised(start);
    const auto [up, ru] = raised(start, p);
    // The middle of every rim on the surface of a merged face, in both blocks' parameters.
    int rims = 0;
    double worst_before = 0, worst_after = 0;
    for (const tmesh::SharedFace& sf : tmesh::shared_faces(up)) {
      const tmesh::TMesh& A = up[static_cast<std::size_t>(sf.a)];
      const tmesh::TMesh& B = up[static_cast<std::size_t>(sf.b)];
      const int a = sf.fa / 2, ab = sf.fb / 2;
      for (const int t : {(a + 1) % 3, (a + 2) % 3})
        for (const int side : {0, 1}) {
          if (!A.boundary[static_cast<std::size_t>(2 * t + side)]) continue;
          const int o = 3 - a - t;  // the rim's own direction
          if (A.size[o] % 2 == 0) continue;  // no point at its middle
          std::array<int, 3> idx{};
          idx[static_cast<std::size_t>(a)] = sf.fa % 2 ? A.size[a] - 1 : 0;
          idx[static_cast<std::size_t>(t)] = side ? A.size[t] - 1 : 0;
          idx[static_cast<std::size_t>(o)] = A.size[o] / 2;
          std::array<int, 3> extra = idx;
          extra[static_cast<std::size_t>(a)] = sf.fa % 2 ? A.size[a] - 2 : 1;
          const int e = static_cast<int>(at(A, extra));
          if (!std::any_of(A.constraints.begin(), A.constraints.end(), [&](const tmesh::TMesh::Constraint& k) { return k.point == e && k.smooth; })) continue;
          // The same face point in B, and its parameters there (0, 1/2 or 1: symmetric knots).
          const int id = A.function_ids[at(A, idx)];
          const auto it = std::find(B.function_ids.begin(), B.function_ids.end(), id);
          ASSERT_NE(it, B.function_ids.end());
          const std::array<int, 3> g = grid_of(B, static_cast<std::size_t>(it - B.function_ids.begin()));
          Eigen::Vector3d pa, pb;
          for (int d = 0; d < 3; ++d) pa[d] = double(idx[static_cast<std::size_t>(d)]) / (A.size[d] - 1), pb[d] = double(g[static_cast<std::size_t>(d)]) / (B.size[d] - 1);
          auto jump_at = [&](const std::vector<tmesh::TMesh>& ts) {
            const auto [a1, a2] = face_derivatives(ts[static_cast<std::size_t>(sf.a)], a, sf.fa % 2, 0, pa);
            const auto [b1, b2] = face_derivatives(ts[static_cast<std::size_t>(sf.b)], ab, sf.fb % 2, 0, pb);
            return std::max((a1 + b1).norm(), (a2 - b2).norm()) / (a1.norm() + a2.norm());
          };
          ++rims;
          worst_before = std::max(worst_before, jump_at(start));
          worst_after = std::max(worst_after, jump_at(up));
        }
    }
    std::printf("%s: %d lines (%d in the surface) against %d without the surface layer; %d rims C2 at their middle: jump %.3g before, %.3g after\n",
                c.name, ru.lines, ru.surface_lines, ri.lines, rims, worst_before, worst_after);
    EXPECT_GT(ru.lines, ri.lines) << c.name;
    EXPECT_EQ(ri.surface_lines, 0) << c.name;
    EXPECT_GT(ru.surface_lines, 0) << c.name;
    EXPECT_GT(rims, 0) << c.name;
    EXPECT_LT(worst_after, 1e-8) << c.name;
    EXPECT_GT(worst_before, 1e-6) << c.name << ": C2 before, the check proves nothing";
    // surface_move_max: a fifth of the largest surface move of the unbounded run.
    double largest = 0;
    auto surface_moves = [&](const std::vector<tmesh::TMesh>& ts, double* most) {
      for (std::size_t b = 0; b < ts.size(); ++b) {
        const tmesh::TMesh& t = start[b];
        for (std::size_t i = 0; i < t.control_points.size(); ++i) {
          const std::array<int, 3> g = grid_of(t, i);
          bool on = false;
          for (int d = 0; d < 3; ++d)
            on = on || (t.boundary[static_cast<std::size_t>(2 * d)] && g[static_cast<std::size_t>(d)] == 0) ||
                 (t.boundary[static_cast<std::size_t>(2 * d + 1)] && g[static_cast<std::size_t>(d)] == t.size[d] - 1);
          if (!on) continue;
          const auto& x = ts[b].control_points[i];
          const auto& y = t.control_points[i];
          *most = std::max(*most, std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]));
        }
      }
    };
    surface_moves(up, &largest);
    ASSERT_GT(largest, 0) << c.name;
    p.surface_move_max = 0.2 * largest;
    const auto [bounded, rb] = raised(start, p);
    double most = 0;
    surface_moves(bounded, &most);
    EXPECT_LE(most, p.surface_move_max + 1e-12) << c.name;
    EXPECT_LT(rb.surface_lines, ru.surface_lines) << c.name;
    EXPECT_GT(rb.lines_kept, 0) << c.name;
  }
}

// smooth_rows_as_bsplines: the same spline (no block point moves, so the Bézier elements are the
// same) in the C2 spline's B-spline basis: every line rewritten, one free node per line, as many
// global functions as with the knot removal's rows, a partition of unity, every function's
// Bézier pieces reproducing the hexes (global_basis checks it), and no negative Bernstein
// coefficient where the knot removal's rows had some. The rows read back from the stage file.
TEST(Continuity, SmoothRowsAsBSplinesGiveANonNegativeBasisOfTheSameSpline) {
  for (const Case& c : family()) {
    tmesh::ContinuityParams p;
    p.surface_layer = true;
    auto [ts, r] = raised(c.make(), p);
    const extract::GlobalBasis before = global_basis_of(ts);
    const std::vector<tmesh::TMesh> removal = ts;
    const int lines = tmesh::smooth_rows_as_bsplines(ts);
    const extract::GlobalBasis after = global_basis_of(ts);
    std::size_t free_nodes = 0;
    for (const auto& t : ts) free_nodes += t.free_nodes.size();
    std::printf("%s: %d of %d lines as B-splines; %zu global functions (%zu before); smallest coefficient %.3g (%.3g before)\n", c.name, lines,
                r.lines, after.points.size(), before.points.size(), after.min_coefficient, before.min_coefficient);
    EXPECT_EQ(lines, r.lines) << c.name;
    EXPECT_GE(free_nodes, static_cast<std::size_t>(lines)) << c.name;  // each in the blocks that name it
    EXPECT_EQ(after.points.size(), before.points.size()) << c.name;
    EXPECT_LT(after.partition_of_unity_error, 1e-12) << c.name;
    EXPECT_LT(before.min_coefficient, 0.0) << c.name;
    EXPECT_GE(after.min_coefficient, -1e-12) << c.name;
    for (std::size_t b = 0; b < ts.size(); ++b) EXPECT_EQ(ts[b].control_points, removal[b].control_points) << c.name;
    std::vector<tmesh::TMesh> read;
    for (const auto& t : ts) read.push_back(tmesh::from_json(tmesh::to_json(t), "test"));
    EXPECT_EQ(global_basis_of(read).points.size(), after.points.size()) << c.name;
  }
}

namespace {

// Where the spline is C2 across the inner faces: per shared face, per element of the face (its
// centre), whether the first and second derivatives across it agree (to 1e-9 of their size), and
// the element's distance (in elements) from the face's rims, each rim regular (its middle point
// held by four blocks) or not.
struct FaceSample {
  bool c2 = false;
  int near_rims = 0;         // rims within two elements
  bool near_regular = true;  // all of them regular edges
};
std::vector<FaceSample> face_samples(const std::vector<tmesh::TMesh>& ts) {
  std::map<int, int> held;
  for (const auto& t : ts)
    for (const int id : t.function_ids) ++held[id];
  std::vector<FaceSample> out;
  for (const tmesh::SharedFace& sf : tmesh::shared_faces(ts)) {
    const tmesh::TMesh& A = ts[static_cast<std::size_t>(sf.a)];
    const tmesh::TMesh& B = ts[static_cast<std::size_t>(sf.b)];
    const int a = sf.fa / 2, u = (a + 1) % 3, w = (a + 2) % 3, ab = sf.fb / 2;
    auto a_id = [&](int i, int j) {
      std::array<int, 3> idx{};
      idx[static_cast<std::size_t>(a)] = sf.fa % 2 ? A.size[a] - 1 : 0, idx[static_cast<std::size_t>(u)] = i, idx[static_cast<std::size_t>(w)] = j;
      return A.function_ids[at(A, idx)];
    };
    auto b_grid = [&](int id) {
      const auto it = std::find(B.function_ids.begin(), B.function_ids.end(), id);
      return grid_of(B, static_cast<std::size_t>(it - B.function_ids.begin()));
    };
    // B's axes for A's u and w, and whether they run the same way.
    const auto g00 = b_grid(a_id(0, 0)), g10 = b_grid(a_id(A.size[u] - 1, 0)), g01 = b_grid(a_id(0, A.size[w] - 1));
    int bu = 0, bw = 0;
    for (int d = 0; d < 3; ++d) {
      if (g10[static_cast<std::size_t>(d)] != g00[static_cast<std::size_t>(d)]) bu = d;
      if (g01[static_cast<std::size_t>(d)] != g00[static_cast<std::size_t>(d)]) bw = d;
    }
    const bool fu = g10[static_cast<std::size_t>(bu)] > g00[static_cast<std::size_t>(bu)], fw = g01[static_cast<std::size_t>(bw)] > g00[static_cast<std::size_t>(bw)];
    const int nu = A.size[u] - 3, nw = A.size[w] - 3;
    // Regular rims: u low, u high, w low, w high.
    auto regular = [&](int i, int j) { return held[a_id(i, j)] == 4; };
    const bool rim[4] = {regular(0, A.size[w] / 2), regular(A.size[u] - 1, A.size[w] / 2), regular(A.size[u] / 2, 0), regular(A.size[u] / 2, A.size[w] - 1)};
    for (int ej = 0; ej < nw; ++ej)
      for (int ei = 0; ei < nu; ++ei) {
        const double su = (ei + 0.5) / nu, sw = (ej + 0.5) / nw;
        Eigen::Vector3d pa(0.5, 0.5, 0.5), pb(0.5, 0.5, 0.5);
        pa[u] = su, pa[w] = sw;
        pb[bu] = fu ? su : 1 - su, pb[bw] = fw ? sw : 1 - sw;
        const auto [a1, a2] = face_derivatives(A, a, sf.fa % 2, 0, pa);
        const auto [b1, b2] = face_derivatives(B, ab, sf.fb % 2, 0, pb);
        FaceSample f;
        // In index units on both sides (B's toward its face is A's away from it).
        const double scale = a1.norm() + a2.norm();
        f.c2 = (a1 + b1).norm() <= 1e-8 * scale && (a2 - b2).norm() <= 1e-8 * scale;
        const int dist[4] = {ei, nu - 1 - ei, ej, nw - 1 - ej};
        for (int k = 0; k < 4; ++k)
          if (dist[k] < 2) ++f.near_rims, f.near_regular = f.near_regular && rim[k];
        out.push_back(f);
      }
  }
  return out;
}

}  // namespace

// Regular edges (ContinuityParams::regular_edges): where four blocks meet around an inner edge
// (rings of pillowed cubes: the cores' edges at the faces between cubes, the slabs' between
// them), the spline is C2 across both faces up to the edge — C0 there before, within two elements
// of every inner rim — while edges of valence 3 (the pillowed cube's) keep the margin; the B-spline
// basis is then non-negative, a partition of unity, with a function fewer per extra.
TEST(Continuity, RegularEdgesAreC2UpToTheEdgeAndNonNegative) {
  std::vector<Case> cases = family();
  cases.push_back({"ring of 4, pillow 2", [] { return ring_blocks(4, 3, 2); }});
  for (const Case& c : cases) {
    tmesh::ContinuityParams p;
    p.surface_layer = true;  // the slabs' lines up to the surface: a slab two elements thick has no other
    const auto [plain, r0] = raised(c.make(), p);
    p.regular_edges = true;
    auto [ts, r] = raised(c.make(), p);
    const std::vector<FaceSample> before = face_samples(plain), after = face_samples(ts);
    ASSERT_EQ(before.size(), after.size()) << c.name;
    int by_edge = 0, missed = 0, c2_before = 0, c2_after = 0;
    for (std::size_t k = 0; k < after.size(); ++k) {
      c2_before += before[k].c2, c2_after += after[k].c2;
      if (after[k].near_rims == 1 && after[k].near_regular) by_edge += after[k].c2 && !before[k].c2, missed += !after[k].c2;
    }
    std::printf("%s: %d edge points; C2 face samples %d -> %d of %zu; next to one regular rim: %d became C2, %d not\n", c.name, r.edge_points, c2_before,
                c2_after, after.size(), by_edge, missed);
    EXPECT_EQ(r.constrained, 2 * r.lines + 8 * r.edge_points) << c.name;
    EXPECT_GE(c2_after, c2_before) << c.name;
    const bool ring_with_pillow = std::string(c.name).find("ring") != std::string::npos && std::string(c.name).find("pillow 0") == std::string::npos;
    if (!ring_with_pillow) {
      EXPECT_EQ(r.edge_points, 0) << c.name << ": every inner edge has three blocks around it (or none is inner)";
      continue;
    }
    EXPECT_GT(r.edge_points, 0) << c.name;
    EXPECT_GT(by_edge, 0) << c.name;
    EXPECT_EQ(missed, 0) << c.name;
    // In the B-spline basis: the same spline, non-negative functions, W one per edge point.
    const extract::GlobalBasis removal = global_basis_of(ts);
    const std::vector<tmesh::TMesh> kept = ts;
    EXPECT_EQ(tmesh::smooth_rows_as_bsplines(ts), r.lines) << c.name;
    const extract::GlobalBasis bs = global_basis_of(ts);
    std::set<int> free_ids;
    for (const auto& t : ts)
      for (const auto& f : t.free_nodes) free_ids.insert(f.id);
    EXPECT_EQ(free_ids.size(), static_cast<std::size_t>(r.lines + r.edge_points)) << c.name;
    EXPECT_EQ(bs.points.size(), removal.points.size()) << c.name;
    EXPECT_LT(bs.partition_of_unity_error, 1e-12) << c.name;
    EXPECT_LT(removal.min_coefficient, 0.0) << c.name;
    EXPECT_GE(bs.min_coefficient, -1e-12) << c.name;
    for (std::size_t b = 0; b < ts.size(); ++b) EXPECT_EQ(ts[b].control_points, kept[b].control_points) << c.name;
    EXPECT_EQ(face_samples(ts).size(), after.size());
  }
}
