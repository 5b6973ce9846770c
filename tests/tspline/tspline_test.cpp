// Tests of tspline/tspline.h over families of octree T-meshes (uniform levels 0–3; balanced
// adaptive trees refined toward a point, a plane and a sphere; random predicates with fixed seeds):
// uniform trees give the tensor-product clamped cubic B-splines, the local knot vectors agree with
// brute-force ray casting, the Bézier pieces reproduce direct evaluation, R is a partition of unity
// with positive Bézier denominators, and the rational Bézier hexes reproduce Σ R_i P_i. The number
// of adaptive trees whose polynomial basis does not sum to one is printed, not asserted.
#include "tspline/tspline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <string>

#include "bezier/bernstein.h"
#include "bezier/bspline.h"
#include "common/octree_families.h"
#include "core/errors.h"
#include "octree/refine.h"

using namespace volts;
using namespace volts::tspline;
using octree::Cell;
using octree::Index3;
using octree::Octree;

namespace {

constexpr double kTol = 1e-12;

Octree uniform(int level) {
  Octree t(octree::OctreeParams{level});
  t.refine([](const Cell&) { return true; });
  return t;
}

struct Family {
  std::string name;
  std::unique_ptr<Octree> tree;
  std::unique_ptr<TSpline> spline;
};

Family make(const std::string& name, Octree tree) {
  tree.balance();
  Family f{name, std::make_unique<Octree>(std::move(tree)), nullptr};
  f.spline = std::make_unique<TSpline>(*f.tree);
  return f;
}

// The adaptive families, balanced, built once.
const std::vector<Family>& adaptive() {
  static const std::vector<Family> families = [] {
    std::vector<Family> out;
    // Toward a point, a plane and a sphere surface (common/octree_families.h).
    Octree point(octree::OctreeParams{4}), plane(octree::OctreeParams{4}), sphere(octree::OctreeParams{4});
    point.refine(test::toward_point);
    plane.refine(test::toward_plane);
    sphere.refine(test::toward_sphere);
    out.push_back(make("point", std::move(point)));
    out.push_back(make("plane", std::move(plane)));
    out.push_back(make("sphere", std::move(sphere)));
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      Octree t(octree::OctreeParams{seed <= 4 ? 3 : 4});
      const double p = seed <= 4 ? 0.4 : 0.2;
      t.refine([&](const Cell& c) { return c.level == 0 || octree::random_split(c, seed, p); });
      out.push_back(make("random" + std::to_string(seed), std::move(t)));
    }
    return out;
  }();
  return families;
}

Eigen::VectorXd tensor_bernstein(const Eigen::Vector3d& xi) {
  const Eigen::VectorXd b0 = bezier::bernstein_basis(3, xi[0]), b1 = bezier::bernstein_basis(3, xi[1]),
                        b2 = bezier::bernstein_basis(3, xi[2]);
  Eigen::VectorXd B(kBernstein);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) B[i + 4 * (j + 4 * k)] = b0[i] * b1[j] * b2[k];
  return B;
}

Eigen::Vector3d random_unit(std::mt19937& rng) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  return {U(rng), U(rng), U(rng)};
}

// Brute-force ray casting from the definition: the first two integer positions beyond the anchor
// on a closed face x_a = lo_a or hi_a of a leaf whose closed box contains the point.
std::vector<int> brute_hits(const Octree& t, const Index3& node, int a, int dir) {
  std::vector<int> hits;
  for (int x = node[a] + dir; x >= 0 && x <= t.root_side() && hits.size() < 2; x += dir) {
    Index3 q = node;
    q[a] = x;
    for (const Cell& c : t.leaves()) {
      bool inside = true;
      for (int d = 0; d < 3; ++d) inside = inside && c.lo[d] <= q[d] && q[d] <= c.hi()[d];
      if (inside && (q[a] == c.lo[a] || q[a] == c.hi()[a])) {
        hits.push_back(x);
        break;
      }
    }
  }
  return hits;
}

}  // namespace

TEST(TSpline, UniformTreesGiveClampedTensorProductBSplines) {
  std::mt19937 rng(7);
  for (int level = 0; level <= 3; ++level) {
    const Octree tree = uniform(level);
    const TSpline ts(tree);
    const int n = 1 << level;
    ASSERT_EQ(ts.num_functions(), (n + 3) * (n + 3) * (n + 3)) << "level " << level;
    EXPECT_EQ(ts.elements().size(), std::size_t(n) * n * n);
    EXPECT_EQ(ts.split_leaves(), 0);
    EXPECT_LT(ts.partition_of_unity_error(), kTol);
    // Index of each function in the clamped knot vector, per axis.
    std::vector<int> clamped_index(4, 0);
    for (int i = 1; i < n; ++i) clamped_index.push_back(i);
    clamped_index.insert(clamped_index.end(), 4, n);
    const std::vector<double> U = bezier::open_uniform_knots(n, 3);
    std::vector<std::array<int, 3>> tp(ts.num_functions());
    std::vector<int> seen((n + 3) * (n + 3) * (n + 3), 0);
    for (int i = 0; i < ts.num_functions(); ++i) {
      for (int a = 0; a < 3; ++a) {
        int found = -1;
        for (int j = 0; j + 5 <= int(clamped_index.size()); ++j)
          if (std::equal(clamped_index.begin() + j, clamped_index.begin() + j + 5, ts.functions()[i].knots[a].begin()))
            found = j;
        ASSERT_GE(found, 0) << "function " << i << " axis " << a << " has no clamped knots";
        tp[i][a] = found;
      }
      ++seen[tp[i][0] + (n + 3) * (tp[i][1] + (n + 3) * tp[i][2])];
    }
    for (int s : seen) EXPECT_EQ(s, 1);  // a bijection onto the tensor-product basis
    for (int r = 0; r < 30; ++r) {
      Eigen::Vector3d u = random_unit(rng);
      if (r < 8)  // corners of the root too (clamped ends: interpolation)
        for (int a = 0; a < 3; ++a) u[a] = (r >> a) & 1;
      std::array<bezier::BasisValues, 3> bv;
      for (int a = 0; a < 3; ++a) bv[a] = bezier::basis_functions(U, 3, u[a]);
      double sum = 0;
      for (int i = 0; i < ts.num_functions(); ++i) {
        double expected = 1;
        for (int a = 0; a < 3; ++a) {
          const int k = tp[i][a] - (bv[a].span - 3);
          expected *= (k >= 0 && k <= 3) ? bv[a].values[k] : 0.0;
        }
        const double got = ts.basis(i, u);
        EXPECT_NEAR(got, expected, kTol) << "level " << level << " function " << i;
        sum += got;
      }
      EXPECT_NEAR(sum, 1.0, kTol);
    }
  }
}

TEST(TSpline, KnotVectorsMatchBruteForceRayCasting) {
  for (const Family& f : adaptive()) {
    if (f.tree->max_level() > 3) continue;  // brute force is O(nodes · S · leaves)
    const TSpline& ts = *f.spline;
    const int S = ts.root_side();
    for (const BlendingFunction& fn : ts.functions()) {
      for (int a = 0; a < 3; ++a) {
        std::vector<int> minus = brute_hits(*f.tree, fn.anchor, a, -1), plus = brute_hits(*f.tree, fn.anchor, a, +1);
        while (minus.size() < 2) minus.push_back(0);
        while (plus.size() < 2) plus.push_back(S);
        LocalKnots expected{minus[1], minus[0], fn.anchor[a], plus[0], plus[1]};
        if (fn.layer[a] == -1) expected = {0, 0, 0, 0, plus[0]};
        if (fn.layer[a] == +1) expected = {minus[0], S, S, S, S};
        EXPECT_EQ(fn.knots[a], expected) << f.name << " anchor " << fn.anchor[0] << "," << fn.anchor[1] << ","
                                         << fn.anchor[2] << " axis " << a;
      }
    }
  }
}

// Per element: the Bézier form of every listed function equals its direct evaluation, listed
// functions are positive inside, and every function not listed is zero there.
TEST(TSpline, BezierPiecesReproduceDirectEvaluation) {
  std::mt19937 rng(11);
  std::vector<const TSpline*> splines;
  std::vector<std::unique_ptr<TSpline>> own;
  for (int level = 0; level <= 3; ++level) own.push_back(std::make_unique<TSpline>(uniform(level)));
  for (auto& s : own) splines.push_back(s.get());
  for (const Family& f : adaptive()) splines.push_back(f.spline.get());
  std::uniform_int_distribution<int> pick(0, 1 << 30);
  for (const TSpline* ts : splines) {
    for (int e = 0; e < int(ts->elements().size()); ++e) {
      const BezierElement& el = ts->elements()[e];
      ASSERT_TRUE(std::is_sorted(el.functions.begin(), el.functions.end()));
      for (int r = 0; r < 2; ++r) {
        const Eigen::Vector3d xi = random_unit(rng), u = ts->element_point(e, xi);
        const Eigen::VectorXd vals = el.op * tensor_bernstein(xi);
        for (const auto& [i, v] : ts->basis(u)) {
          const auto it = std::lower_bound(el.functions.begin(), el.functions.end(), i);
          if (it == el.functions.end() || *it != i) {
            EXPECT_EQ(v, 0.0) << "function " << i << " not listed on element " << e;
            continue;
          }
          EXPECT_NEAR(vals[it - el.functions.begin()], v, kTol) << "function " << i << " element " << e;
          EXPECT_GT(v, 0.0);
        }
        // A few functions not listed: exactly zero by direct evaluation.
        for (int k = 0; k < 3; ++k) {
          const int i = pick(rng) % ts->num_functions();
          if (!std::binary_search(el.functions.begin(), el.functions.end(), i)) {
            EXPECT_EQ(ts->basis(i, u), 0.0);
          }
        }
      }
    }
  }
}

TEST(TSpline, RationalBasisIsAPartitionOfUnityWithPositiveDenominators) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> W(0.5, 2.0);
  for (const Family& cf : adaptive()) {
    TSpline ts = *cf.spline;
    for (int pass = 0; pass < 2; ++pass) {
      if (pass == 1) {
        std::vector<double> w(ts.num_functions());
        for (double& x : w) x = W(rng);
        ts.set_weights(w);
      }
      for (int e = 0; e < int(ts.elements().size()); ++e) {
        const BezierElement& el = ts.elements()[e];
        const Eigen::VectorXd den = ts.denominator_coefficients(e);
        EXPECT_GT(den.minCoeff(), 0.0) << cf.name << " element " << e;
        const Eigen::Vector3d xi = random_unit(rng);
        const Eigen::VectorXd N = el.op * tensor_bernstein(xi);
        Eigen::VectorXd wN(N.size());
        for (int r = 0; r < N.size(); ++r) wN[r] = ts.weights()[el.functions[r]] * N[r];
        const Eigen::VectorXd R = wN / wN.sum();
        EXPECT_NEAR(R.sum(), 1.0, kTol);
        const auto direct = ts.rational_basis(ts.element_point(e, xi));
        double direct_sum = 0;
        for (const auto& [i, v] : direct) {
          direct_sum += v;
          const auto it = std::lower_bound(el.functions.begin(), el.functions.end(), i);
          if (it != el.functions.end() && *it == i) {
            EXPECT_NEAR(R[it - el.functions.begin()], v, kTol);
          } else {
            EXPECT_EQ(v, 0.0);
          }
        }
        EXPECT_NEAR(direct_sum, 1.0, kTol);
      }
    }
  }
}

TEST(TSpline, RationalBezierHexesReproduceTheSpline) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> W(0.5, 2.0), X(-1.0, 1.0);
  std::vector<TSpline> splines;
  splines.emplace_back(uniform(2));
  for (const Family& f : adaptive()) splines.push_back(*f.spline);
  for (TSpline& ts : splines) {
    for (int pass = 0; pass < 2; ++pass) {
      if (pass == 1) {
        std::vector<double> w(ts.num_functions());
        for (double& x : w) x = W(rng);
        ts.set_weights(w);
      }
      const Eigen::Vector3d c(0.3, -1.7, 2.25);
      const std::vector<Eigen::Vector3d> constant(ts.num_functions(), c);
      std::vector<Eigen::Vector3d> P(ts.num_functions());
      for (auto& p : P) p = {X(rng), X(rng), X(rng)};
      for (int e = 0; e < int(ts.elements().size()); ++e) {
        const bezier::BezierHex hc = ts.element_hex(e, constant), hp = ts.element_hex(e, P);
        const Eigen::Vector3d xi = random_unit(rng), u = ts.element_point(e, xi);
        EXPECT_LT((bezier::evaluate(hc, xi) - c).norm(), kTol);
        EXPECT_LT((bezier::evaluate(hp, xi) - ts.evaluate(P, u)).norm(), kTol) << "element " << e;
      }
    }
  }
}

// Not an assertion: how often the polynomial basis of a balanced octree T-mesh fails to sum to one
// (not analysis-suitable), and how many leaves knot planes split into several Bézier elements.
// Linear precision on a uniform tree: control points at the Greville points (k1 + k2 + k3) / 3S
// give the identity map, through the rational Bézier hexes and by direct evaluation.
TEST(TSpline, UniformTreeWithGrevillePointsIsTheIdentity) {
  std::mt19937 rng(9);
  const TSpline ts(uniform(2));
  std::vector<Eigen::Vector3d> P(ts.num_functions());
  for (int i = 0; i < ts.num_functions(); ++i)
    for (int a = 0; a < 3; ++a) {
      const LocalKnots& k = ts.functions()[i].knots[a];
      P[i][a] = (k[1] + k[2] + k[3]) / (3.0 * ts.root_side());
    }
  for (int e = 0; e < int(ts.elements().size()); ++e) {
    const bezier::BezierHex hex = ts.element_hex(e, P);
    for (int r = 0; r < 3; ++r) {
      const Eigen::Vector3d xi = random_unit(rng), u = ts.element_point(e, xi);
      EXPECT_LT((bezier::evaluate(hex, xi) - u).norm(), kTol);
      EXPECT_LT((ts.evaluate(P, u) - u).norm(), kTol);
    }
  }
}

TEST(TSpline, ReportPartitionOfUnityOfAdaptiveTrees) {
  int failing = 0;
  std::printf("%-9s %6s %6s %9s %8s %8s %10s\n", "tree", "leaves", "nodes", "functions", "elements", "split", "PoU error");
  for (const Family& f : adaptive()) {
    const TSpline& ts = *f.spline;
    const double err = ts.partition_of_unity_error();
    failing += err > kTol;
    std::printf("%-9s %6zu %6zu %9d %8zu %8d %10.3g\n", f.name.c_str(), f.tree->leaves().size(), ts.nodes().size(),
                ts.num_functions(), ts.elements().size(), ts.split_leaves(), err);
  }
  std::printf("adaptive balanced trees whose Σ N_j != 1 somewhere: %d of %zu\n", failing, adaptive().size());
  SUCCEED();
}

TEST(TSpline, TypedErrors) {
  TSpline ts(uniform(1));
  EXPECT_THROW(ts.set_weights(std::vector<double>(3, 1.0)), core::InvalidInputError);
  std::vector<double> w(ts.num_functions(), 1.0);
  w[4] = 0.0;
  EXPECT_THROW(ts.set_weights(w), core::InvalidInputError);
  w[4] = std::nan("");
  EXPECT_THROW(ts.set_weights(w), core::InvalidInputError);
  EXPECT_THROW(ts.basis(-1, Eigen::Vector3d(0.5, 0.5, 0.5)), core::InvalidInputError);
  EXPECT_THROW(ts.basis(ts.num_functions(), Eigen::Vector3d(0.5, 0.5, 0.5)), core::InvalidInputError);
  EXPECT_THROW(ts.basis(0, Eigen::Vector3d(1.5, 0.5, 0.5)), core::InvalidInputError);
  EXPECT_THROW(ts.basis(Eigen::Vector3d(0.5, std::nan(""), 0.5)), core::InvalidInputError);
  EXPECT_THROW(ts.element_hex(0, std::vector<Eigen::Vector3d>(2)), core::InvalidInputError);
  EXPECT_THROW(ts.element_hex(-1, std::vector<Eigen::Vector3d>(ts.num_functions())), core::InvalidInputError);
  EXPECT_THROW(ts.denominator_coefficients(int(ts.elements().size())), core::InvalidInputError);
  EXPECT_THROW(ts.evaluate(std::vector<Eigen::Vector3d>(1), Eigen::Vector3d(0.5, 0.5, 0.5)), core::InvalidInputError);
}
