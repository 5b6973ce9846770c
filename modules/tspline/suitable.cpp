// Refinement rules making the polynomial T-spline basis of an octree T-mesh a partition of unity:
// the slab rule, iterative repair, graded balance (see suitable.h for what was measured).
#include "tspline/suitable.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "core/errors.h"

namespace volts::tspline {
namespace {

using octree::Cell;
using octree::Index3;
using octree::Octree;
using LeafKey = std::array<int, 4>;  // level and corner: a leaf's identity across rebuilds

LeafKey leaf_key(const Cell& c) { return {c.level, c.lo[0], c.lo[1], c.lo[2]}; }

// Splits the listed leaves (once each: their children are not in the set) and 2:1 balances.
int split_marked(Octree& tree, const std::set<LeafKey>& marked) {
  if (marked.empty()) return 0;
  const int n = tree.refine([&](const Cell& c) { return marked.count(leaf_key(c)) > 0; });
  return n + tree.balance();
}

double column_sum_error(const BezierElement& e) {
  if (e.op.rows() == 0) return 1.0;
  return ((Eigen::RowVectorXd::Ones(e.op.rows()) * e.op).array() - 1.0).abs().maxCoeff();
}

}  // namespace

std::vector<int> non_unity_leaves(const TSpline& spline, double tolerance) {
  std::vector<int> out;
  for (const BezierElement& e : spline.elements())
    if (column_sum_error(e) > tolerance) out.push_back(e.leaf);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

int slab_closure(Octree& tree, int axis) {
  if (axis < 0 || axis > 2) throw core::InvalidInputError("tspline: slab axis " + std::to_string(axis) + " out of [0, 2]");
  const int S = tree.root_side();
  int splits = tree.balance();
  for (;;) {
    // Deepest level over each unit slab [x, x + 1] along the axis.
    std::vector<int> deepest(std::size_t(S), 0);
    for (const Cell& c : tree.leaves())
      for (int x = c.lo[axis]; x < c.lo[axis] + c.side; ++x) deepest[x] = std::max(deepest[x], c.level);
    std::set<LeafKey> marked;
    for (const Cell& c : tree.leaves()) {
      const auto first = deepest.begin() + c.lo[axis];
      if (*std::max_element(first, first + c.side) > c.level) marked.insert(leaf_key(c));
    }
    if (marked.empty()) return splits;
    splits += split_marked(tree, marked);
  }
}

int repair_partition_of_unity(Octree& tree, double tolerance, int max_iterations, int* iterations) {
  if (!(tolerance > 0)) throw core::InvalidInputError("tspline: partition of unity tolerance must be positive");
  int splits = tree.balance(), rounds = 0;
  for (;;) {
    const TSpline spline(tree);
    const std::vector<int> bad = non_unity_leaves(spline, tolerance);
    if (bad.empty()) break;
    if (rounds == max_iterations)
      throw core::NumericalError("tspline: partition of unity repair did not converge in " + std::to_string(max_iterations) +
                                 " rounds (" + std::to_string(bad.size()) + " leaves still defective)");
    std::set<LeafKey> marked;
    for (int l : bad)
      if (tree.leaves()[l].level < tree.max_level()) marked.insert(leaf_key(tree.leaves()[l]));
    if (marked.empty())  // only finest leaves defective: the uniform tree is a partition of unity
      for (const Cell& c : tree.leaves())
        if (c.level < tree.max_level()) marked.insert(leaf_key(c));
    if (marked.empty())  // cannot happen: a uniform tree at max level sums to one
      throw core::NumericalError("tspline: uniform tree at max level is not a partition of unity");
    splits += split_marked(tree, marked);
    ++rounds;
  }
  if (iterations) *iterations = rounds;
  return splits;
}

int balance_neighbourhood(Octree& tree, int radius) {
  if (radius < 1) throw core::InvalidInputError("tspline: neighbourhood radius must be >= 1, got " + std::to_string(radius));
  const int S = tree.root_side();
  int splits = tree.balance();
  for (;;) {
    std::set<LeafKey> marked;
    for (const Cell& c : tree.leaves()) {
      if (c.level + 2 > tree.max_level()) continue;  // nothing can be two levels deeper
      // A level+1 cell aligned in the expanded box is subdivided iff the leaf at its corner is
      // deeper than level+1 (dyadic cells nest).
      const int h = c.side / 2, r = radius * c.side;
      bool deeper = false;
      for (int z = std::max(0, c.lo[2] - r); z < std::min(S, c.lo[2] + c.side + r) && !deeper; z += h)
        for (int y = std::max(0, c.lo[1] - r); y < std::min(S, c.lo[1] + c.side + r) && !deeper; y += h)
          for (int x = std::max(0, c.lo[0] - r); x < std::min(S, c.lo[0] + c.side + r) && !deeper; x += h)
            deeper = tree.leaves()[tree.locate({x, y, z})].level > c.level + 1;
      if (deeper) marked.insert(leaf_key(c));
    }
    if (marked.empty()) return splits;
    splits += split_marked(tree, marked);
  }
}

int make_partition_of_unity(Octree& tree, const SuitableParams& params, SuitableReport* report) {
  if (params.axis < -1 || params.axis > 2)
    throw core::InvalidInputError("tspline: slab axis " + std::to_string(params.axis) + " out of [-1, 2]");
  if (!(params.tolerance > 0)) throw core::InvalidInputError("tspline: partition of unity tolerance must be positive");
  SuitableReport r;
  r.splits = tree.balance();
  if (params.rule == SuitableRule::slab) {
    int best_axis = params.axis;
    if (best_axis < 0) {  // try the three axes on copies; fewest leaves wins (ties: lowest axis)
      std::size_t fewest = std::numeric_limits<std::size_t>::max();
      for (int a = 0; a < 3; ++a) {
        Octree copy = tree;
        slab_closure(copy, a);
        if (copy.leaves().size() < fewest) {
          fewest = copy.leaves().size();
          best_axis = a;
        }
      }
    }
    r.axis = best_axis;
    r.splits += slab_closure(tree, best_axis);
  }
  r.splits += repair_partition_of_unity(tree, params.tolerance, params.max_iterations, &r.repair_iterations);
  r.pou_error = TSpline(tree).partition_of_unity_error();
  if (report) *report = r;
  return r.splits;
}

std::vector<Eigen::Vector3d> greville_points(const TSpline& spline) {
  std::vector<Eigen::Vector3d> g(spline.num_functions());
  const double S = spline.root_side();
  for (int i = 0; i < spline.num_functions(); ++i)
    for (int a = 0; a < 3; ++a) {
      const LocalKnots& k = spline.functions()[i].knots[a];
      g[i][a] = (k[1] + k[2] + k[3]) / (3.0 * S);
    }
  return g;
}

double greville_identity_error(const TSpline& spline) {
  const std::vector<Eigen::Vector3d> g = greville_points(spline);
  const double S = spline.root_side();
  double err = 0;
  for (const BezierElement& e : spline.elements()) {
    Eigen::MatrixXd G(e.functions.size(), 3);
    for (std::size_t r = 0; r < e.functions.size(); ++r) G.row(Eigen::Index(r)) = g[e.functions[r]].transpose();
    const Eigen::MatrixXd bez = e.op.transpose() * G;  // kBernstein x 3
    for (int k = 0; k <= kDegree; ++k)
      for (int j = 0; j <= kDegree; ++j)
        for (int i = 0; i <= kDegree; ++i) {
          const int b = i + (kDegree + 1) * (j + (kDegree + 1) * k);
          const std::array<int, 3> ijk{i, j, k};
          for (int a = 0; a < 3; ++a) {
            const double id = (e.lo[a] + ijk[a] * (e.hi[a] - e.lo[a]) / double(kDegree)) / S;
            err = std::max(err, std::abs(bez(b, a) - id));
          }
        }
  }
  return err;
}

}  // namespace volts::tspline
